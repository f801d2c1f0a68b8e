// SPDX-License-Identifier: MIT
// The energy balance (issue 10): the LPS force is the exact gradient of its energy also for a
// family that lost bonds; KE + elastic + contact + fracture + damping + friction + viscous -
// external work keeps its t = 0 value when bonds break, contacts damp and rub, and viscous
// relaxation acts; each dissipation term is counted where it happens.
#include "core/log.hpp"
#include "pipeline/scene.hpp"
#include "solver/solver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <utility>

namespace {

using namespace pd;

const Log quiet("test", 0, Verbosity::quiet);

using solver::energy_in_play;

double balance(const solver::Observables& o) {
    return solver::energy_balance(o);
}

double in_play(const solver::Observables& o) {
    return energy_in_play(o);
}

/// Largest |balance - balance(0)| over the run, relative to the largest energy in play.
struct Drift {
    double worst = 0, scale = 0, b0 = 0;
    void start(const solver::Observables& o) {
        b0 = balance(o);
        scale = in_play(o);
    }
    void add(const solver::Observables& o) {
        scale = std::max(scale, in_play(o));
        worst = std::max(worst, std::abs(balance(o) - b0));
    }
    double relative() const { return worst / scale; }
};

// A pre-cracked plate pulled apart at 2 m/s top and bottom (as tests/mpi/scenes.py PLATE).
std::string plate(const std::string& law) {
    return R"({"dimension": 2, "title": "plate",
      "materials": {"m": {"law": ")" +
           law + R"(", "density": 1200, "youngs_modulus": 3.24e7,)" +
           (law == "lps" ? R"( "poisson_ratio": 0.25,)" : "") + R"( "fracture_energy": 5}},
      "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
      "shapes": {"plate": {"type": "rectangle", "corners": [[0, 0], [0.01, 0.005]],
                           "mesh": "grid"}},
      "particles": [{"shape": "plate", "center": [0, 0], "material": "m"}],
      "cracks": [{"from": [-1e-3, 0.00251], "to": [0.004, 0.00251]}],
      "loading": {"conditions": [
        {"name": "top", "kind": "displacement", "region": {"min": [-1, 0.0046], "max": [1, 1]},
         "components": ["y"], "time_function": "linear", "value": 2.0},
        {"name": "bottom", "kind": "displacement", "region": {"min": [-1, -1], "max": [1, 4e-4]},
         "components": ["y"], "time_function": "linear", "value": -2.0}]},
      "solver": {"final_time": 1e-4}})";
}

TEST(Lps, ForceIsTheGradientOfTheEnergyWithBrokenBonds) {
    // A disc with a third of its bonds broken (every bond crossing x > 0.3 R from the left, and
    // random others) and a random small deformation: f_i V_i = -dE/dx_i by central differences.
    // Without the q term (the derivative of the deviatoric energy through theta when m_intact !=
    // m) the damaged nodes' forces are off by several per cent.
    auto m = pipeline::build_scene(R"({"dimension": 2, "title": "t",
      "materials": {"m": {"law": "lps", "density": 1200, "youngs_modulus": 3.24e7,
                          "poisson_ratio": 0.2}},
      "discretization": {"mesh_size": 2.5e-4, "horizon_factor": 3},
      "particles": [{"radius": 1e-3, "center": [0, 0], "material": "m"}],
      "solver": {"final_time": 1e-3}})",
                                   "t", quiet);
    // Unbreakable material: break bonds by hand; the kernel must honour them, so make the law
    // breakable with a huge critical stretch instead.
    m.materials[0].fracture_energy = 1e12;
    solver::Solver s(m);
    auto& st = s.state();
    auto& b = s.bonds();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> U(-1, 1);
    std::size_t broken = 0;
    for (std::size_t i = 0; i < st.n; ++i)
        for (auto k = b.offsets[i]; k < b.offsets[i + 1]; ++k) {
            const auto j = static_cast<std::size_t>(b.neighbor[k]);
            const bool cut = (st.x0[3 * i] < 3e-4) != (st.x0[3 * j] < 3e-4) ||
                             (i * 7919 + j * 7919) % 5 == 0; // symmetric in i, j
            if (cut) {
                b.alive[k] = 0;
                ++broken;
            }
        }
    ASSERT_GT(broken, b.alive.size() / 8);
    for (std::size_t k = 0; k < 3 * st.n; ++k)
        if (k % 3 != 2)
            st.x[k] = st.x0[k] + 2e-6 * U(rng);
    auto energy_and_force = [&] {
        s.initialize();
        return s.observe().elastic_energy;
    };
    energy_and_force();
    const auto f = st.f;
    double fscale = 0;
    for (std::size_t i = 0; i < st.n; ++i)
        fscale = std::max(fscale, std::hypot(f[3 * i], f[3 * i + 1]) * st.vol[i]);
    double worst = 0;
    const double h = 1e-9;
    for (std::size_t i = 0; i < st.n; i += 3)
        for (std::size_t d = 0; d < 2; ++d) {
            const double x = st.x[3 * i + d];
            st.x[3 * i + d] = x + h;
            const double ep = energy_and_force();
            st.x[3 * i + d] = x - h;
            const double em = energy_and_force();
            st.x[3 * i + d] = x;
            const double fd = -(ep - em) / (2 * h);
            worst = std::max(worst, std::abs(fd - f[3 * i + d] * st.vol[i]));
        }
    EXPECT_LT(worst / fscale, 1e-5);
}

TEST(Energy, FractureClosesTheBalance) {
    // The pre-cracked plate, PMB and LPS: ~1500 bonds break in 1e-4 s. Without the fracture
    // term the balance drifts by the fracture energy (4-9 % of the energy in play); counting the
    // released energy at the positions of the breaking step without the half-step work
    // correction leaves 2 %; with it, the drift is the integrator's (measured 0.1-0.2 %).
    for (const char* law : {"pmb", "lps"}) {
        auto sc = plate(law);
        if (std::string(law) == "pmb") { // the bond-based law fixes nu = 1/3
            const auto p = sc.find(R"( "poisson_ratio": 0.25,)");
            if (p != std::string::npos)
                sc.erase(p, 22);
        }
        auto m = pipeline::build_scene(sc, "t", quiet);
        solver::Solver s(m);
        s.set_dt(0.7 * s.stable_dt().limit);
        s.initialize();
        Drift drift;
        drift.start(s.observe());
        const auto steps = static_cast<int>(1e-4 / s.dt());
        for (int k = 0; k < steps; ++k) {
            s.advance();
            drift.add(s.observe());
        }
        const auto o = s.observe();
        EXPECT_GT(o.broken_bonds, 1500) << law;
        // The fracture term must be large against the drift bound below, so that the balance
        // cannot close without it: 6x. (It was 5 % of the energy in play at the step of the
        // row-sum estimate; the crack of this plate is irregular in dt: measured at 0.35, 0.5,
        // 0.6, 0.7 x the Lanczos estimate, LPS 4.2, 5.1, 4.1, 4.4 %, PMB 7.6, 6.8, 8.8, 7.5 %.)
        EXPECT_GT(o.fracture_energy, 0.03 * drift.scale) << law;
        EXPECT_LT(drift.relative(), 5e-3) << law;
    }
}

/// Two PMB discs colliding obliquely for 0.6 ms with the given contact and loading, at
/// `safety` x the stability limit; returns the final observables and the balance's drift.
std::pair<solver::Observables, Drift> oblique_discs(const std::string& contact,
                                                    const std::string& loading, double safety) {
    auto m = pipeline::build_scene(R"({"dimension": 2, "title": "t",
      "materials": {"m": {"law": "pmb", "density": 1200, "youngs_modulus": 3.24e7}},
      "discretization": {"mesh_size": 1e-4, "horizon_factor": 3},
      "particles": [
        {"radius": 1e-3, "center": [-1.1e-3, 0], "material": "m", "velocity": [1, 0.3]},
        {"radius": 1e-3, "center": [1.1e-3, 0.6e-3], "material": "m", "velocity": [-1, -0.3]}],
      "contact": )" + contact + R"(, "loading": )" +
                                       loading + R"(,
      "solver": {"final_time": 6e-4}})",
                                   "t", quiet);
    solver::Solver s(m);
    s.set_dt(safety * s.stable_dt().limit);
    s.initialize();
    Drift drift;
    drift.start(s.observe());
    const auto steps = static_cast<int>(6e-4 / s.dt());
    for (int k = 0; k < steps; ++k) {
        s.advance();
        drift.add(s.observe());
    }
    return {s.observe(), drift};
}

TEST(Energy, DampingFrictionAndViscousDissipationAreCounted) {
    // Two discs collide obliquely with restitution 0.5 and friction 0.4, in a viscous medium:
    // every channel takes energy, and the balance closes, at first order in dt: velocity
    // Verlet's kick with a force that depends on the velocity (damping, friction) is first
    // order. Surface law: 0.52 / 0.26 / 0.13 % at 0.7 / 0.35 / 0.175 x the limit (its contact,
    // stiffer than the node law's, lasts fewer steps: the node law drifted < 0.5 % at 0.7).
    const std::string contact = R"({"restitution": 0.5, "friction": 0.4})";
    const auto [o, drift] = oblique_discs(contact, R"({"viscous_damping": 50})", 0.7);
    const double ke0 = drift.scale;
    EXPECT_GT(o.damping_dissipation, 0.05 * ke0);
    EXPECT_GT(o.friction_dissipation, 1e-3 * ke0);
    EXPECT_GT(o.viscous_dissipation, 0.01 * ke0);
    EXPECT_LT(drift.relative(), 6e-3);
    const auto half = oblique_discs(contact, R"({"viscous_damping": 50})", 0.35).second;
    std::printf("[ dissipation ] balance drift %.3g %% at 0.7 x, %.3g %% at 0.35 x the limit\n",
                100 * drift.relative(), 100 * half.relative());
    EXPECT_LT(half.relative(), 0.6 * drift.relative()) << "not first order in dt";
}

TEST(Energy, FrictionAloneIsStableAtTheAutomaticStep) {
    // Friction without any damping at the automatic dt (0.85 x the limit): the stick cap once
    // stopped each pair's slip within one step, a node with several partners overshot, and the
    // balance grew by 5.4 % in 203 steps (pd-solve stopped the run); now 0.21 %.
    const auto [o, drift] = oblique_discs(R"({"restitution": 1.0, "friction": 0.4})", "{}", 0.85);
    EXPECT_GT(o.friction_dissipation, 1e-3 * drift.scale);
    EXPECT_LT(drift.relative(), 5e-3);
}

TEST(Energy, ViscousDissipationEqualsTheKineticEnergyLost) {
    // A free disc in a viscous medium: v(t) = v0 exp(-c t), all of the kinetic energy lost is
    // viscous dissipation.
    auto m = pipeline::build_scene(R"({"dimension": 2, "title": "t",
      "materials": {"m": {"law": "pmb", "density": 1200, "youngs_modulus": 3.24e7}},
      "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
      "particles": [{"radius": 1e-3, "center": [0, 0], "material": "m", "velocity": [1, 2]}],
      "loading": {"viscous_damping": 2000},
      "solver": {"final_time": 1e-3}})",
                                   "t", quiet);
    solver::Solver s(m);
    // The step this test was written for: 0.5 x the old row-sum estimate, which was 0.58 of the
    // sharp estimate of this disc (issue 11); the dissipation's bookkeeping error is O(c dt).
    s.set_dt(0.29 * s.stable_dt().limit);
    s.initialize();
    const auto o0 = s.observe();
    const int steps = static_cast<int>(5e-4 / s.dt());
    for (int k = 0; k < steps; ++k)
        s.advance();
    const auto o = s.observe();
    const double t = s.state().time;
    EXPECT_NEAR(o.kinetic_energy / o0.kinetic_energy, std::exp(-2 * 2000 * t), 1e-3);
    EXPECT_NEAR(o.viscous_dissipation / (o0.kinetic_energy - o.kinetic_energy), 1.0, 1e-3);
}

TEST(Energy, GravityPotentialIsTheWorkOfGravity) {
    auto m = pipeline::build_scene(R"({"dimension": 2, "title": "t",
      "materials": {"m": {"law": "pmb", "density": 1200, "youngs_modulus": 3.24e7}},
      "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
      "particles": [{"radius": 1e-3, "center": [0, 0], "material": "m", "velocity": [0, 1]}],
      "loading": {"gravity": [0, -100]},
      "solver": {"final_time": 1e-3}})",
                                   "t", quiet);
    solver::Solver s(m);
    s.set_dt(0.5 * s.stable_dt().limit);
    s.initialize();
    for (int k = 0; k < 500; ++k)
        s.advance();
    const auto o = s.observe();
    EXPECT_NEAR(o.gravity_potential / -o.external_work, 1.0, 1e-6);
    EXPECT_GT(o.gravity_potential, 0); // it rose
}

} // namespace

namespace {

/// Two discs, the right one moved left until the nearest nodes are 0.5 R_c apart, then `push`
/// (m) further: node pairs the contact finds with a node more than R_c + h/2 inside the other
/// grain.
std::int64_t inside_after_push(double push, double radius_factor, double disc = 1e-3,
                               const char* radius_key = "radius_factor") {
    using namespace pd;
    const std::string r = std::to_string(disc), c = std::to_string(1.2 * disc);
    const std::string sc = R"({"dimension": 2, "title": "t",
      "materials": {"m": {"law": "pmb", "density": 1200, "youngs_modulus": 3.24e7}},
      "discretization": {"mesh_size": 1e-4, "horizon_factor": 3},
      "particles": [{"radius": )" +
                           r + R"(, "center": [-)" + c +
                           R"(, 0], "material": "m"},
                    {"radius": )" +
                           r + R"(, "center": [)" + c +
                           R"(, 0], "material": "m", "orientation": 0.3}],
      "contact": {")" + radius_key +
                           R"(": )" + std::to_string(radius_factor) + R"(},
      "solver": {"final_time": 1e-3}})";
    auto m = pipeline::build_scene(sc, "t", quiet);
    solver::Solver s(m);
    auto& st = s.state();
    double xmax0 = -1, xmin1 = 1;
    for (std::size_t i = 0; i < st.n; ++i) {
        if (st.body[i] == 0)
            xmax0 = std::max(xmax0, st.x0[3 * i]);
        else
            xmin1 = std::min(xmin1, st.x0[3 * i]);
    }
    const double shift = (xmin1 - xmax0) - 0.5 * m.contact.at(0).radius + push;
    for (std::size_t i = 0; i < st.n; ++i)
        if (st.body[i] == 1)
            st.x[3 * i] = st.x0[3 * i] - shift;
    s.initialize();
    return s.observe().inside_pairs;
}

} // namespace

TEST(Contact, NodesDeepInsideAnotherGrainAreFound) {
    // The guard of pd-solve (exit 3): a node within min(R_c, h) of a node below the other
    // grain's surface layer (R_c + h/2 + min(R_c, h)) is more than R_c + h/2 inside it. Pressed by
    // one mesh size (R_c = 0.95 h) or two (R_c = 3 h) grains are not flagged; pressed 4 h (8 h)
    // they are.
    EXPECT_EQ(inside_after_push(0.0, 0.95), 0);
    EXPECT_EQ(inside_after_push(1e-4, 0.95), 0);
    EXPECT_GT(inside_after_push(4e-4, 0.95), 0);
    EXPECT_EQ(inside_after_push(2e-4, 3.0), 0);
    EXPECT_GT(inside_after_push(8e-4, 3.0), 0);
}

TEST(Contact, NodesDeepInsideSmallGrainsAreFoundAtLargeRadius) {
    // R_c = 3 mesh_size = 0.3 mm on discs of 0.6 mm: a surface layer 2 R_c + h/2 deep (0.64
    // mm) left no node below it, so the guard never fired; the layer R_c + h/2 + min(R_c, h)
    // (0.41 mm, h = 0.07 mm the smallest spacing) leaves a core. Pressed by one mesh size the
    // grains are not flagged; pressed 0.6 mm (a node about 0.45 mm inside: R_c + 2 h) they are.
    EXPECT_EQ(inside_after_push(0.0, 3.0, 6e-4, "radius_mesh_factor"), 0);
    EXPECT_EQ(inside_after_push(1e-4, 3.0, 6e-4, "radius_mesh_factor"), 0);
    EXPECT_GT(inside_after_push(6e-4, 3.0, 6e-4, "radius_mesh_factor"), 0);
}

TEST(Contact, NodesThroughARigidWallAreFound) {
    // pd-solve's rigid-wall guard (exit 3): a node more than h/2 beyond a wall's surface.
    auto beyond_after_drop = [](double drop) {
        auto m = pipeline::build_scene(R"({"dimension": 2, "title": "t",
          "materials": {"m": {"law": "pmb", "density": 1200, "youngs_modulus": 3.24e7}},
          "discretization": {"mesh_size": 1e-4, "horizon_factor": 3},
          "particles": [{"radius": 1e-3, "center": [0, 1.2e-3], "material": "m"}],
          "walls": [{"type": "plane", "point": [0, 0], "normal": [0, 1]}],
          "solver": {"final_time": 1e-3}})",
                                       "t", quiet);
        solver::Solver s(m);
        auto& st = s.state();
        double ymin = 1;
        for (std::size_t i = 0; i < st.n; ++i)
            ymin = std::min(ymin, st.x0[3 * i + 1]);
        for (std::size_t i = 0; i < st.n; ++i) // lowest node at y = -drop
            st.x[3 * i + 1] = st.x0[3 * i + 1] - ymin - drop;
        s.initialize();
        return s.observe().beyond_wall;
    };
    EXPECT_EQ(beyond_after_drop(-0.5e-4), 0); // 0.5 h above: in contact
    EXPECT_EQ(beyond_after_drop(0.2e-4), 0);  // 0.2 h below: inside the bound (h/2 of the body)
    EXPECT_GT(beyond_after_drop(2e-4), 0);    // 2 h below
}
