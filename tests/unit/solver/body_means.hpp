// SPDX-License-Identifier: MIT
// Test helper: mass-weighted means of nodal vector fields over one body.
#pragma once

#include "model/model.hpp"
#include "solver/state.hpp"

#include <array>
#include <vector>

namespace pd::test {

/// Mass-weighted mean of a nodal vector field (3 per node) over body b (e.g. the centre of mass
/// from s.x, its velocity from s.v).
inline std::array<double, 3> com(const model::Model& m, const solver::State& s, std::size_t b,
                                 const std::vector<double>& field) {
    std::array<double, 3> p{0, 0, 0};
    double mass = 0;
    for (auto i = m.bodies.begin(b); i < m.bodies.end(b); ++i) {
        const auto ii = static_cast<std::size_t>(i);
        const double mi = s.rho[ii] * s.vol[ii];
        mass += mi;
        for (std::size_t d = 0; d < 3; ++d)
            p[d] += mi * field[3 * ii + d];
    }
    for (double& x : p)
        x /= mass;
    return p;
}

} // namespace pd::test
