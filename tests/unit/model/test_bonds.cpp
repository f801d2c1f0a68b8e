// SPDX-License-Identifier: MIT
// CSR bond-list invariants (spec 2.4): monotone offsets, no self bonds, same body only, strict
// |xi| < delta, symmetric, complete against a brute-force search.
#include "model/model.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace {

using namespace pd::model;

TEST(Bonds, CsrInvariantsAgainstBruteForce) {
    Nodes nodes;
    Bodies bodies;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    const int per_body = 300;
    for (int b = 0; b < 2; ++b) {
        for (int i = 0; i < per_body; ++i) {
            nodes.x0.insert(nodes.x0.end(), {u(rng) + 0.5 * b, u(rng), 0.0});
            nodes.volume.push_back(1e-3);
            nodes.body.push_back(b);
        }
        bodies.node_offsets.push_back(bodies.node_offsets.back() + per_body);
        bodies.horizon.push_back(b == 0 ? 0.125 : 0.15);
    }
    // A node exactly at distance delta from node 0 must not be a neighbour (strict).
    nodes.x0[0] = 0.5;
    nodes.x0[1] = 0.5;
    nodes.x0[3] = 0.625; // exactly 0.125 = delta away in binary floating point
    nodes.x0[4] = 0.5;
    Bonds bonds = build_bonds(nodes, bodies, false);
    const std::size_t n = nodes.num();
    ASSERT_EQ(bonds.offsets.size(), n + 1);
    EXPECT_TRUE(std::is_sorted(bonds.offsets.begin(), bonds.offsets.end()));
    auto has = [&](std::size_t i, int j) {
        return std::binary_search(bonds.neighbor.begin() + bonds.offsets[i],
                                  bonds.neighbor.begin() + bonds.offsets[i + 1], j);
    };
    std::size_t expected = 0;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) {
            if (i == j || nodes.body[i] != nodes.body[j])
                continue;
            const double d = bodies.horizon[static_cast<std::size_t>(nodes.body[i])];
            double r2 = 0;
            for (int k = 0; k < 3; ++k)
                r2 += std::pow(nodes.x0[3 * i + k] - nodes.x0[3 * j + k], 2);
            const bool want = r2 < d * d;
            expected += want;
            EXPECT_EQ(has(i, static_cast<int>(j)), want) << i << " " << j;
        }
    EXPECT_EQ(bonds.num(), expected);
    EXPECT_FALSE(has(0, 1)); // exactly at delta
    for (std::size_t i = 0; i < n; ++i)
        for (auto k = bonds.offsets[i]; k < bonds.offsets[i + 1]; ++k)
            EXPECT_TRUE(has(static_cast<std::size_t>(bonds.neighbor[k]), static_cast<int>(i)));
}

} // namespace
