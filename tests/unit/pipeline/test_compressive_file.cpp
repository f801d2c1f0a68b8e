// SPDX-License-Identifier: MIT
// The compressive-breaking switch (Material::break_in_compression, PeriDEM's |s| > s0) goes from
// the scene key through the file (/materials/<name>/break_in_compression, pd-file 1.4.0) and
// back, on and off; a bad value is refused with the key named.
#include "core/errors.hpp"
#include "h5/file.hpp"
#include "pipeline/scene.hpp"
#include "store/model_io.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace {

using namespace pd;

std::string scene(const std::string& value) {
    return R"({"dimension": 2, "title": "t",
      "materials": {"a": {"law": "lps", "density": 1200, "youngs_modulus": 3.24e7,
                          "poisson_ratio": 0.25, "fracture_energy": 5,
                          "break_in_compression": )" +
           value + R"(},
                    "b": {"density": 1200, "youngs_modulus": 3.24e7, "fracture_energy": 5}},
      "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
      "particles": [{"radius": 1e-3, "center": [0, 0], "material": "a"},
                    {"radius": 1e-3, "center": [3e-3, 0], "material": "b"}],
      "solver": {"final_time": 1e-3}})";
}

TEST(CompressiveBreaking, SceneKeyAndFileRoundTrip) {
    const Log quiet("test", 0, Verbosity::quiet);
    const auto path = std::filesystem::temp_directory_path() / "pd_test_compressive.h5";
    for (const bool on : {true, false}) {
        const auto built = pipeline::build_scene(scene(on ? "true" : "false"), "s.json", quiet);
        ASSERT_EQ(built.materials.size(), 2u);
        EXPECT_EQ(built.materials[0].break_in_compression, on);
        EXPECT_FALSE(built.materials[1].break_in_compression); // default: tension only
        {
            h5::File f(path.string(), h5::Mode::create_truncate);
            store::write_model(f, built);
        }
        h5::File f(path.string(), h5::Mode::read);
        const auto back = store::read_model(f);
        EXPECT_EQ(back.materials[0].break_in_compression, on);
        EXPECT_FALSE(back.materials[1].break_in_compression);
    }
    std::filesystem::remove(path);
    EXPECT_THROW(pipeline::build_scene(scene("1"), "s.json", quiet), ConfigError);
}

} // namespace
