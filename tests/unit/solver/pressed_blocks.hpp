// SPDX-License-Identifier: MIT
// Test helpers: two 2D blocks under the surface contact law, b (body 1) pressed into a (body 0),
// and a rigid shift of b.
#pragma once

#include "core/log.hpp"
#include "model/model.hpp"
#include "pipeline/scene.hpp"
#include "solver/state.hpp"

#include <cstddef>

namespace pd::test {

/// Block b (2 x 1 mm) pressed `depth` into block a (4 x 1 mm) below it, h = 0.2 mm, delta = 3 h,
/// E = 32.4 MPa, rho = 1200, surface law with its automatic stiffness (bonds unstretched).
inline model::Model pressed_blocks(double depth) {
    const Log quiet("test", 0, Verbosity::quiet);
    auto m = pipeline::build_scene(R"({"dimension": 2,
      "materials": {"m": {"density": 1200, "youngs_modulus": 3.24e7}},
      "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
      "shapes": {"a": {"type": "rectangle", "corners": [[-2e-3, -1e-3], [2e-3, 0]]},
                 "b": {"type": "rectangle", "corners": [[-1e-3, 0], [1e-3, 1e-3]]}},
      "particles": [{"shape": "a", "center": [0, 0], "material": "m"},
                    {"shape": "b", "center": [0, 1e-4], "material": "m"}],
      "contact": {"law": "surface"}, "solver": {"final_time": 1}})",
                                   "t", quiet);
    for (auto i = m.bodies.begin(1); i < m.bodies.end(1); ++i)
        m.nodes.x0[3 * static_cast<std::size_t>(i) + 1] -= 1e-4 + depth;
    return m;
}

/// Moves block b (body 1) of pressed_blocks `dy` along y at once, at rest.
inline void shift_b(const model::Model& m, solver::State& st, double dy) {
    for (auto i = m.bodies.begin(1); i < m.bodies.end(1); ++i) {
        const auto k = static_cast<std::size_t>(i);
        st.x[3 * k + 1] += dy;
        st.u[3 * k + 1] += dy;
    }
}

} // namespace pd::test
