// SPDX-License-Identifier: MIT
// The surface contact law (model::ContactLaw::surface, solver/surface_contact.cpp) with its auto
// stiffness and no factor: an elastic disc on a rigid wall converges to an elastodynamic
// reference; its restitution; brittle discs that shatter on each other keep their energy.
#include "body_means.hpp"
#include "core/log.hpp"
#include "pipeline/scene.hpp"
#include "pressed_blocks.hpp"
#include "solver/solver.hpp"
#include "solver/surface_penalty.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace {

using namespace pd;

const Log quiet("test", 0, Verbosity::quiet);

struct Impact {
    double duration = 0; ///< s, first to last step with a wall force
    double peak = 0;     ///< N per m of thickness
    std::int64_t beyond = 0;
};

/// A PMB disc (R = 1 mm, E = 32.4 MPa, rho = 1200, plane stress nu = 1/3) at `v` onto a rigid
/// floor, mesh size h, surface law, no damping.
Impact disc_on_wall(double h, double v) {
    const std::string sc = R"({"dimension": 2,
      "materials": {"m": {"density": 1200, "youngs_modulus": 3.24e7}},
      "discretization": {"mesh_size": )" +
                           std::to_string(h) +
                           R"(, "horizon_factor": 3},
      "particles": [{"radius": 1e-3, "center": [0, )" +
                           std::to_string(1e-3 + 0.5 * h) +
                           R"(], "material": "m", "velocity": [0, )" + std::to_string(-v) +
                           R"(]}],
      "walls": [{"type": "plane", "point": [0, 0], "normal": [0, 1]}],
      "contact": {"law": "surface"}, "solver": {"final_time": 1}})";
    auto m = pipeline::build_scene(sc, "t", quiet);
    solver::Solver s(m);
    s.set_dt(0.85 * s.stable_dt().limit);
    s.initialize();
    Impact r;
    double first = -1, last = -1;
    while (s.state().time < 0.5 * h / v + 1.5e-4) {
        s.advance();
        const auto o = s.observe();
        s.end_interval();
        r.beyond += o.beyond_wall;
        if (o.wall_force[1] != 0) {
            if (first < 0)
                first = s.state().time - s.dt();
            last = s.state().time;
            r.peak = std::max(r.peak, std::abs(o.wall_force[1]));
        }
    }
    r.duration = last - first;
    return r;
}

/// Rebound / impact speed of a gmsh disc (R = 1 mm, PMB, h) at 1 m/s on a plane wall, or of two
/// equal ones head-on at +-1 m/s, surface law with restitution eps: centres of mass once apart.
double surface_restitution(double h, double eps, bool wall) {
    const std::string sc = fmt::format(
        R"({{"dimension": 2, "materials": {{"m": {{"density": 1200, "youngs_modulus": 3.24e7}}}},
      "discretization": {{"mesh_size": {}, "horizon_factor": 3}},
      "particles": [{{"radius": 1e-3, "center": [0, {}], "material": "m", "velocity": [0, -1]}}
                    {}],
      {} "contact": {{"law": "surface", "restitution": {}}}, "solver": {{"final_time": 1}}}})",
        h, 1e-3 + 0.05 * h,
        wall ? ""
             : fmt::format(R"(, {{"radius": 1e-3, "center": [0, {}], "material": "m",
                                       "velocity": [0, 1], "orientation": 0.5}})",
                           -1e-3 - 0.05 * h),
        wall ? R"("walls": [{"type": "plane", "point": [0, 0], "normal": [0, 1]}],)" : "", eps);
    auto m = pipeline::build_scene(sc, "t", quiet);
    solver::Solver s(m);
    s.set_dt(0.85 * s.stable_dt().limit);
    s.initialize();
    bool touched = false;
    for (int k = 0; k < 200000; ++k) {
        s.advance();
        const auto n = s.observe().contact_count;
        touched = touched || n > 0;
        if (touched && n == 0)
            break;
    }
    EXPECT_TRUE(touched);
    const double v0 = test::com(m, s.state(), 0, s.state().v)[1];
    return wall ? v0 : (v0 - test::com(m, s.state(), 1, s.state().v)[1]) / 2;
}

TEST(SurfaceContact, DiscOnAWallConvergesToTheElastodynamicReference) {
    // Reference (issue 26): linear plane-stress finite elements of the disc on a frictionless
    // rigid wall, graded mesh, converged to 0.2 %: t_c = 46.53 us, F_max = 259.1 N/m at 1 m/s.
    // Measured (gmsh disc, surface correction on, auto stiffness c = kappa / h^2, 0.85 x the
    // automatic step): t_c +38.4 / +20.3 %, F_max -16.7 / -9.7 % at h = 0.1 / 0.05 mm. Of the
    // +20 %, ~13 points are the penalty's compliance: an infinitely stiff penalty
    // (stiffness_factor 100) leaves +7.3 %, the PD disc's own (without the surface correction
    // +26.6 %). h = 0.025 mm, the other speeds, two discs, 3D: workflows/accuracy/SURFACE_LAW.md
    // (hertz_surface.py). The bounds are the measured figures plus ~1 point (the node law's
    // default: +255 % at h = 0.1 mm).
    const double tc = 46.53e-6, fmax = 259.1;
    const double bound_t[2] = {0.40, 0.215}, bound_f[2] = {0.18, 0.11};
    double prev_t = 1e9, prev_f = 1e9;
    int level = 0;
    for (double h : {1e-4, 5e-5}) {
        const auto r = disc_on_wall(h, 1.0);
        const double et = r.duration / tc - 1, ef = r.peak / fmax - 1;
        std::printf("[ disc on wall ] h = %.3g mm: t_c %+.1f %%, F_max %+.1f %%\n", h * 1e3,
                    100 * et, 100 * ef);
        EXPECT_EQ(r.beyond, 0) << "a node went h/2 through the wall";
        EXPECT_GT(et, 0) << "the PD disc and the penalty are softer than the reference";
        EXPECT_LT(ef, 0);
        EXPECT_LT(std::abs(et), prev_t) << "t_c does not converge";
        EXPECT_LT(std::abs(ef), prev_f) << "F_max does not converge";
        EXPECT_LT(std::abs(et), bound_t[level]) << "h = " << h;
        EXPECT_LT(std::abs(ef), bound_f[level]) << "h = " << h;
        prev_t = std::abs(et);
        prev_f = std::abs(ef);
        ++level;
    }
}

TEST(SurfaceContact, RestitutionAtTheCoarseLevel) {
    // Issue 26 item 4 at h = 0.1 mm, gmsh discs at 1 m/s. Measured: two discs -0.60 / -0.43 /
    // -0.78 / -0.98 %, on a wall -0.09 / -0.17 / -0.21 / -0.23 % at eps = 0.5 / 0.8 / 0.95 / 1;
    // finer meshes lose more to the grains' vibration (h = 0.025 mm: to -1.9 %, R on R/2 to
    // -3.0 %; hertz_surface.py --restitution, workflows/accuracy/SURFACE_LAW.md).
    for (double eps : {0.5, 0.8, 0.95, 1.0})
        for (bool wall : {false, true}) {
            const double e = surface_restitution(1e-4, eps, wall);
            std::printf("[ restitution ] %s eps %.2f: %.4f (%+.2f %%)\n",
                        wall ? "disc on wall" : "two discs", eps, e, 100 * (e / eps - 1));
            EXPECT_NEAR(e, eps, 0.015 * eps) << (wall ? "wall" : "two discs");
        }
}

TEST(SurfaceContact, ShatteringDiscsKeepTheirEnergy) {
    // Two brittle LPS discs at 10 m/s break into single nodes (every bond within 0.27 ms): the
    // facets of a broken grain stop pushing once a node lost half its bonds, and a node deeper
    // than h/2 behind a facet that still stands (in a crack) is let go with no jump in energy.
    // Before both rules the energy rose 2400 x, then 15 x.
    auto m = pipeline::build_scene(R"({"dimension": 2,
      "materials": {"m": {"law": "lps", "poisson_ratio": 0.25, "density": 1200,
                          "youngs_modulus": 3.24e7, "fracture_energy": 0.05}},
      "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
      "particles": [{"radius": 1e-3, "center": [-1.1e-3, 0], "material": "m", "velocity": [5, 0]},
                    {"radius": 1e-3, "center": [1.1e-3, 0], "material": "m", "velocity": [-5, 0],
                     "orientation": 1.0}],
      "contact": {"law": "surface"}, "solver": {"final_time": 1e-3}})",
                                   "t", quiet);
    solver::Solver s(m);
    s.set_dt(0.5 * s.stable_dt().limit);
    s.initialize();
    const double k0 = s.observe().kinetic_energy;
    double worst = 0;
    std::int64_t touched = 0;
    while (s.state().time < 3e-4) {
        s.advance();
        const auto o = s.observe();
        touched = std::max(touched, o.contact_count);
        worst = std::max(
            worst,
            (o.kinetic_energy + o.elastic_energy + o.contact_energy + o.fracture_energy) / k0 - 1);
    }
    EXPECT_GT(touched, 0);
    EXPECT_GT(s.observe().broken_bonds, 3000);
    EXPECT_LT(worst, 0.02);
}

TEST(SurfaceContact, PackSettlesStablyAtTheAutomaticStep) {
    // 36 circles and hexagons settle in a box with friction at 0.85 x the automatic step. In a
    // pack grains meet in threes: a node there is inside, and a facet node for, two other
    // bodies, so the stability bound counts 4 dim c / rho. With 4 c / rho a box like this blew
    // up at a triple junction (a node flung at 8.9 m/s, the balance 16 % off).
    auto m = pipeline::build_scene(R"({"dimension": 2,
      "materials": {"m": {"law": "pmb", "density": 1200, "youngs_modulus": 3.24e7}},
      "discretization": {"mesh_size": 2.5e-4, "horizon_factor": 3},
      "shapes": {"hex": {"type": "hexagon", "radius": 1e-3},
                 "disc": {"type": "circle", "radius": 1e-3}},
      "particles": [{"generate": "random_pack",
        "container": {"type": "rectangle", "corners": [[0, 0], [0.012, 0.016]]},
        "count": 36, "radius": [0.8e-3, 1.0e-3], "shapes": {"disc": 0.5, "hex": 0.5},
        "gap": 1e-4, "seed": 3, "material": "m"}],
      "walls": [{"type": "plane", "point": [0, 0], "normal": [0, 1]},
                {"type": "plane", "point": [0, 0], "normal": [1, 0]},
                {"type": "plane", "point": [0.012, 0], "normal": [-1, 0]}],
      "contact": {"law": "surface", "restitution": 0.5, "friction": 0.3},
      "loading": {"gravity": [0, -200]}, "solver": {"final_time": 1}})",
                                   "t", quiet);
    solver::Solver s(m);
    s.set_dt(0.85 * s.stable_dt().limit);
    s.initialize();
    double worst = 0, scale = 0, lowest = 0, fastest = 0;
    std::int64_t touching = 0;
    while (s.state().time < 0.02) {
        s.advance();
        const auto o = s.observe();
        scale = std::max(scale, solver::energy_in_play(o));
        worst = std::max(worst, std::abs(solver::energy_balance(o)));
        touching = std::max(touching, o.contact_count);
        const auto& st = s.state();
        for (std::size_t i = 0; i < st.n; ++i) {
            lowest = std::min(lowest, st.x[3 * i + 1]);
            fastest = std::max(fastest, std::hypot(st.v[3 * i], st.v[3 * i + 1]));
        }
        s.end_interval();
    }
    std::printf("[ pack ] balance %.2e of %.3e J, lowest node %.2e m, fastest %.3f m/s, %lld "
                "touching\n",
                worst / scale, scale, lowest, fastest, static_cast<long long>(touching));
    EXPECT_GT(touching, 100);
    EXPECT_LT(worst / scale, 0.01);
    EXPECT_GT(lowest, -0.25 * 2.5e-4); // no node more than h/4 below the floor
    EXPECT_LT(fastest, 5.0);           // twice a free fall from 16 mm at 200 m/s2 (2.5 m/s)
}

/// A 2 mm square block (gmsh mesh, h = 0.25 mm, E = 100 MPa) on a rigid floor under gravity,
/// surface law with `contact`, released `drop` above the floor, at 0.85 x the automatic step.
struct Resting {
    double drift = 0, scale = 0, ke_end = 0, work = 0;
    double reaction = 0; ///< mean over the last 5 ms, over the weight
};
Resting block_on_floor(const std::string& contact, double drop, double t_end) {
    auto m =
        pipeline::build_scene(R"({"dimension": 2,
      "materials": {"m": {"density": 1000, "youngs_modulus": 1e8}},
      "discretization": {"mesh_size": 2.5e-4, "horizon_factor": 3},
      "shapes": {"block": {"type": "square", "radius": 1.4142135623730951e-3}},
      "particles": [{"shape": "block", "center": [0, )" +
                                  fmt::format("{:.12g}", 1e-3 + drop) + R"(], "material": "m"}],
      "walls": [{"type": "plane", "point": [0, 0], "normal": [0, 1]}],
      "contact": )" + contact + R"(, "loading": {"gravity": [0, -10]},
      "solver": {"final_time": 1}})",
                              "t", quiet);
    solver::Solver s(m);
    s.set_dt(0.85 * s.stable_dt().limit);
    s.initialize();
    Resting r;
    const double b0 = solver::energy_balance(s.observe()), weight = 10 * 1000 * 4e-6;
    double sum = 0;
    int count = 0;
    while (s.state().time < t_end) {
        s.advance();
        const auto o = s.observe();
        s.end_interval();
        r.scale = std::max(r.scale, solver::energy_in_play(o));
        r.drift = std::max(r.drift, std::abs(solver::energy_balance(o) - b0));
        if (s.state().time > t_end - 5e-3) {
            sum += o.wall_force[1];
            ++count;
        }
        r.ke_end = o.kinetic_energy;
        r.work = o.external_work;
    }
    r.reaction = -sum / count / weight;
    return r;
}

TEST(SurfaceContact, BlockSetDownOnAFloorStaysAtRest) {
    // Set down 1 nm above the floor, no damping: the bottom nodes cross the floor at every
    // vibration. With a penalty whose stiffness jumps from 0 to c there, velocity Verlet made an
    // energy error at each crossing and they added up: the block blew up after 2.3 ms (3.5e-10 J
    // of kinetic energy from 1.6e-12 J of gravity's work). With the C1 onset
    // (surface_penalty.hpp) the balance holds; the block sinks into the onset (16 nm) and,
    // undamped, rings with what gravity gave it.
    const auto r = block_on_floor(R"({"law": "surface"})", 1e-9, 0.01);
    std::printf("[ block at rest ] drift %.2e J, kinetic energy %.2e J, gravity's work %.2e J, "
                "reaction / weight %.4f\n",
                r.drift, r.ke_end, r.work, r.reaction);
    EXPECT_LT(r.drift, 1e-11);
    EXPECT_LT(r.ke_end, r.work);
    EXPECT_NEAR(r.reaction, 1.0, 0.05);
}

TEST(SurfaceContact, DroppedBlockComesToRestWithTheBalanceClosed) {
    // Dropped 0.25 mm with restitution 0.3 (1e-5 J of drop energy): without the onset the
    // resting contact pumped energy into the block's vibration, 3.4e-5 J in 35 ms, and it never
    // came to rest (grain-level damping cannot reach vibration). Now the balance closes and the
    // vibration dies out.
    const auto r = block_on_floor(R"({"law": "surface", "restitution": 0.3})", 0.25e-3, 0.035);
    std::printf("[ block dropped ] drift %.2e of %.2e J, kinetic energy %.2e J, reaction / weight "
                "%.4f\n",
                r.drift, r.scale, r.ke_end, r.reaction);
    EXPECT_LT(r.drift, 0.02 * r.scale);
    EXPECT_LT(r.ke_end, 1e-3 * r.scale);
    EXPECT_NEAR(r.reaction, 1.0, 0.02);
}

TEST(WallWork, MovingWallWorkIsExactAtFirstContact) {
    // A rigid plate at 10 m/s onto a square grain at rest (no gravity, no damping): the work the
    // plate does equals the energy it puts in (kinetic + elastic + contact). The trapezoid of
    // F . v_wall counted 4.1 x (node law) and 1.8 x (surface law) the energy at the first contact
    // step, and pd-solve stopped there (energy guard, 5 %); first contacts are now counted as the
    // spring energy the wall's motion stored (WallLoad::work). Measured, node law at 0.5 / 0.85 x
    // the limit: within 0.65 / 1.85 % from the first contact step on. The surface law's stiffer
    // spring leaves Velocity Verlet's synchronous kinetic energy dt^2 F^2 / (8 m) at the first
    // contact step (11 / 27 % of the contact energy); it telescopes: 0.41 / 2.45 % ten steps on.
    // The plate's 10 m/s (Mach 0.06 of the grain) raises the surface law's stiffness to 1.2 x
    // kappa / h^2 (pipeline/scene/contact_speed.cpp): 0.55 / 3.05 % ten steps on.
    for (const char* law : {"node", "surface"})
        for (double safety : {0.5, 0.85}) {
            auto m = pipeline::build_scene(std::string(R"({"dimension": 2,
              "materials": {"m": {"density": 1200, "youngs_modulus": 3.24e7}},
              "discretization": {"mesh_size": 1e-4, "horizon_factor": 3},
              "shapes": {"sq": {"type": "rectangle", "corners": [[-5e-4, -5e-4], [5e-4, 5e-4]],
                                "mesh": "grid"}},
              "particles": [{"shape": "sq", "center": [0, 0], "material": "m"}],
              "walls": [{"type": "plane", "point": [0, 7e-4], "normal": [0, -1],
                         "velocity": [0, -10]}],
              "contact": {"law": ")") + law + R"("}, "solver": {"final_time": 1}})",
                                           "t", quiet);
            solver::Solver s(m);
            s.set_dt(safety * s.stable_dt().limit);
            s.initialize();
            const bool node = std::string(law) == "node";
            int after = 0;
            double worst = 0;
            while (after < 60) {
                s.advance();
                const auto o = s.observe();
                if (o.contact_count == 0 && after == 0)
                    continue;
                ++after;
                const double e = o.kinetic_energy + o.elastic_energy + o.contact_energy;
                if (node || after > 10)
                    worst = std::max(worst, std::abs(e - o.external_work) / std::max(e, 1e-300));
            }
            std::printf("[ plate ] %s law, dt %.2f x limit: |E - W| / E at most %.4f\n", law,
                        safety, worst);
            EXPECT_LT(worst, node ? 0.025 : 0.035) << law << " " << safety;
        }
}

} // namespace

TEST(SurfaceContact, ADepthThatJumpsIsLeftAlone) {
    // A node's depth behind a boundary grows by at most its motion relative to the facet; one
    // that jumps did not come through it (a facet torn under it, a corner that rearranged) and
    // gets no force: the oedometer's cuboid corner had created 1e-5 J in one step that way. Here
    // b, pressed 0.02 h into a, is moved 0.4 h deeper at rest between two steps: the pairs are
    // left alone (no energy appears), while the same blocks set up 0.42 h deep from the start
    // hold the energy of that depth (the rule, not the geometry, drops the force).
    const double h = 2e-4;
    auto m = test::pressed_blocks(0.02 * h);
    solver::Solver s(m);
    s.initialize();
    const double e0 = s.observe().contact_energy;
    test::shift_b(m, s.state(), -0.4 * h);
    s.advance();
    const double jumped = s.observe().contact_energy;
    auto deep = test::pressed_blocks(0.42 * h);
    solver::Solver s2(deep);
    s2.initialize();
    const double held = s2.observe().contact_energy;
    std::printf("[ depth jump ] energy at 0.02 h %.3e J; moved to 0.42 h at once %.3e J; set up "
                "at 0.42 h %.3e J\n",
                e0, jumped, held);
    EXPECT_GT(e0, 0.0);
    EXPECT_GT(held, 100 * e0);
    EXPECT_LT(jumped, 2 * e0);
}

TEST(SurfaceContact, AJumpedPairIsHeldUntilTheNodeIsOutside) {
    // A pair left alone after a jump stays so while its node is inside that body: the jump
    // allowance grows with the speeds, and a held node let back in where it next fits (at the
    // depth it then has) got the energy of that depth from nothing. In examples/oedometer_3d
    // such re-entries (7-11 um, 1e-7 J each) were the balance's drift once grains chipped:
    // 4.06 % at 13.8 ms, 0.05 % held. Here b jumps 0.4 h into a (held), then moves up at
    // v with 4 v dt = 0.5 h and 0.15 h back at once (0.14 h deep after the step): without the hold
    // the pairs took that depth (78 x the energy at the 0.02 h start); held, none. Set outside and
    // then 0.01 h in, b is pushed again (the hold ends where the node is found outside).
    const double h = 2e-4;
    auto m = test::pressed_blocks(0.02 * h);
    solver::Solver s(m);
    s.set_dt(0.5 * s.stable_dt().limit);
    s.initialize();
    const double e0 = s.observe().contact_energy;
    test::shift_b(m, s.state(), -0.4 * h);
    s.advance();
    const double jumped = s.observe().contact_energy;
    auto& st = s.state();
    const double v = 0.125 * h / s.dt();
    for (auto i = m.bodies.begin(1); i < m.bodies.end(1); ++i)
        st.v[3 * static_cast<std::size_t>(i) + 1] = v;
    test::shift_b(m, st, 0.15 * h);
    s.advance();
    const double back = s.observe().contact_energy;
    for (auto i = m.bodies.begin(1); i < m.bodies.end(1); ++i)
        st.v[3 * static_cast<std::size_t>(i) + 1] = 0;
    // Where is b now? Its lowest node's depth below a's top (y = 0).
    double lowest = 1;
    for (auto i = m.bodies.begin(1); i < m.bodies.end(1); ++i)
        lowest = std::min(lowest, st.x[3 * static_cast<std::size_t>(i) + 1]);
    test::shift_b(m, st, -lowest + 0.1 * h); // 0.1 h above a: outside
    s.advance();
    const double outside = s.observe().contact_energy;
    test::shift_b(m, st, -0.11 * h); // 0.01 h in: within the onset's allowance
    s.advance();
    const double again = s.observe().contact_energy;
    std::printf("[ held ] energy at 0.02 h %.3e J; jumped %.3e J; back to %.2f h deep, fast, "
                "%.3e J; outside %.3e J; 0.01 h in again %.3e J\n",
                e0, jumped, -lowest / h, back, outside, again);
    EXPECT_LT(jumped, 2 * e0);
    EXPECT_GT(-lowest, 0.1 * h); // b was still well inside a when it moved back
    EXPECT_LT(back, 2 * e0);
    EXPECT_EQ(outside, 0.0);
    EXPECT_GT(again, 0.0);
}

TEST(SurfaceContact, ARestartKeepsTheDepthHistory) {
    // The depth rule reads the last evaluation's depths: a restart continues from the
    // checkpoint's (pd-solve --restart, /checkpoints/*/surface_depths). The same jump as above,
    // made after a restart from the state and history of a run, is left alone as in that run;
    // a restart without the history takes the jumped depth (0.58 J). Without it the oedometer's
    // full run, restarted at 16 ms, gained 38 % of its energy within 4 steps.
    const double h = 2e-4;
    auto m = test::pressed_blocks(0.02 * h);
    solver::Solver a(m);
    a.initialize();
    const double e0 = a.observe().contact_energy;
    std::vector<std::int64_t> pairs;
    std::vector<double> depths;
    double time = -1;
    a.surface_depths(pairs, depths, time);
    ASSERT_GE(time, 0.0);
    ASSERT_FALSE(depths.empty());
    std::vector<std::uint8_t> alive;
    a.alive_into(alive);
    auto jump_after_restart = [&](bool history) {
        solver::Solver b(m);
        const auto& st = a.state();
        b.restore(st.step, st.time, st.u, st.v, st.f, alive, a.broken_total());
        if (history)
            b.set_surface_depths(pairs, depths, time);
        test::shift_b(m, b.state(), -0.4 * h);
        b.advance();
        return b.observe().contact_energy;
    };
    const double kept = jump_after_restart(true), lost = jump_after_restart(false);
    std::printf("[ restart ] energy at 0.02 h %.3e J; jumped 0.4 h after a restart with the "
                "history %.3e J, without %.3e J\n",
                e0, kept, lost);
    EXPECT_LT(kept, 2 * e0);
    EXPECT_GT(lost, 100 * e0); // the case the history is for
}

TEST(SurfaceContact, UnloadingDampingHoldsAPressedStack) {
    // Grain-level damping (restitution < 1) reduces the contact force by 1 - eps^2 while the
    // grains' centres separate. Pressed grains separate at a vibration's speed under a large
    // static force: uncapped, the reduction reversed that speed within a step, switched on and
    // off with its sign, and did negative work booked as dissipation (a 2D box of 78 grains
    // pressed by a plate gained 0.39 J in 20 ms). Capped at half of what stops the separation
    // within the step (contact_damping.cpp), b set onto a fixed a under 2000 g holds: the balance
    // within 2 % of gravity's work, and the damping dissipates less than that work (all there
    // is). Measured: 3.2e-7 J of 6.3e-5 J; uncapped 6.3e-4 J created, 6.6e-4 J "dissipated".
    auto m = test::pressed_blocks(0);
    for (auto& p : m.contact)
        p.restitution = 0.5;
    m.loading.gravity = {0, -2e4, 0};
    m.bodies.fixed[0] = 1; // a is a fixed floor
    solver::Solver s(m);
    s.set_dt(0.85 * s.stable_dt().limit);
    s.initialize();
    const auto o0 = s.observe();
    double worst = 0;
    const auto steps = static_cast<int>(5e-3 / s.dt());
    for (int k = 0; k < steps; ++k) {
        s.advance();
        const auto o = s.observe();
        worst = std::max(worst, std::abs(solver::energy_balance(o) - solver::energy_balance(o0)));
    }
    const auto o = s.observe();
    std::printf("[ pressed stack ] balance drift %.3e J of %.3e J of work, damping %.3e J\n", worst,
                o.external_work, o.damping_dissipation);
    EXPECT_GT(o.damping_dissipation, 0.0);
    EXPECT_LT(o.damping_dissipation, o.external_work);
    EXPECT_LT(worst, 0.02 * o.external_work);
}

TEST(SurfaceContact, FacetSkipKeepsEveryForceWithinTheMeshSize) {
    // Each evaluation skips a facet whose vertices' sphere (centroid, radius r) is farther than
    // r + h from a node (surface_contact.cpp, facet_spheres): the law has no force beyond h.
    // Two blocks pressed 0.9 h into each other put nodes in the potential's tail (h/2 < d < h)
    // and nodes just inside: the contact energy must be that of each node's exact distance from
    // the other (axis-aligned) block's nearest side. A skip of reach r (no h) was tried: 1e-30 J
    // against 3.08e-2 J (every force dropped). The skip changes no force: the run of 3D spheres
    // poured to 14 ms (42 contacts) and a 2D box of 78 grains (30 ms) are bitwise the same.
    auto m = test::pressed_blocks(0); // b's bottom side at y = 0, then down to -depth: into a
    // h: each body's mesh size as the law takes it (measured on its mesh, not the nominal 0.2 mm)
    const double ha = m.bodies.mesh_size[0], hb = m.bodies.mesh_size[1];
    const double depth = 0.9 * std::min(ha, hb);
    for (auto i = m.bodies.begin(1); i < m.bodies.end(1); ++i)
        m.nodes.x0[3 * static_cast<std::size_t>(i) + 1] -= depth;
    const double c = m.contact.at(0).stiffness, yb = -depth;
    const double d0 = solver::onset_share * m.contact.at(0).radius;
    solver::Solver s(m);
    s.initialize();
    const auto& st = s.state();
    // Exact: a node strictly inside the other block, at distance d from its nearest side.
    struct Block {
        double x0, x1, y0, y1;
    } blocks[2] = {{-2e-3, 2e-3, -1e-3, 0}, {-1e-3, 1e-3, yb, yb + 1e-3}};
    double energy = 0;
    std::int64_t tail = 0;
    for (std::size_t b = 0; b < 2; ++b) {
        const auto& o = blocks[1 - b];
        const double h = b == 0 ? hb : ha; // the other body's, whose facets push
        for (auto i = m.bodies.begin(b); i < m.bodies.end(b); ++i) {
            const auto k = static_cast<std::size_t>(i);
            const double x = st.x[3 * k], y = st.x[3 * k + 1];
            const double d = std::min({x - o.x0, o.x1 - x, y - o.y0, o.y1 - y});
            if (!(d > 1e-9 * h && d < h))
                continue;
            const double d1 = 0.5 * h;
            const double u1 = solver::surface_penalty(c, std::min(d, d1), d0).energy;
            energy += st.vol[k] * (d <= d1 ? u1 : u1 * (h - d) * (h - d) / ((h - d1) * (h - d1)));
            tail += d > d1;
        }
    }
    ASSERT_GT(tail, 0) << "no node in the potential's tail: the test does not reach the skip";
    const double got = s.observe().contact_energy;
    std::printf("[ facet skip ] %lld node(s) in the tail, contact energy %.6e J (exact %.6e)\n",
                static_cast<long long>(tail), got, energy);
    EXPECT_NEAR(got, energy, 1e-9 * energy);
}

TEST(SurfaceContact, RowSkipWakesUpBeforeTheGrainsMeet) {
    // A row (a node near another grain) is skipped while its slack at the last rebuild (its
    // distance from every listed facet's sphere, less r + h) exceeds 4x the farthest any node
    // moved since (surface_row). With a skin of 20 h no rebuild happens while a block falls 3 h
    // onto another: the rows must wake up in time, so the blocks touch and nothing goes h/2 in.
    // Tried on purpose with 0x the motion: no contact at all, the block passes 0.3 h in.
    auto m = pipeline::build_scene(R"({"dimension": 2,
      "materials": {"m": {"density": 1200, "youngs_modulus": 3.24e7}},
      "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
      "shapes": {"a": {"type": "rectangle", "corners": [[-2e-3, -1e-3], [2e-3, 0]]},
                 "b": {"type": "rectangle", "corners": [[-1e-3, 0], [1e-3, 1e-3]]}},
      "particles": [{"shape": "a", "center": [0, 0], "material": "m", "fixed": true},
                    {"shape": "b", "center": [0, 6e-4], "material": "m", "velocity": [0, -2]}],
      "contact": {"law": "surface"}, "solver": {"final_time": 1, "contact_skin": 4e-3}})",
                                   "t", quiet);
    solver::Solver s(m);
    s.set_dt(0.85 * s.stable_dt().limit);
    s.initialize();
    std::int64_t touching = 0, deep = 0;
    double lowest = 1;
    while (s.state().time < (6e-4 + 0.3 * m.bodies.mesh_size[1]) / 2) {
        s.advance();
        const auto o = s.observe();
        touching = std::max(touching, o.contact_count);
        deep += o.inside_pairs;
        for (auto i = m.bodies.begin(1); i < m.bodies.end(1); ++i)
            lowest = std::min(lowest, s.state().x[3 * static_cast<std::size_t>(i) + 1]);
    }
    std::printf("[ row skip ] %lld touching, lowest node of b %.3g h below a's top, %lld "
                "rebuild(s)\n",
                static_cast<long long>(touching), -lowest / m.bodies.mesh_size[0],
                static_cast<long long>(s.contact().rebuilds()));
    EXPECT_GT(touching, 0);
    EXPECT_EQ(deep, 0);
    EXPECT_GT(lowest, -0.5 * m.bodies.mesh_size[0]);
}
