// SPDX-License-Identifier: MIT
#include "solver/solver.hpp"

#include "core/errors.hpp"
#include "model/pmb.hpp"
#include "solver/bond_forces.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pd::solver {

Solver::Solver(const model::Model& m) : m_(m) {
    const std::size_t n = m.nodes.num(), nb = m.bodies.num();
    s_.n = n;
    s_.x0 = m.nodes.x0;
    s_.x = m.nodes.x0;
    s_.u.assign(3 * n, 0.0);
    s_.v.assign(3 * n, 0.0);
    s_.f.assign(3 * n, 0.0);
    s_.vol = m.nodes.volume;
    s_.body = m.nodes.body;
    s_.rho.resize(n);
    s_.moving.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const auto b = static_cast<std::size_t>(s_.body[i]);
        s_.rho[i] = m.materials[static_cast<std::size_t>(m.bodies.material[b])].density;
        s_.moving[i] = m.bodies.fixed[b] ? 0 : 1;
    }
    // Bond data: reference lengths and partial-volume factors, computed once.
    b_.offsets = m.bonds.offsets;
    b_.neighbor = m.bonds.neighbor;
    b_.xi.resize(b_.neighbor.size());
    b_.beta.resize(b_.neighbor.size());
    b_.alive.assign(b_.neighbor.size(), 1);
    for (std::size_t i = 0; i < n; ++i) {
        const auto b = static_cast<std::size_t>(s_.body[i]);
        for (auto k = b_.offsets[i]; k < b_.offsets[i + 1]; ++k) {
            const auto j = static_cast<std::size_t>(b_.neighbor[static_cast<std::size_t>(k)]);
            double r2 = 0;
            for (int d = 0; d < 3; ++d)
                r2 += std::pow(s_.x0[3 * j + d] - s_.x0[3 * i + d], 2);
            const double r = std::sqrt(r2);
            if (!(r > 0))
                throw InputError(fmt::format("nodes {} and {} coincide (zero-length bond)", i, j));
            b_.xi[static_cast<std::size_t>(k)] = r;
            b_.beta[static_cast<std::size_t>(k)] =
                model::partial_volume(r, m.bodies.horizon[b], m.bodies.mesh_size[b]);
        }
    }
    law_.c.resize(nb);
    law_.s0.resize(nb);
    for (std::size_t b = 0; b < nb; ++b) {
        const auto& mat = m.materials[static_cast<std::size_t>(m.bodies.material[b])];
        auto k = model::pmb_constants(mat, m.bodies.horizon[b], m.dimension, m.planar);
        law_.c[b] = k.c;
        law_.s0[b] = k.s0;
        law_.any_breakable = law_.any_breakable || (std::isfinite(k.s0) && !m.bodies.fixed[b]);
    }
    for (int d = 0; d < 3; ++d)
        g_[d] = m.loading.gravity[static_cast<std::size_t>(d)];
    double rc = 0;
    for (const auto& p : m.contact)
        rc = std::max(rc, p.radius);
    const double skin = m.solver.contact_skin > 0 ? m.solver.contact_skin : rc;
    contact_ = std::make_unique<ContactList>(m, skin > 0 ? skin : 1.0);
    t_bonds_ = timers_.id("pd::solver::bond_forces");
    t_search_ = timers_.id("pd::solver::contact_search");
    t_contact_ = timers_.id("pd::solver::contact_forces");
    t_integrate_ = timers_.id("pd::solver::integrate");
}

StableDt Solver::stable_dt() const {
    StableDt r;
    r.pd = std::numeric_limits<double>::infinity();
    r.contact = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < s_.n; ++i) {
        if (!s_.moving[i])
            continue;
        const auto b = static_cast<std::size_t>(s_.body[i]);
        double k = 0;
        for (auto q = b_.offsets[i]; q < b_.offsets[i + 1]; ++q) {
            const auto qq = static_cast<std::size_t>(q);
            k += law_.c[b] * b_.beta[qq] * s_.vol[static_cast<std::size_t>(b_.neighbor[qq])] /
                 b_.xi[qq];
        }
        if (k > 0)
            r.pd = std::min(r.pd, std::sqrt(2.0 * s_.rho[i] / k));
    }
    if (contact_->active()) {
        // Worst case: a node pressed into a neighbour body whose nodes fill a contact disc
        // (sphere in 3D) of radius R_c at the densest nodal spacing of the scene.
        double vmin_density = 0; // max volume fraction per node area: V_i / h_i^d
        for (std::size_t b = 0; b < m_.bodies.num(); ++b)
            for (auto i = m_.bodies.begin(b); i < m_.bodies.end(b); ++i)
                vmin_density = std::max(vmin_density, s_.vol[static_cast<std::size_t>(i)] /
                                                          std::pow(m_.bodies.mesh_size[b],
                                                                   m_.dimension));
        for (const auto& p : m_.contact) {
            if (p.stiffness <= 0 || p.radius <= 0)
                continue;
            const double reach = m_.dimension == 3 ? 4.0 / 3.0 * M_PI * std::pow(p.radius, 3)
                                                   : M_PI * p.radius * p.radius;
            double hmin = std::numeric_limits<double>::infinity();
            for (double h : m_.bodies.mesh_size)
                hmin = std::min(hmin, h);
            // Node count within R_c (at least 1) times the largest nodal volume.
            const double nodes_in = std::max(1.0, reach / std::pow(hmin, m_.dimension));
            double vmax = 0, rho_min = std::numeric_limits<double>::infinity();
            for (std::size_t i = 0; i < s_.n; ++i) {
                vmax = std::max(vmax, s_.vol[i]);
                rho_min = std::min(rho_min, s_.rho[i]);
            }
            const double sumv = nodes_in * vmax;
            r.contact = std::min(r.contact, std::sqrt(2.0 * rho_min / (p.stiffness * sumv)));
        }
        (void)vmin_density;
    }
    r.limit = std::min(r.pd, r.contact);
    r.governing = r.contact < r.pd ? "contact stiffness" : "peridynamic bonds";
    return r;
}

void Solver::compute_forces() {
    {
        ScopedTimer t(timers_, t_bonds_);
        auto res = pmb_bond_forces(s_, b_, law_);
        elastic_energy_ = res.elastic_energy;
        broken_total_ += res.newly_broken;
    }
    if (contact_->active()) {
        {
            ScopedTimer t(timers_, t_search_);
            contact_->update(s_);
        }
        ScopedTimer t(timers_, t_contact_);
        contact_count_ = contact_->add_forces(s_);
    }
    if (g_[0] != 0 || g_[1] != 0 || g_[2] != 0) {
        const auto n = static_cast<std::int64_t>(s_.n);
#pragma omp parallel for schedule(static)
        for (std::int64_t i = 0; i < n; ++i)
            for (int d = 0; d < 3; ++d)
                s_.f[3 * i + d] += s_.rho[static_cast<std::size_t>(i)] * g_[d];
    }
}

void Solver::initialize() {
    for (std::size_t b = 0; b < m_.bodies.num(); ++b) {
        if (m_.bodies.fixed[b])
            continue;
        for (auto i = m_.bodies.begin(b); i < m_.bodies.end(b); ++i)
            for (int d = 0; d < 3; ++d)
                s_.v[3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(d)] =
                    m_.bodies.initial_velocity[3 * b + static_cast<std::size_t>(d)];
    }
    compute_forces();
}

void Solver::advance() {
    const double dt = dt_;
    const auto n = static_cast<std::int64_t>(s_.n);
    const bool verlet = m_.solver.integrator == model::Integrator::velocity_verlet;
    const double kick = verlet ? 0.5 * dt : dt;
    {
        ScopedTimer t(timers_, t_integrate_);
#pragma omp parallel for schedule(static)
        for (std::int64_t i = 0; i < n; ++i) {
            if (!s_.moving[static_cast<std::size_t>(i)])
                continue;
            const double a = kick / s_.rho[static_cast<std::size_t>(i)];
            for (int d = 0; d < 3; ++d) {
                const auto k = static_cast<std::size_t>(3 * i + d);
                s_.v[k] += a * s_.f[k];
                s_.u[k] += dt * s_.v[k];
                s_.x[k] = s_.x0[k] + s_.u[k];
            }
        }
    }
    s_.time += dt;
    ++s_.step;
    compute_forces();
    if (verlet) {
        ScopedTimer t(timers_, t_integrate_);
#pragma omp parallel for schedule(static)
        for (std::int64_t i = 0; i < n; ++i) {
            if (!s_.moving[static_cast<std::size_t>(i)])
                continue;
            const double a = kick / s_.rho[static_cast<std::size_t>(i)];
            for (int d = 0; d < 3; ++d) {
                const auto k = static_cast<std::size_t>(3 * i + d);
                s_.v[k] += a * s_.f[k];
            }
        }
    }
}

Observables Solver::observe() const {
    Observables o;
    double ke = 0, p0 = 0, p1 = 0, p2 = 0;
    const auto n = static_cast<std::int64_t>(s_.n);
#pragma omp parallel for schedule(static) reduction(+ : ke, p0, p1, p2)
    for (std::int64_t i = 0; i < n; ++i) {
        const double mass = s_.rho[static_cast<std::size_t>(i)] * s_.vol[static_cast<std::size_t>(i)];
        const double* v = &s_.v[3 * i];
        ke += 0.5 * mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        p0 += mass * v[0];
        p1 += mass * v[1];
        p2 += mass * v[2];
    }
    o.kinetic_energy = ke;
    o.momentum[0] = p0;
    o.momentum[1] = p1;
    o.momentum[2] = p2;
    o.elastic_energy = elastic_energy_;
    o.contact_count = contact_count_;
    o.broken_bonds = broken_total_ / 2;
    return o;
}

void Solver::damage(std::vector<double>& phi) const { damage_phi(s_, b_, phi); }

void Solver::nodal_force(std::vector<double>& out) const {
    out.resize(3 * s_.n);
    for (std::size_t i = 0; i < s_.n; ++i)
        for (int d = 0; d < 3; ++d)
            out[3 * i + static_cast<std::size_t>(d)] =
                s_.f[3 * i + static_cast<std::size_t>(d)] * s_.vol[i];
}

std::int64_t Solver::first_nonfinite() const {
    for (std::size_t i = 0; i < s_.n; ++i)
        for (int d = 0; d < 3; ++d)
            if (!std::isfinite(s_.x[3 * i + static_cast<std::size_t>(d)]) ||
                !std::isfinite(s_.v[3 * i + static_cast<std::size_t>(d)]))
                return static_cast<std::int64_t>(i);
    return -1;
}

} // namespace pd::solver
