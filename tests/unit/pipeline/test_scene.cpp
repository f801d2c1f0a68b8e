// SPDX-License-Identifier: MIT
// Scene validation: unknown keys get the closest valid key, overlaps name the grains, missing
// materials and coarse horizons are refused with the key at fault.
#include "core/errors.hpp"
#include "pipeline/scene.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using namespace pd;

const Log quiet("test", 0, Verbosity::quiet);

std::string base(const std::string& particles, const std::string& disc = R"("horizon_factor": 3)",
                 const std::string& extra = "") {
    return R"({"dimension": 2,
      "materials": {"m1": {"density": 1200, "youngs_modulus": 3.24e7}},
      "discretization": {"mesh_size": 2e-4, )" +
           disc + R"(},
      "particles": [)" +
           particles + R"(], )" + extra + R"(
      "solver": {"final_time": 1e-3}})";
}

std::string error_of(const std::string& text) {
    try {
        pipeline::build_scene(text, "scene.json", quiet);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

const std::string one = R"({"radius": 1e-3, "center": [0, 0], "material": "m1"})";

TEST(Scene, Valid) {
    EXPECT_EQ(error_of(base(one)), "");
}

TEST(Scene, UnknownKeySuggestsClosest) {
    auto e = error_of(base(R"({"radius": 1e-3, "centre": [0, 0], "material": "m1"})"));
    EXPECT_NE(e.find("particles[0].centre"), std::string::npos) << e;
    EXPECT_NE(e.find("did you mean 'center'"), std::string::npos) << e;
    e = error_of(base(one, R"("horizon_factor": 3)", R"("solvr": {},)"));
    EXPECT_NE(e.find("did you mean 'solver'"), std::string::npos) << e;
}

TEST(Scene, OverlapNamesGrains) {
    auto e = error_of(base(one + R"(, {"radius": 1e-3, "center": [1.5e-3, 0], "material": "m1"})"));
    EXPECT_NE(e.find("particles[0], particles[1]"), std::string::npos) << e;
    EXPECT_NE(e.find("overlap"), std::string::npos) << e;
}

TEST(Scene, MissingMaterial) {
    auto e = error_of(base(R"({"radius": 1e-3, "center": [0, 0], "material": "steel"})"));
    EXPECT_NE(e.find("particles[0].material"), std::string::npos) << e;
    EXPECT_NE(e.find("steel"), std::string::npos) << e;
}

TEST(Scene, CoarseHorizon) {
    auto e = error_of(base(one, R"("horizon": 1e-4)"));
    EXPECT_NE(e.find("discretization.horizon"), std::string::npos) << e;
}

TEST(Scene, BadValues) {
    EXPECT_NE(error_of(base(R"({"radius": -1, "center": [0, 0], "material": "m1"})"))
                  .find("particles[0].radius"),
              std::string::npos);
    EXPECT_NE(error_of("{not json").find("not valid JSON"), std::string::npos);
    EXPECT_NE(error_of(base(one, R"("horizon_factor": 3)", R"("contact": {"restitution": 2},)"))
                  .find("contact.restitution"),
              std::string::npos);
}

TEST(Scene, CommentsAllowed) {
    EXPECT_EQ(error_of("// a comment\n" + base(one)), "");
}

} // namespace

namespace {

std::string with_material(const std::string& mat) {
    return R"({"dimension": 2, "materials": {"m": {"density": 1000, )" + mat + R"(}},
      "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
      "particles": [{"radius": 1e-3, "center": [0, 0], "material": "m"}],
      "solver": {"final_time": 1e-3}})";
}

TEST(Scene, TwoOfEKGNuAndToughness) {
    // LPS from K and G: E = 9KG/(3K+G), nu = (3K-2G)/(2(3K+G)) (spec 1.3).
    auto m = pipeline::build_scene(
        with_material(R"("law": "lps", "bulk_modulus": 2.16e7, "shear_modulus": 1.296e7,
                         "fracture_toughness": 1000)"),
        "s", quiet);
    EXPECT_NEAR(m.materials[0].youngs_modulus, 3.24e7, 1e-6);
    EXPECT_NEAR(m.materials[0].poisson_ratio, 0.25, 1e-12);
    EXPECT_NEAR(m.materials[0].fracture_energy, 1e6 / 3.24e7, 1e-12); // KIc^2 / E
    // PMB in plane stress fixes nu = 1/3: E and G must agree with it (G = E / (2 (1 + nu))).
    m = pipeline::build_scene(with_material(R"("youngs_modulus": 8e9, "shear_modulus": 3e9)"), "s",
                              quiet);
    EXPECT_NEAR(m.materials[0].youngs_modulus, 8e9, 1e-3);
    auto e = error_of(with_material(R"("youngs_modulus": 8e9, "shear_modulus": 4e9)"));
    EXPECT_NE(e.find("fixes nu"), std::string::npos) << e;
    e = error_of(with_material(R"("law": "lps", "youngs_modulus": 8e9)"));
    EXPECT_NE(e.find("two of"), std::string::npos) << e;
}

} // namespace

TEST(Scene, ContactRadiusTiedToMeshSize) {
    // radius_mesh_factor: R_c = factor x mesh_size (not x the smallest node spacing), and the
    // auto Kn's (0.95 h / R_c)^(d+1) on the same h: against the same R_c given in metres (whose
    // Kn takes the smallest spacing h_min), Kn is (mesh_size / h_min)^3 larger in 2D.
    const std::string two =
        std::string(one) + R"(, {"radius": 1e-3, "center": [3e-3, 0], "material": "m1"})";
    auto by_mesh = pipeline::build_scene(
        base(two, R"("horizon_factor": 3)", R"("contact": {"radius_mesh_factor": 3},)"), "s",
        quiet);
    auto by_metre = pipeline::build_scene(
        base(two, R"("horizon_factor": 3)", R"("contact": {"radius": 6e-4},)"), "s", quiet);
    ASSERT_EQ(by_mesh.contact.size(), 1u);
    EXPECT_NEAR(by_mesh.contact[0].radius, 6e-4, 1e-15);
    const double hmin = by_mesh.bodies.mesh_size[0];
    EXPECT_LT(hmin, 1.9e-4); // gmsh's smallest spacing is below mesh_size
    EXPECT_NEAR(by_mesh.contact[0].stiffness / by_metre.contact[0].stiffness,
                std::pow(2e-4 / hmin, 3), 1e-9);
    const auto e = error_of(base(one, R"("horizon_factor": 3)",
                                 R"("contact": {"radius_factor": 1, "radius_mesh_factor": 3},)"));
    EXPECT_NE(e.find("at most one of radius"), std::string::npos) << e;
}
