// SPDX-License-Identifier: MIT
// mesh::boundary_distance (a k-d tree over the boundary nodes, mesh/nearest.hpp) gives, bit for
// bit, the distance a scan of every boundary node gives: 2D gmsh and grid meshes (a ring with a
// hole, a drum2d with concave sides, a grid rectangle, quadrangles) and 3D tetrahedra; and the
// tree alone on random clouds with ties and duplicates.
#include "mesh/discretize.hpp"
#include "mesh/nearest.hpp"
#include "mesh/shape_mesher.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <random>

namespace {

using namespace pd;
using geometry::Shape;
constexpr double mm = 1e-3;

/// The reference: boundary nodes as vertices of facets used by one cell, then a scan.
std::vector<double> scanned(const model::RefMesh& m, int dimension) {
    const std::size_t n = m.nodes.size() / 3;
    const auto npc = static_cast<std::size_t>(m.nodes_per_cell);
    std::map<std::array<std::int32_t, 3>, int> count;
    auto add = [&](std::int32_t a, std::int32_t b, std::int32_t c) {
        std::array<std::int32_t, 3> k{a, b, c};
        std::sort(k.begin(), k.end());
        ++count[k];
    };
    for (std::size_t c = 0; c + npc <= m.cells.size(); c += npc) {
        const std::int32_t* v = &m.cells[c];
        if (dimension == 2) {
            for (std::size_t e = 0; e < npc; ++e)
                add(-1, v[e], v[(e + 1) % npc]);
        } else {
            add(v[0], v[1], v[2]);
            add(v[0], v[1], v[3]);
            add(v[0], v[2], v[3]);
            add(v[1], v[2], v[3]);
        }
    }
    std::vector<std::uint8_t> boundary(n, 0);
    for (const auto& [k, c] : count)
        if (c == 1)
            for (auto v : k)
                if (v >= 0)
                    boundary[static_cast<std::size_t>(v)] = 1;
    std::vector<double> out(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        if (boundary[i])
            continue;
        double d = std::numeric_limits<double>::infinity();
        for (std::size_t b = 0; b < n; ++b)
            if (boundary[b])
                d = std::min(d, mesh::point_distance(&m.nodes[3 * i], &m.nodes[3 * b]));
        out[i] = d;
    }
    return out;
}

void expect_same_bits(const model::RefMesh& m, int dimension, const char* label) {
    const auto fast = mesh::boundary_distance(m, dimension);
    const auto ref = scanned(m, dimension);
    ASSERT_EQ(fast.size(), ref.size()) << label;
    std::size_t inner = 0;
    for (std::size_t i = 0; i < ref.size(); ++i) {
        ASSERT_EQ(fast[i], ref[i]) << label << ": node " << i; // exact, not near
        inner += ref[i] > 0;
    }
    EXPECT_GT(inner, ref.size() / 4) << label << ": too few inner nodes to test anything";
}

TEST(BoundaryDistance, EqualsTheScanOfEveryBoundaryNode) {
    mesh::MeshOptions quads;
    quads.quads = true;
    const Shape ring = Shape::difference(Shape::circle(3 * mm), {Shape::circle(1.5 * mm)});
    expect_same_bits(mesh::mesh_shape(ring, 0.15 * mm), 2, "gmsh ring");
    expect_same_bits(mesh::mesh_shape(Shape::drum2d(2 * mm, 1.2 * mm), 0.12 * mm), 2,
                     "gmsh drum2d");
    expect_same_bits(mesh::mesh_shape(Shape::hexagon(2 * mm), 0.1 * mm, quads), 2, "quads");
    expect_same_bits(mesh::uniform_grid(Shape::rectangle(6 * mm, 3 * mm), 0.1 * mm), 2,
                     "grid rectangle");
    expect_same_bits(mesh::mesh_shape(Shape::sphere(1 * mm), 0.15 * mm), 3, "gmsh sphere");
    expect_same_bits(mesh::mesh_shape(Shape::box(2 * mm, 1 * mm, 1 * mm), 0.15 * mm), 3,
                     "gmsh box");
}

TEST(NearestPoints, EqualsTheScanOnCloudsWithTiesAndDuplicates) {
    std::mt19937_64 rng(7);
    for (int dim : {2, 3}) {
        for (std::size_t count : {0, 1, 5, 9, 200, 3000}) {
            std::vector<double> xyz;
            std::uniform_int_distribution<int> grid(0, 12); // many equal coordinates
            for (std::size_t k = 0; k < count + 500; ++k)
                for (int d = 0; d < 3; ++d)
                    xyz.push_back(d < dim ? 0.1 * grid(rng) : 0.0);
            std::vector<std::int32_t> ids(count);
            for (std::size_t k = 0; k < count; ++k)
                ids[k] = static_cast<std::int32_t>(k);
            const mesh::NearestPoints tree(xyz, ids, dim);
            for (std::size_t q = 0; q < xyz.size() / 3; ++q) {
                double ref = std::numeric_limits<double>::infinity();
                for (auto p : ids)
                    ref = std::min(ref, mesh::point_distance(
                                            &xyz[3 * q], &xyz[3 * static_cast<std::size_t>(p)]));
                ASSERT_EQ(tree.distance(&xyz[3 * q]), ref)
                    << dim << "D, " << count << " points, query " << q;
            }
        }
    }
}

} // namespace
