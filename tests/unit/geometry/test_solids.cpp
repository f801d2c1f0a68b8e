// SPDX-License-Identifier: MIT
// 3D shapes beyond the primitives: closed surface meshes read from STL files (ASCII and binary;
// exact polyhedron volume and centroid, containment, clearance, placement, bad files) and 3D CSG
// (union of two spheres against the lens formula, a box with a cylindrical hole, exact
// containment on the tree, placement).
#include "core/errors.hpp"
#include "geometry/shapes.hpp"
#include "stl_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace {

using namespace pd;
using geometry::Shape;
using pd_test::StlDir;
constexpr double mm = 1e-3;
constexpr double pi = std::numbers::pi;

double rel(double a, double b) {
    return std::abs(a / b - 1);
}
double dist(const geometry::Vec3& a, const geometry::Vec3& b) {
    return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

class SurfaceMesh : public StlDir {};

TEST_F(SurfaceMesh, IcosphereVolumeCentroidExact) {
    // 1280 triangles on a sphere of radius 1 mm about c; the polyhedron is inscribed, so its
    // volume is below the ball's and is compared with its own exact value.
    const pd_test::V3 c{0.4 * mm, -0.2 * mm, 0.7 * mm};
    const auto ico = pd_test::icosphere(1 * mm, 3, c);
    pd_test::write_ascii_stl(path("ico.stl"), ico);
    const Shape s = Shape::surface_mesh(path("ico.stl"));
    const auto [v, g] = pd_test::moments(ico);
    EXPECT_EQ(s.kind(), geometry::ShapeKind::surface_mesh);
    EXPECT_EQ(s.dimension(), 3);
    EXPECT_EQ(s.surface_vertices().size(), ico.v.size()); // duplicates merged
    EXPECT_EQ(s.surface_triangles().size(), 1280u);
    std::printf("[ stl      ] icosphere 1280 tri: volume %.6e m3 (polyhedron %.6e, ball %.6e), "
                "centroid error %.2e m\n",
                s.area_or_volume(), v, 4.0 / 3 * pi * std::pow(mm, 3), dist(s.centroid(), c));
    EXPECT_LT(rel(s.area_or_volume(), v), 1e-12);
    EXPECT_LT(rel(v, 4.0 / 3 * pi * std::pow(mm, 3)), 0.01); // the fixture is a sphere
    EXPECT_LT(dist(s.centroid(), g), 1e-15);
    EXPECT_LT(dist(s.centroid(), c), 1e-15);
    // Bounding radius (about the file origin) = farthest vertex, below |c| + r.
    double far = 0;
    for (const auto& p : ico.v)
        far = std::max(far, std::hypot(p[0], p[1], p[2]));
    EXPECT_NEAR(s.bounding_radius(), far, 1e-18);
    EXPECT_LT(s.bounding_radius(), std::hypot(c[0], c[1], c[2]) + mm);
    const auto b = s.bounding_box();
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(b[static_cast<std::size_t>(i)], c[static_cast<std::size_t>(i)] - mm, 1e-15);
        EXPECT_NEAR(b[static_cast<std::size_t>(i) + 3], c[static_cast<std::size_t>(i)] + mm, 1e-15);
    }
    EXPECT_TRUE(s.contains(c[0], c[1], c[2]));
    EXPECT_TRUE(s.contains(c[0] + 0.95 * mm, c[1], c[2]));
    EXPECT_FALSE(s.contains(c[0] + 1.01 * mm, c[1], c[2]));
    EXPECT_NEAR(s.clearance(c[0], c[1], c[2]), mm, 0.01 * mm); // inscribed: within the sagitta
    const Shape centred = s.centered();
    EXPECT_LT(dist(centred.centroid(), {0, 0, 0}), 1e-15);
    EXPECT_NEAR(centred.bounding_radius(), mm, 1e-15);
}

TEST_F(SurfaceMesh, BinaryCubeAndTetrahedronExact) {
    // Coordinates exact in float32, so the binary file holds the geometry exactly.
    const auto cube = pd_test::cube(0.5, {0.25, -1, 2});
    pd_test::write_binary_stl(path("cube.stl"), cube);
    const Shape s = Shape::surface_mesh(path("cube.stl"));
    EXPECT_EQ(s.surface_vertices().size(), 8u);
    EXPECT_DOUBLE_EQ(s.area_or_volume(), 0.125);
    EXPECT_LT(dist(s.centroid(), {0.5, -0.75, 2.25}), 1e-15);
    // Clearance equals the box's exact signed distance.
    const Shape box = Shape::box(0.5, 0.5, 0.5).translated(0.5, -0.75, 2.25);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    for (int k = 0; k < 200; ++k) {
        const double x = 0.5 + u(rng), y = -0.75 + u(rng), z = 2.25 + u(rng);
        EXPECT_EQ(s.contains(x, y, z), box.contains(x, y, z)) << x << ' ' << y << ' ' << z;
        EXPECT_NEAR(s.clearance(x, y, z), box.clearance(x, y, z), 1e-14);
    }
    // A binary file whose header starts like an ASCII one.
    pd_test::write_binary_stl(path("solid_header.stl"), cube, "solid cube exported as binary");
    EXPECT_DOUBLE_EQ(Shape::surface_mesh(path("solid_header.stl")).area_or_volume(), 0.125);
    const auto tet = pd_test::tetrahedron({0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 3});
    pd_test::write_ascii_stl(path("tet.stl"), tet);
    const Shape t = Shape::surface_mesh(path("tet.stl"));
    EXPECT_NEAR(t.area_or_volume(), 1.0, 1e-15);
    EXPECT_LT(dist(t.centroid(), {0.25, 0.5, 0.75}), 1e-15);
}

TEST_F(SurfaceMesh, InvertedOrientationIsFixed) {
    auto cube = pd_test::cube(1);
    for (auto& t : cube.t)
        std::swap(t[1], t[2]); // every normal inwards
    pd_test::write_ascii_stl(path("inside_out.stl"), cube);
    const Shape s = Shape::surface_mesh(path("inside_out.stl"));
    EXPECT_DOUBLE_EQ(s.area_or_volume(), 1.0);
    EXPECT_TRUE(s.contains(0.5, 0.5, 0.5));
}

TEST_F(SurfaceMesh, RotationTranslationExact) {
    const auto ico = pd_test::icosphere(1.0, 2, {0.3, 0.1, -0.2});
    pd_test::write_ascii_stl(path("ico.stl"), ico);
    const Shape s = Shape::surface_mesh(path("ico.stl"));
    const double th = 0.7;
    const geometry::Vec3 t{2, -1, 0.5};
    const Shape p = s.rotated(th).translated(t[0], t[1], t[2]);
    EXPECT_EQ(p.area_or_volume(), s.area_or_volume());
    const auto c0 = s.centroid();
    const double co = std::cos(th), si = std::sin(th);
    const geometry::Vec3 expect{co * c0[0] - si * c0[1] + t[0], si * c0[0] + co * c0[1] + t[1],
                                c0[2] + t[2]};
    EXPECT_LT(dist(p.centroid(), expect), 1e-15);
    double far = 0;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.3, 1.3);
    for (const auto& v : ico.v) {
        const geometry::Vec3 q{co * v[0] - si * v[1] + t[0], si * v[0] + co * v[1] + t[1],
                               v[2] + t[2]};
        far = std::max(far, std::hypot(q[0], q[1], q[2]));
    }
    EXPECT_NEAR(p.bounding_radius(), far, 1e-14);
    for (int k = 0; k < 300; ++k) {
        const geometry::Vec3 X{0.3 + u(rng), 0.1 + u(rng), -0.2 + u(rng)};
        const geometry::Vec3 x{co * X[0] - si * X[1] + t[0], si * X[0] + co * X[1] + t[1],
                               X[2] + t[2]};
        EXPECT_EQ(p.contains(x[0], x[1], x[2]), s.contains(X[0], X[1], X[2]));
        EXPECT_NEAR(p.clearance(x[0], x[1], x[2]), s.clearance(X[0], X[1], X[2]), 1e-14);
    }
}

void expect_refused(const std::string& file, const std::vector<std::string>& words) {
    try {
        (void)Shape::surface_mesh(file);
        ADD_FAILURE() << "no error for " << file;
    } catch (const InputError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find(file), std::string::npos) << msg;
        for (const auto& w : words)
            EXPECT_NE(msg.find(w), std::string::npos) << msg;
    }
}

TEST_F(SurfaceMesh, BadFilesNameTheFile) {
    auto open = pd_test::cube(1);
    open.t.pop_back();
    pd_test::write_ascii_stl(path("open.stl"), open);
    expect_refused(path("open.stl"), {"open", "border edges"});
    expect_refused(path("missing.stl"), {"cannot open"});
    std::ofstream(path("garbage.stl"))
        << "solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0\n";
    expect_refused(path("garbage.stl"), {"not a readable STL"});
    // Two overlapping cubes in one file: closed and manifold, but self-intersecting.
    auto two = pd_test::cube(1);
    const auto b = pd_test::cube(1, {0.5, 0.5, 0.5});
    for (auto t : b.t) {
        for (auto& k : t)
            k += 8;
        two.t.push_back(t);
    }
    two.v.insert(two.v.end(), b.v.begin(), b.v.end());
    pd_test::write_ascii_stl(path("overlap.stl"), two);
    expect_refused(path("overlap.stl"), {"intersects itself"});
    // An edge shared by three triangles (a fin on the cube).
    auto fin = pd_test::cube(1);
    fin.v.push_back({0.5, -1, 0});
    fin.t.push_back({0, 1, 8});
    pd_test::write_ascii_stl(path("fin.stl"), fin);
    expect_refused(path("fin.stl"), {"2-manifold"});
}

// ------------------------------------------------------------------------------------------------
TEST(Csg3d, UnionOfTwoSpheresLensFormula) {
    const double r = 1 * mm, d = 1.2 * mm;
    const Shape u = Shape::unite({Shape::sphere(r), Shape::sphere(r).translated(d, 0, 0)});
    EXPECT_EQ(u.dimension(), 3);
    const double lens = pi * (4 * r + d) * (2 * r - d) * (2 * r - d) / 12;
    const double exact = 2 * 4.0 / 3 * pi * r * r * r - lens;
    std::printf("[ csg3d    ] two spheres: volume error %.2e, centroid error %.2e r\n",
                rel(u.area_or_volume(), exact), dist(u.centroid(), {d / 2, 0, 0}) / r);
    EXPECT_LT(rel(u.area_or_volume(), exact), 1e-3);
    EXPECT_LT(dist(u.centroid(), {d / 2, 0, 0}), 1e-3 * r);
    EXPECT_NEAR(u.bounding_radius(), d + r, 1e-15);
    // Containment on the tree: exact.
    EXPECT_TRUE(u.contains(d + 0.999 * r, 0, 0));
    EXPECT_FALSE(u.contains(d + 1.001 * r, 0, 0));
    EXPECT_TRUE(u.contains(d / 2, 0, std::sqrt(r * r - d * d / 4) * 0.999));
    EXPECT_FALSE(u.contains(d / 2, 0, std::sqrt(r * r - d * d / 4) * 1.001));
    // The clearance never exceeds the true distance: outside exact, in the neck a lower bound.
    EXPECT_NEAR(u.clearance(-2 * r, 0, 0), -r, 1e-15);
    EXPECT_NEAR(u.clearance(0, 0, 0), r, 1e-15);
    // A sphere united with a ball inside it is that sphere (the quadrature alone).
    const Shape same =
        Shape::unite({Shape::sphere(r), Shape::sphere(0.3 * r).translated(0.2 * r, 0, 0)});
    std::printf("[ csg3d    ] sphere by octree: volume error %.2e\n",
                rel(same.area_or_volume(), 4.0 / 3 * pi * r * r * r));
    EXPECT_LT(rel(same.area_or_volume(), 4.0 / 3 * pi * r * r * r), 1e-3);
    EXPECT_LT(dist(same.centroid(), {0, 0, 0}), 1e-4 * r);
}

TEST(Csg3d, BoxMinusCylinder) {
    const double lx = 4 * mm, ly = 3 * mm, lz = 2 * mm, r = 0.8 * mm, e = 0.6 * mm;
    const Shape s =
        Shape::difference(Shape::box(lx, ly, lz), {Shape::cylinder(r, 3 * lz).translated(e, 0, 0)});
    const double hole = pi * r * r * lz, exact = lx * ly * lz - hole;
    const geometry::Vec3 g{-hole * e / exact, 0, 0};
    std::printf("[ csg3d    ] box - cylinder: volume error %.2e, centroid error %.2e m\n",
                rel(s.area_or_volume(), exact), dist(s.centroid(), g));
    EXPECT_LT(rel(s.area_or_volume(), exact), 1e-3);
    EXPECT_LT(dist(s.centroid(), g), 1e-3 * mm);
    EXPECT_FALSE(s.contains(e, 0, 0));
    EXPECT_FALSE(s.contains(e + 0.999 * r, 0, 0.9 * lz / 2));
    EXPECT_TRUE(s.contains(e + 1.001 * r, 0, 0.9 * lz / 2));
    EXPECT_TRUE(s.contains(-lx / 2, -ly / 2, -lz / 2)); // closed: corners belong to it
    EXPECT_FALSE(s.contains(0, 0, lz));
    // Rotated and moved: the same volume, the centroid moved exactly.
    const double th = 0.4;
    const Shape p = s.rotated(th).translated(1 * mm, 2 * mm, 3 * mm);
    EXPECT_EQ(p.area_or_volume(), s.area_or_volume());
    const auto c = s.centroid();
    EXPECT_LT(
        dist(p.centroid(), {std::cos(th) * c[0] - std::sin(th) * c[1] + 1 * mm,
                            std::sin(th) * c[0] + std::cos(th) * c[1] + 2 * mm, c[2] + 3 * mm}),
        1e-18);
    EXPECT_TRUE(p.contains(1 * mm, 2 * mm + 1.2 * mm, 3 * mm)); // beside the hole, rotated frame
    EXPECT_FALSE(p.contains(1 * mm + std::cos(th) * e, 2 * mm + std::sin(th) * e, 3 * mm));
}

class Csg3dStl : public StlDir {};

TEST_F(Csg3dStl, SurfaceMeshInCsgAndMixedDimensions) {
    pd_test::write_binary_stl(path("cube.stl"), pd_test::cube(2, {-1, -1, -1}));
    const Shape cube = Shape::surface_mesh(path("cube.stl"));
    const Shape s = Shape::difference(cube, {Shape::sphere(0.5).translated(1, 1, 1)});
    const double exact = 8 - 4.0 / 3 * pi * 0.125 / 8; // an octant of the ball removed
    EXPECT_LT(rel(s.area_or_volume(), exact), 1e-3);
    EXPECT_FALSE(s.contains(0.9, 0.9, 0.9));
    EXPECT_TRUE(s.contains(0.1, 0.1, 0.1));
    EXPECT_THROW((void)Shape::unite({Shape::sphere(1), Shape::circle(1)}), InputError);
}

} // namespace
