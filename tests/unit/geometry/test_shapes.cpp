// SPDX-License-Identifier: MIT
// Shapes against closed forms: area/volume, centroid, bounding radius and box of every kind
// (also translated/rotated and CSG), contains() and clearance() on sample points, input errors.
#include "core/errors.hpp"
#include "geometry/shapes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace {

using pd::geometry::Shape;
using pd::geometry::Vec3;
constexpr double pi = std::numbers::pi;
const double s3 = std::sqrt(3.0);
constexpr double mm = 1e-3;

/// Relative tolerance of CSG with curved parts (inscribed 1024-gons).
constexpr double csg_rel = 1e-5;

void expect_centroid(const Shape& s, double x, double y, double z, double tol) {
    const Vec3 c = s.centroid();
    EXPECT_NEAR(c[0], x, tol) << s.name();
    EXPECT_NEAR(c[1], y, tol) << s.name();
    EXPECT_NEAR(c[2], z, tol) << s.name();
}

TEST(Shapes, PrimitiveAreasCentroidsRadii) {
    const double r = 1 * mm;
    struct Case {
        Shape s;
        double area, radius;
    };
    const double w = 0.4 * r;
    const Case cases[] = {
        {Shape::circle(r), pi * r * r, r},
        {Shape::ellipse(2 * r, r), pi * 2 * r * r, 2 * r},
        {Shape::ellipse(r, 3 * r), pi * 3 * r * r, 3 * r},
        {Shape::triangle(r), 3 * s3 / 4 * r * r, r},
        {Shape::square(r), 2 * r * r, r},
        {Shape::hexagon(r), 3 * s3 / 2 * r * r, r},
        {Shape::regular_polygon(5, r), 2.5 * r * r * std::sin(2 * pi / 5), r},
        {Shape::rectangle(3 * r, r), 3 * r * r, std::hypot(1.5 * r, 0.5 * r)},
        {Shape::drum2d(r, w), (w + r) * r * s3 / 2, r},
    };
    for (const auto& c : cases) {
        EXPECT_EQ(c.s.dimension(), 2);
        EXPECT_NEAR(c.s.area_or_volume() / c.area, 1.0, 1e-14) << c.s.name();
        expect_centroid(c.s, 0, 0, 0, 1e-15 * r);
        EXPECT_NEAR(c.s.bounding_radius(), c.radius, 1e-15 * r) << c.s.name();
    }
}

TEST(Shapes, VerticesFollowSpec) {
    const double r = 2.0;
    const auto tri = Shape::triangle(r).vertices();
    ASSERT_EQ(tri.size(), 3u);
    EXPECT_DOUBLE_EQ(tri[0][0], 0.0);
    EXPECT_DOUBLE_EQ(tri[0][1], r);
    EXPECT_DOUBLE_EQ(tri[1][0], -r * s3 / 2);
    EXPECT_DOUBLE_EQ(tri[1][1], -r / 2);
    const auto hex = Shape::hexagon(r).vertices();
    ASSERT_EQ(hex.size(), 6u);
    EXPECT_DOUBLE_EQ(hex[0][0], r); // a vertex on +x
    EXPECT_DOUBLE_EQ(hex[0][1], 0.0);
    const auto drum = Shape::drum2d(r, 0.5).vertices();
    ASSERT_EQ(drum.size(), 6u);
    EXPECT_DOUBLE_EQ(drum[0][0], 0.25);
    EXPECT_DOUBLE_EQ(drum[1][0], r / 2);
    EXPECT_DOUBLE_EQ(drum[1][1], r * s3 / 2);
}

TEST(Shapes, PolygonEitherOrientation) {
    // L-shape: [0,2]x[0,1] plus [0,1]x[1,2]; area 3, centroid (5/6, 5/6). Given clockwise.
    const Shape l = Shape::polygon({{0, 0}, {0, 2}, {1, 2}, {1, 1}, {2, 1}, {2, 0}});
    EXPECT_DOUBLE_EQ(l.area_or_volume(), 3.0);
    expect_centroid(l, 5.0 / 6, 5.0 / 6, 0, 1e-15);
    EXPECT_DOUBLE_EQ(l.bounding_radius(), std::sqrt(5.0));
    EXPECT_TRUE(l.contains(0.5, 1.5));
    EXPECT_FALSE(l.contains(1.5, 1.5));
    EXPECT_TRUE(l.contains(2, 0.5)); // boundary is part of the shape
    const Shape c = l.centered();
    expect_centroid(c, 0, 0, 0, 1e-15);
    EXPECT_NEAR(c.area_or_volume(), 3.0, 1e-14);
    EXPECT_TRUE(c.contains(0.5 - 5.0 / 6, 1.5 - 5.0 / 6));
}

TEST(Shapes, Solids) {
    const double r = 1.5, l = 4;
    const Shape sp = Shape::sphere(r), bx = Shape::box(1, 2, 3), cy = Shape::cylinder(r, l);
    EXPECT_EQ(sp.dimension(), 3);
    EXPECT_DOUBLE_EQ(sp.area_or_volume(), 4.0 / 3 * pi * r * r * r);
    EXPECT_DOUBLE_EQ(bx.area_or_volume(), 6.0);
    EXPECT_DOUBLE_EQ(cy.area_or_volume(), pi * r * r * l);
    EXPECT_DOUBLE_EQ(sp.bounding_radius(), r);
    EXPECT_DOUBLE_EQ(bx.bounding_radius(), std::sqrt(0.25 + 1 + 2.25));
    EXPECT_DOUBLE_EQ(cy.bounding_radius(), std::hypot(r, l / 2));
    EXPECT_TRUE(sp.contains(0, 0, r));
    EXPECT_FALSE(sp.contains(r, r, 0));
    EXPECT_TRUE(bx.contains(0.5, -1, 1.5));
    EXPECT_FALSE(bx.contains(0.5, -1, 1.6));
    EXPECT_TRUE(cy.contains(r / s3, r / s3, -l / 2));
    EXPECT_FALSE(cy.contains(r, r * 0.1, 0));
    EXPECT_DOUBLE_EQ(sp.clearance(0.5, 0, 0), r - 0.5);
    EXPECT_DOUBLE_EQ(bx.clearance(0, 0, 1), 0.5);
    EXPECT_DOUBLE_EQ(bx.clearance(0, 0, 2), -0.5);
    EXPECT_DOUBLE_EQ(cy.clearance(0, 0, 1.5), 0.5);
    EXPECT_DOUBLE_EQ(cy.clearance(r + 3, 0, l / 2 + 4), -5.0);
    // Translated solids: exact bounding radii and centroids.
    const Shape t = cy.translated(3, 4, 1).rotated(pi / 2);
    expect_centroid(t, -4, 3, 1, 1e-14);
    EXPECT_NEAR(t.bounding_radius(), std::hypot(5 + r, 1 + l / 2), 1e-14);
    EXPECT_TRUE(t.contains(-4, 3, 1 + l / 2));
    EXPECT_NEAR(sp.translated(1, 2, 2).bounding_radius(), 3 + r, 1e-15);
}

TEST(Shapes, PlacementMovesEverything) {
    const double r = 1;
    const Shape h = Shape::hexagon(r).rotated(pi / 6).translated(3, 4);
    EXPECT_NEAR(h.area_or_volume(), 3 * s3 / 2, 1e-14);
    expect_centroid(h, 3, 4, 0, 1e-14);
    // After a 30 degree turn a vertex points along (cos30, sin30): the farthest from the origin
    // is the vertex best aligned with (3, 4).
    double far = 0;
    for (int k = 0; k < 6; ++k) {
        const double t = pi / 6 + k * pi / 3;
        far = std::max(far, std::hypot(3 + std::cos(t), 4 + std::sin(t)));
    }
    EXPECT_NEAR(h.bounding_radius(), far, 1e-14);
    EXPECT_TRUE(h.contains(3, 4 + 0.99 * r)); // a vertex now points along +y
    EXPECT_FALSE(h.contains(3 + 0.9 * r, 4)); // and +x is the middle of a side
    const Shape c = Shape::circle(2).translated(3, 4);
    EXPECT_DOUBLE_EQ(c.bounding_radius(), 7.0);
    const auto b = c.bounding_box();
    EXPECT_DOUBLE_EQ(b[0], 1.0);
    EXPECT_DOUBLE_EQ(b[4], 6.0);
    const Shape e = Shape::ellipse(2, 1).rotated(pi / 2);
    EXPECT_TRUE(e.contains(0, 1.9));
    EXPECT_FALSE(e.contains(1.9, 0));
    EXPECT_NEAR(e.bounding_box()[3], 1.0, 1e-15);
    EXPECT_NEAR(e.bounding_radius(), 2.0, 1e-15);
}

TEST(Shapes, ContainsAndClearancePrimitives) {
    const double r = 1;
    const Shape c = Shape::circle(r);
    EXPECT_TRUE(c.contains(r, 0));
    EXPECT_FALSE(c.contains(r * 1.000001, 0));
    EXPECT_DOUBLE_EQ(c.clearance(0.25, 0), 0.75);
    EXPECT_DOUBLE_EQ(c.clearance(3, 4), -4.0);
    const Shape h = Shape::hexagon(r);
    EXPECT_TRUE(h.contains(0.99 * r, 0));
    EXPECT_FALSE(h.contains(0, 0.9 * r)); // apothem r sqrt3/2 = 0.866 r
    EXPECT_NEAR(h.clearance(0, 0), r * s3 / 2, 1e-15);
    const Shape t = Shape::triangle(r);
    EXPECT_TRUE(t.contains(0, 0.99 * r));
    EXPECT_FALSE(t.contains(0, -0.51 * r));
    EXPECT_NEAR(t.clearance(0, 0), r / 2, 1e-15); // inradius
    const double w = 0.5 * r;
    const Shape d = Shape::drum2d(r, w);
    EXPECT_TRUE(d.contains(0.24 * r, 0));
    EXPECT_FALSE(d.contains(0.26 * r, 0)); // the neck
    EXPECT_TRUE(d.contains(0.45 * r, 0.8 * r));
    const Shape e = Shape::ellipse(2, 1);
    EXPECT_TRUE(e.contains(1.99, 0));
    EXPECT_FALSE(e.contains(1.5, 0.7));        // 0.5625 + 0.49 > 1
    EXPECT_NEAR(e.clearance(0, 0), 1.0, 2e-5); // chord depth + tolerance of the 1024-gon
    EXPECT_LE(e.clearance(0, 0), 1.0);         // conservative
    const Shape rect = Shape::rectangle(4, 2);
    EXPECT_DOUBLE_EQ(rect.clearance(1, 0), 1.0);
    EXPECT_DOUBLE_EQ(rect.clearance(5, 4), -std::hypot(3, 3));
    const Shape rc = Shape::rectangle_corners(1, 2, 5, 3);
    expect_centroid(rc, 3, 2.5, 0, 1e-15);
    EXPECT_TRUE(rc.contains(1, 2));
    EXPECT_FALSE(rc.contains(0.99, 2.5));
}

TEST(Shapes, AnnulusAndDrumWithBar) {
    // Attrition drum (spec 8.5): annulus 20-21 mm, plus a bar [15, 20.5] x [-1.5, 1.5] mm.
    const Shape ring = Shape::difference(Shape::circle(21 * mm), {Shape::circle(20 * mm)});
    const double a_ring = pi * (21 * 21 - 20 * 20) * mm * mm;
    EXPECT_NEAR(ring.area_or_volume() / a_ring, 1.0, csg_rel);
    expect_centroid(ring, 0, 0, 0, 1e-9 * mm);
    EXPECT_DOUBLE_EQ(ring.bounding_radius(), 21 * mm);
    EXPECT_TRUE(ring.contains(20.5 * mm, 0));
    EXPECT_TRUE(ring.contains(0, -20 * mm)); // inner boundary belongs to the closed set
    EXPECT_FALSE(ring.contains(0, 0));
    EXPECT_FALSE(ring.contains(21.01 * mm, 0));
    EXPECT_NEAR(ring.clearance(0, 20.5 * mm), 0.5 * mm, 1e-4 * mm);
    EXPECT_LE(ring.clearance(0, 20.5 * mm), 0.5 * mm);
    EXPECT_NEAR(ring.clearance(0, 0), -20 * mm, 1e-3 * mm);

    const Shape bar = Shape::rectangle_corners(15 * mm, -1.5 * mm, 20.5 * mm, 1.5 * mm);
    const Shape drum = Shape::unite({ring, bar});
    // Extra area: the part of the bar inside r < 20 mm.
    const double R = 20, a = 1.5;
    const double extra = (a * std::sqrt(R * R - a * a) + R * R * std::asin(a / R) - 15 * 2 * a);
    const double mx = ((R * R - 225) * 2 * a - 2 * a * a * a / 3) / 2; // integral of x over it
    const double area = a_ring + extra * mm * mm;
    EXPECT_NEAR(drum.area_or_volume() / area, 1.0, csg_rel);
    expect_centroid(drum, mx * mm * mm * mm / area, 0, 0, csg_rel * drum.bounding_radius());
    EXPECT_TRUE(drum.contains(16 * mm, 0));
    EXPECT_FALSE(drum.contains(14.9 * mm, 0));
    EXPECT_DOUBLE_EQ(drum.bounding_radius(), 21 * mm);
}

TEST(Shapes, UChannelAndLens) {
    // PeriDEM's n500 U-wall (spec 8.3): outer minus inner rectangle sharing the top edge.
    const Shape u = Shape::difference(
        Shape::rectangle_corners(-0.82 * mm, -0.82 * mm, 69.32 * mm, 41.82 * mm),
        {Shape::rectangle_corners(-0.22 * mm, -0.22 * mm, 68.72 * mm, 41.82 * mm)});
    const double ao = 70.14 * 42.64, ai = 68.94 * 42.04;
    const double area = (ao - ai) * mm * mm;
    EXPECT_NEAR(u.area_or_volume() / area, 1.0, 1e-12);
    const double cx = (ao * 34.25 - ai * 34.25) / (ao - ai);
    const double cy = (ao * 20.5 - ai * 20.8) / (ao - ai);
    expect_centroid(u, cx * mm, cy * mm, 0, 1e-9 * mm);
    EXPECT_TRUE(u.contains(-0.5 * mm, 20 * mm));
    EXPECT_FALSE(u.contains(30 * mm, 20 * mm));
    EXPECT_NEAR(u.clearance(-0.52 * mm, 20 * mm), 0.3 * mm, 1e-12);

    // Union of two unit circles 1 apart: 2 pi - lens.
    const double d = 1;
    const Shape two = Shape::unite({Shape::circle(1), Shape::circle(1).translated(d, 0)});
    const double lens = 2 * std::acos(d / 2) - d / 2 * std::sqrt(4 - d * d);
    EXPECT_NEAR(two.area_or_volume() / (2 * pi - lens), 1.0, csg_rel);
    expect_centroid(two, 0.5, 0, 0, 1e-6);
    EXPECT_DOUBLE_EQ(two.bounding_radius(), 2.0);
    EXPECT_TRUE(two.contains(1.9, 0));
    // Nested CSG keeps exact containment: a lens cut out of the union.
    const Shape cut = Shape::difference(two, {Shape::circle(0.2).translated(0.5, 0)});
    EXPECT_FALSE(cut.contains(0.5, 0.1));
    EXPECT_TRUE(cut.contains(0.5, 0.21));
    EXPECT_NEAR(cut.area_or_volume() / (2 * pi - lens - pi * 0.04), 1.0, csg_rel);
    // Rotating a CSG shape rotates its children.
    const Shape rot = two.rotated(pi / 2);
    expect_centroid(rot, 0, 0.5, 0, 1e-6);
    EXPECT_TRUE(rot.contains(0, 1.9));
}

TEST(Shapes, BadInputIsInputError) {
    using pd::InputError;
    EXPECT_THROW(Shape::circle(0), InputError);
    EXPECT_THROW(Shape::circle(-1), InputError);
    EXPECT_THROW(Shape::circle(std::nan("")), InputError);
    EXPECT_THROW(Shape::ellipse(1, 0), InputError);
    EXPECT_THROW(Shape::regular_polygon(2, 1), InputError);
    EXPECT_THROW(Shape::drum2d(1, 2), InputError);
    EXPECT_THROW(Shape::rectangle_corners(1, 0, 0, 1), InputError);
    EXPECT_THROW(Shape::polygon({{0, 0}, {1, 1}}), InputError);
    EXPECT_THROW(Shape::polygon({{0, 0}, {1, 1}, {1, 0}, {0, 1}}), InputError); // bow tie
    EXPECT_THROW(Shape::polygon({{0, 0}, {1, 0}, {2, 0}}), InputError);         // collinear
    EXPECT_THROW(Shape::unite({Shape::circle(1)}), InputError);
    EXPECT_THROW(Shape::unite({Shape::circle(1), Shape::sphere(1)}), InputError);
    EXPECT_THROW(Shape::difference(Shape::circle(1), {}), InputError);
    EXPECT_THROW(Shape::difference(Shape::circle(1), {Shape::circle(2)}), InputError); // empty
    EXPECT_THROW(Shape::circle(1).translated(0, 0, 1), InputError);
    EXPECT_THROW(Shape::sphere(1).rotated(INFINITY), InputError);
    try {
        Shape::ellipse(1, -2);
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("semi-axis b"), std::string::npos) << e.what();
    }
}

} // namespace
