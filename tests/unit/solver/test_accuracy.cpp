// SPDX-License-Identifier: MIT
// Accuracy against analytic answers (issue 4): uniaxial stretch of a plate (strain = sigma / E,
// error falling with h at fixed m = delta / h), wave speed sqrt(E / rho) in a bar, a pre-notched
// plate breaking from the notch tip, Coulomb friction on an incline (stick below tan = mu, slide
// above with the analytic acceleration), restitution of a non-circular grain, and a 3D
// two-sphere collision.
#include "body_means.hpp"
#include "core/log.hpp"
#include "pipeline/scene.hpp"
#include "solver/solver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <ctime>
#include <numeric>

namespace {

using namespace pd;

const Log quiet("test", 0, Verbosity::quiet);

using test::com;

/// Relative error of the interior strain of a plate L x W under uniaxial stress sigma, pulled by
/// a force density on its right band and held on its left band, relaxed to equilibrium.
double plate_strain_error(double h) {
    const double L = 8e-3, W = 4e-3, E = 1e9, rho = 1000, sigma = 1e5;
    const double delta = 3 * h;
    const std::string sc =
        fmt::format(R"({{"dimension": 2,
      "materials": {{"m": {{"density": {}, "youngs_modulus": {}}}}},
      "discretization": {{"mesh_size": {}, "horizon_factor": 3}},
      "shapes": {{"plate": {{"type": "rectangle", "size": [{}, {}], "mesh": "grid"}}}},
      "particles": [{{"shape": "plate", "center": [0, 0], "material": "m"}}],
      "loading": {{"viscous_damping": {}, "conditions": [
        {{"kind": "displacement", "region": {{"min": [{}, {}], "max": [{}, {}]}},
          "components": ["x"], "value": 0}},
        {{"kind": "displacement", "region": {{"min": [{}, {}], "max": [{}, {}]}},
          "components": ["y"], "value": 0}},
        {{"kind": "force_density", "region": {{"min": [{}, {}], "max": [{}, {}]}},
          "components": ["x"], "value": 1}}]}},
      "solver": {{"final_time": 1}}}})",
                    rho, E, h, L, W,
                    // critical damping of the fundamental mode
                    2 * M_PI * std::sqrt(E / rho) / (2 * L), -L, -W, -L / 2 + delta + 1e-9, W, -L,
                    -1e-9, -L / 2 + delta + 1e-9, 1e-9, L / 2 - delta - 1e-9, -W, L, W);
    auto m = pipeline::build_scene(sc, "plate", quiet);
    // Force density so that the band carries sigma W (per unit thickness) in total.
    auto& pull = m.loading.conditions[2];
    double band = 0;
    for (auto i : pull.nodes)
        band += m.nodes.volume[static_cast<std::size_t>(i)];
    pull.amplitude = sigma * W / band;
    solver::Solver s(m);
    s.set_dt(0.8 * s.stable_dt().limit);
    s.initialize();
    const int steps = static_cast<int>(40 * 2 * L / std::sqrt(E / rho) / s.dt());
    for (int k = 0; k < steps; ++k)
        s.advance();
    // Least-squares slope of u_x(X) over the interior (two horizons from every edge).
    const auto& st = s.state();
    double sx = 0, su = 0, sxx = 0, sxu = 0;
    int cnt = 0;
    for (std::size_t i = 0; i < st.n; ++i) {
        const double X = st.x0[3 * i], Y = st.x0[3 * i + 1];
        if (std::abs(X) > L / 2 - 2 * delta - 1e-3 || std::abs(Y) > W / 2 - 2 * delta)
            continue;
        sx += X;
        su += st.u[3 * i];
        sxx += X * X;
        sxu += X * st.u[3 * i];
        ++cnt;
    }
    const double slope = (cnt * sxu - sx * su) / (cnt * sxx - sx * sx);
    return slope / (sigma / E) - 1;
}

TEST(Accuracy, UniaxialStretchOfAPlate) {
    // Interior strain of a 2D PMB plate relaxed under uniaxial stress, at fixed m = 3. With the
    // constants calibrated on the quadrature (model/quadrature.hpp) the bulk is exact and what is
    // left is the softer surface layer of width ~delta, O(h): the error falls at first order and
    // extrapolates to ~0. Measured 0.0496 / 0.0236 (order 1.07, limit -0.2 %). Without the
    // calibration: 0.0045 / -0.0204, limit -4.5 % (the discrete bulk 4.5 % too stiff; the small
    // coarse error was that bulk error cancelling the surface's), which these checks refuse.
    const double e1 = plate_strain_error(2e-4), e2 = plate_strain_error(1e-4);
    const double order = std::log(std::abs(e1) / std::abs(e2)) / std::log(2.0);
    std::printf("[ plate ] relative strain error h=0.2mm %.4f, h=0.1mm %.4f, order %.2f, "
                "extrapolated %.4f\n",
                e1, e2, order, 2 * e2 - e1);
    EXPECT_LT(std::abs(e2), std::abs(e1));
    EXPECT_GT(order, 0.8);
    EXPECT_LT(std::abs(2 * e2 - e1), 0.01); // Richardson limit (order 1): the bulk error
}

TEST(Accuracy, WaveSpeedInABar) {
    const double L = 40e-3, W = 2e-3, E = 1e9, rho = 1000, v0 = 0.1, h = 1e-4;
    const double c0 = std::sqrt(E / rho);
    const std::string sc = fmt::format(R"({{"dimension": 2,
      "materials": {{"m": {{"density": {}, "youngs_modulus": {}}}}},
      "discretization": {{"mesh_size": {}, "horizon_factor": 3}},
      "shapes": {{"bar": {{"type": "rectangle", "size": [{}, {}], "mesh": "grid"}}}},
      "particles": [{{"shape": "bar", "center": [{}, 0], "material": "m"}}],
      "loading": {{"conditions": [
        {{"kind": "displacement", "region": {{"min": [-1, -1], "max": [{}, 1]}},
          "components": ["x"], "value": {}, "time_function": "linear"}}]}},
      "solver": {{"final_time": 1}}}})",
                                       rho, E, h, L, W, L / 2, 3 * h, v0);
    auto m = pipeline::build_scene(sc, "bar", quiet);
    solver::Solver s(m);
    s.set_dt(0.5 * s.stable_dt().limit);
    s.initialize();
    // Two stations on the axis; arrival = the axial velocity first exceeding v0 / 2.
    const double xs[2] = {12e-3, 28e-3};
    std::size_t node[2] = {0, 0};
    for (int k = 0; k < 2; ++k)
        for (std::size_t i = 0; i < s.state().n; ++i)
            if (std::hypot(s.state().x0[3 * i] - xs[k], s.state().x0[3 * i + 1]) <
                std::hypot(s.state().x0[3 * node[k]] - xs[k], s.state().x0[3 * node[k] + 1]))
                node[k] = i;
    double arrive[2] = {-1, -1};
    double prev[2] = {0, 0}, tprev = 0;
    while (arrive[1] < 0 && s.state().time < 2 * L / c0) {
        s.advance();
        for (int k = 0; k < 2; ++k) {
            const double v = s.state().v[3 * node[k]];
            if (arrive[k] < 0 && v > 0.5 * v0) // linear interpolation of the crossing
                arrive[k] = tprev + (s.state().time - tprev) * (0.5 * v0 - prev[k]) / (v - prev[k]);
            prev[k] = v;
        }
        tprev = s.state().time;
    }
    ASSERT_GT(arrive[1], 0);
    const double dx = s.state().x0[3 * node[1]] - s.state().x0[3 * node[0]];
    const double c = dx / (arrive[1] - arrive[0]);
    std::printf("[ wave ] measured %.2f m/s, sqrt(E/rho) %.2f m/s, error %.4f\n", c, c0,
                c / c0 - 1);
    // Measured -3.3 % (calibrated constants; the bar's surface layer is delta / W = 15 % of its
    // width at h = 0.1 mm, and a step front travels a strip of finite width a little off the bar
    // speed). Convergence with h: workflows/accuracy (the `accuracy.quick` ctest).
    EXPECT_NEAR(c / c0, 1.0, 0.045);
}

TEST(Accuracy, NotchedPlateBreaksFromTheTip) {
    const double L = 10e-3, W = 10e-3, h = 2e-4, delta = 3 * h;
    const double tip_x = 0;
    const std::string sc = fmt::format(R"({{"dimension": 2,
      "materials": {{"m": {{"density": 2440, "youngs_modulus": 72e9, "fracture_energy": 3.8}}}},
      "discretization": {{"mesh_size": {}, "horizon_factor": 3}},
      "shapes": {{"plate": {{"type": "rectangle", "size": [{}, {}], "mesh": "grid"}}}},
      "particles": [{{"shape": "plate", "center": [0, 0], "material": "m"}}],
      "cracks": [{{"from": [{}, 0.5e-5], "to": [{}, 0.5e-5]}}],
      "loading": {{"conditions": [
        {{"kind": "displacement", "region": {{"min": [-1, {}], "max": [1, 1]}},
          "components": ["y"], "value": 0.2, "time_function": "linear"}},
        {{"kind": "displacement", "region": {{"min": [-1, -1], "max": [1, {}]}},
          "components": ["y"], "value": -0.2, "time_function": "linear"}}]}},
      "solver": {{"final_time": 1}}}})",
                                       h, L, W, -L, tip_x, W / 2 - delta, -W / 2 + delta);
    auto m = pipeline::build_scene(sc, "notch", quiet);
    solver::Solver s(m);
    s.set_dt(0.8 * s.stable_dt().limit);
    s.initialize();
    const auto pre = s.broken_total();
    ASSERT_GT(pre, 0);
    // Phi is zero away from the crack before loading breaks anything new.
    std::vector<double> phi;
    for (int k = 0; k < 200000 && s.broken_total() == pre; ++k)
        s.advance();
    ASSERT_GT(s.broken_total(), pre) << "no new bond broke";
    // Every bond broken by the loading so far has an end within two horizons of the tip.
    const auto& b = s.bonds();
    const auto& st = s.state();
    int fresh = 0;
    double far = 0;
    for (std::size_t i = 0; i < st.n; ++i)
        for (auto k = b.offsets[i]; k < b.offsets[i + 1]; ++k) {
            const auto j = static_cast<std::size_t>(b.neighbor[static_cast<std::size_t>(k)]);
            const double xi = st.x0[3 * i], yi = st.x0[3 * i + 1];
            const double xj = st.x0[3 * j], yj = st.x0[3 * j + 1];
            const double yc = 0.5e-5;
            const bool crosses =
                (yi - yc) * (yj - yc) < 0 && xi + (xj - xi) * (yc - yi) / (yj - yi) <= tip_x;
            if (b.alive[static_cast<std::size_t>(k)] || crosses)
                continue;
            ++fresh;
            far = std::max(far, std::hypot(xi - tip_x, yi));
        }
    EXPECT_GT(fresh, 0);
    EXPECT_LT(far, 2 * delta);
}

/// A square block on a rigid floor with gravity tilted by `angle`: the block's downhill
/// displacement and velocity change between t1 and t2 (after landing).
std::pair<double, double> incline_slide(double angle, double mu, double t1, double t2,
                                        const char* law = "node") {
    const std::string sc = fmt::format(R"({{"dimension": 2,
      "materials": {{"m": {{"density": 1000, "youngs_modulus": 1e8}}}},
      "discretization": {{"mesh_size": 2.5e-4, "horizon_factor": 3}},
      "shapes": {{"block": {{"type": "square", "radius": 1.4142135623730951e-3}}}},
      "particles": [{{"shape": "block", "center": [0, 1.25e-3], "material": "m"}}],
      "walls": [{{"type": "plane", "point": [0, 0], "normal": [0, 1]}}],
      "contact": {{"law": "{}", "restitution": 0.3, "friction": {}}},
      "loading": {{"gravity": [{}, {}]}},
      "solver": {{"final_time": 1}}}})",
                                       law, mu, 10 * std::sin(angle), -10 * std::cos(angle));
    auto m = pipeline::build_scene(sc, "incline", quiet);
    solver::Solver s(m);
    s.set_dt(0.7 * s.stable_dt().limit);
    s.initialize();
    double x1 = 0, v1 = 0;
    bool marked = false;
    while (s.state().time < t2) {
        s.advance();
        if (!marked && s.state().time >= t1) {
            x1 = com(m, s.state(), 0, s.state().x)[0];
            v1 = com(m, s.state(), 0, s.state().v)[0];
            marked = true;
        }
    }
    return {com(m, s.state(), 0, s.state().x)[0] - x1, com(m, s.state(), 0, s.state().v)[0] - v1};
}

/// The block sticks at tan = 0.3 and slides at tan = 0.8 with g (sin - mu cos), mu = 0.5.
void check_incline(const char* law) {
    const double mu = 0.5, t1 = 0.02, t2 = 0.04;
    const auto stick = incline_slide(std::atan(0.3), mu, t1, t2, law);
    const double th = std::atan(0.8);
    const auto slide = incline_slide(th, mu, t1, t2, law);
    const double a = 10 * (std::sin(th) - mu * std::cos(th)); // sliding: g (sin - mu cos)
    const double measured = slide.second / (t2 - t1);
    std::printf("[ incline, %s law ] tan = 0.3: moved %.3e m; tan = 0.8: moved %.3e m, "
                "acceleration %.4f m/s2 (analytic %.4f)\n",
                law, stick.first, slide.first, measured, a);
    EXPECT_NEAR(measured / a, 1.0, 0.05);
    EXPECT_LT(std::abs(stick.first), 0.05 * slide.first); // sticks (creeps < 5 % of sliding)
}

TEST(Accuracy, CoulombFrictionOnAnIncline) {
    check_incline("node");
}

TEST(Accuracy, CoulombFrictionOnAnInclineSurfaceLaw) {
    // Before the surface law's C1 onset (solver/surface_penalty.hpp) the resting contact pumped
    // energy into the block's vibration; it bounced (in contact 8-59 % of the steps) and crept
    // 0.218 mm between 20 and 40 ms, against 0.095 mm allowed.
    check_incline("surface");
}

TEST(Accuracy, HexagonRestitution) {
    for (double eps : {0.5, 0.8, 0.95}) {
        const std::string sc = fmt::format(R"({{"dimension": 2,
          "materials": {{"m": {{"density": 1200, "youngs_modulus": 3.24e7}}}},
          "discretization": {{"mesh_size": 2e-4, "horizon_factor": 3}},
          "shapes": {{"hex": {{"type": "hexagon", "radius": 1e-3}}}},
          "particles": [{{"shape": "hex", "center": [0, 1.2e-3], "material": "m",
                          "velocity": [0, -0.5]}}],
          "walls": [{{"type": "plane", "point": [0, 0], "normal": [0, 1]}}],
          "contact": {{"restitution": {}}},
          "solver": {{"final_time": 1}}}})",
                                           eps);
        auto m = pipeline::build_scene(sc, "hex", quiet);
        solver::Solver s(m);
        s.set_dt(0.7 * s.stable_dt().limit);
        s.initialize();
        bool touched = false;
        for (int k = 0; k < 40000; ++k) {
            s.advance();
            const auto c = s.observe().contact_count;
            touched = touched || c > 0;
            if (touched && c == 0)
                break;
        }
        const double ratio = com(m, s.state(), 0, s.state().v)[1] / 0.5;
        std::printf("[ hexagon ] eps %.2f measured %.4f\n", eps, ratio);
        EXPECT_NEAR(ratio, eps, 0.05 * eps);
    }
}

TEST(Accuracy, TwoSpheresCollide3D) {
    const std::string sc = R"({"dimension": 3,
      "materials": {"m": {"density": 1200, "youngs_modulus": 3.24e7}},
      "discretization": {"mesh_size": 3e-4, "horizon_factor": 3},
      "shapes": {"ball": {"type": "sphere", "radius": 1e-3}},
      "particles": [{"shape": "ball", "center": [-1.2e-3, 0, 0], "material": "m",
                     "velocity": [0.5, 0, 0]},
                    {"shape": "ball", "center": [1.2e-3, 0.2e-3, 0], "material": "m",
                     "velocity": [-0.5, 0, 0], "orientation": 0.4}],
      "solver": {"final_time": 1}})";
    auto m = pipeline::build_scene(sc, "spheres", quiet);
    solver::Solver s(m);
    s.set_dt(0.7 * s.stable_dt().limit);
    s.initialize();
    const auto o0 = s.observe();
    const double p1 = 0.5 * 1200 * 4.0 / 3.0 * M_PI * 1e-9;
    bool touched = false;
    double maxdp = 0, drift = 0;
    for (int k = 0; k < 20000; ++k) {
        s.advance();
        const auto o = s.observe();
        maxdp = std::max(
            {maxdp, std::abs(o.momentum[0]), std::abs(o.momentum[1]), std::abs(o.momentum[2])});
        drift = std::max(drift, std::abs((o.kinetic_energy + o.elastic_energy + o.contact_energy) /
                                             o0.kinetic_energy -
                                         1));
        touched = touched || o.contact_count > 0;
        if (touched && o.contact_count == 0)
            break;
    }
    std::printf("[ spheres ] momentum %.2e (relative), energy drift %.2e\n", maxdp / p1, drift);
    EXPECT_TRUE(touched);
    EXPECT_LT(maxdp / p1, 1e-12);
    EXPECT_LT(drift, 5e-3);
}

} // namespace

namespace {

/// Force transmitted across the mid-section x = 0 of a 3D bar (lx x ly x lz; PMB, or LPS with
/// nu = 1/4) under the affine uniaxial-stress field u = eps (x, -nu y, -nu z), nu = 1/4: the
/// net bond force on the half x < 0 is minus what crosses the section, to compare with
/// sigma A = E eps A.
double bar3d_section_error(double h, bool correction = false, const char* law = "pmb") {
    const double lx = 10e-3, ly = 5e-3, E = 1e9, eps = 1e-4, nu = 0.25;
    const std::string sc = fmt::format(R"({{"dimension": 3,
      "materials": {{"m": {{"law": "{}", "density": 1000, "youngs_modulus": {},
                            "poisson_ratio": 0.25}}}},
      "discretization": {{"mesh_size": {}, "horizon_factor": 3}},
      "shapes": {{"bar": {{"type": "box", "size": [{}, {}, {}], "mesh": "grid"}}}},
      "particles": [{{"shape": "bar", "center": [0, 0, 0], "material": "m"}}],
      "solver": {{"final_time": 1, "surface_correction": {}}}}})",
                                       law, E, h, lx, ly, ly, correction);
    auto m = pipeline::build_scene(sc, "bar3d", quiet);
    solver::Solver s(m);
    auto& st = s.state();
    for (std::size_t i = 0; i < st.n; ++i) {
        st.x[3 * i] = st.x0[3 * i] * (1 + eps);
        st.x[3 * i + 1] = st.x0[3 * i + 1] * (1 - nu * eps);
        st.x[3 * i + 2] = st.x0[3 * i + 2] * (1 - nu * eps);
    }
    s.initialize();
    double F = 0;
    for (std::size_t i = 0; i < st.n; ++i)
        if (st.x0[3 * i] < 0)
            F += st.f[3 * i] * st.vol[i]; // the right half pulls it towards +x
    return F / (E * eps * ly * ly) - 1;
}

TEST(Accuracy, BarSectionForce3D) {
    const double e1 = bar3d_section_error(5e-4), e2 = bar3d_section_error(2.5e-4);
    const double rate = std::log(std::abs(e1) / std::abs(e2)) / std::log(2.0);
    std::printf("[ bar3d ] section force error h=0.5mm %.4f, h=0.25mm %.4f, rate %.2f, "
                "extrapolated %.4f\n",
                e1, e2, rate, 2 * e2 - e1);
    // Calibrated constants (model/quadrature.hpp), bar 10 x 5 x 5 mm: -0.1625 / -0.0844, rate
    // 0.95, first-order extrapolation -0.6 %: the surface layer shrinking towards an exact bulk.
    // (A 4 mm bar has no complete interior family at h = 0.5 mm, reach delta + h/2 = 1.75 mm
    // against 1.75 mm from the centre node to the outer nodes, so that level kept the continuum
    // constants: -0.139 / -0.104, rate 0.41, which the checks below refuse.) Without the
    // calibration the bulk is 7.7 % too stiff and the extrapolated limit far off.
    EXPECT_LT(std::abs(e2), 0.12);
    EXPECT_GT(rate, 0.7);                   // falls at about first order with h at fixed m
    EXPECT_LT(std::abs(2 * e2 - e1), 0.04); // first-order extrapolation: the bulk error
}

TEST(Accuracy, SurfaceCorrectionBarSection3D) {
    // solver.surface_correction (model/surface_correction.hpp) on the same bar and field: the
    // truncated families of the faces, edges and corners get the axis factors of a complete
    // family. Measured +0.0125 / +0.0059 at h = 0.5 / 0.25 mm, against -0.1625 / -0.0844 without
    // (test above); the former isotropic factor gave +9 % at h = 0.25 mm.
    const double e1 = bar3d_section_error(5e-4, true), e2 = bar3d_section_error(2.5e-4, true);
    std::printf("[ bar3d ] surface correction: section force error %.4f, %.4f\n", e1, e2);
    EXPECT_LT(std::abs(e1), 0.025);
    EXPECT_LT(std::abs(e2), 0.012);
    EXPECT_LT(std::abs(e2), std::abs(e1));
    // LPS (nu = 1/4): measured +0.0238 / +0.0118, first order as PMB.
    const double l1 = bar3d_section_error(5e-4, true, "lps");
    const double l2 = bar3d_section_error(2.5e-4, true, "lps");
    std::printf("[ bar3d ] surface correction, LPS: section force error %.4f, %.4f\n", l1, l2);
    EXPECT_LT(std::abs(l1), 0.035);
    EXPECT_LT(std::abs(l2), 0.018);
    EXPECT_LT(std::abs(l2), 0.6 * std::abs(l1));
}

TEST(Accuracy, DISABLED_BarSection3DLevels) {
    // The 3D static rows of workflows/accuracy/RESULTS.md (issue 11): the corrected bar at four
    // levels, PMB and LPS, with process CPU seconds. Not in CI: h = 0.0625 mm is 1.06 M nodes,
    // about 15 GB and 200 CPU s for LPS. Run with --gtest_also_run_disabled_tests.
    for (const char* law : {"pmb", "lps"})
        for (double h : {5e-4, 2.5e-4, 1.25e-4, 6.25e-5}) {
            const std::clock_t c0 = std::clock();
            const double e = bar3d_section_error(h, true, law);
            std::printf("| %s + surface correction | %g | %+.3f %% | %.1f |\n", law, h * 1e3,
                        100 * e, static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
        }
}

} // namespace
