// SPDX-License-Identifier: MIT
// A gmsh-meshed disc: nodal volumes sum to pi R^2 within 1%, h equals the minimum pairwise node
// distance, instances are exact rotations/scalings of the reference.
#include "core/errors.hpp"
#include "mesh/discretize.hpp"
#include "mesh/gmsh_mesher.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace {

using namespace pd;

TEST(Disc, NodalVolumesSumToArea) {
    for (double h : {2e-4, 1e-4}) {
        auto m = mesh::mesh_disc(1e-3, h);
        auto v = mesh::lumped_volumes(m, 2);
        double sum = 0;
        for (double x : v) {
            EXPECT_GT(x, 0.0);
            sum += x;
        }
        const double area = std::numbers::pi * 1e-6;
        EXPECT_NEAR(sum / area, 1.0, 0.01) << "h = " << h;
        EXPECT_LT(sum, area); // inscribed polygon
    }
}

TEST(Disc, CentreIsANode) {
    auto m = mesh::mesh_disc(1e-3, 2e-4);
    double best = 1;
    for (std::size_t i = 0; i < m.nodes.size(); i += 3)
        best = std::min(best, std::hypot(m.nodes[i], m.nodes[i + 1]));
    EXPECT_LT(best, 1e-12);
}

TEST(Disc, MinEdgeIsMinPairwiseDistance) {
    auto m = mesh::mesh_disc(1e-3, 2e-4);
    double brute = std::numeric_limits<double>::infinity();
    const std::size_t n = m.nodes.size() / 3;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j)
            brute = std::min(brute, std::hypot(m.nodes[3 * i] - m.nodes[3 * j],
                                               m.nodes[3 * i + 1] - m.nodes[3 * j + 1]));
    EXPECT_DOUBLE_EQ(mesh::min_edge_length(m), brute);
    EXPECT_GT(brute, 0.3 * 2e-4);
}

TEST(Disc, InstanceTransformIsExact) {
    auto m = mesh::mesh_disc(1e-3, 2e-4);
    std::vector<double> x;
    const double th = 0.7, s = 1.5;
    mesh::place_instance(m, th, s, {0.01, -0.02, 0}, x);
    ASSERT_EQ(x.size(), m.nodes.size());
    for (std::size_t i = 0; i < m.nodes.size(); i += 3) {
        const double X = m.nodes[i], Y = m.nodes[i + 1];
        EXPECT_NEAR(x[i], 0.01 + s * (std::cos(th) * X - std::sin(th) * Y), 1e-15);
        EXPECT_NEAR(x[i + 1], -0.02 + s * (std::sin(th) * X + std::cos(th) * Y), 1e-15);
        // distances to the centre scale exactly by s
        EXPECT_NEAR(std::hypot(x[i] - 0.01, x[i + 1] + 0.02), s * std::hypot(X, Y), 1e-15);
    }
}

TEST(Disc, BadSizesAreInputErrors) {
    EXPECT_THROW(mesh::mesh_disc(1e-3, 0), pd::InputError);
    EXPECT_THROW(mesh::mesh_disc(-1, 1e-4), pd::InputError);
}

} // namespace
