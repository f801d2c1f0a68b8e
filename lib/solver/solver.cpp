// SPDX-License-Identifier: MIT
#include "solver/solver.hpp"

#include "core/errors.hpp"
#include "model/functions.hpp"
#include "model/lps.hpp"
#include "model/pmb.hpp"
#include "model/quadrature.hpp"
#include "model/rnp.hpp"
#include "model/slots.hpp"
#include "model/surface_correction.hpp"
#include "solver/bond_forces.hpp"
#include "solver/stability.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <tuple>

namespace pd::solver {

namespace {

using model::space_value; // `box`: xmin, xmax, ymin, ymax of the condition's nodes

/// The rows `rows` of a whole bond-list array (CSR `whole`), concatenated: this rank's CSR.
template <class T>
std::vector<T> rows_of(const std::vector<T>& from, const std::vector<offset_t>& whole,
                       const std::vector<index_t>& rows) {
    std::vector<T> out;
    for (auto row : rows) {
        const auto i = static_cast<std::size_t>(row);
        out.insert(out.end(), from.begin() + whole[i], from.begin() + whole[i + 1]);
    }
    return out;
}

/// Writes this rank's CSR rows (`local`, over `rows`) into their places of a whole-list array.
template <class T>
void put_rows(const std::vector<T>& from, const std::vector<offset_t>& local,
              const std::vector<index_t>& rows, const std::vector<offset_t>& whole,
              std::vector<T>& to) {
    for (std::size_t a = 0; a < rows.size(); ++a)
        std::copy(from.begin() + local[a], from.begin() + local[a + 1],
                  to.begin() + whole[static_cast<std::size_t>(rows[a])]);
}

} // namespace

double energy_balance(const Observables& o) {
    return o.kinetic_energy + o.elastic_energy + o.contact_energy + o.fracture_energy +
           o.damping_dissipation + o.friction_dissipation + o.viscous_dissipation - o.external_work;
}

double energy_in_play(const Observables& o) {
    return o.kinetic_energy + o.elastic_energy + o.contact_energy + std::abs(o.fracture_energy) +
           o.damping_dissipation + o.friction_dissipation + o.viscous_dissipation +
           std::abs(o.external_work);
}

Solver::Solver(const model::Model& m, Domain* dom, std::vector<index_t> row_neighbors)
    : m_(m)
    , dom_(dom)
    , row_neighbors_(std::move(row_neighbors))
    , reactions_(m) {
    const std::size_t n = m.nodes.num(), nb = m.bodies.num();
    if (!dom_) {
        serial_ = std::make_unique<Domain>(n);
        dom_ = serial_.get();
    }
    if (dom_->num_nodes() != n)
        throw InternalError(
            fmt::format("domain of {} nodes for a model of {}", dom_->num_nodes(), n));
    s_.n = n;
    s_.rows = dom_->rows();
    s_.x0 = m.nodes.x0;
    s_.x = m.nodes.x0;
    s_.u.assign(3 * n, 0.0);
    s_.v.assign(3 * n, 0.0);
    s_.f.assign(3 * n, 0.0);
    s_.vol = m.nodes.volume;
    s_.body = m.nodes.body;
    s_.rho.resize(n);
    s_.moving.resize(n);
    s_.fixed_dof.assign(n, 0);
    for (const auto& c : m.loading.conditions) {
        std::array<double, 4> box{1e300, -1e300, 1e300, -1e300};
        for (auto i : c.nodes) {
            const auto ii = static_cast<std::size_t>(i);
            box[0] = std::min(box[0], s_.x0[3 * ii]);
            box[1] = std::max(box[1], s_.x0[3 * ii]);
            box[2] = std::min(box[2], s_.x0[3 * ii + 1]);
            box[3] = std::max(box[3], s_.x0[3 * ii + 1]);
        }
        cond_box_.push_back(box);
        if (!c.is_force) {
            for (auto i : c.nodes)
                s_.fixed_dof[static_cast<std::size_t>(i)] |= c.dofs;
            has_prescribed_ = true;
        } else {
            fbc_.assign(3 * n, 0.0);
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        const auto b = static_cast<std::size_t>(s_.body[i]);
        s_.rho[i] = m.materials[static_cast<std::size_t>(m.bodies.material[b])].density;
        s_.moving[i] = m.bodies.fixed[b] ? 0 : 1;
    }
    law_.c.resize(nb);
    law_.s0.resize(nb);
    law_.lps.assign(nb, 0);
    law_.rnp.assign(nb, 0);
    law_.rnp_c.assign(nb, 0.0);
    law_.rnp_beta.assign(nb, 0.0);
    law_.rnp_rbar.assign(nb, 0.0);
    law_.rnp_inv.assign(nb, 1.0);
    law_.kappa.assign(nb, 0.0);
    law_.mu.assign(nb, 0.0);
    law_.dimension = m.dimension;
    law_.krep.assign(nb, 0.0);
    law_.rrep.assign(nb, 0.0);
    law_.alpha = m.dimension == 3 ? 15.0 : 8.0;
    for (std::size_t b = 0; b < nb; ++b) {
        const auto& mat = m.materials[static_cast<std::size_t>(m.bodies.material[b])];
        // Constants calibrated on the body's actual quadrature (model/quadrature.hpp); computed
        // from the reference nodes, so every rank gets the same factors.
        const auto qf = m.solver.quadrature_calibration && !m.bodies.fixed[b]
                            ? model::quadrature_factors(m, b)
                            : model::QuadratureFactors{};
        if (mat.law == model::Law::rnp) {
            auto k = model::rnp_constants(mat, m.bodies.horizon[b], m.dimension);
            law_.rnp[b] = 1;
            law_.rnp_c[b] = k.C;
            law_.rnp_beta[b] = k.beta;
            law_.rnp_rbar[b] = k.rbar;
            law_.rnp_inv[b] = k.inv_factor / qf.pmb;
            law_.s0[b] = k.rbar; // breakable (S_c depends on the bond length)
            law_.c[b] = 4 * k.C * k.beta / law_.rnp_inv[b]; // small-strain stiffness, dt estimate
            law_.any_rnp = law_.any_rnp || !m.bodies.fixed[b];
        } else if (mat.law == model::Law::lps) {
            auto k = model::lps_constants(mat, m.bodies.horizon[b], m.dimension, m.planar);
            law_.lps[b] = 1;
            law_.kappa[b] = k.kappa * qf.kappa;
            law_.mu[b] = k.mu * qf.mu;
            law_.s0[b] = k.s0;
            // Bond-based micromodulus of the same Young's modulus: for the dt estimate only.
            law_.c[b] = model::pmb_constants(mat, m.bodies.horizon[b], m.dimension, m.planar).c;
            law_.any_lps = law_.any_lps || !m.bodies.fixed[b];
        } else {
            auto k = model::pmb_constants(mat, m.bodies.horizon[b], m.dimension, m.planar);
            law_.c[b] = k.c * qf.pmb;
            law_.s0[b] = k.s0;
            law_.any_pmb = law_.any_pmb || !m.bodies.fixed[b];
        }
        law_.any_breakable =
            law_.any_breakable || (std::isfinite(law_.s0[b]) && !m.bodies.fixed[b]);
        law_.krep[b] =
            18.0 * mat.bulk_modulus() / (M_PI * std::pow(m.bodies.horizon[b], m.dimension + 2));
        law_.rrep[b] = 0.95 * m.bodies.mesh_size[b];
    }
    build_bonds();
    for (int d = 0; d < 3; ++d)
        g_[d] = m.loading.gravity[static_cast<std::size_t>(d)];
    double rc = 0;
    for (const auto& p : m.contact)
        rc = std::max(rc, p.radius);
    const double skin = m.solver.contact_skin > 0 ? m.solver.contact_skin : rc;
    contact_ = std::make_unique<ContactList>(m, skin > 0 ? skin : 1.0);
    walls_ = std::make_unique<WallContact>(m, skin > 0 ? skin : 1.0);
    wall_load_.force.assign(3 * m.walls.size(), 0.0);
    wall_load_.moment.assign(3 * m.walls.size(), 0.0);
    for (const auto& p : m.contact) {
        damping_ = damping_ || (p.restitution < 1 && p.stiffness > 0);
        friction_ = friction_ || (p.friction > 0 && p.stiffness > 0);
    }
    records_ = damping_ || friction_;
    take_rows();
    set_bond_ghosts();
    family_factors();
    body_mass_.assign(nb, 0.0);
    for (std::size_t i = 0; i < n; ++i)
        body_mass_[static_cast<std::size_t>(s_.body[i])] += s_.rho[i] * s_.vol[i];
    t_bonds_ = timers_.id("pd::solver::bond_forces");
    t_search_ = timers_.id("pd::solver::contact_search");
    t_contact_ = timers_.id("pd::solver::contact_forces");
    t_integrate_ = timers_.id("pd::solver::integrate");
    t_walls_ = timers_.id("pd::solver::wall_contact");
    t_damping_ = timers_.id("pd::solver::damping_friction");
    if (dom_->distributed())
        t_halo_ = timers_.id("pd::solver::halo_exchange");
}

StableDt Solver::stable_dt() const {
    // solver/stability.hpp: the bonds' omega_max^2 by Lanczos on their stiffness; contact by
    // the Gershgorin bound of the densest contact that can form; the smaller step of the two
    // (measured on the stability map, workflows/accuracy/stability: the contact bound alone is
    // already 1.3-1.6x below the measured limit of contact-governed scenes, and adding it to
    // the bonds' eigenvalue, a strict bound, cost 10 % on two discs and 2.4x on
    // compressive_small).
    StableDt r;
    const auto spec = bond_spectrum(s_, b_, law_, *dom_);
    r.pd = critical_dt(spec.lambda());
    r.lanczos_steps = spec.iterations;
    r.contact = contact_->active() || walls_->active() ? critical_dt(contact_lambda_bound(m_, s_))
                                                       : std::numeric_limits<double>::infinity();
    // The Lanczos value to three significant digits, rounded down: its sums differ in their
    // last bits between rank counts, the step must not (the contact bound is exact everywhere).
    if (std::isfinite(r.pd) && r.pd > 0) {
        const double unit = std::pow(10.0, std::floor(std::log10(r.pd)) - 2);
        r.pd = std::floor(r.pd / unit * (1 + 1e-9)) * unit;
    }
    r.limit = std::min(r.pd, r.contact);
    r.governing = r.contact < r.pd         ? "contact stiffness"
                  : r.limit < 0.995 * r.pd ? "bonds with contact"
                                           : "peridynamic bonds";
    return r;
}

void Solver::compute_forces() {
    {
        ScopedTimer t(timers_, t_bonds_);
        // Energies: kept from the last evaluation that summed them (set_energies).
        double elastic = 0, repulsion = 0;
        auto book = [&](const BondResult& res) {
            elastic += res.elastic_energy;
            broken_total_ += res.newly_broken;
            diss_.fracture += res.released_energy;
            repulsion += res.repulsion_energy;
        };
        if (law_.any_pmb || (!law_.any_lps && !law_.any_rnp))
            book(pmb_bond_forces(s_, b_, law_));
        if (law_.any_lps) {
            std::function<void()> between;
            if (dom_->distributed())
                between = [this] {
                    ScopedTimer t(timers_, t_halo_);
                    dom_->exchange({&law_.theta, &law_.q, &law_.lps_p}, 1);
                };
            book(lps_bond_forces(s_, b_, law_, between));
        }
        if (law_.any_rnp)
            book(rnp_bond_forces(s_, b_, law_));
        if (law_.energy) {
            elastic_energy_ = elastic;
            repulsion_energy_ = repulsion;
        }
    }
    reactions_.before(s_);
    if (contact_->active()) {
        {
            ScopedTimer t(timers_, t_search_);
            if (contact_->update(s_, *dom_) && dom_->distributed())
                set_ghosts();
        }
        ScopedTimer t(timers_, t_contact_);
        contact_count_ =
            contact_->add_forces(s_, contact_energy_, records_ ? &pair_records_ : nullptr);
    } else {
        contact_count_ = 0;
        contact_energy_ = 0;
        pair_records_.clear();
    }
    if (walls_->active()) {
        ScopedTimer t(timers_, t_walls_);
        walls_->update(s_);
        walls_->add_forces(s_, wall_load_, records_ ? &wall_records_ : nullptr);
        contact_count_ += wall_load_.touching;
        contact_energy_ += wall_load_.energy;
    } else {
        wall_load_.force.assign(3 * walls_->num_walls(), 0.0);
        wall_load_.moment.assign(3 * walls_->num_walls(), 0.0);
    }
    contact_energy_ += repulsion_energy_;
    diss_.damping_rate = diss_.friction_rate = diss_.viscous_rate = 0;
    if (damping_) {
        ScopedTimer t(timers_, t_damping_);
        apply_damping(pair_records_, wall_records_);
    }
    if (friction_) {
        ScopedTimer t(timers_, t_damping_);
        apply_friction();
    }
    reactions_.after(s_);
    if (!fbc_.empty())
        std::fill(fbc_.begin(), fbc_.end(), 0.0);
    for (const auto& c : m_.loading.conditions) {
        if (!c.is_force)
            continue;
        double rate = 0;
        const double T = model::time_function(c.time_fn, c.params, s_.time, &rate);
        const auto& box = cond_box_[static_cast<std::size_t>(&c - m_.loading.conditions.data())];
        for (auto i : c.nodes) {
            const auto ii = static_cast<std::size_t>(i);
            const double S = space_value(c.space_fn, c.params[0], &s_.x0[3 * ii], box);
            for (std::size_t d = 0; d < 3; ++d)
                if (c.dofs & (1u << d)) {
                    s_.f[3 * ii + d] += c.amplitude * T * S;
                    fbc_[3 * ii + d] += c.amplitude * T * S;
                }
        }
    }
    if (m_.loading.viscous_damping > 0) {
        const double cd = m_.loading.viscous_damping;
        const auto n = static_cast<std::int64_t>(s_.rows.size());
        // Dissipation rate cd rho |v|^2 V of every moving node, prescribed components included:
        // there the reaction that imposes the motion works against the viscous force, and that
        // work is counted as external work.
        diss_.viscous_rate = sum_rows(n, parallel_min_nodes, [&](std::int64_t a) {
            const std::int64_t i = s_.rows[static_cast<std::size_t>(a)];
            const auto ii = static_cast<std::size_t>(i);
            double rate = 0;
            for (int d = 0; d < 3; ++d) {
                s_.f[3 * i + d] -= cd * s_.rho[ii] * s_.v[3 * i + d];
                if (s_.moving[ii])
                    rate += cd * s_.rho[ii] * s_.v[3 * i + d] * s_.v[3 * i + d] * s_.vol[ii];
            }
            return rate;
        });
    }
    if (g_[0] != 0 || g_[1] != 0 || g_[2] != 0) {
        const auto n = static_cast<std::int64_t>(s_.rows.size());
        for_each_row(n, parallel_min_nodes, [&](std::int64_t a) {
            const std::int64_t i = s_.rows[static_cast<std::size_t>(a)];
            for (int d = 0; d < 3; ++d)
                s_.f[3 * i + d] += s_.rho[static_cast<std::size_t>(i)] * g_[d];
        });
    }
}

void Solver::bond_forces_only(bool reference) {
    if (reference) {
        pmb_bond_forces_reference(s_, b_, law_);
        return;
    }
    if (law_.any_pmb || (!law_.any_lps && !law_.any_rnp))
        pmb_bond_forces(s_, b_, law_);
    if (law_.any_lps)
        lps_bond_forces(s_, b_, law_);
    if (law_.any_rnp)
        rnp_bond_forces(s_, b_, law_);
}

void Solver::apply_damping(const std::vector<BodyPairForce>& pairs,
                           const std::vector<BodyWallForce>& walls) {
    // Grain-level hysteretic damping with true grain masses (spec decision 6). For each pair of
    // grains (or grain and wall) in contact, F = their total normal contact force and v_n the
    // relative normal velocity of their centres of mass. While the contact unloads (v_n > 0, the
    // grains separate) each grain receives -(1 - eps^2) F as a uniform acceleration: the contact
    // returns eps^2 of the energy it stored, so the rebound speed is eps times the impact speed
    // whatever the non-linearity of the node-level contact and the grains' deformation (Walton &
    // Braun 1986 loading/unloading idea, at grain level). Momentum is conserved; a wall's
    // reaction includes the reduction. No per-contact history is needed.
    using Key = std::pair<std::int32_t, std::int32_t>;
    std::map<Key, std::array<double, 3>> force;
    for (const auto& r : pairs) {
        auto& F = force[{r.a, r.b}];
        for (int d = 0; d < 3; ++d)
            F[static_cast<std::size_t>(d)] += r.force[d];
    }
    for (const auto& r : walls) {
        auto& F = force[{r.body, -1 - r.wall}];
        for (int d = 0; d < 3; ++d)
            F[static_cast<std::size_t>(d)] += r.force[d];
    }
    std::map<std::int32_t, std::array<double, 6>> com; // velocity, position of involved bodies
    if (dom_->distributed()) {
        // Whole grains per rank (checked at construction): each owner sums its grains' nodes in
        // the order one rank would, the others add exact zeros.
        std::vector<double> all(6 * m_.bodies.num(), 0.0);
        for (auto row : s_.rows) {
            const auto ii = static_cast<std::size_t>(row);
            const auto b = static_cast<std::size_t>(s_.body[ii]);
            const double mi = s_.rho[ii] * s_.vol[ii];
            for (std::size_t d = 0; d < 3; ++d) {
                all[6 * b + d] += mi * s_.v[3 * ii + d];
                all[6 * b + 3 + d] += mi * s_.x[3 * ii + d];
            }
        }
        dom_->sum(all);
        for (std::size_t b = 0; b < m_.bodies.num(); ++b) {
            std::array<double, 6> c;
            for (std::size_t d = 0; d < 6; ++d)
                c[d] = all[6 * b + d] / body_mass_[b];
            com.emplace(static_cast<std::int32_t>(b), c);
        }
    }
    auto com_of = [&](std::int32_t b) -> const std::array<double, 6>& {
        auto it = com.find(b);
        if (it != com.end())
            return it->second;
        std::array<double, 6> c{};
        const auto bb = static_cast<std::size_t>(b);
        for (auto i = m_.bodies.begin(bb); i < m_.bodies.end(bb); ++i) {
            const auto ii = static_cast<std::size_t>(i);
            const double mi = s_.rho[ii] * s_.vol[ii];
            for (std::size_t d = 0; d < 3; ++d) {
                c[d] += mi * s_.v[3 * ii + d];
                c[3 + d] += mi * s_.x[3 * ii + d];
            }
        }
        for (double& x : c)
            x /= body_mass_[bb];
        return com.emplace(b, c).first->second;
    };
    std::map<std::int32_t, std::array<double, 3>> accel;
    unload_.clear();
    for (const auto& [key, F] : force) {
        const double fm = std::sqrt(F[0] * F[0] + F[1] * F[1] + F[2] * F[2]);
        if (!(fm > 0))
            continue;
        const double n[3] = {F[0] / fm, F[1] / fm, F[2] / fm};
        const bool wall = key.second < 0;
        const auto a = key.first;
        const auto& ca = com_of(a);
        double vrel[3];
        const model::ContactPair* law = nullptr;
        const auto ga = m_.bodies.group[static_cast<std::size_t>(a)];
        if (wall) {
            const auto& w = m_.walls[static_cast<std::size_t>(-1 - key.second)];
            law = m_.contact_between(ga, w.group);
            const auto p = wall_pose(w, s_.time);
            const double r[3] = {ca[3] - p.centre[0], ca[4] - p.centre[1], ca[5] - p.centre[2]};
            const double vw[3] = {p.velocity[0] + p.omega[1] * r[2] - p.omega[2] * r[1],
                                  p.velocity[1] + p.omega[2] * r[0] - p.omega[0] * r[2],
                                  p.velocity[2] + p.omega[0] * r[1] - p.omega[1] * r[0]};
            for (int d = 0; d < 3; ++d)
                vrel[d] = ca[static_cast<std::size_t>(d)] - vw[d]; // grain relative to wall
        } else {
            const auto b = key.second;
            law = m_.contact_between(ga, m_.bodies.group[static_cast<std::size_t>(b)]);
            const auto& cb = com_of(b);
            for (std::size_t d = 0; d < 3; ++d)
                vrel[d] = cb[d] - ca[d]; // b relative to a; n points from a to b
        }
        if (!law || law->restitution >= 1)
            continue;
        const double vn = vrel[0] * n[0] + vrel[1] * n[1] + vrel[2] * n[2];
        if (!(vn > 0))
            continue; // loading (approach): no damping
        // Unloading: the grains get back only eps^2 of their normal contact force.
        const double scale = 1.0 - law->restitution * law->restitution;
        unload_[key] = law->restitution * law->restitution; // friction limit, next evaluation
        // Damping force on b (or on the grain, for a wall): -(1 - eps^2) F, F the contact force
        // on it.
        const double Fd[3] = {-scale * F[0], -scale * F[1], -scale * F[2]};
        if (wall && dom_->owns(m_.bodies.begin(static_cast<std::size_t>(a)))) {
            const auto w = static_cast<std::size_t>(-1 - key.second);
            for (std::size_t d = 0; d < 3; ++d)
                wall_load_.force[3 * w + d] -= Fd[d]; // the wall feels the reduced push too
            const auto p = wall_pose(m_.walls[w], s_.time);
            const double r[3] = {ca[3] - p.centre[0], ca[4] - p.centre[1], ca[5] - p.centre[2]};
            wall_load_.moment[3 * w + 0] -= r[1] * Fd[2] - r[2] * Fd[1];
            wall_load_.moment[3 * w + 1] -= r[2] * Fd[0] - r[0] * Fd[2];
            wall_load_.moment[3 * w + 2] -= r[0] * Fd[1] - r[1] * Fd[0];
        }
        // Dissipation rate -Fd . v_rel (> 0 while unloading), counted once: by the rank that
        // owns grain a.
        if (dom_->owns(m_.bodies.begin(static_cast<std::size_t>(a))))
            diss_.damping_rate -= Fd[0] * vrel[0] + Fd[1] * vrel[1] + Fd[2] * vrel[2];
        if (wall) {
            auto& acc = accel[a];
            for (int d = 0; d < 3; ++d)
                acc[static_cast<std::size_t>(d)] += Fd[d] / body_mass_[static_cast<std::size_t>(a)];
        } else {
            const auto b = key.second;
            auto& acb = accel[b];
            auto& aca = accel[a];
            for (int d = 0; d < 3; ++d) {
                acb[static_cast<std::size_t>(d)] += Fd[d] / body_mass_[static_cast<std::size_t>(b)];
                aca[static_cast<std::size_t>(d)] -= Fd[d] / body_mass_[static_cast<std::size_t>(a)];
            }
            // A meshed wall's reaction: the damping share acts through the other grain's centre
            // (as for rigid walls).
            const double Fa[3] = {-Fd[0], -Fd[1], -Fd[2]};
            for (auto [r, other, Fr] : {std::tuple{a, b, Fa}, std::tuple{b, a, Fd}})
                if (reactions_.records(r) &&
                    dom_->owns(m_.bodies.begin(static_cast<std::size_t>(r))))
                    reactions_.add_damping(r, Fr, &com_of(other)[3], &com_of(r)[3],
                                           m_.bodies.fixed[static_cast<std::size_t>(r)] != 0);
        }
    }
    for (const auto& [b, acc] : accel) {
        if (m_.bodies.fixed[static_cast<std::size_t>(b)] ||
            !dom_->owns(m_.bodies.begin(static_cast<std::size_t>(b))))
            continue; // (a grain split between ranks is refused with damping)
        for (auto i = m_.bodies.begin(static_cast<std::size_t>(b));
             i < m_.bodies.end(static_cast<std::size_t>(b)); ++i) {
            const auto ii = static_cast<std::size_t>(i);
            for (std::size_t d = 0; d < 3; ++d)
                s_.f[3 * ii + d] += s_.rho[ii] * acc[d];
        }
    }
}

void Solver::apply_displacements() {
    const double t = s_.time;
    for (const auto& c : m_.loading.conditions) {
        if (c.is_force)
            continue;
        if (c.time_fn == model::TimeFn::rotation) {
            // u = R(w t)(X - c) - (X - c), v = w R'(w t)(X - c), in the xy plane.
            const double th = c.amplitude * t, cs = std::cos(th), sn = std::sin(th);
            for (auto i : c.nodes) {
                const auto ii = static_cast<std::size_t>(i);
                const double rx = s_.x0[3 * ii] - c.centre[0], ry = s_.x0[3 * ii + 1] - c.centre[1];
                const double u[2] = {cs * rx - sn * ry - rx, sn * rx + cs * ry - ry};
                const double v[2] = {c.amplitude * (-sn * rx - cs * ry),
                                     c.amplitude * (cs * rx - sn * ry)};
                for (std::size_t d = 0; d < 2; ++d)
                    if (c.dofs & (1u << d)) {
                        s_.u[3 * ii + d] = u[d];
                        s_.v[3 * ii + d] = v[d];
                        s_.x[3 * ii + d] = s_.x0[3 * ii + d] + u[d];
                    }
            }
            continue;
        }
        double rate = 0;
        const double T = model::time_function(c.time_fn, c.params, t, &rate);
        const auto& box = cond_box_[static_cast<std::size_t>(&c - m_.loading.conditions.data())];
        for (auto i : c.nodes) {
            const auto ii = static_cast<std::size_t>(i);
            const double S = space_value(c.space_fn, c.params[0], &s_.x0[3 * ii], box);
            for (std::size_t d = 0; d < 3; ++d)
                if (c.dofs & (1u << d)) {
                    s_.u[3 * ii + d] = c.amplitude * T * S;
                    s_.v[3 * ii + d] = c.amplitude * rate * S;
                    s_.x[3 * ii + d] = s_.x0[3 * ii + d] + s_.u[3 * ii + d];
                }
        }
    }
}

void Solver::break_precracks() {
    for (const auto& c : m_.cracks)
        for (std::size_t a = 0; a < s_.rows.size(); ++a) {
            const auto i = static_cast<std::size_t>(s_.rows[a]);
            for (auto k = b_.offsets[a]; k < b_.offsets[a + 1]; ++k) {
                const auto kk = static_cast<std::size_t>(k);
                const auto j = static_cast<std::size_t>(b_.neighbor[kk]);
                if (b_.alive[kk] &&
                    model::segments_cross(&s_.x0[3 * i], &s_.x0[3 * j], c.p0.data(), c.p1.data())) {
                    b_.alive[kk] = 0;
                    ++precracked_;
                }
            }
        }
    broken_total_ += precracked_;
}

void Solver::restore(std::int64_t step, double time, const std::vector<double>& u,
                     const std::vector<double>& v, const std::vector<double>& f,
                     const std::vector<std::uint8_t>& alive, std::int64_t broken_total) {
    PD_CHECK(u.size() == s_.u.size() && v.size() == s_.v.size() && f.size() == s_.f.size() &&
                 alive.size() == m_.bonds.num(),
             "checkpoint sizes");
    initialized_ = true;
    s_.step = step;
    s_.time = time;
    s_.u = u;
    s_.v = v;
    s_.f = f;
    for (std::size_t k = 0; k < s_.x.size(); ++k)
        s_.x[k] = s_.x0[k] + s_.u[k];
    b_.alive = rows_of(alive, m_.bonds.offsets, s_.rows);
    // This rank's share of the broken bonds (`broken_total` counts every rank's).
    broken_total_ = count_broken();
    if (dom_->sum(broken_total_) != broken_total)
        throw InputError(fmt::format("checkpoint: {} broken bond ends recorded, {} in its bond "
                                     "state",
                                     broken_total, dom_->sum(broken_total_)));
}

void Solver::apply_friction() {
    // Coulomb friction on every touching node pair (and node-wall pair) with mu > 0: a force
    // mu |F_n| opposing the tangential slip, F_n scaled like the normal force under unloading
    // (hysteretic damping), and never more than what stops the slip within the step (stick).
    // Serial over the sorted contact records: deterministic; equal and opposite on node pairs.
    // Removes from v its component along the normal force F (|F| = fm); returns |v_t|.
    auto tangential = [](const double* F, double fm, double* v) {
        double vn = 0;
        for (int d = 0; d < 3; ++d)
            vn += v[d] * F[d] / fm;
        double m2 = 0;
        for (int d = 0; d < 3; ++d) {
            v[d] -= vn * F[d] / fm;
            m2 += v[d] * v[d];
        }
        return std::sqrt(m2);
    };
    auto factor = [&](std::int32_t a, std::int32_t b) {
        auto it = unload_.find({a, b});
        return it == unload_.end() ? 1.0 : it->second;
    };
    for (const auto& r : pair_records_) {
        if (!(r.friction > 0))
            continue;
        const auto i = static_cast<std::size_t>(r.i), j = static_cast<std::size_t>(r.j);
        const double fm =
            std::sqrt(r.force[0] * r.force[0] + r.force[1] * r.force[1] + r.force[2] * r.force[2]);
        if (!(fm > 0))
            continue;
        double vt[3];
        for (std::size_t d = 0; d < 3; ++d)
            vt[d] = s_.v[3 * j + d] - s_.v[3 * i + d];
        const double vtm = tangential(r.force, fm, vt);
        if (!(vtm > 0))
            continue;
        const double mi = s_.rho[i] * s_.vol[i], mj = s_.rho[j] * s_.vol[j];
        const double stop = mi * mj / (mi + mj) * vtm / dt_;
        const double ft = std::min(r.friction * fm * factor(r.a, r.b), stop) / vtm; // N per m/s
        if (dom_->owns(r.i)) // a pair's record may be on two ranks: counted once
            diss_.friction_rate += ft * vtm * vtm;
        for (std::size_t d = 0; d < 3; ++d) {
            s_.f[3 * i + d] += ft * vt[d] / s_.vol[i]; // i is dragged along the slip of j
            s_.f[3 * j + d] -= ft * vt[d] / s_.vol[j];
        }
    }
    for (const auto& r : wall_records_) {
        if (!(r.friction > 0))
            continue;
        const auto i = static_cast<std::size_t>(r.node);
        const auto w = static_cast<std::size_t>(r.wall);
        const double fm =
            std::sqrt(r.force[0] * r.force[0] + r.force[1] * r.force[1] + r.force[2] * r.force[2]);
        if (!(fm > 0))
            continue;
        const auto p = wall_pose(m_.walls[w], s_.time);
        const double* x = &s_.x[3 * i];
        const double rr[3] = {x[0] - p.centre[0], x[1] - p.centre[1], x[2] - p.centre[2]};
        const double vw[3] = {p.velocity[0] + p.omega[1] * rr[2] - p.omega[2] * rr[1],
                              p.velocity[1] + p.omega[2] * rr[0] - p.omega[0] * rr[2],
                              p.velocity[2] + p.omega[0] * rr[1] - p.omega[1] * rr[0]};
        double vt[3];
        for (std::size_t d = 0; d < 3; ++d)
            vt[d] = vw[d] - s_.v[3 * i + d];
        const double vtm = tangential(r.force, fm, vt);
        if (!(vtm > 0))
            continue;
        const double stop = s_.rho[i] * s_.vol[i] * vtm / dt_;
        const double ft = std::min(r.friction * fm * factor(r.body, -1 - r.wall), stop) / vtm;
        diss_.friction_rate += ft * vtm * vtm;
        double F[3];
        for (std::size_t d = 0; d < 3; ++d) {
            s_.f[3 * i + d] += ft * vt[d] / s_.vol[i];
            F[d] = -ft * vt[d]; // received by the wall
            wall_load_.force[3 * w + d] += F[d];
        }
        wall_load_.moment[3 * w + 0] += rr[1] * F[2] - rr[2] * F[1];
        wall_load_.moment[3 * w + 1] += rr[2] * F[0] - rr[0] * F[2];
        wall_load_.moment[3 * w + 2] += rr[0] * F[1] - rr[1] * F[0];
    }
}

namespace {
/// |X_j - X_i|, computed the same way wherever a bond's length is needed (bitwise equal).
double bond_length(const std::vector<double>& x0, std::size_t i, std::size_t j) {
    double r2 = 0;
    for (std::size_t d = 0; d < 3; ++d)
        r2 += std::pow(x0[3 * j + d] - x0[3 * i + d], 2);
    return std::sqrt(r2);
}
} // namespace

void Solver::build_bonds() {
    // This rank's rows of the bond list (s_.rows; all on one rank): reference lengths,
    // partial-volume factors and influence, computed once. Bond data of other ranks' rows is
    // never stored. The neighbour lists come from the model, or, when it was read without
    // them, from row_neighbors_ (the rows of s_.rows, read by hyperslab).
    const auto& m = m_;
    const std::size_t nr = s_.rows.size();
    b_.offsets.assign(nr + 1, 0);
    for (std::size_t a = 0; a < nr; ++a) {
        const auto i = static_cast<std::size_t>(s_.rows[a]);
        b_.offsets[a + 1] = b_.offsets[a] + (m.bonds.offsets[i + 1] - m.bonds.offsets[i]);
    }
    const auto nbond = static_cast<std::size_t>(b_.offsets[nr]);
    if (m.bonds.complete()) {
        b_.neighbor = rows_of(m.bonds.neighbor, m.bonds.offsets, s_.rows);
    } else {
        if (row_neighbors_.size() != nbond)
            throw InternalError(fmt::format("{} neighbours given for {} bonds of this rank's rows",
                                            row_neighbors_.size(), nbond));
        b_.neighbor = std::move(row_neighbors_);
        row_neighbors_.clear();
    }
    b_.xi.resize(nbond);
    b_.beta.resize(nbond);
    b_.alive.assign(nbond, 1);
    for (std::size_t a = 0; a < nr; ++a) {
        const auto i = static_cast<std::size_t>(s_.rows[a]);
        const auto b = static_cast<std::size_t>(s_.body[i]);
        for (auto k = b_.offsets[a]; k < b_.offsets[a + 1]; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            const auto j = b_.neighbor[kk];
            const double r = bond_length(s_.x0, i, static_cast<std::size_t>(j));
            if (!(r > 0))
                throw InputError(fmt::format("nodes {} and {} coincide (zero-length bond)", i, j));
            b_.xi[kk] = r;
            b_.beta[kk] = model::partial_volume(r, m.bodies.horizon[b], m.bodies.mesh_size[b]);
        }
    }
    b_.omega.clear();
    if (law_.any_lps || law_.any_rnp) {
        b_.omega.resize(nbond);
        for (std::size_t a = 0; a < nr; ++a) {
            const auto b = static_cast<std::size_t>(s_.body[static_cast<std::size_t>(s_.rows[a])]);
            const auto inf = m.materials[static_cast<std::size_t>(m.bodies.material[b])].influence;
            for (auto k = b_.offsets[a]; k < b_.offsets[a + 1]; ++k) {
                const auto kk = static_cast<std::size_t>(k);
                b_.omega[kk] = model::influence(inf, b_.xi[kk] / m.bodies.horizon[b]);
            }
        }
    }
}

void Solver::family_factors() {
    // Per-node sums over a node's family, of the owned rows; the ghosts' values come from their
    // owners (the bond ghosts must be set).
    const std::size_t nr = s_.rows.size(), n = s_.n;
    auto own_sum = [&](auto&& term, std::vector<double>& out) {
        out.assign(n, 0.0);
        for (std::size_t a = 0; a < nr; ++a) {
            double sum = 0;
            for (auto k = b_.offsets[a]; k < b_.offsets[a + 1]; ++k) {
                const auto kk = static_cast<std::size_t>(k);
                sum += term(kk, s_.vol[static_cast<std::size_t>(b_.neighbor[kk])]);
            }
            out[static_cast<std::size_t>(s_.rows[a])] = sum;
        }
    };
    // Surface correction (solver.surface_correction; model/surface_correction.hpp): per-node
    // axis factors relative to a complete family of the body, a directional factor per bond on
    // the PMB micromodulus or the LPS influence function (before m_i is summed from it).
    b_.stiff = b_.beta;
    if (m_.solver.surface_correction) {
        std::vector<double> w(b_.xi.size(), 0.0), angle(n, 0.0), ref(m_.bodies.num(), 1.0);
        for (std::size_t b = 0; b < ref.size(); ++b) // a complete family's axis moment
            if (!m_.bodies.fixed[b])
                ref[b] = std::max(model::quadrature_factors(m_, b).axis_moment, 1e-300);
        for (std::size_t a = 0; a < nr; ++a) {
            const auto i = static_cast<std::size_t>(s_.rows[a]);
            const auto body = static_cast<std::size_t>(s_.body[i]);
            for (auto k = b_.offsets[a]; k < b_.offsets[a + 1]; ++k) {
                const auto kk = static_cast<std::size_t>(k);
                const double r = b_.xi[kk], vb = b_.beta[kk] *
                                                 s_.vol[static_cast<std::size_t>(b_.neighbor[kk])] /
                                                 ref[body];
                // RNP and fixed bodies: no bonds counted, factors 1.
                w[kk] = law_.rnp[body] || m_.bodies.fixed[body] ? 0.0
                        : law_.lps[body]                        ? b_.omega[kk] * r * r * vb
                                                                : r * vb;
            }
        }
        for (std::size_t i = 0; i < n; ++i)
            angle[i] = m_.bodies.orientation[static_cast<std::size_t>(s_.body[i])];
        const model::FamilyRows f{b_.offsets, b_.neighbor, s_.rows, s_.x0, angle};
        const auto G = model::surface_bond_factors(
            f, w, m_.dimension, n, [&](std::vector<double>& g) { dom_->exchange({&g}, 3); }, 1);
        for (std::size_t a = 0; a < nr; ++a) {
            const auto body =
                static_cast<std::size_t>(s_.body[static_cast<std::size_t>(s_.rows[a])]);
            for (auto k = b_.offsets[a]; k < b_.offsets[a + 1]; ++k) {
                const auto kk = static_cast<std::size_t>(k);
                (law_.lps[body] ? b_.omega[kk] : b_.stiff[kk]) *= G[kk];
            }
        }
    }
    if (law_.any_lps) {
        // LPS weighted volume m_i = sum_j w xi^2 beta V_j (spec 1.3).
        own_sum([&](std::size_t k,
                    double vj) { return b_.omega[k] * b_.xi[k] * b_.xi[k] * b_.beta[k] * vj; },
                law_.m);
        for (auto row : s_.rows) {
            auto& w = law_.m[static_cast<std::size_t>(row)];
            w = w > 0 ? w : 1.0; // a node with no bond has theta = 0 and no force
        }
        dom_->exchange({&law_.m}, 1);
        law_.theta.assign(n, 0.0);
        law_.q.assign(n, 0.0);
    }
    // Per-bond and per-node constants of the kernels, from the per-body law and the per-bond
    // factors above, so that a calibration of either composes.
    bond_constants(s_, b_, law_);
}

void Solver::check_whole_grains() const {
    if (!damping_ || !dom_->distributed())
        return;
    for (std::size_t b = 0; b < m_.bodies.num(); ++b) {
        const auto i0 = m_.bodies.begin(b);
        for (auto i = i0; i < m_.bodies.end(b); ++i)
            if (dom_->owner(i) != dom_->owner(i0))
                throw InputError(fmt::format(
                    "body {} is split between MPI ranks {} and {}, but grain-level damping "
                    "(restitution < 1) needs whole grains per rank: partition by grain "
                    "(pd-partition --by grain)",
                    b, dom_->owner(i0), dom_->owner(i)));
    }
}

std::vector<double> Solver::body_centres() const {
    std::vector<double> c(3 * m_.bodies.num(), 0.0);
    for (auto row : s_.rows) {
        const auto i = static_cast<std::size_t>(row);
        const auto b = static_cast<std::size_t>(s_.body[i]);
        for (std::size_t d = 0; d < 3; ++d)
            c[3 * b + d] += s_.rho[i] * s_.vol[i] * s_.x[3 * i + d];
    }
    dom_->sum(c);
    for (std::size_t b = 0; b < m_.bodies.num(); ++b)
        for (std::size_t d = 0; d < 3; ++d)
            c[3 * b + d] /= body_mass_[b];
    return c;
}

void Solver::redistribute(Domain* dom) {
    // Everything where its old owner has it, on every rank.
    dom_->allgather(s_.x, 3);
    dom_->allgather(s_.u, 3);
    dom_->allgather(s_.v, 3);
    dom_->allgather(s_.f, 3);
    const auto alive = global_alive();
    std::vector<index_t> neighbors;
    if (!m_.bonds.complete())
        neighbors = global_neighbors();
    // The unloading factors of the last evaluation (friction limits of the next one).
    std::vector<double> mine;
    for (const auto& [key, value] : unload_)
        mine.insert(mine.end(), {double(key.first), double(key.second), value});
    const double work = dom_->sum(external_work_), power = dom_->sum(power_);
    std::vector<double> diss{diss_.fracture,    diss_.damping,      diss_.friction,
                             diss_.viscous,     diss_.damping_rate, diss_.friction_rate,
                             diss_.viscous_rate};
    dom_->sum(diss);
    if (dom_->distributed()) {
        int len = static_cast<int>(mine.size());
        std::vector<int> lens(static_cast<std::size_t>(dom_->size()));
        MPI_Allgather(&len, 1, MPI_INT, lens.data(), 1, MPI_INT, dom_->comm());
        std::vector<int> disp(lens.size() + 1, 0);
        for (std::size_t p = 0; p < lens.size(); ++p)
            disp[p + 1] = disp[p] + lens[p];
        std::vector<double> all(static_cast<std::size_t>(disp.back()));
        MPI_Allgatherv(mine.data(), len, MPI_DOUBLE, all.data(), lens.data(), disp.data(),
                       MPI_DOUBLE, dom_->comm());
        for (std::size_t k = 0; k + 2 < all.size(); k += 3)
            unload_[{static_cast<std::int32_t>(all[k]), static_cast<std::int32_t>(all[k + 1])}] =
                all[k + 2];
    }
    // The new rows.
    dom_ = dom;
    if (dom_->num_nodes() != s_.n)
        throw InternalError("redistribute: a domain of another model");
    take_rows();
    const auto& B = m_.bonds;
    if (!B.complete()) // the new rows' neighbour lists
        row_neighbors_ = rows_of(neighbors, B.offsets, s_.rows);
    build_bonds();
    b_.alive = rows_of(alive, B.offsets, s_.rows);
    set_bond_ghosts(); // contact ghosts join at the next (forced) rebuild
    family_factors();
    external_work_ = dom_->rank() == 0 ? work : 0.0;
    power_ = dom_->rank() == 0 ? power : 0.0;
    for (double& d : diss)
        d = dom_->rank() == 0 ? d : 0.0;
    diss_ = {diss[0], diss[1], diss[2], diss[3], diss[4], diss[5], diss[6]};
    broken_total_ = count_broken();
    contact_->invalidate();
    walls_->invalidate();
}

std::int64_t Solver::count_broken() const {
    return static_cast<std::int64_t>(std::count(b_.alive.begin(), b_.alive.end(), 0));
}

void Solver::alive_into(std::vector<std::uint8_t>& full) const {
    full.resize(m_.bonds.num());
    put_rows(b_.alive, b_.offsets, s_.rows, m_.bonds.offsets, full);
}

std::vector<index_t> Solver::global_neighbors() const {
    if (m_.bonds.complete())
        return m_.bonds.neighbor;
    std::vector<index_t> full(m_.bonds.num(), 0);
    put_rows(b_.neighbor, b_.offsets, s_.rows, m_.bonds.offsets, full);
    dom_->allgather_csr(full, m_.bonds.offsets);
    return full;
}

std::vector<std::uint8_t> Solver::global_alive() const {
    std::vector<std::uint8_t> full(m_.bonds.num(), 1);
    alive_into(full);
    dom_->allgather_csr(full, m_.bonds.offsets);
    return full;
}

void Solver::take_rows() {
    s_.rows = dom_->rows();
    contact_->set_owned(*dom_);
    reactions_.set_rows(s_);
}

void Solver::set_bond_ghosts() {
    bonds_cross_ranks_ = false;
    if (!dom_->distributed())
        return;
    check_whole_grains();
    bond_ghosts_.clear();
    for (auto j : b_.neighbor)
        if (!dom_->owns(j))
            bond_ghosts_.push_back(j);
    std::sort(bond_ghosts_.begin(), bond_ghosts_.end());
    bond_ghosts_.erase(std::unique(bond_ghosts_.begin(), bond_ghosts_.end()), bond_ghosts_.end());
    bonds_cross_ranks_ = dom_->any(!bond_ghosts_.empty());
    dom_->set_ghosts(bond_ghosts_);
}

void Solver::set_ghosts() {
    std::vector<index_t> g = bond_ghosts_;
    contact_->ghosts(g);
    dom_->set_ghosts(g);
    dom_->exchange({&s_.x, &s_.u, &s_.v}, 3); // new ghosts' velocities (friction, damping)
}

void Solver::initialize() {
    initialized_ = true;
    break_precracks();
    for (std::size_t b = 0; b < m_.bodies.num(); ++b) {
        if (m_.bodies.fixed[b])
            continue;
        for (auto i = m_.bodies.begin(b); i < m_.bodies.end(b); ++i)
            for (int d = 0; d < 3; ++d)
                s_.v[3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(d)] =
                    m_.bodies.initial_velocity[3 * b + static_cast<std::size_t>(d)];
    }
    apply_displacements();
    compute_forces();
    power_ = external_power();
    external_work_ = 0;
    diss_.fracture = diss_.damping = diss_.friction = diss_.viscous = 0;
}

void Solver::advance() {
    const double dt = dt_;
    const auto n = static_cast<std::int64_t>(s_.rows.size());
    const index_t* rows = s_.rows.data();
    const bool verlet = m_.solver.integrator == model::Integrator::velocity_verlet;
    const double kick = verlet ? 0.5 * dt : dt;
    {
        ScopedTimer t(timers_, t_integrate_);
        for_each_row(n, parallel_min_nodes, [&](std::int64_t r) {
            const std::int64_t i = rows[r];
            if (!s_.moving[static_cast<std::size_t>(i)])
                return;
            const double a = kick / s_.rho[static_cast<std::size_t>(i)];
            const auto fixed = s_.fixed_dof[static_cast<std::size_t>(i)];
            for (int d = 0; d < 3; ++d) {
                if (fixed & (1u << d))
                    continue;
                const auto k = static_cast<std::size_t>(3 * i + d);
                s_.v[k] += a * s_.f[k];
                s_.u[k] += dt * s_.v[k];
                s_.x[k] = s_.x0[k] + s_.u[k];
            }
        });
    }
    s_.time += dt;
    ++s_.step;
    // Dissipation rates of the last evaluation (compute_forces sets the new ones).
    const double damping_rate0 = diss_.damping_rate, friction_rate0 = diss_.friction_rate,
                 viscous_rate0 = diss_.viscous_rate;
    apply_displacements();
    if (dom_->distributed()) {
        ScopedTimer t(timers_, t_halo_);
        dom_->exchange({&s_.x, &s_.u, &s_.v}, 3);
    }
    compute_forces();
    if (verlet) {
        ScopedTimer t(timers_, t_integrate_);
        for_each_row(n, parallel_min_nodes, [&](std::int64_t r) {
            const std::int64_t i = rows[r];
            if (!s_.moving[static_cast<std::size_t>(i)])
                return;
            const double a = kick / s_.rho[static_cast<std::size_t>(i)];
            const auto fixed = s_.fixed_dof[static_cast<std::size_t>(i)];
            for (int d = 0; d < 3; ++d) {
                if (fixed & (1u << d))
                    continue;
                const auto k = static_cast<std::size_t>(3 * i + d);
                s_.v[k] += a * s_.f[k];
            }
        });
    }
    const double p = external_power();
    external_work_ += 0.5 * (power_ + p) * dt; // trapezoidal in time
    power_ = p;
    diss_.damping += 0.5 * (damping_rate0 + diss_.damping_rate) * dt;
    diss_.friction += 0.5 * (friction_rate0 + diss_.friction_rate) * dt;
    diss_.viscous += 0.5 * (viscous_rate0 + diss_.viscous_rate) * dt;
}

double Solver::external_power() const {
    // Power of gravity and force conditions on every component, of the reactions that impose
    // prescribed displacements (minus the internal force there), and of moving walls.
    double pw = 0;
    const auto n = static_cast<std::int64_t>(s_.rows.size());
    const bool g = g_[0] != 0 || g_[1] != 0 || g_[2] != 0;
    const bool bc = !fbc_.empty();
    const bool prescribed = has_prescribed_;
    if (g || bc || prescribed) {
        pw = sum_rows(n, parallel_min_nodes, [&](std::int64_t a) {
            const auto ii = static_cast<std::size_t>(s_.rows[static_cast<std::size_t>(a)]);
            if (!s_.moving[ii])
                return 0.0;
            double p = 0;
            for (std::size_t d = 0; d < 3; ++d) {
                const double ext = s_.rho[ii] * g_[d] + (bc ? fbc_[3 * ii + d] : 0.0);
                p += ext * s_.v[3 * ii + d];
                if (s_.fixed_dof[ii] & (1u << d))
                    p -= s_.f[3 * ii + d] * s_.v[3 * ii + d];
            }
            return p * s_.vol[ii];
        });
    }
    for (std::size_t w = 0; w < m_.walls.size(); ++w) {
        const auto p = wall_pose(m_.walls[w], s_.time);
        for (std::size_t d = 0; d < 3; ++d)
            pw -= wall_load_.force[3 * w + d] * p.velocity[d] +
                  wall_load_.moment[3 * w + d] * p.omega[d];
    }
    return pw;
}

Observables Solver::observe() const {
    Observables o;
    double ke = 0, p0 = 0, p1 = 0, p2 = 0, gp = 0;
    const auto n = static_cast<std::int64_t>(s_.rows.size());
    auto node = [&](std::int64_t a, double& ke, double& p0, double& p1, double& p2, double& gp) {
        const std::int64_t i = s_.rows[static_cast<std::size_t>(a)];
        const double mass =
            s_.rho[static_cast<std::size_t>(i)] * s_.vol[static_cast<std::size_t>(i)];
        const double* v = &s_.v[3 * i];
        ke += 0.5 * mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        p0 += mass * v[0];
        p1 += mass * v[1];
        p2 += mass * v[2];
        if (s_.moving[static_cast<std::size_t>(i)])
            gp -= mass * (g_[0] * s_.u[3 * i] + g_[1] * s_.u[3 * i + 1] + g_[2] * s_.u[3 * i + 2]);
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
    o.elastic_energy = elastic_energy_;
    o.contact_energy = contact_energy_;
    o.external_work = external_work_;
    o.fracture_energy = diss_.fracture;
    o.damping_dissipation = diss_.damping;
    o.friction_dissipation = diss_.friction;
    o.viscous_dissipation = diss_.viscous;
    o.gravity_potential = gp;
    o.contact_count = contact_count_;
    o.wall_force = wall_load_.force;
    o.wall_moment = wall_load_.moment;
    o.broken_bonds = broken_total_;
    if (contact_->active()) {
        const auto& pen = contact_->penetration();
        o.inside_pairs = pen.count;
        o.inside_node = pen.node;
        o.inside_body = pen.body;
        o.inside_of = pen.inside;
    }
    if (walls_->active()) {
        o.beyond_wall = wall_load_.beyond;
        o.beyond_node = wall_load_.beyond_node;
        o.beyond_wall_index = wall_load_.beyond_wall;
    }
    if (dom_->distributed()) {
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
        dom_->sum(all);
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
    o.broken_bonds /= 2;
    reactions_.result(*dom_, o.body_force, o.body_moment);
    return o;
}

void Solver::damage(std::vector<double>& phi) const {
    damage_phi(s_, b_, phi);
}

void Solver::broken_per_node(std::vector<double>& count) const {
    count.assign(s_.n, 0.0);
    for (std::size_t a = 0; a < s_.rows.size(); ++a) {
        const auto i = static_cast<std::size_t>(s_.rows[a]);
        for (auto k = b_.offsets[a]; k < b_.offsets[a + 1]; ++k)
            count[i] += b_.alive[static_cast<std::size_t>(k)] ? 0.0 : 1.0;
    }
}

void Solver::fragments(std::vector<double>& id) const {
    // Union-find over intact bonds; the smaller root becomes the root, so every id is the
    // smallest node index of its component whatever the order of the unions. When no bond joins
    // two ranks (whole grains per rank) each rank's rows hold its nodes' components entirely;
    // otherwise every rank needs every bond (gathered: memory of the whole bond list, briefly).
    std::vector<index_t> parent(s_.n);
    for (std::size_t i = 0; i < s_.n; ++i)
        parent[i] = static_cast<index_t>(i);
    auto find = [&](index_t a) {
        while (parent[static_cast<std::size_t>(a)] != a) {
            auto& p = parent[static_cast<std::size_t>(a)];
            p = parent[static_cast<std::size_t>(p)]; // path halving
            a = p;
        }
        return a;
    };
    auto unite = [&](index_t i, index_t j) {
        const index_t a = find(i), b = find(j);
        if (a != b)
            parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
    };
    if (!bonds_cross_ranks_) {
        for (std::size_t a = 0; a < s_.rows.size(); ++a)
            for (auto k = b_.offsets[a]; k < b_.offsets[a + 1]; ++k)
                if (b_.alive[static_cast<std::size_t>(k)])
                    unite(s_.rows[a], b_.neighbor[static_cast<std::size_t>(k)]);
    } else {
        const auto alive = global_alive();
        const auto neighbor = global_neighbors();
        const auto& B = m_.bonds;
        for (std::size_t i = 0; i < s_.n; ++i)
            for (auto k = B.offsets[i]; k < B.offsets[i + 1]; ++k)
                if (alive[static_cast<std::size_t>(k)])
                    unite(static_cast<index_t>(i), neighbor[static_cast<std::size_t>(k)]);
    }
    id.resize(s_.n);
    for (std::size_t i = 0; i < s_.n; ++i)
        id[i] = static_cast<double>(find(static_cast<index_t>(i)));
}

void Solver::damage_z(std::vector<double>& z) const {
    z.assign(s_.n, 0.0);
    const auto n = static_cast<std::int64_t>(s_.rows.size());
#pragma omp parallel for schedule(static) if (n > parallel_min)
    for (std::int64_t a = 0; a < n; ++a) {
        const auto ii = static_cast<std::size_t>(s_.rows[static_cast<std::size_t>(a)]);
        const auto b = static_cast<std::size_t>(s_.body[ii]);
        const double s0 = law_.s0[b];
        if (!std::isfinite(s0) || !s_.moving[ii])
            continue;
        double zmax = 0;
        for (auto k = b_.offsets[a]; k < b_.offsets[a + 1]; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            const auto j = static_cast<std::size_t>(b_.neighbor[kk]);
            const double r = b_.xi[kk];
            double st;
            if (law_.rnp[b]) {
                double dot = 0;
                for (std::size_t d = 0; d < 3; ++d)
                    dot += (s_.u[3 * j + d] - s_.u[3 * ii + d]) *
                           (s_.x0[3 * j + d] - s_.x0[3 * ii + d]);
                st = std::abs(dot / (r * r)) / (law_.rnp_rbar[b] / std::sqrt(r));
            } else {
                double l2 = 0;
                for (std::size_t d = 0; d < 3; ++d)
                    l2 +=
                        (s_.x[3 * j + d] - s_.x[3 * ii + d]) * (s_.x[3 * j + d] - s_.x[3 * ii + d]);
                st = std::abs(std::sqrt(l2) - r) / r / s0;
            }
            zmax = std::max(zmax, st);
        }
        z[ii] = zmax;
    }
}

void Solver::nodal_force(std::vector<double>& out) const {
    out.resize(3 * s_.n);
    for (std::size_t i = 0; i < s_.n; ++i)
        for (int d = 0; d < 3; ++d)
            out[3 * i + static_cast<std::size_t>(d)] =
                s_.f[3 * i + static_cast<std::size_t>(d)] * s_.vol[i];
}

std::int64_t Solver::first_nonfinite() const {
    for (auto row : s_.rows) {
        const auto i = static_cast<std::size_t>(row);
        for (std::size_t d = 0; d < 3; ++d)
            if (!std::isfinite(s_.x[3 * i + d]) || !std::isfinite(s_.v[3 * i + d]))
                return static_cast<std::int64_t>(i);
    }
    return -1;
}

} // namespace pd::solver
