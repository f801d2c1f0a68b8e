// SPDX-License-Identifier: MIT
// The force terms of issue 16 (lib/solver/forces.hpp, terms/terms.def): a scene's list holds the
// terms it needs and no other, in the order of the sum; a term not in the list adds nothing.
#include "core/log.hpp"
#include "pipeline/scene.hpp"
#include "solver/solver.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace {

using namespace pd;

const Log quiet("test", 0, Verbosity::quiet);
using Names = std::vector<std::string>;

TEST(SolverTerms, TwoDiscsWithDampingFrictionAndViscosityHaveTheirTerms) {
    auto m = pipeline::build_scene(R"({"dimension": 2, "title": "t",
      "materials": {"m": {"law": "pmb", "density": 1200, "youngs_modulus": 3.24e7}},
      "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
      "particles": [
        {"radius": 1e-3, "center": [-1.1e-3, 0], "material": "m", "velocity": [1, 0]},
        {"radius": 1e-3, "center": [1.1e-3, 0], "material": "m", "velocity": [-1, 0]}],
      "contact": {"restitution": 0.5, "friction": 0.4},
      "loading": {"viscous_damping": 50},
      "solver": {"final_time": 1e-4}})",
                                   "t", quiet);
    solver::Solver s(m);
    EXPECT_EQ(s.terms(), (Names{"pmb_bonds", "node_contact", "contact_damping", "friction",
                                "viscous_damping"}));
}

TEST(SolverTerms, AFreeDiscUnderGravityHasBondsAndGravityOnly) {
    // One body: no contact (nothing to touch), no damping, no walls. At rest and undeformed its
    // bonds pull (next to) nothing, so the force density after initialize() is rho g at every
    // node.
    auto m = pipeline::build_scene(R"({"dimension": 2, "title": "t",
      "materials": {"m": {"law": "pmb", "density": 1200, "youngs_modulus": 3.24e7}},
      "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
      "particles": [{"radius": 1e-3, "center": [0, 0], "material": "m"}],
      "loading": {"gravity": [0, -9.81]},
      "solver": {"final_time": 1e-4}})",
                                   "t", quiet);
    solver::Solver s(m);
    EXPECT_EQ(s.terms(), (Names{"pmb_bonds", "gravity"}));
    s.set_dt(0.5 * s.stable_dt().limit);
    s.initialize();
    const auto& st = s.state();
    ASSERT_GT(st.n, 50u);
    for (std::size_t i = 0; i < st.n; ++i) {
        EXPECT_NEAR(st.f[3 * i], 0.0, 1e-6 * 1200 * 9.81);
        EXPECT_NEAR(st.f[3 * i + 1], 1200 * -9.81, 1e-6 * 1200 * 9.81);
    }
    EXPECT_EQ(s.observe().contact_count, 0);
}

TEST(SolverTerms, LpsPlateWithoutGravityHasNoPmbOrGravityTerm) {
    auto m = pipeline::build_scene(R"({"dimension": 2, "title": "t",
      "materials": {"m": {"law": "lps", "density": 1200, "youngs_modulus": 3.24e7,
                          "poisson_ratio": 0.25}},
      "discretization": {"mesh_size": 5e-4, "horizon_factor": 3},
      "shapes": {"plate": {"type": "rectangle", "corners": [[0, 0], [0.01, 0.005]],
                           "mesh": "grid"}},
      "particles": [{"shape": "plate", "center": [0, 0], "material": "m"}],
      "solver": {"final_time": 1e-4}})",
                                   "t", quiet);
    solver::Solver s(m);
    EXPECT_EQ(s.terms(), (Names{"lps_bonds"}));
    // The bond limit comes from the LPS term: a finite step from the Lanczos estimate.
    const auto dt = s.stable_dt();
    EXPECT_GT(dt.lanczos_steps, 0);
    EXPECT_GT(dt.pd, 0);
    EXPECT_EQ(dt.governing, "peridynamic bonds");
}

} // namespace
