// SPDX-License-Identifier: MIT
// The penetration guard under the surface contact law (solver/surface_contact.cpp): a node that
// came through another body's boundary stays counted however deep it goes within that body's
// reach; a node inside another body's intact material is counted whatever its history, one in
// a crack is not.
#include "pressed_blocks.hpp"
#include "solver/solver.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

namespace {

using namespace pd;

/// The depth of block b's lowest node below a's top (y = 0), m.
double lowest_depth(const model::Model& m, const solver::State& st) {
    double lowest = 1;
    for (auto i = m.bodies.begin(1); i < m.bodies.end(1); ++i)
        lowest = std::min(lowest, st.x[3 * static_cast<std::size_t>(i) + 1]);
    return -lowest;
}

/// Gives block b the velocity vy (m/s) along y.
void set_vy(const model::Model& m, solver::State& st, double vy) {
    for (auto i = m.bodies.begin(1); i < m.bodies.end(1); ++i)
        st.v[3 * static_cast<std::size_t>(i) + 1] = vy;
}

} // namespace

TEST(SurfaceGuard, ANodeThatWentThroughStaysCounted) {
    // Block b is driven into a at 0.1 x the mesh spacing per step (a small step, so the
    // contact's own motion is negligible against it) from 0.02 of it deep. The guard counts the
    // pairs more than h / 2 inside (h: a's mesh size as the law has it); past h (the law's
    // reach: no force) they must stay counted while the nodes are within reach of a's facets.
    // Before, between h and the depth where the next row of nodes came into play (1.06-1.35 h
    // here) no pair was counted: a run could end with a node h deep in another grain, exit 0.
    const double dx = 2e-4; // the grid spacing
    auto m = test::pressed_blocks(0.02 * dx);
    const double h = m.bodies.mesh_size[0];
    solver::Solver s(m);
    s.set_dt(0.05 * s.stable_dt().limit);
    s.initialize();
    auto& st = s.state();
    int seen_between = 0, seen_beyond = 0, steps_beyond = 0;
    for (int k = 0; k < 13; ++k) {
        set_vy(m, st, -0.1 * dx / s.dt());
        s.advance();
        const double d = lowest_depth(m, st);
        const auto pairs = s.observe().inside_pairs;
        std::printf("[ through ] depth %.3f h: %lld pair(s) counted\n", d / h,
                    static_cast<long long>(pairs));
        if (d > 0.55 * h && d < 0.95 * h)
            seen_between += pairs > 0;
        if (d > 1.05 * h) {
            ++steps_beyond;
            seen_beyond += pairs > 0;
        }
    }
    EXPECT_GT(seen_between, 0);
    EXPECT_GE(steps_beyond, 5);
    EXPECT_EQ(seen_beyond, steps_beyond);
    // Back out, at rest: nothing is counted.
    set_vy(m, st, 0.0);
    test::shift_b(m, st, lowest_depth(m, st) + 0.1 * h);
    s.advance();
    const auto o = s.observe();
    std::printf("[ through ] back out: %lld pair(s)\n", static_cast<long long>(o.inside_pairs));
    EXPECT_EQ(o.inside_pairs, 0);
}

TEST(SurfaceGuard, ANodeInsideIntactMaterialIsCountedWithoutHistory) {
    // The same blocks moved 1.2 h deeper between two steps at rest: the depth jumped, so the
    // law does not count them (surface_row leaves a jumped pair alone: in a breaking run it may
    // lie in a crack of a grain behind a facet that still stands). The material test does: the
    // nodes lie inside a's intact cells a layer below its boundary (surface_inside.cpp).
    const double dx = 2e-4;
    auto m = test::pressed_blocks(0.02 * dx);
    const double h = m.bodies.mesh_size[0];
    solver::Solver s(m);
    s.initialize();
    s.advance();
    test::shift_b(m, s.state(), -1.2 * h);
    s.advance();
    const auto o = s.observe();
    std::printf("[ jumped ] depth %.3f h: %lld pair(s), node %lld of body %d in body %d\n",
                lowest_depth(m, s.state()) / h, static_cast<long long>(o.inside_pairs),
                static_cast<long long>(o.inside_node), o.inside_body, o.inside_of);
    EXPECT_GT(o.inside_pairs, 0);
    EXPECT_EQ(o.inside_body + o.inside_of, 1); // a node of b in a, or of a in b
}

TEST(SurfaceGuard, ANodeInACrackIsNotCounted) {
    // A crack through a (its nodes right of x = 0 moved 1.5 dx to the right) and b's lowest
    // nodes above the gap moved 2.5 h down into it at once (below a layer of cells): they are
    // behind a's (stretched) top facets, but in no intact cell of a, so nothing counts them; the
    // same nodes moved as far into a's intact left half are counted.
    const double dx = 2e-4;
    for (const bool crack : {true, false}) {
        auto m = test::pressed_blocks(0.02 * dx);
        const double h = m.bodies.mesh_size[0];
        solver::Solver s(m);
        s.set_dt(0.05 * s.stable_dt().limit);
        s.initialize();
        s.advance();
        auto& st = s.state();
        for (auto i = m.bodies.begin(0); i < m.bodies.end(0); ++i) {
            const auto k = static_cast<std::size_t>(i);
            if (m.nodes.x0[3 * k] > 1e-9) {
                st.x[3 * k] += 1.5 * dx;
                st.u[3 * k] += 1.5 * dx;
            }
        }
        // b's lowest nodes over the gap (crack) or over a's left half (no crack).
        const double x_lo = crack ? 0.2 * dx : -1.3 * dx, x_hi = x_lo + 1.1 * dx;
        const double y_low = -lowest_depth(m, st);
        int moved = 0;
        for (auto i = m.bodies.begin(1); i < m.bodies.end(1); ++i) {
            const auto k = static_cast<std::size_t>(i);
            if (st.x[3 * k] > x_lo && st.x[3 * k] < x_hi && st.x[3 * k + 1] < y_low + 0.5 * dx) {
                st.x[3 * k + 1] -= 2.5 * h;
                st.u[3 * k + 1] -= 2.5 * h;
                ++moved;
            }
        }
        s.advance();
        const auto o = s.observe();
        std::printf("[ crack ] %s: %d node(s) moved 2.5 h down, %lld pair(s) counted\n",
                    crack ? "into the crack" : "into intact material", moved,
                    static_cast<long long>(o.inside_pairs));
        EXPECT_GT(moved, 0);
        if (crack)
            EXPECT_EQ(o.inside_pairs, 0);
        else
            EXPECT_GT(o.inside_pairs, 0);
    }
}
