// SPDX-License-Identifier: MIT
// Meshing the new 3D shapes: closed surface meshes (STL) into gmsh tetrahedra and into the uniform
// lattice, 3D CSG through gmsh OpenCASCADE booleans and the lattice. The sum of lumped nodal
// volumes must match the analytic volume within 1% and the volume-weighted node centroid the
// analytic centroid; instance transforms scale volumes by s^3 exactly.
#include "../geometry/stl_fixture.hpp"
#include "core/errors.hpp"
#include "geometry/shapes.hpp"
#include "mesh/discretize.hpp"
#include "mesh/shape_mesher.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace {

using namespace pd;
using geometry::Shape;
constexpr double mm = 1e-3;
constexpr double pi = std::numbers::pi;

struct Sums {
    double volume = 0;
    geometry::Vec3 centroid{0, 0, 0};
    std::size_t nodes = 0;
    double seconds = 0;
};

/// Meshes (gmsh or grid), checks positive nodal volumes and nodes inside, returns the sums.
Sums discretise(const Shape& s, double h, bool grid) {
    const auto t0 = std::chrono::steady_clock::now();
    const model::RefMesh m = grid ? mesh::uniform_grid(s, h) : mesh::mesh_shape(s, h);
    Sums r;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(m.nodes_per_cell, grid ? 8 : 4);
    const auto v = mesh::nodal_volumes(m, 3);
    r.nodes = v.size();
    for (std::size_t i = 0; i < v.size(); ++i) {
        EXPECT_GT(v[i], 0.0);
        r.volume += v[i];
        for (std::size_t k = 0; k < 3; ++k)
            r.centroid[k] += v[i] * m.nodes[3 * i + k];
    }
    for (auto& c : r.centroid)
        c /= r.volume;
    if (!grid) { // gmsh nodes lie on or in the shape (the grid's may stick out by half a cell)
        for (std::size_t i = 0; i < m.nodes.size(); i += 3) {
            EXPECT_GE(s.clearance(m.nodes[i], m.nodes[i + 1], m.nodes[i + 2]),
                      -1e-6 * s.bounding_radius())
                << s.name() << " node " << i / 3;
        }
    }
    return r;
}

/// gmsh tetrahedra of size h and the lattice of spacing h_grid (a staircase: finer for 1%).
void check(const char* label, const Shape& s, double h, double h_grid, double exact,
           geometry::Vec3 g) {
    for (bool grid : {false, true}) {
        const Sums r = discretise(s, grid ? h_grid : h, grid);
        const double verr = r.volume / exact - 1;
        const double cerr =
            std::hypot(r.centroid[0] - g[0], r.centroid[1] - g[1], r.centroid[2] - g[2]) /
            std::cbrt(exact);
        std::printf("[ mesh3d   ] %-18s %-4s h=%.3g: %7zu nodes, volume error %+.2e, centroid "
                    "error %.2e L, %.2f s\n",
                    label, grid ? "grid" : "gmsh", grid ? h_grid : h, r.nodes, verr, cerr,
                    r.seconds);
        EXPECT_LT(std::abs(verr), 0.01) << label << (grid ? " grid" : " gmsh");
        EXPECT_LT(cerr, 0.01) << label << (grid ? " grid" : " gmsh");
    }
}

class MeshSurface : public pd_test::StlDir {};

TEST_F(MeshSurface, IcosphereStl) {
    const auto ico = pd_test::icosphere(1 * mm, 3, {0.2 * mm, 0, -0.1 * mm});
    pd_test::write_ascii_stl(path("ico.stl"), ico);
    const Shape s = Shape::surface_mesh(path("ico.stl"));
    const auto [v, g] = pd_test::moments(ico);
    check("icosphere.stl", s, 0.1 * mm, 0.05 * mm, v, g);
    // Centred and rotated as a grain: the same volumes, centroid at the origin.
    check("icosphere centred", s.centered().rotated(0.5), 0.1 * mm, 0.05 * mm, v, {0, 0, 0});
}

TEST_F(MeshSurface, BinaryCubeAndTetrahedronStl) {
    pd_test::write_binary_stl(path("cube.stl"), pd_test::cube(2, {-1, -0.5, 0}));
    check("cube.stl", Shape::surface_mesh(path("cube.stl")), 0.25, 0.25, 8, {0, 0.5, 1});
    const auto tet = pd_test::tetrahedron({0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 2});
    pd_test::write_ascii_stl(path("tet.stl"), tet);
    const auto [v, g] = pd_test::moments(tet);
    check("tetrahedron.stl", Shape::surface_mesh(path("tet.stl")), 0.1, 0.02, v, g);
}

TEST_F(MeshSurface, InstanceScaleAndRotationExact) {
    const auto ico = pd_test::icosphere(1 * mm, 2);
    pd_test::write_ascii_stl(path("ico.stl"), ico);
    const auto m = mesh::mesh_shape(Shape::surface_mesh(path("ico.stl")), 0.25 * mm);
    const double th = 0.9, s = 1.7;
    const std::array<double, 3> t{0.01, -0.02, 0.03};
    std::vector<double> x;
    mesh::place_instance(m, th, s, t, x);
    model::RefMesh inst = m;
    inst.nodes = x;
    double v0 = 0, v1 = 0;
    for (double v : mesh::nodal_volumes(m, 3))
        v0 += v;
    for (double v : mesh::nodal_volumes(inst, 3))
        v1 += v;
    EXPECT_NEAR(v1 / v0, s * s * s, 1e-12);
    for (std::size_t i = 0; i < x.size(); i += 3)
        EXPECT_NEAR(std::hypot(x[i] - t[0], x[i + 1] - t[1], x[i + 2] - t[2]),
                    s * std::hypot(m.nodes[i], m.nodes[i + 1], m.nodes[i + 2]), 1e-16);
}

TEST(MeshCsg3d, BoxMinusCylinderAndTwoSpheres) {
    const double lx = 4 * mm, ly = 3 * mm, lz = 2 * mm, r = 0.8 * mm, e = 0.6 * mm;
    const Shape holed =
        Shape::difference(Shape::box(lx, ly, lz), {Shape::cylinder(r, 3 * lz).translated(e, 0, 0)});
    const double hole = pi * r * r * lz, v = lx * ly * lz - hole;
    check("box - cylinder", holed, 0.2 * mm, 0.05 * mm, v, {-hole * e / v, 0, 0});
    const double R = 1 * mm, d = 1.2 * mm;
    const Shape two = Shape::unite({Shape::sphere(R), Shape::sphere(R).translated(d, 0, 0)});
    const double lens = pi * (4 * R + d) * (2 * R - d) * (2 * R - d) / 12;
    check("sphere + sphere", two, 0.1 * mm, 0.05 * mm, 2 * 4.0 / 3 * pi * R * R * R - lens,
          {d / 2, 0, 0});
}

/// The octree volumes and centroids of 3D CSG against OpenCASCADE's B-rep integrals and the
/// analytic values.
TEST(MeshCsg3d, OctreeAgreesWithOpenCascade) {
    const double lx = 4 * mm, ly = 3 * mm, lz = 2 * mm, r = 0.8 * mm, e = 0.6 * mm;
    const Shape holed =
        Shape::difference(Shape::box(lx, ly, lz), {Shape::cylinder(r, 3 * lz).translated(e, 0, 0)});
    const double hole = pi * r * r * lz, vh = lx * ly * lz - hole;
    const double R = 1 * mm, d = 1.2 * mm;
    const Shape two = Shape::unite({Shape::sphere(R), Shape::sphere(R).translated(d, 0, 0)})
                          .rotated(0.3)
                          .translated(0, 0, 1 * mm);
    const double vt =
        2 * 4.0 / 3 * pi * R * R * R - pi * (4 * R + d) * (2 * R - d) * (2 * R - d) / 12;
    struct Row {
        const char* label;
        Shape s;
        double v;
        geometry::Vec3 g;
    };
    for (const Row& c : {Row{"box - cylinder", holed, vh, {-hole * e / vh, 0, 0}},
                         Row{"sphere + sphere",
                             two,
                             vt,
                             {std::cos(0.3) * d / 2, std::sin(0.3) * d / 2, 1 * mm}}}) {
        const auto occ = mesh::occ_mass_properties(c.s);
        const auto g = c.s.centroid();
        const double L = std::cbrt(c.v);
        std::printf("[ mass3d   ] %-16s volume error: OCC %+.1e, octree %+.1e; centroid error: "
                    "OCC %.1e L, octree %.1e L\n",
                    c.label, occ.measure / c.v - 1, c.s.area_or_volume() / c.v - 1,
                    std::hypot(occ.centroid[0] - c.g[0], occ.centroid[1] - c.g[1],
                               occ.centroid[2] - c.g[2]) /
                        L,
                    std::hypot(g[0] - c.g[0], g[1] - c.g[1], g[2] - c.g[2]) / L);
        EXPECT_NEAR(occ.measure / c.v, 1.0, 1e-6) << c.label;
        EXPECT_NEAR(c.s.area_or_volume() / c.v, 1.0, 1e-3) << c.label;
        for (int i = 0; i < 3; ++i) {
            EXPECT_NEAR(occ.centroid[static_cast<std::size_t>(i)], c.g[static_cast<std::size_t>(i)],
                        1e-6 * L)
                << c.label;
            EXPECT_NEAR(g[static_cast<std::size_t>(i)], c.g[static_cast<std::size_t>(i)], 1e-4 * L)
                << c.label;
        }
    }
}

class MeshCsgStl : public pd_test::StlDir {};

TEST_F(MeshCsgStl, SurfaceMeshInCsgGridOnly) {
    pd_test::write_binary_stl(path("cube.stl"), pd_test::cube(2, {-1, -1, -1}));
    const Shape s = Shape::difference(Shape::surface_mesh(path("cube.stl")),
                                      {Shape::sphere(0.5).translated(1, 1, 1)});
    try {
        (void)mesh::mesh_shape(s, 0.2);
        ADD_FAILURE() << "gmsh meshed a CSG with a surface mesh";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("\"grid\""), std::string::npos) << e.what();
    }
    const Sums r = discretise(s, 0.1, true);
    EXPECT_NEAR(r.volume / s.area_or_volume(), 1.0, 0.01);
}

} // namespace
