// SPDX-License-Identifier: MIT
// Reference shapes of grains and containers (spec 2.5): 2D circle, ellipse, regular polygons,
// rectangle, drum2d, general polygons and their CSG unions/differences; 3D sphere, box, cylinder,
// closed surface meshes (STL) and their CSG unions/differences.
// A Shape is an immutable value (cheap to copy) that knows its exact area/volume, centroid,
// bounding radius and point containment. No CGAL here: exact polygon work is in region.cpp, exact
// surface-mesh work in solid.cpp.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pd::geometry {

using Vec2 = std::array<double, 2>;
using Vec3 = std::array<double, 3>;

enum class ShapeKind : std::uint8_t {
    circle,
    ellipse,
    regular_polygon, ///< includes triangle, square, hexagon
    rectangle,
    drum2d,
    polygon,
    unite,      ///< CSG union of two or more shapes
    difference, ///< CSG difference: first shape minus the others
    sphere,
    box,
    cylinder,
    surface_mesh, ///< solid bounded by a closed triangle surface (STL file)
};

/// Rigid placement x = R_z(theta) X + t of a shape's own frame in its parent frame.
struct Placement {
    double theta = 0; ///< rotation about the z axis through the origin, rad
    Vec3 t{0, 0, 0};  ///< translation, m
    Vec3 apply(const Vec3& x) const;
    Vec3 apply_inverse(const Vec3& x) const;
    /// The placement x -> this(other(x)).
    Placement compose(const Placement& other) const;
    bool is_identity() const { return theta == 0 && t[0] == 0 && t[1] == 0 && t[2] == 0; }
};

/// Number of polygon vertices used for a full circle or ellipse wherever a curved boundary must be
/// made polygonal (CSG areas and centroids, distance to curved boundaries). The polygon is
/// inscribed, so the boundary moves inwards by at most R (1 - cos(pi/n)) = 4.7e-6 R and a
/// circle's area is low by 2 pi^2 / (3 n^2) = 6.3e-6 (relative).
inline constexpr int curve_segments = 1024;

/// 3D CSG volume and centroid: the bounding cube is refined as an octree down to cells of side
/// L / 2^csg_octree_depth (L the longest bounding-box side) wherever the cell may cross the
/// boundary (|clearance(centre)| < half diagonal, rigorous since the CSG clearance is a
/// 1-Lipschitz bound of the distance); boundary cells at the finest level count with the fraction
/// 1/2 + clearance / side (exact for a face-parallel plane). Measured volume errors 5e-5 (union
/// of two spheres against the lens formula) and 3e-5 (box minus cylinder), centroid errors below
/// 1e-5 of the size (tests/unit/geometry/test_solids.cpp); cost ~0.1 s for primitives, ~1 s with
/// a surface-mesh part (AABB distance queries).
inline constexpr int csg_octree_depth = 8;

/// Limits on the work of building a shape (issue 27), which pd-pack counts from the scene before
/// any shape is built (pipeline/scene/shape_budget.cpp) and refuses above: a 2D union/difference
/// costs its exact Boolean operations (each CSG node rebuilds its subtree, then joins or
/// subtracts child after child against a result holding up to all their vertices: measured
/// 1-3.5e-5 s per vertex operation, 30 disjoint circles 9.2e5 in 12 s, 100 in 209 s), a 3D one
/// its octree (each CSG node evaluates every part of its subtree at each cell: about 16 ms per
/// part evaluation, 125 spheres in 2.5 s; a surface_mesh part counts surface_mesh_weight).
/// A polygon's vertices (its boundary in every Boolean operation, containment and distance
/// query, and gmsh's points): at most as many as a regular_polygon's sides.
inline constexpr int max_polygon_vertices = 10000;
/// Parts (leaves) of one union/difference tree.
inline constexpr int max_csg_parts = 256;
/// Vertex operations (2D) of the scene's unions and differences together: sum over the CSG
/// nodes of (children x the boundary vertices below it); about 3-10 s at the limit. The largest
/// example (attrition_sim1) needs 4.1e3, ten disjoint circles 1e5.
inline constexpr double max_csg_vertex_work = 3e5;
/// Part evaluations (3D) of the scene's unions and differences together: sum over the CSG nodes
/// of the parts below it; about 8 s at the limit.
inline constexpr double max_csg_part_work = 512;
/// What one surface_mesh part counts in those (its AABB distance queries against a primitive's
/// formula: ~1 s against ~0.1 s, see csg_octree_depth).
inline constexpr double surface_mesh_weight = 10;

/// A shape in its own frame (lengths in m). The **reference point is the frame origin**: every
/// grain primitive is centred so that its centroid (and the centre of its bounding circle) is the
/// origin, as PeriDEM rotates reference meshes about the origin (spec 2.5). Polygons given by
/// vertices and CSG shapes keep the coordinates they are given; use centered() to move their
/// centroid to the origin (e.g. for grains), keep them as they are for containers and walls.
class Shape {
  public:
    // ---- 2D primitives (the z coordinate is ignored by 2D queries).
    /// Disc of radius r.
    static Shape circle(double r);
    /// Ellipse with semi-axis a along x and b along y.
    static Shape ellipse(double a, double b);
    /// Regular n-gon with circumradius r; vertex k at angle phase + 2 pi k / n. The default phase
    /// puts a vertex on the +x axis (PeriDEM's hexagon).
    static Shape regular_polygon(int n, double r, double phase = 0);
    /// Equilateral triangle, circumradius r, vertices (0, r), (-r cos30, -r sin30), (r cos30,
    /// -r sin30) (spec 2.5).
    static Shape triangle(double r);
    /// Axis-aligned square with circumradius r (side r sqrt 2), vertices at 45 + k 90 degrees.
    static Shape square(double r);
    /// Regular hexagon, circumradius r, a vertex on +x (spec 2.5).
    static Shape hexagon(double r);
    /// Axis-aligned rectangle lx by ly centred at the origin.
    static Shape rectangle(double lx, double ly);
    /// Axis-aligned rectangle with corners (x0, y0) and (x1, y1) (kept where it is).
    static Shape rectangle_corners(double x0, double y0, double x1, double y1);
    /// PeriDEM's concave drum, bounding radius r, full neck width w (0 < w < r): vertices
    /// (w/2, 0), (r/2, r sqrt3/2), (-r/2, r sqrt3/2), (-w/2, 0), (-r/2, -r sqrt3/2),
    /// (r/2, -r sqrt3/2) (spec 2.5).
    static Shape drum2d(double r, double w);
    /// Simple polygon (3 to max_polygon_vertices vertices, no self-intersection, CW or CCW; stored
    /// CCW).
    static Shape polygon(std::vector<Vec2> vertices);

    // ---- CSG (2D or 3D; all parts of one dimension). Children keep their placements (use
    // translated()/rotated()). Containment is exact on the tree in both cases.
    /// Union of parts (at least 2). 2D: its area and centroid come from the exact Boolean union of
    /// the polygonal boundaries (curves as inscribed polygons, see curve_segments). 3D: from an
    /// adaptive octree over the tree's signed distance bound, see csg_octree_depth.
    static Shape unite(std::vector<Shape> parts);
    /// base minus every tool (at least 1), e.g. annulus = difference(circle(21e-3),
    /// {circle(20e-3)}).
    static Shape difference(Shape base, std::vector<Shape> tools);

    // ---- 3D primitives, centred at the origin.
    static Shape sphere(double r);
    /// Axis-aligned box lx by ly by lz.
    static Shape box(double lx, double ly, double lz);
    /// Cylinder of radius r, axis z, z in [-l/2, l/2].
    static Shape cylinder(double r, double l);
    /// Solid bounded by the closed triangle surface in an STL file (ASCII or binary), kept in the
    /// file's coordinates (use centered() for grains). Volume and centroid are exact for the
    /// polyhedron (divergence theorem), containment and clearance exact (CGAL). Throws InputError
    /// naming the file if it is missing, unreadable, open, not a 2-manifold, self-intersecting or
    /// degenerate.
    static Shape surface_mesh(const std::string& stl_path);

    // ---- placement
    /// This shape moved by (dx, dy, dz) m (dz must be 0 for a 2D shape).
    Shape translated(double dx, double dy, double dz = 0) const;
    /// This shape rotated by theta rad about the z axis through the origin.
    Shape rotated(double theta) const;
    /// This shape translated so that its centroid is the origin.
    Shape centered() const;

    // ---- queries: about the placed shape, i.e. after placement() is applied
    ShapeKind kind() const;
    int dimension() const; ///< 2 or 3
    /// Short description, e.g. "hexagon(r=0.001)" or "difference(circle(r=0.021), circle(r=0.02))".
    std::string name() const;
    /// Exact area (2D, m2) or volume (3D, m3). Circles pi r^2, ellipses pi a b, polygons by the
    /// shoelace formula, surface meshes by the divergence theorem. 2D CSG: from the Boolean
    /// result; with curved parts it is low by at most 6.3e-6 relative to the curved parts' areas
    /// (curve_segments). 3D CSG: octree quadrature (csg_octree_depth).
    double area_or_volume() const;
    /// Centroid, m (exact for primitives and polygons; CSG as area_or_volume()).
    Vec3 centroid() const;
    /// Maximum distance of the shape from the frame origin (the reference point), m. Exact for
    /// primitives and surface meshes (also translated/rotated) and unions of them; for a 2D
    /// difference with curved parts an upper bound within 5e-6 of the curved radii, for a 3D
    /// difference the base's (an upper bound).
    double bounding_radius() const;
    /// An axis-aligned box containing the shape: {xmin, ymin, zmin, xmax, ymax, zmax}, m (exact
    /// for unrotated primitives; 2D shapes have z range [0, 0]).
    std::array<double, 6> bounding_box() const;
    /// True if the point lies in the closed shape. Exact for circles, ellipses, rectangles, 3D
    /// primitives and their CSG (evaluated on the tree, no polygonisation); polygons and surface
    /// meshes use CGAL's exact predicates.
    bool contains(double x, double y, double z = 0) const;
    /// Signed distance to the boundary, m: positive inside, negative outside. Exact for circles,
    /// rectangles, polygons, 3D primitives and surface meshes (AABB tree); for ellipses and 2D CSG
    /// the distance to the polygonal boundary (CGAL squared distance) made conservative (never
    /// larger than the true value) by the polygonisation tolerance, cost O(boundary edges); for
    /// 3D CSG max (union) / min (difference) of the parts' values, never larger in magnitude than
    /// the true distance.
    double clearance(double x, double y, double z = 0) const;

    // ---- structure (for meshers)
    /// Kind-specific parameters in the shape's own frame (before placement()): circle {r}; ellipse
    /// {a, b}; regular_polygon {n, r, phase}; rectangle {lx, ly}; drum2d {r, w}; sphere {r}; box
    /// {lx, ly, lz}; cylinder {r, l}; polygon and CSG {}.
    const std::vector<double>& parameters() const;
    /// Vertices (CCW, own frame) of polygonal kinds (regular_polygon, rectangle, drum2d, polygon).
    const std::vector<Vec2>& vertices() const;
    /// CSG operands: for difference, the base first.
    const std::vector<Shape>& children() const;
    /// surface_mesh: vertices (own frame, m) and outward-oriented triangles of the closed surface,
    /// and the file it was read from; empty for other kinds.
    const std::vector<Vec3>& surface_vertices() const;
    const std::vector<std::array<std::int32_t, 3>>& surface_triangles() const;
    const std::string& source_file() const;
    /// Placement of this shape's own frame in the frame of whoever holds it (identity for shapes
    /// made by the factories; set by translated()/rotated()).
    const Placement& placement() const;

    struct Node; ///< implementation (shapes.cpp)

  private:
    friend struct ShapeAccess;
    explicit Shape(std::shared_ptr<const Node> node)
        : node_(std::move(node)) {}
    std::shared_ptr<const Node> node_;
};

} // namespace pd::geometry
