// SPDX-License-Identifier: MIT
// The integrator: velocity Verlet (default) or symplectic Euler over the sum of the force terms
// (solver/forces.hpp, terms/terms.def); the stable time step of the terms' limits.
#include "solver/solver.hpp"

#include "core/errors.hpp"
#include "solver/bond_forces.hpp"
#include "solver/detail.hpp"
#include "solver/stability.hpp"

#include <cmath>
#include <limits>

namespace pd::solver {

Solver::Solver(const model::Model& m, Domain* dom, std::vector<index_t> row_neighbors)
    : f_(m)
    , row_neighbors_(std::move(row_neighbors)) {
    f_.dom = dom;
    if (!f_.dom) {
        serial_ = std::make_unique<Domain>(m.nodes.num());
        f_.dom = serial_.get();
    }
    if (f_.dom->num_nodes() != m.nodes.num())
        throw InternalError(fmt::format("domain of {} nodes for a model of {}", f_.dom->num_nodes(),
                                        m.nodes.num()));
    init_state();
    detail::law_constants(f_);
    detail::build_bonds(f_, row_neighbors_);
    init_contact();
    take_rows();
    detail::set_bond_ghosts(f_);
    detail::family_factors(f_);
    f_.body_mass.assign(m.bodies.num(), 0.0);
    for (std::size_t i = 0; i < f_.s.n; ++i)
        f_.body_mass[static_cast<std::size_t>(f_.s.body[i])] += f_.s.rho[i] * f_.s.vol[i];
    auto& t = f_.timers;
    f_.t_bonds = t.id("pd::solver::bond_forces");
    f_.t_search = t.id("pd::solver::contact_search");
    f_.t_contact = t.id("pd::solver::contact_forces");
    f_.t_integrate = t.id("pd::solver::integrate");
    f_.t_walls = t.id("pd::solver::wall_contact");
    f_.t_damping = t.id("pd::solver::damping_friction");
    if (f_.dom->distributed())
        f_.t_halo = t.id("pd::solver::halo_exchange");
    terms_ = make_terms(f_, &term_names_);
}

void Solver::init_state() {
    const auto& m = f_.m;
    auto& s = f_.s;
    const std::size_t n = m.nodes.num();
    s.n = n;
    s.rows = f_.dom->rows();
    s.x0 = m.nodes.x0;
    s.x = m.nodes.x0;
    s.u.assign(3 * n, 0.0);
    s.v.assign(3 * n, 0.0);
    s.f.assign(3 * n, 0.0);
    s.vol = m.nodes.volume;
    s.body = m.nodes.body;
    s.rho.resize(n);
    s.moving.resize(n);
    s.fixed_dof.assign(n, 0);
    detail::condition_boxes(f_);
    for (std::size_t i = 0; i < n; ++i) {
        const auto b = static_cast<std::size_t>(s.body[i]);
        s.rho[i] = m.materials[static_cast<std::size_t>(m.bodies.material[b])].density;
        s.moving[i] = m.bodies.fixed[b] ? 0 : 1;
    }
}

void Solver::init_contact() {
    const auto& m = f_.m;
    for (int d = 0; d < 3; ++d)
        f_.g[d] = m.loading.gravity[static_cast<std::size_t>(d)];
    double rc = 0;
    for (const auto& p : m.contact)
        rc = std::max(rc, p.radius);
    const double skin = m.solver.contact_skin > 0 ? m.solver.contact_skin : rc;
    f_.contact = std::make_unique<ContactList>(m, skin > 0 ? skin : 1.0);
    f_.walls = std::make_unique<WallContact>(m, skin > 0 ? skin : 1.0);
    f_.wall_load.force.assign(3 * m.walls.size(), 0.0);
    f_.wall_load.moment.assign(3 * m.walls.size(), 0.0);
    for (const auto& p : m.contact) {
        f_.damping = f_.damping || (p.restitution < 1 && p.stiffness > 0);
        f_.approach = f_.approach || (p.approach > 0 && p.stiffness > 0);
        f_.friction = f_.friction || (p.friction > 0 && p.stiffness > 0);
    }
    f_.records = f_.damping || f_.friction;
}

StableDt Solver::stable_dt() const {
    // solver/stability.hpp: the bonds' omega_max^2 by Lanczos on their stiffness; contact by
    // the Gershgorin bound of the densest contact that can form; the smaller step of the two
    // (measured on the stability map, workflows/accuracy/stability: the contact bound alone is
    // already 1.3-1.6x below the measured limit of contact-governed scenes, and adding it to
    // the bonds' eigenvalue, a strict bound, cost 10 % on two discs and 2.4x on
    // compressive_small). Each term of the list tightens the limit it has.
    StableDt r;
    r.contact = std::numeric_limits<double>::infinity();
    for (const auto& t : terms_)
        t->limit_dt(f_, r);
    // The Lanczos value to three significant digits, rounded down: its sums differ in their
    // last bits between rank counts, the step must not (the contact bound is exact everywhere).
    r.pd = round_step(r.pd, step_digits);
    r.limit = std::min(r.pd, r.contact);
    r.governing = r.contact < r.pd         ? "contact stiffness"
                  : r.limit < 0.995 * r.pd ? "bonds with contact"
                                           : "peridynamic bonds";
    return r;
}

void Solver::compute_forces() {
    f_.begin_evaluation();
    for (const auto& t : terms_)
        t->add(f_);
    // Energies: kept from the last evaluation that summed them (set_energies).
    if (f_.law.energy) {
        elastic_energy_ = f_.elastic;
        repulsion_energy_ = f_.repulsion;
    }
    contact_energy_ = f_.contact_energy + repulsion_energy_;
    contact_count_ = f_.contact_count;
}

void Solver::bond_forces_only(bool reference) {
    if (reference) {
        pmb_bond_forces_reference(f_.s, f_.b, f_.law);
        return;
    }
    if (f_.law.any_pmb || (!f_.law.any_lps && !f_.law.any_rnp))
        pmb_bond_forces(f_.s, f_.b, f_.law);
    if (f_.law.any_lps)
        lps_bond_forces(f_.s, f_.b, f_.law);
    if (f_.law.any_rnp)
        rnp_bond_forces(f_.s, f_.b, f_.law);
}

void Solver::apply_displacements() {
    detail::apply_displacements(f_);
}

void Solver::initialize() {
    initialized_ = true;
    detail::break_precracks(f_);
    for (std::size_t b = 0; b < f_.m.bodies.num(); ++b) {
        if (f_.m.bodies.fixed[b])
            continue;
        for (auto i = f_.m.bodies.begin(b); i < f_.m.bodies.end(b); ++i)
            for (int d = 0; d < 3; ++d)
                f_.s.v[3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(d)] =
                    f_.m.bodies.initial_velocity[3 * b + static_cast<std::size_t>(d)];
    }
    detail::apply_displacements(f_);
    compute_forces();
    power_ = detail::external_power(f_);
    external_work_ = 0;
    f_.diss.fracture = f_.diss.damping = f_.diss.friction = f_.diss.viscous = 0;
}

const double* Solver::kick_per_rho(double kick) {
    if (kick_rho_.size() != f_.s.n || kick != kick_) {
        kick_rho_.resize(f_.s.n);
        for (std::size_t i = 0; i < f_.s.n; ++i)
            kick_rho_[i] = kick / f_.s.rho[i];
        kick_ = kick;
    }
    return kick_rho_.data();
}

double Solver::second_kick(bool verlet, const double* kr) {
    const auto n = static_cast<std::int64_t>(f_.s.rows.size());
    const index_t* rows = f_.s.rows.data();
    const std::uint8_t *moving = f_.s.moving.data(), *fixed_dof = f_.s.fixed_dof.data();
    double* v = f_.s.v.data();
    const double* force = f_.s.f.data();
    const auto kick = [&](std::int64_t i) {
        const double a = kr[i];
        const auto fixed = fixed_dof[i];
        for (int d = 0; d < 3; ++d)
            if (!(fixed & (1u << d)))
                v[3 * i + d] += a * force[3 * i + d];
    };
    if (verlet && !threaded(n, parallel_min_nodes)) {
        // The half kick and the nodes' external power in one pass (the power summed in row
        // order, as sum_rows adds it on one thread: the same bits).
        ScopedTimer t(f_.timers, f_.t_integrate);
        const bool power = detail::node_power_needed(f_);
        double pw = 0;
        for (std::int64_t r = 0; r < n; ++r) {
            const std::int64_t i = rows[r];
            if (moving[i])
                kick(i);
            if (power)
                pw += detail::node_power(f_, static_cast<std::size_t>(i));
        }
        return detail::external_power(f_, pw);
    }
    if (verlet) {
        ScopedTimer t(f_.timers, f_.t_integrate);
        for_each_row(n, parallel_min_nodes, [&](std::int64_t r) {
            if (moving[rows[r]])
                kick(rows[r]);
        });
    }
    return detail::external_power(f_);
}

void Solver::advance() {
    const double dt = dt_;
    const auto n = static_cast<std::int64_t>(f_.s.rows.size());
    const index_t* rows = f_.s.rows.data();
    const bool verlet = f_.m.solver.integrator == model::Integrator::velocity_verlet;
    const double* kr = kick_per_rho(verlet ? 0.5 * dt : dt);
    const std::uint8_t *moving = f_.s.moving.data(), *fixed_dof = f_.s.fixed_dof.data();
    double *v = f_.s.v.data(), *u = f_.s.u.data(), *x = f_.s.x.data();
    const double *x0 = f_.s.x0.data(), *force = f_.s.f.data();
    {
        ScopedTimer t(f_.timers, f_.t_integrate);
        for_each_row(n, parallel_min_nodes, [&](std::int64_t r) {
            const std::int64_t i = rows[r];
            if (!moving[i])
                return;
            const double a = kr[i];
            const auto fixed = fixed_dof[i];
            for (int d = 0; d < 3; ++d) {
                if (fixed & (1u << d))
                    continue;
                const auto k = 3 * i + d;
                v[k] += a * force[k];
                u[k] += dt * v[k];
                x[k] = x0[k] + u[k];
            }
        });
    }
    f_.s.time += dt;
    ++f_.s.step;
    // Dissipation rates of the last evaluation (compute_forces sets the new ones).
    const double damping_rate0 = f_.diss.damping_rate, friction_rate0 = f_.diss.friction_rate,
                 viscous_rate0 = f_.diss.viscous_rate;
    detail::apply_displacements(f_);
    if (f_.dom->distributed()) {
        ScopedTimer t(f_.timers, f_.t_halo);
        detail::exchange_motion(f_);
    }
    compute_forces();
    const double p = second_kick(verlet, kr);
    // Trapezoidal in time; first contacts with moving walls corrected (WallLoad::work).
    external_work_ += 0.5 * (power_ + p) * dt + f_.wall_load.work;
    power_ = p;
    f_.diss.damping += 0.5 * (damping_rate0 + f_.diss.damping_rate) * dt;
    f_.diss.friction += 0.5 * (friction_rate0 + f_.diss.friction_rate) * dt;
    f_.diss.viscous += 0.5 * (viscous_rate0 + f_.diss.viscous_rate) * dt;
    add_interval();
}

void Solver::add_interval() {
    // Reactions averaged over the observation interval (a few additions per wall and body).
    const auto& wf = f_.wall_load.force;
    const auto& wm = f_.wall_load.moment;
    const auto& bl = f_.reactions.load();
    if (interval_sum_.size() != wf.size() + wm.size() + bl.size())
        interval_sum_.assign(wf.size() + wm.size() + bl.size(), 0.0);
    double* acc = interval_sum_.data();
    for (const double v : wf)
        *acc++ += v;
    for (const double v : wm)
        *acc++ += v;
    for (const double v : bl)
        *acc++ += v;
    ++interval_steps_;
}

void Solver::end_interval() {
    std::fill(interval_sum_.begin(), interval_sum_.end(), 0.0);
    interval_steps_ = 0;
}

void Solver::set_interval(std::vector<double> sum, std::int64_t steps) {
    const std::size_t want =
        f_.wall_load.force.size() + f_.wall_load.moment.size() + f_.reactions.load().size();
    if (steps < 0 || (steps > 0 && sum.size() != want))
        throw InternalError(fmt::format("interval sums: {} values over {} steps, expected {}",
                                        sum.size(), steps, want));
    interval_sum_ = std::move(sum);
    interval_steps_ = steps;
}

} // namespace pd::solver
