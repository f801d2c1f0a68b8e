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
    // The disc drops 0.2 mm and rests 1 mm right of the floor's centroid: while it rests the
    // floor carries its weight and the moment -x W about its centroid (time averages over the
    // node-level chatter). (Viscous damping brings it to rest: on a meshed floor grain-level
    // damping alone lets it start bouncing again after a few ms.)
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
    const int steps = static_cast<int>(0.015 / s.dt());
    // Rest: the disc's kinetic energy below 1e-10 J (it lands with 7e-6 J); sums over the
    // longest resting stretch.
    struct Run {
        int n = 0;
        double fx = 0, fy = 0, mz = 0, arm = 0;
    } run, best;
    for (int k = 0; k < steps; ++k) {
        s.advance();
        const auto o = s.observe(); // this step's reactions (an interval of one step)
        s.end_interval();
        ASSERT_EQ(o.body_force.size(), 3u);
        double ke = 0;
        for (auto i = m.bodies.begin(1); i < m.bodies.end(1); ++i) {
            const auto ii = static_cast<std::size_t>(i);
            const double* vi = &s.state().v[3 * ii];
            ke += 0.5 * s.state().rho[ii] * s.state().vol[ii] *
                  (vi[0] * vi[0] + vi[1] * vi[1] + vi[2] * vi[2]);
        }
        if (ke < 1e-10 && k > 100) {
            ++run.n;
            run.fx += o.body_force[0];
            run.fy += o.body_force[1];
            run.mz += o.body_moment[2];
            run.arm += test::com(m, s.state(), 1, s.state().x)[0] - floor_c[0];
        } else {
            run = Run{};
        }
        if (run.n > best.n)
            best = run;
    }
    ASSERT_GT(best.n * s.dt(), 1e-3) << "the disc never rests for 1 ms";
    const double arm = best.arm / best.n;
    std::printf("[ meshed floor ] rests %.3g ms: reaction / weight %.5f, moment / (-arm W) %.5f, "
                "arm %.4g m\n",
                best.n * s.dt() * 1e3, -best.fy / best.n / weight,
                best.mz / best.n / (-arm * weight), arm);
    EXPECT_NEAR(-best.fy / best.n / weight, 1.0, 0.01);
    EXPECT_NEAR(best.fx / best.n / weight, 0.0, 0.01);
    EXPECT_NEAR(best.mz / best.n / (-arm * weight), 1.0, 0.02);
    EXPECT_NEAR(arm, 1e-3, 2e-5);
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
