// SPDX-License-Identifier: MIT
// The observables of a step (summed over the ranks), and the state's checks and node products.
#include "solver/solver.hpp"

#include <cmath>

namespace pd::solver {

double energy_balance(const Observables& o) {
    return o.kinetic_energy + o.elastic_energy + o.contact_energy + o.fracture_energy +
           o.damping_dissipation + o.friction_dissipation + o.viscous_dissipation - o.external_work;
}

double energy_in_play(const Observables& o) {
    return o.kinetic_energy + o.elastic_energy + o.contact_energy + std::abs(o.fracture_energy) +
           o.damping_dissipation + o.friction_dissipation + o.viscous_dissipation +
           std::abs(o.external_work);
}

namespace {

/// Kinetic energy, momentum and gravity potential of this rank's rows.
void node_sums(const Forces& f, Observables& o) {
    double ke = 0, p0 = 0, p1 = 0, p2 = 0, gp = 0;
    const auto n = static_cast<std::int64_t>(f.s.rows.size());
    auto node = [&](std::int64_t a, double& ke, double& p0, double& p1, double& p2, double& gp) {
        const std::int64_t i = f.s.rows[static_cast<std::size_t>(a)];
        const double mass =
            f.s.rho[static_cast<std::size_t>(i)] * f.s.vol[static_cast<std::size_t>(i)];
        const double* v = &f.s.v[3 * i];
        ke += 0.5 * mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        p0 += mass * v[0];
        p1 += mass * v[1];
        p2 += mass * v[2];
        if (f.s.moving[static_cast<std::size_t>(i)])
            gp -= mass *
                  (f.g[0] * f.s.u[3 * i] + f.g[1] * f.s.u[3 * i + 1] + f.g[2] * f.s.u[3 * i + 2]);
    };
    if (threaded(n, parallel_min_nodes)) {
#pragma omp parallel for schedule(static) reduction(+ : ke, p0, p1, p2, gp)
        for (std::int64_t a = 0; a < n; ++a)
            node(a, ke, p0, p1, p2, gp);
    } else {
        for (std::int64_t a = 0; a < n; ++a)
            node(a, ke, p0, p1, p2, gp);
    }
    o.kinetic_energy = ke;
    o.momentum[0] = p0;
    o.momentum[1] = p1;
    o.momentum[2] = p2;
    o.gravity_potential = gp;
}

/// The sums over ranks (counts are exact in doubles below 2^53).
void reduce(const Domain& dom, Observables& o) {
    // One reduction for every sum over ranks (counts are exact in doubles below 2^53).
    std::vector<double> all{o.kinetic_energy,
                            o.momentum[0],
                            o.momentum[1],
                            o.momentum[2],
                            o.elastic_energy,
                            o.contact_energy,
                            o.external_work,
                            static_cast<double>(o.contact_count),
                            static_cast<double>(o.broken_bonds),
                            o.fracture_energy,
                            o.damping_dissipation,
                            o.friction_dissipation,
                            o.viscous_dissipation,
                            o.gravity_potential,
                            static_cast<double>(o.inside_pairs),
                            static_cast<double>(o.beyond_wall)};
    all.insert(all.end(), o.wall_force.begin(), o.wall_force.end());
    all.insert(all.end(), o.wall_moment.begin(), o.wall_moment.end());
    dom.sum(all);
    o.kinetic_energy = all[0];
    for (std::size_t d = 0; d < 3; ++d)
        o.momentum[d] = all[1 + d];
    o.elastic_energy = all[4];
    o.contact_energy = all[5];
    o.external_work = all[6];
    o.contact_count = static_cast<std::int64_t>(all[7]);
    o.broken_bonds = static_cast<std::int64_t>(all[8]);
    o.fracture_energy = all[9];
    o.damping_dissipation = all[10];
    o.friction_dissipation = all[11];
    o.viscous_dissipation = all[12];
    o.gravity_potential = all[13];
    o.inside_pairs = static_cast<std::int64_t>(all[14]);
    o.beyond_wall = static_cast<std::int64_t>(all[15]);
    constexpr std::ptrdiff_t first = 16;
    const auto nw = static_cast<std::ptrdiff_t>(o.wall_force.size());
    std::copy(all.begin() + first, all.begin() + first + nw, o.wall_force.begin());
    std::copy(all.begin() + first + nw, all.end(), o.wall_moment.begin());
}

} // namespace

Observables Solver::observe() const {
    Observables o;
    node_sums(f_, o);
    o.elastic_energy = elastic_energy_;
    o.contact_energy = contact_energy_;
    o.external_work = external_work_;
    o.fracture_energy = f_.diss.fracture;
    o.damping_dissipation = f_.diss.damping;
    o.friction_dissipation = f_.diss.friction;
    o.viscous_dissipation = f_.diss.viscous;
    o.contact_count = contact_count_;
    const bool averaged = interval_steps_ > 0 && !interval_sum_.empty();
    const std::size_t nw = f_.wall_load.force.size();
    if (averaged) {
        // Sums over the interval's steps (reduced over the ranks below), then the mean.
        o.wall_force.assign(interval_sum_.begin(), interval_sum_.begin() + nw);
        o.wall_moment.assign(interval_sum_.begin() + nw, interval_sum_.begin() + 2 * nw);
    } else {
        o.wall_force = f_.wall_load.force;
        o.wall_moment = f_.wall_load.moment;
    }
    o.broken_bonds = f_.broken_total;
    for (const auto& t : terms_)
        t->observe(f_, o);
    if (f_.dom->distributed())
        reduce(*f_.dom, o);
    o.broken_bonds /= 2;
    if (averaged) {
        for (std::size_t k = 0; k < nw; ++k) {
            o.wall_force[k] /= static_cast<double>(interval_steps_);
            o.wall_moment[k] /= static_cast<double>(interval_steps_);
        }
        const std::vector<double> load(interval_sum_.begin() + 2 * nw, interval_sum_.end());
        f_.reactions.result(*f_.dom, o.body_force, o.body_moment, &load, interval_steps_);
    } else {
        f_.reactions.result(*f_.dom, o.body_force, o.body_moment);
    }
    return o;
}

void Solver::nodal_force(std::vector<double>& out) const {
    out.resize(3 * f_.s.n);
    for (std::size_t i = 0; i < f_.s.n; ++i)
        for (int d = 0; d < 3; ++d)
            out[3 * i + static_cast<std::size_t>(d)] =
                f_.s.f[3 * i + static_cast<std::size_t>(d)] * f_.s.vol[i];
}

std::int64_t Solver::first_nonfinite() const {
    for (auto row : f_.s.rows) {
        const auto i = static_cast<std::size_t>(row);
        for (std::size_t d = 0; d < 3; ++d)
            if (!std::isfinite(f_.s.x[3 * i + d]) || !std::isfinite(f_.s.v[3 * i + d]))
                return static_cast<std::int64_t>(i);
    }
    return -1;
}

std::vector<double> Solver::body_centres() const {
    std::vector<double> c(3 * f_.m.bodies.num(), 0.0);
    for (auto row : f_.s.rows) {
        const auto i = static_cast<std::size_t>(row);
        const auto b = static_cast<std::size_t>(f_.s.body[i]);
        for (std::size_t d = 0; d < 3; ++d)
            c[3 * b + d] += f_.s.rho[i] * f_.s.vol[i] * f_.s.x[3 * i + d];
    }
    f_.dom->sum(c);
    for (std::size_t b = 0; b < f_.m.bodies.num(); ++b)
        for (std::size_t d = 0; d < 3; ++d)
            c[3 * b + d] /= f_.body_mass[b];
    return c;
}

} // namespace pd::solver
