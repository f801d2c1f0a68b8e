// SPDX-License-Identifier: MIT
// Reactions of meshed walls (fixed or driven bodies): a disc resting on a fixed meshed floor
// under gravity loads it with its weight (and the moment of its offset); a driven plate pushing
// a free disc receives exactly minus what the disc receives (momentum balance over the run,
// with damping, friction and gravity).
#include "body_means.hpp"
#include "core/log.hpp"
#include "pipeline/scene.hpp"
#include "solver/solver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace {

using namespace pd;

const Log quiet("test", 0, Verbosity::quiet);

std::string scene(const std::string& particles, const std::string& rest) {
    return R"({"dimension": 2,
      "materials": {"m1": {"density": 1200, "youngs_modulus": 3.24e7, "fracture_energy": 50}},
      "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
      "shapes": {"slab": {"type": "rectangle", "corners": [[-3e-3, -0.6e-3], [3e-3, 0]]}},
      "particles": [)" +
           particles + "], " + rest + R"(, "solver": {"final_time": 1}})";
}

double body_mass(const model::Model& m, const solver::State& s, std::size_t b) {
    double mass = 0;
    for (auto i = m.bodies.begin(b); i < m.bodies.end(b); ++i)
        mass += s.rho[static_cast<std::size_t>(i)] * s.vol[static_cast<std::size_t>(i)];
    return mass;
}

TEST(BodyReaction, FixedMeshedFloorCarriesTheWeight) {
    // The disc drops 0.2 mm and settles 1 mm right of the floor's centroid: over the last 20 ms
    // of 50 the floor carries its weight and the moment -x W about its centroid (x the disc's
    // mean offset), to within what the disc's momentum changes by over the window. (Viscous
    // damping brings it to rest: on a meshed floor grain-level damping alone lets it start
    // bouncing again after a few ms. On the surface law the polygonal disc, dropped onto a
    // node, rocks onto a facet before it rests, at 23 ms: 0.2 mm of drop in 8 ms, then bounces
    // of 14 and 2 um; the node law's R_c standoff rested it by 10 ms.)
    auto m = pipeline::build_scene(
        scene(R"({"shape": "slab", "center": [0, 0], "material": "m1", "fixed": true},
                 {"radius": 1e-3, "center": [1e-3, 1.2e-3], "material": "m1"})",
              R"("contact": {"restitution": 0.5},
                 "loading": {"gravity": [0, -10], "viscous_damping": 200})"),
        "t", quiet);
    solver::Solver s(m);
    ASSERT_EQ(s.reaction_bodies(), std::vector<std::int32_t>{0});
    s.set_dt(0.7 * s.stable_dt().limit);
    s.initialize();
    const double mass = body_mass(m, s.state(), 1), weight = 10 * mass;
    const auto floor_c = test::com(m, s.state(), 0, s.state().x);
    const int steps = static_cast<int>(0.05 / s.dt()), from = static_cast<int>(0.03 / s.dt());
    const auto com_v = [&] { return test::com(m, s.state(), 1, s.state().v); };
    double fx = 0, fy = 0, mz = 0, arm = 0, ke = 0, side = 0, landing = 0;
    std::array<double, 3> v0{};
    for (int k = 0; k < steps; ++k) {
        if (k == from)
            v0 = com_v();
        s.advance();
        const auto vk = com_v();
        landing = std::max(landing, -vk[1]);
        side = std::max(side, std::abs(vk[0]));
        const auto o = s.observe(); // this step's reactions (an interval of one step)
        s.end_interval();
        ASSERT_EQ(o.body_force.size(), 3u);
        if (k < from)
            continue;
        fx += o.body_force[0];
        fy += o.body_force[1];
        mz += o.body_moment[2];
        arm += test::com(m, s.state(), 1, s.state().x)[0] - floor_c[0];
        ke = std::max(ke, o.kinetic_energy);
    }
    const double n = steps - from, T = n * s.dt();
    const auto v1 = com_v();
    // The floor's mean reaction is the weight plus the disc's momentum change over the window.
    const double dpx = mass * (v1[0] - v0[0]) / T, dpy = mass * (v1[1] - v0[1]) / T;
    arm /= n;
    std::printf("[ meshed floor ] reaction / weight %.5f (momentum %+.1e), moment / (-arm W) %.5f, "
                "arm %.4g m, largest KE %.2g J\n",
                -fy / n / weight, dpy / weight, mz / n / (-arm * weight), arm, ke);
    std::printf("[ meshed floor ] landing %.4g m/s, largest sideways speed %.3g m/s\n", landing,
                side);
    EXPECT_NEAR(-fy / n / weight, 1.0, 0.01);
    EXPECT_NEAR((-fy / n - dpy) / weight, 1.0, 2e-3);
    EXPECT_NEAR((fx / n + dpx) / weight, 0.0, 2e-3);
    EXPECT_NEAR(mz / n / (-arm * weight), 1.0, 0.02);
    EXPECT_NEAR(arm, 1e-3, 2e-5);
    // At rest: what is left is 1e-3 of the 7e-6 J the disc lands with.
    EXPECT_LT(ke, 7e-9);
}

TEST(BodyReaction, DrivenPlateBalancesTheDiscMomentum) {
    // A plate driven down at 0.5 m/s (both components prescribed) hits a free disc: over the
    // run, the impulse the plate receives equals minus the disc's change of momentum, gravity's
    // impulse removed (velocity Verlet: trapezoidal in the forces, exactly).
    auto m =
        pipeline::build_scene(scene(R"({"radius": 1e-3, "center": [0.3e-3, 0], "material": "m1"},
                 {"shape": "slab", "center": [0, 1.75e-3], "material": "m1"})",
                                    R"("contact": {"restitution": 0.8, "friction": 0.3},
                 "loading": {"gravity": [0, -10], "conditions": [
                   {"name": "down", "kind": "displacement", "particles": [1],
                    "components": ["y"], "time_function": "linear", "value": -0.5},
                   {"name": "still", "kind": "displacement", "particles": [1],
                    "components": ["x"], "value": 0}]})"),
                              "t", quiet);
    solver::Solver s(m);
    ASSERT_EQ(s.reaction_bodies(), std::vector<std::int32_t>{1});
    s.set_dt(0.7 * s.stable_dt().limit);
    s.initialize();
    const double mass = body_mass(m, s.state(), 0);
    auto momentum = [&] {
        const auto v = test::com(m, s.state(), 0, s.state().v);
        return std::array<double, 3>{mass * v[0], mass * v[1], mass * v[2]};
    };
    const auto p0 = momentum();
    auto prev = s.observe().body_force;
    double impulse[2] = {0, 0}, peak = 0;
    const int steps = static_cast<int>(6e-4 / s.dt());
    for (int k = 0; k < steps; ++k) {
        s.advance();
        const auto f = s.observe().body_force; // this step's (an interval of one step)
        s.end_interval();
        for (std::size_t d = 0; d < 2; ++d)
            impulse[d] += 0.5 * s.dt() * (prev[d] + f[d]);
        peak = std::max(peak, std::abs(f[1]));
        prev = f;
    }
    const auto p1 = momentum();
    const double T = steps * s.dt();
    const double dp[2] = {p1[0] - p0[0], p1[1] - p0[1] + 10 * mass * T}; // gravity removed
    std::printf("[ driven plate ] impulse %.6e %.6e N s, -dP %.6e %.6e, peak %.4g N\n", impulse[0],
                impulse[1], -dp[0], -dp[1], peak);
    ASSERT_GT(peak, 0) << "the plate never touched the disc";
    ASSERT_GT(std::abs(dp[1]), 0.1 * mass * 0.5) << "the disc was barely pushed";
    EXPECT_NEAR(impulse[1], -dp[1], 1e-9 * std::abs(dp[1]));
    EXPECT_NEAR(impulse[0], -dp[0], 1e-9 * std::abs(dp[1]));
    EXPECT_GT(impulse[1], 0); // the disc pushes the plate up
}

} // namespace
