// SPDX-License-Identifier: MIT
// Every shape meshed once with gmsh: lumped nodal volumes sum to the exact area/volume within 1%
// and their weighted node centroid matches the shape's; the centre node; quadrangles; uniform
// lattices (PeriDEM's boundary weights); .msh files (2.2, 4.1); exact instance transforms.
#include "core/errors.hpp"
#include "mesh/discretize.hpp"
#include "mesh/shape_mesher.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>

namespace {

using namespace pd;
using geometry::Shape;
constexpr double mm = 1e-3;
constexpr double pi = std::numbers::pi;

struct Case {
    const char* label;
    Shape shape;
    double h;
};

std::vector<Case> all_shapes() {
    const double r = 1 * mm;
    const Shape ring = Shape::difference(Shape::circle(21 * mm), {Shape::circle(20 * mm)});
    const Shape bar = Shape::rectangle_corners(15 * mm, -1.5 * mm, 20.5 * mm, 1.5 * mm);
    return {
        {"circle", Shape::circle(r), 0.2 * mm},
        {"ellipse", Shape::ellipse(1.5 * r, 0.75 * r), 0.15 * mm},
        {"ellipse_tall", Shape::ellipse(0.75 * r, 1.5 * r), 0.15 * mm},
        {"triangle", Shape::triangle(r), 0.2 * mm},
        {"square", Shape::square(r), 0.2 * mm},
        {"hexagon", Shape::hexagon(r), 0.2 * mm},
        {"pentagon", Shape::regular_polygon(5, r), 0.2 * mm},
        {"rectangle", Shape::rectangle(3 * r, r), 0.2 * mm},
        {"drum2d", Shape::drum2d(r, 0.4 * r), 0.1 * mm},
        {"polygon_L",
         Shape::polygon({{0, 0}, {0, 2 * r}, {r, 2 * r}, {r, r}, {2 * r, r}, {2 * r, 0}}),
         0.2 * mm},
        {"hexagon_moved", Shape::hexagon(r).rotated(0.3).translated(2 * r, -r), 0.2 * mm},
        {"annulus", ring, 0.25 * mm},
        {"annulus_bar", Shape::unite({ring, bar}), 0.25 * mm},
        {"u_channel",
         Shape::difference(
             Shape::rectangle_corners(-0.82 * mm, -0.82 * mm, 69.32 * mm, 41.82 * mm),
             {Shape::rectangle_corners(-0.22 * mm, -0.22 * mm, 68.72 * mm, 41.82 * mm)}),
         0.2 * mm},
        {"two_discs", Shape::unite({Shape::circle(r), Shape::circle(r).translated(r, 0)}),
         0.2 * mm},
        {"sphere", Shape::sphere(r), 0.15 * mm},
        {"box", Shape::box(2 * r, r, 1.5 * r), 0.2 * mm},
        {"cylinder", Shape::cylinder(r, 2 * r), 0.15 * mm},
    };
}

TEST(ShapeMesh, VolumesAndCentroidOfEveryShape) {
    std::printf("[ shapes   ] %-14s %7s %7s %12s %12s\n", "shape", "nodes", "cells", "vol err",
                "centroid err");
    for (const auto& c : all_shapes()) {
        const int dim = c.shape.dimension();
        const model::RefMesh m = mesh::mesh_shape(c.shape, c.h);
        ASSERT_EQ(m.nodes_per_cell, dim == 2 ? 3 : 4) << c.label;
        const auto v = mesh::lumped_volumes(m, dim);
        double sum = 0, cx = 0, cy = 0, cz = 0;
        for (std::size_t i = 0; i < v.size(); ++i) {
            EXPECT_GT(v[i], 0.0) << c.label;
            sum += v[i];
            cx += v[i] * m.nodes[3 * i];
            cy += v[i] * m.nodes[3 * i + 1];
            cz += v[i] * m.nodes[3 * i + 2];
        }
        const double exact = c.shape.area_or_volume();
        const auto g = c.shape.centroid();
        const double cerr = std::sqrt(std::pow(cx / sum - g[0], 2) + std::pow(cy / sum - g[1], 2) +
                                      std::pow(cz / sum - g[2], 2)) /
                            c.shape.bounding_radius();
        std::printf("[ shapes   ] %-14s %7zu %7zu %12.3e %12.3e\n", c.label, v.size(),
                    m.cells.size() / static_cast<std::size_t>(m.nodes_per_cell), sum / exact - 1,
                    cerr);
        EXPECT_NEAR(sum / exact, 1.0, 0.01) << c.label;
        EXPECT_LT(cerr, 0.01) << c.label;
        // Nodes lie in the shape (up to the conservative polygonal clearance of curved CSG).
        const double slack = 1e-5 * c.shape.bounding_radius();
        for (std::size_t i = 0; i < m.nodes.size(); i += 3)
            ASSERT_GE(c.shape.clearance(m.nodes[i], m.nodes[i + 1], m.nodes[i + 2]), -slack)
                << c.label << " node " << i / 3;
        EXPECT_GT(mesh::min_edge_length(m), 0.2 * c.h) << c.label;
        // The centroid is a node when it lies well inside.
        if (c.shape.clearance(g[0], g[1], g[2]) >= 0.5 * c.h) {
            double best = 1;
            for (std::size_t i = 0; i < m.nodes.size(); i += 3)
                best = std::min(best, std::hypot(m.nodes[i] - g[0], m.nodes[i + 1] - g[1],
                                                 m.nodes[i + 2] - g[2]));
            EXPECT_LT(best, 1e-9 * c.shape.bounding_radius()) << c.label;
        }
    }
}

TEST(ShapeMesh, CellsArePositive) {
    for (const Shape& s : {Shape::drum2d(1, 0.5), Shape::cylinder(1, 1)}) {
        const auto m = mesh::mesh_shape(s, 0.2);
        const auto npc = static_cast<std::size_t>(m.nodes_per_cell);
        for (std::size_t c = 0; c < m.cells.size(); c += npc) {
            const double* a = &m.nodes[3 * static_cast<std::size_t>(m.cells[c])];
            const double* b = &m.nodes[3 * static_cast<std::size_t>(m.cells[c + 1])];
            const double* d = &m.nodes[3 * static_cast<std::size_t>(m.cells[c + 2])];
            if (npc == 3) {
                EXPECT_GT((b[0] - a[0]) * (d[1] - a[1]) - (d[0] - a[0]) * (b[1] - a[1]), 0);
            } else {
                const double* e = &m.nodes[3 * static_cast<std::size_t>(m.cells[c + 3])];
                const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
                const double v[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
                const double w[3] = {e[0] - a[0], e[1] - a[1], e[2] - a[2]};
                EXPECT_GT(u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                              u[2] * (v[0] * w[1] - v[1] * w[0]),
                          0);
            }
        }
    }
}

TEST(ShapeMesh, Quadrangles) {
    for (const Shape& s : {Shape::circle(1), Shape::hexagon(1), Shape::drum2d(1, 0.5)}) {
        mesh::MeshOptions o;
        o.quads = true;
        const auto m = mesh::mesh_shape(s, 0.15, o);
        EXPECT_EQ(m.nodes_per_cell, 4);
        double sum = 0;
        for (double x : mesh::nodal_volumes(m, 2))
            sum += x;
        EXPECT_NEAR(sum / s.area_or_volume(), 1.0, 0.01) << s.name();
    }
    mesh::MeshOptions o;
    o.quads = true;
    EXPECT_THROW(mesh::mesh_shape(Shape::sphere(1), 0.2, o), InputError);
}

TEST(ShapeMesh, BadSize) {
    EXPECT_THROW(mesh::mesh_shape(Shape::circle(1), 0), InputError);
    EXPECT_THROW(mesh::mesh_shape(Shape::circle(1), -1), InputError);
    EXPECT_THROW(mesh::mesh_shape(Shape::circle(1), 2), InputError);
    EXPECT_THROW(mesh::uniform_grid(Shape::circle(1), NAN), InputError);
}

TEST(UniformGrid, RectangleMatchesPeriDem) {
    // Spec 8.6: [0, 10]^2 mm with h = 0.2 mm has 51^2 nodes.
    const double h = 0.2 * mm;
    const auto m = mesh::uniform_grid(Shape::rectangle_corners(0, 0, 10 * mm, 10 * mm), h);
    ASSERT_EQ(m.nodes.size() / 3, 51u * 51u);
    EXPECT_EQ(m.nodes_per_cell, 4);
    const auto v = mesh::nodal_volumes(m, 2);
    double sum = 0;
    std::size_t full = 0, half = 0, quarter = 0;
    for (double x : v) {
        sum += x;
        full += std::abs(x - h * h) < 1e-6 * h * h;
        half += std::abs(x - h * h / 2) < 1e-6 * h * h;
        quarter += std::abs(x - h * h / 4) < 1e-6 * h * h;
    }
    EXPECT_NEAR(sum, 1e-4, 1e-16);
    EXPECT_EQ(full, 49u * 49u);
    EXPECT_EQ(half, 4u * 49u);
    EXPECT_EQ(quarter, 4u);
    EXPECT_NEAR(mesh::min_edge_length(m), h, 1e-15);
}

TEST(UniformGrid, CurvedAndSolid) {
    const auto disc = mesh::uniform_grid(Shape::circle(1), 0.05);
    double sum = 0;
    for (double x : mesh::nodal_volumes(disc, 2))
        sum += x;
    EXPECT_NEAR(sum / pi, 1.0, 0.02);
    const auto ring = Shape::difference(Shape::circle(1), {Shape::circle(0.5)});
    for (std::size_t i = 0; i < disc.nodes.size(); i += 3)
        EXPECT_LE(std::hypot(disc.nodes[i], disc.nodes[i + 1]), 1 + 0.05 * std::sqrt(0.5) + 1e-12);
    const auto rm = mesh::uniform_grid(ring, 0.05);
    for (std::size_t i = 0; i < rm.nodes.size(); i += 3)
        EXPECT_GE(std::hypot(rm.nodes[i], rm.nodes[i + 1]), 0.5 - 0.05 * std::sqrt(0.5) - 1e-12);
    const auto box = mesh::uniform_grid(Shape::box(1, 2, 3), 0.25);
    EXPECT_EQ(box.nodes_per_cell, 8);
    EXPECT_EQ(box.nodes.size() / 3, 5u * 9u * 13u);
    sum = 0;
    for (double x : mesh::nodal_volumes(box, 3))
        sum += x;
    EXPECT_NEAR(sum, 6.0, 1e-12);
    const auto ball = mesh::uniform_grid(Shape::sphere(1), 0.05);
    sum = 0;
    for (double x : mesh::nodal_volumes(ball, 3))
        sum += x;
    EXPECT_NEAR(sum / (4.0 / 3 * pi), 1.0, 0.02);
}

class MshFiles : public ::testing::Test {
  protected:
    void SetUp() override {
        // One directory per test: ctest may run these tests in parallel processes.
        dir_ = std::filesystem::temp_directory_path() /
               (std::string("pd_test_msh_") +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(dir_);
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }
    std::string write(const std::string& name, const std::string& text) {
        const std::string p = (dir_ / name).string();
        std::ofstream(p) << text;
        return p;
    }
    std::filesystem::path dir_;
};

// Unit square split into two triangles; plus a point element that must not become a node.
const char* msh22_tri = R"($MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
5
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
5 7 7 0
$EndNodes
$Elements
3
1 15 2 0 1 5
2 2 2 0 1 1 2 3
3 2 2 0 1 1 3 4
$EndElements
)";

TEST_F(MshFiles, Ascii22Triangles) {
    const auto m = mesh::read_msh(write("square22.msh", msh22_tri));
    EXPECT_EQ(m.nodes_per_cell, 3);
    EXPECT_EQ(m.nodes.size() / 3, 4u);
    EXPECT_EQ(m.cells.size(), 6u);
    EXPECT_EQ(m.name, "square22");
    double sum = 0;
    for (double x : mesh::lumped_volumes(m, 2))
        sum += x;
    EXPECT_DOUBLE_EQ(sum, 1.0);
}

TEST_F(MshFiles, Ascii41QuadsAndTets) {
    const char* quad41 = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Nodes
1 6 1 6
2 1 0 6
1
2
3
4
5
6
0 0 0
1 0 0
2 0 0
0 1 0
1 1 0
2 1 0
$EndNodes
$Elements
1 2 1 2
2 1 3 2
1 1 2 5 4
2 2 3 6 5
$EndElements
)";
    const auto q = mesh::read_msh(write("quads41.msh", quad41));
    EXPECT_EQ(q.nodes_per_cell, 4);
    EXPECT_EQ(q.cells.size(), 8u);
    double sum = 0;
    for (double x : mesh::nodal_volumes(q, 2))
        sum += x;
    EXPECT_DOUBLE_EQ(sum, 2.0);

    const char* tet41 = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Nodes
1 5 1 5
3 1 0 5
1
2
3
4
5
0 0 0
1 0 0
0 1 0
0 0 1
1 1 1
$EndNodes
$Elements
1 2 1 2
3 1 4 2
1 1 2 3 4
2 2 3 4 5
$EndElements
)";
    const auto t = mesh::read_msh(write("tets41.msh", tet41));
    EXPECT_EQ(t.nodes_per_cell, 4);
    EXPECT_EQ(t.cells.size(), 8u);
    sum = 0;
    for (double x : mesh::lumped_volumes(t, 3))
        sum += x;
    EXPECT_DOUBLE_EQ(sum, 1.0 / 6 + 1.0 / 3);
    EXPECT_THROW(mesh::read_msh(write("tets41b.msh", tet41), 2), InputError);
}

TEST_F(MshFiles, Errors) {
    EXPECT_THROW(mesh::read_msh((dir_ / "missing.msh").string()), InputError);
    const char* mixed = R"($MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
5
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
5 2 0 0
$EndNodes
$Elements
2
1 3 2 0 1 1 2 3 4
2 2 2 0 1 2 5 3
$EndElements
)";
    try {
        mesh::read_msh(write("mixed.msh", mixed));
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("mixes 1 triangles and 1 quadrangles"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_THROW(mesh::read_msh(write("garbage.msh", "this is not a mesh\n")), InputError);
}

TEST(Instances, RotationScaleTranslationExact) {
    const Shape hex = Shape::hexagon(1 * mm);
    const auto m = mesh::mesh_shape(hex, 0.2 * mm);
    const double th = 1.1, s = 1.05;
    const std::array<double, 3> t{0.03, -0.01, 0};
    std::vector<double> x;
    mesh::place_instance(m, th, s, t, x);
    ASSERT_EQ(x.size(), m.nodes.size());
    const double c = std::cos(th), sn = std::sin(th);
    const Shape placed = Shape::hexagon(s * 1 * mm).rotated(th).translated(t[0], t[1]);
    for (std::size_t i = 0; i < x.size(); i += 3) {
        const double X = m.nodes[i], Y = m.nodes[i + 1];
        EXPECT_NEAR(x[i], t[0] + s * (c * X - sn * Y), 1e-18);
        EXPECT_NEAR(x[i + 1], t[1] + s * (sn * X + c * Y), 1e-18);
        // Exact up to the rounding of x - t (|t| = 0.03 m: ulp 3.5e-18 m).
        EXPECT_NEAR(std::hypot(x[i] - t[0], x[i + 1] - t[1]), s * std::hypot(X, Y), 1e-16);
        EXPECT_GE(placed.clearance(x[i], x[i + 1]), -1e-15);
    }
    // Volumes scale by s^2; the centre node lands on t.
    double v0 = 0, v1 = 0;
    model::RefMesh inst = m;
    inst.nodes = x;
    for (double v : mesh::lumped_volumes(m, 2))
        v0 += v;
    for (double v : mesh::lumped_volumes(inst, 2))
        v1 += v;
    EXPECT_NEAR(v1 / v0, s * s, 1e-12);
    double best = 1;
    for (std::size_t i = 0; i < x.size(); i += 3)
        best = std::min(best, std::hypot(x[i] - t[0], x[i + 1] - t[1]));
    EXPECT_LT(best, 1e-15);
}

} // namespace
