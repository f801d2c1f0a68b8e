// SPDX-License-Identifier: MIT
// Coulomb friction on every touching node pair (and node-wall pair) with mu > 0: a force
// mu |F_n| opposing the tangential slip, F_n scaled like the normal force under unloading
// (hysteretic damping), and never more than half of what stops the slip within the step (stick).
// Serial over the sorted contact records: deterministic; equal and opposite on node pairs.
#include "solver/forces.hpp"

#include <algorithm>
#include <cmath>

namespace pd::solver {

namespace {

/// The stick cap's share of the impulse that would stop a slip within one step. At 1 (a
/// deadbeat damper for one pair alone) a node sticking to several partners at once gets several
/// such impulses in one step, and an explicit damper overshoots once their sum passes
/// 2 m_i / dt: two PMB discs with friction 0.4 and no damping gained 5.4 % energy in 203 steps
/// at the automatic dt (9.93e-7 s; 0.23 % at 6e-7 s). At 0.5 the same run drifts 0.21 %, and
/// up to three partners per node stay below the bound; the slip then stops over a few steps.
constexpr double stick_share = 0.5;

/// Removes from v its component along the normal force F (|F| = fm); returns |v_t|.
double tangential(const double* F, double fm, double* v) {
    double vn = 0;
    for (int d = 0; d < 3; ++d)
        vn += v[d] * F[d] / fm;
    double m2 = 0;
    for (int d = 0; d < 3; ++d) {
        v[d] -= vn * F[d] / fm;
        m2 += v[d] * v[d];
    }
    return std::sqrt(m2);
}

double norm(const double* F) {
    return std::sqrt(F[0] * F[0] + F[1] * F[1] + F[2] * F[2]);
}

class Friction final : public ForceTerm {
  public:
    void add(Forces& f) override {
        ScopedTimer t(f.timers, f.t_damping);
        for (const auto& r : f.pair_records)
            if (r.friction > 0)
                node_pair(f, r);
        for (const auto& r : f.wall_records)
            if (r.friction > 0)
                node_wall(f, r);
    }
    std::vector<const char*> checkpointed() const override { return {"friction", "friction_rate"}; }

  private:
    /// The unloading factor of the pair's damping at the last evaluation (1: none).
    static double factor(const Forces& f, std::int32_t a, std::int32_t b) {
        auto it = f.unload.find({a, b});
        return it == f.unload.end() ? 1.0 : it->second;
    }
    static void node_pair(Forces& f, const BodyPairForce& r) {
        auto& s = f.s;
        const auto i = static_cast<std::size_t>(r.i), j = static_cast<std::size_t>(r.j);
        const double fm = norm(r.force);
        if (!(fm > 0))
            return;
        double vt[3];
        for (std::size_t d = 0; d < 3; ++d)
            vt[d] = s.v[3 * j + d] - s.v[3 * i + d];
        const double vtm = tangential(r.force, fm, vt);
        if (!(vtm > 0))
            return;
        const double mi = s.rho[i] * s.vol[i], mj = s.rho[j] * s.vol[j];
        const double stop = stick_share * mi * mj / (mi + mj) * vtm / f.dt;
        const double ft = std::min(r.friction * fm * factor(f, r.a, r.b), stop) / vtm; // N per m/s
        if (f.dom->owns(r.i)) // a pair's record may be on two ranks: counted once
            f.diss.friction_rate += ft * vtm * vtm;
        for (std::size_t d = 0; d < 3; ++d) {
            s.f[3 * i + d] += ft * vt[d] / s.vol[i]; // i is dragged along the slip of j
            s.f[3 * j + d] -= ft * vt[d] / s.vol[j];
        }
    }
    static void node_wall(Forces& f, const BodyWallForce& r) {
        auto& s = f.s;
        const auto i = static_cast<std::size_t>(r.node);
        const auto w = static_cast<std::size_t>(r.wall);
        const double fm = norm(r.force);
        if (!(fm > 0))
            return;
        const auto p = wall_pose(f.m.walls[w], s.time);
        const double* x = &s.x[3 * i];
        const double rr[3] = {x[0] - p.centre[0], x[1] - p.centre[1], x[2] - p.centre[2]};
        const double vw[3] = {p.velocity[0] + p.omega[1] * rr[2] - p.omega[2] * rr[1],
                              p.velocity[1] + p.omega[2] * rr[0] - p.omega[0] * rr[2],
                              p.velocity[2] + p.omega[0] * rr[1] - p.omega[1] * rr[0]};
        double vt[3];
        for (std::size_t d = 0; d < 3; ++d)
            vt[d] = vw[d] - s.v[3 * i + d];
        const double vtm = tangential(r.force, fm, vt);
        if (!(vtm > 0))
            return;
        const double stop = stick_share * s.rho[i] * s.vol[i] * vtm / f.dt;
        const double ft = std::min(r.friction * fm * factor(f, r.body, -1 - r.wall), stop) / vtm;
        f.diss.friction_rate += ft * vtm * vtm;
        double F[3];
        auto& load = f.wall_load;
        for (std::size_t d = 0; d < 3; ++d) {
            s.f[3 * i + d] += ft * vt[d] / s.vol[i];
            F[d] = -ft * vt[d]; // received by the wall
            load.force[3 * w + d] += F[d];
        }
        load.moment[3 * w + 0] += rr[1] * F[2] - rr[2] * F[1];
        load.moment[3 * w + 1] += rr[2] * F[0] - rr[0] * F[2];
        load.moment[3 * w + 2] += rr[0] * F[1] - rr[1] * F[0];
    }
};

} // namespace

std::unique_ptr<ForceTerm> make_friction(Forces& f) {
    // Not needed when no contact law has mu > 0 (or a stiffness): every record would be skipped.
    return f.friction ? std::make_unique<Friction>() : nullptr;
}

} // namespace pd::solver
