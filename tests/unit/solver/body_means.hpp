// SPDX-License-Identifier: MIT
// Test helpers: mass-weighted means of nodal vector fields over one body; the mean wall
// reaction of a body resting under gravity.
#pragma once

#include "model/model.hpp"
#include "solver/solver.hpp"
#include "solver/state.hpp"
#include "solver/walls.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace pd::test {

/// Mass-weighted mean of a nodal vector field (3 per node) over body b (e.g. the centre of mass
/// from s.x, its velocity from s.v).
inline std::array<double, 3> com(const model::Model& m, const solver::State& s, std::size_t b,
                                 const std::vector<double>& field) {
    std::array<double, 3> p{0, 0, 0};
    double mass = 0;
    for (auto i = m.bodies.begin(b); i < m.bodies.end(b); ++i) {
        const auto ii = static_cast<std::size_t>(i);
        const double mi = s.rho[ii] * s.vol[ii];
        mass += mi;
        for (std::size_t d = 0; d < 3; ++d)
            p[d] += mi * field[3 * ii + d];
    }
    for (double& x : p)
        x /= mass;
    return p;
}

/// A state at the reference configuration (at rest, density 1000, every node moving and an owned
/// row), for tests of the contact searches without a Solver.
inline solver::State state_of(const model::Model& m) {
    solver::State s;
    s.n = m.nodes.num();
    s.x0 = m.nodes.x0;
    s.x = s.x0;
    s.u.assign(3 * s.n, 0.0);
    s.v.assign(3 * s.n, 0.0);
    s.f.assign(3 * s.n, 0.0);
    s.vol = m.nodes.volume;
    s.rho.assign(s.n, 1000.0);
    s.body = m.nodes.body;
    s.moving.assign(s.n, 1);
    s.fixed_dof.assign(s.n, 0);
    for (std::size_t i = 0; i < s.n; ++i)
        s.rows.push_back(static_cast<solver::index_t>(i));
    return s;
}

/// A rotating wall swept into a grain at rest: the scene's first wall at t = 10 k R_c (k = 0..100,
/// R_c the first contact law's radius; 1 rad/s), the wall search updated and its forces added
/// each time. `near(s, i)` says whether node i should touch at s.time. Returns the largest
/// number touching and the first step k where the search's count differs from near's (-1: none).
struct Sweep {
    std::int64_t touched = 0;
    int bad_step = -1;
    std::int64_t got = 0, want = 0; ///< at bad_step
};
template <class Near>
Sweep rotating_wall_sweep(const model::Model& m, Near near) {
    const double rc = m.contact.front().radius;
    auto s = state_of(m);
    solver::WallContact wc(m, rc);
    Sweep r;
    for (int k = 0; k <= 100; ++k) {
        s.time = k * 10.0 * rc; // 1 rad/s at 10 mm: the wall near the disc rises 0.1 R_c a step
        wc.update(s);
        solver::WallLoad load;
        wc.add_forces(s, load, nullptr);
        std::int64_t n = 0;
        for (std::size_t i = 0; i < s.n; ++i)
            n += near(s, i) ? 1 : 0;
        if (load.touching != n && r.bad_step < 0) {
            r.bad_step = k;
            r.got = load.touching;
            r.want = n;
        }
        r.touched = std::max(r.touched, n);
    }
    return r;
}

/// Solves 40 ms at 0.7x the automatic step with gravity g along -axis and returns the walls'
/// reaction along +axis, time-averaged over the last 20 ms (the body rests), over the weight.
/// Dropped 0.2 mm, a disc on the surface law (no standoff) bounces until 17.5 ms (restitution
/// 0.5); the node law's R_c standoff stopped it by 15 ms. A mean over bounces is off by the
/// momentum they carry (1.044 x over 15-30 ms on the surface law).
inline double resting_reaction(solver::Solver& s, int axis, double g = 10) {
    s.set_dt(0.7 * s.stable_dt().limit);
    s.initialize();
    double weight = 0;
    for (std::size_t i = 0; i < s.state().n; ++i)
        weight += g * s.state().rho[i] * s.state().vol[i];
    const int steps = static_cast<int>(0.04 / s.dt());
    double sum = 0;
    int count = 0;
    for (int k = 0; k < steps; ++k) {
        s.advance();
        if (k >= steps / 2) {
            sum += s.observe().wall_force[static_cast<std::size_t>(axis)];
            ++count;
        }
        s.end_interval(); // observe() reports the mean over the steps since the last one
    }
    return -sum / count / weight;
}

} // namespace pd::test
