// SPDX-License-Identifier: MIT
// Scene validation: unknown keys get the closest valid key, overlaps name the grains, missing
// materials and coarse horizons are refused with the key at fault.
#include "core/errors.hpp"
#include "pipeline/scene.hpp"

#include <gtest/gtest.h>

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

TEST(Scene, Valid) { EXPECT_EQ(error_of(base(one)), ""); }

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
