// SPDX-License-Identifier: MIT
// Grain-level hysteretic damping with true grain masses (spec decision 6). For each pair of
// grains (or grain and wall) in contact, F = their total normal contact force and v_n the
// relative normal velocity of their centres of mass. While the contact unloads (v_n > 0, the
// grains separate) each grain receives -(1 - eps^2) F as a uniform acceleration: the contact
// returns eps^2 of the energy it stored, so the rebound speed is eps times the impact speed
// whatever the non-linearity of the node-level contact and the grains' deformation (Walton &
// Braun 1986 loading/unloading idea, at grain level). Momentum is conserved; a wall's
// reaction includes the reduction. No per-contact history is needed.
#include "solver/forces.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

namespace pd::solver {

namespace {

using Key = std::pair<std::int32_t, std::int32_t>; ///< grains (a, b), or (a, -1 - wall)

/// The unloading reduction's cap: this share of the force that stops the pair's separation
/// within one step (0.5, as friction's stick_share: a grain in several contacts gets several).
constexpr double damping_stop_share = 0.5;
using Com = std::array<double, 6>; ///< velocity, position of a centre of mass

class ContactDamping final : public ForceTerm {
  public:
    void add(Forces& f) override {
        ScopedTimer t(f.timers, f.t_damping);
        const auto force = pair_forces(f);
        com_.clear();
        if (f.dom->distributed())
            all_centres(f);
        accel_.clear();
        f.unload.clear();
        for (const auto& [key, F] : force)
            unload(f, key, F);
        accelerate(f);
    }
    std::vector<const char*> checkpointed() const override { return {"damping", "damping_rate"}; }

  private:
    /// The total normal contact force of each touching pair of grains (and grain and wall).
    static std::map<Key, std::array<double, 3>> pair_forces(const Forces& f) {
        std::map<Key, std::array<double, 3>> force;
        for (const auto& r : f.pair_records) {
            auto& F = force[{r.a, r.b}];
            for (int d = 0; d < 3; ++d)
                F[static_cast<std::size_t>(d)] += r.force[d];
        }
        for (const auto& r : f.wall_records) {
            auto& F = force[{r.body, -1 - r.wall}];
            for (int d = 0; d < 3; ++d)
                F[static_cast<std::size_t>(d)] += r.force[d];
        }
        return force;
    }
    /// Every body's centre of mass, over the ranks. Whole grains per rank (checked at
    /// construction): each owner sums its grains' nodes in the order one rank would, the others
    /// add exact zeros.
    void all_centres(const Forces& f) {
        const auto& s = f.s;
        std::vector<double> all(6 * f.m.bodies.num(), 0.0);
        for (auto row : s.rows) {
            const auto ii = static_cast<std::size_t>(row);
            const auto b = static_cast<std::size_t>(s.body[ii]);
            const double mi = s.rho[ii] * s.vol[ii];
            for (std::size_t d = 0; d < 3; ++d) {
                all[6 * b + d] += mi * s.v[3 * ii + d];
                all[6 * b + 3 + d] += mi * s.x[3 * ii + d];
            }
        }
        f.dom->sum(all);
        for (std::size_t b = 0; b < f.m.bodies.num(); ++b) {
            Com c;
            for (std::size_t d = 0; d < 6; ++d)
                c[d] = all[6 * b + d] / f.body_mass[b];
            com_.emplace(static_cast<std::int32_t>(b), c);
        }
    }
    /// Body b's centre of mass (summed on first use on one rank).
    const Com& com_of(const Forces& f, std::int32_t b) {
        auto it = com_.find(b);
        if (it != com_.end())
            return it->second;
        const auto& s = f.s;
        Com c{};
        const auto bb = static_cast<std::size_t>(b);
        for (auto i = f.m.bodies.begin(bb); i < f.m.bodies.end(bb); ++i) {
            const auto ii = static_cast<std::size_t>(i);
            const double mi = s.rho[ii] * s.vol[ii];
            for (std::size_t d = 0; d < 3; ++d) {
                c[d] += mi * s.v[3 * ii + d];
                c[3 + d] += mi * s.x[3 * ii + d];
            }
        }
        for (double& x : c)
            x /= f.body_mass[bb];
        return com_.emplace(b, c).first->second;
    }
    /// The contact law of the pair and the velocity of the second grain (or wall) relative to
    /// the first, the two centres of mass seen along `n` (from a to b).
    const model::ContactPair* relative(Forces& f, const Key& key, const Com& ca, double* vrel) {
        const auto a = key.first;
        const auto ga = f.m.bodies.group[static_cast<std::size_t>(a)];
        if (key.second < 0) {
            const auto& w = f.m.walls[static_cast<std::size_t>(-1 - key.second)];
            const auto p = wall_pose(w, f.s.time);
            const double r[3] = {ca[3] - p.centre[0], ca[4] - p.centre[1], ca[5] - p.centre[2]};
            const double vw[3] = {p.velocity[0] + p.omega[1] * r[2] - p.omega[2] * r[1],
                                  p.velocity[1] + p.omega[2] * r[0] - p.omega[0] * r[2],
                                  p.velocity[2] + p.omega[0] * r[1] - p.omega[1] * r[0]};
            for (int d = 0; d < 3; ++d)
                vrel[d] = ca[static_cast<std::size_t>(d)] - vw[d]; // grain relative to wall
            return f.m.contact_between(ga, w.group);
        }
        const auto b = key.second;
        const auto* law = f.m.contact_between(ga, f.m.bodies.group[static_cast<std::size_t>(b)]);
        const auto& cb = com_of(f, b);
        for (std::size_t d = 0; d < 3; ++d)
            vrel[d] = cb[d] - ca[d]; // b relative to a; n points from a to b
        return law;
    }
    /// One touching pair: when it unloads, the damping force, its dissipation and reactions.
    void unload(Forces& f, const Key& key, const std::array<double, 3>& F) {
        const double fm = std::sqrt(F[0] * F[0] + F[1] * F[1] + F[2] * F[2]);
        if (!(fm > 0))
            return;
        const double n[3] = {F[0] / fm, F[1] / fm, F[2] / fm};
        const bool wall = key.second < 0;
        const auto a = key.first;
        const auto& ca = com_of(f, a);
        double vrel[3];
        const model::ContactPair* law = relative(f, key, ca, vrel);
        if (!law || law->restitution >= 1)
            return;
        const double vn = vrel[0] * n[0] + vrel[1] * n[1] + vrel[2] * n[2];
        if (!(vn > 0))
            return; // loading (approach): no damping
        // Unloading: the grains get back only eps^2 of their normal contact force, but the
        // reduction never takes more than half of what stops the separation within the step
        // (as friction's stick cap, friction.cpp). Jammed grains separate at a vibration's
        // speed (~1e-4 m/s) under a large static force: (1 - eps^2) F reversed that speed within
        // a step, the sign flipped it on and off, and the force did negative work counted as
        // dissipation: a 2D box of 78 grains pressed by a plate (restitution 0.5) gained 0.39 J
        // in 20 ms (restitution 1: 7e-5 J). An impact's unloading is far from the cap.
        const auto& B = f.m.bodies;
        const auto mass = [&](std::int32_t k) {
            return k < 0 || B.fixed[static_cast<std::size_t>(k)]
                       ? std::numeric_limits<double>::infinity()
                       : f.body_mass[static_cast<std::size_t>(k)];
        };
        const double ma = mass(a), mb = mass(wall ? -1 : key.second);
        const double meff = std::isfinite(ma) ? (std::isfinite(mb) ? ma * mb / (ma + mb) : ma) : mb;
        const double stop = damping_stop_share * meff * vn / f.dt;
        const double scale = std::min(1.0 - law->restitution * law->restitution,
                                      std::isfinite(stop) ? stop / fm : 1.0);
        f.unload[key] = 1.0 - scale; // friction limit, next evaluation
        // Damping force on b (or on the grain, for a wall): -(1 - eps^2) F, F the contact force
        // on it.
        const double Fd[3] = {-scale * F[0], -scale * F[1], -scale * F[2]};
        const bool owner = f.dom->owns(f.m.bodies.begin(static_cast<std::size_t>(a)));
        if (wall && owner)
            wall_reaction(f, static_cast<std::size_t>(-1 - key.second), ca, Fd);
        // Dissipation rate -Fd . v_rel (> 0 while unloading), counted once: by the rank that
        // owns grain a.
        if (owner)
            f.diss.damping_rate -= Fd[0] * vrel[0] + Fd[1] * vrel[1] + Fd[2] * vrel[2];
        if (wall) {
            auto& acc = accel_[a];
            for (int d = 0; d < 3; ++d)
                acc[static_cast<std::size_t>(d)] +=
                    Fd[d] / f.body_mass[static_cast<std::size_t>(a)];
        } else {
            grain_pair(f, a, key.second, Fd);
        }
    }
    /// The wall feels the reduced push too.
    static void wall_reaction(Forces& f, std::size_t w, const Com& ca, const double* Fd) {
        auto& load = f.wall_load;
        for (std::size_t d = 0; d < 3; ++d)
            load.force[3 * w + d] -= Fd[d];
        const auto p = wall_pose(f.m.walls[w], f.s.time);
        const double r[3] = {ca[3] - p.centre[0], ca[4] - p.centre[1], ca[5] - p.centre[2]};
        load.moment[3 * w + 0] -= r[1] * Fd[2] - r[2] * Fd[1];
        load.moment[3 * w + 1] -= r[2] * Fd[0] - r[0] * Fd[2];
        load.moment[3 * w + 2] -= r[0] * Fd[1] - r[1] * Fd[0];
    }
    /// Two grains: equal and opposite accelerations; a meshed wall's reaction gets the damping
    /// share, acting through the other grain's centre (as for rigid walls).
    void grain_pair(Forces& f, std::int32_t a, std::int32_t b, const double* Fd) {
        auto& acb = accel_[b];
        auto& aca = accel_[a];
        for (int d = 0; d < 3; ++d) {
            acb[static_cast<std::size_t>(d)] += Fd[d] / f.body_mass[static_cast<std::size_t>(b)];
            aca[static_cast<std::size_t>(d)] -= Fd[d] / f.body_mass[static_cast<std::size_t>(a)];
        }
        const double Fa[3] = {-Fd[0], -Fd[1], -Fd[2]};
        for (auto [r, other, Fr] : {std::tuple{a, b, Fa}, std::tuple{b, a, Fd}})
            if (f.reactions.records(r) &&
                f.dom->owns(f.m.bodies.begin(static_cast<std::size_t>(r))))
                f.reactions.add_damping(r, Fr, &com_of(f, other)[3], &com_of(f, r)[3],
                                        f.m.bodies.fixed[static_cast<std::size_t>(r)] != 0);
    }
    /// Each damped grain's acceleration, on every node of it.
    void accelerate(Forces& f) const {
        for (const auto& [b, acc] : accel_) {
            const auto bb = static_cast<std::size_t>(b);
            if (f.m.bodies.fixed[bb] || !f.dom->owns(f.m.bodies.begin(bb)))
                continue; // (a grain split between ranks is refused with damping)
            for (auto i = f.m.bodies.begin(bb); i < f.m.bodies.end(bb); ++i) {
                const auto ii = static_cast<std::size_t>(i);
                for (std::size_t d = 0; d < 3; ++d)
                    f.s.f[3 * ii + d] += f.s.rho[ii] * acc[d];
            }
        }
    }

    std::map<std::int32_t, Com> com_;
    std::map<std::int32_t, std::array<double, 3>> accel_;
};

} // namespace

std::unique_ptr<ForceTerm> make_contact_damping(Forces& f) {
    // Not needed when every contact law has restitution 1 (or no stiffness): no pair unloads with
    // a loss, and the unloading factors friction reads stay 1.
    return f.damping ? std::make_unique<ContactDamping>() : nullptr;
}

} // namespace pd::solver
