// SPDX-License-Identifier: MIT
// Shape: factories with input checks, exact measures of primitives, CSG evaluated on the tree
// (containment) or on the exact Boolean result of the polygonal boundaries (2D area, centroid,
// distance; region.cpp) or by octree quadrature (3D volume, centroid); closed surface meshes
// (solid.cpp). Derived quantities are computed once, when a shape is made or placed.
#include "geometry/shapes.hpp"

#include "core/errors.hpp"
#include "geometry/shape_node.hpp"

#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>

namespace pd::geometry {

using detail::Region;
using detail::Ring;
using detail::Solid;
using namespace detail;

// ------------------------------------------------------------------------------------------------
Vec3 Placement::apply(const Vec3& x) const {
    if (theta == 0)
        return {x[0] + t[0], x[1] + t[1], x[2] + t[2]};
    const double c = std::cos(theta), s = std::sin(theta);
    return {c * x[0] - s * x[1] + t[0], s * x[0] + c * x[1] + t[1], x[2] + t[2]};
}

Vec3 Placement::apply_inverse(const Vec3& x) const {
    const double dx = x[0] - t[0], dy = x[1] - t[1], dz = x[2] - t[2];
    if (theta == 0)
        return {dx, dy, dz};
    const double c = std::cos(theta), s = std::sin(theta);
    return {c * dx + s * dy, -s * dx + c * dy, dz};
}

Placement Placement::compose(const Placement& other) const {
    return Placement{theta + other.theta, apply(other.t)};
}

// ------------------------------------------------------------------------------------------------
Shape Shape::circle(double r) {
    require_length("circle", "radius", r);
    return make(primitive(ShapeKind::circle, 2, {r}, fmt::format("circle(r={})", fmt_len(r))));
}

Shape Shape::ellipse(double a, double b) {
    require_length("ellipse", "semi-axis a", a);
    require_length("ellipse", "semi-axis b", b);
    return make(primitive(ShapeKind::ellipse, 2, {a, b},
                          fmt::format("ellipse(a={}, b={})", fmt_len(a), fmt_len(b))));
}

Shape Shape::regular_polygon(int n, double r, double phase) {
    if (n < 3)
        throw InputError(fmt::format("regular polygon: needs at least 3 sides, got {}", n));
    require_length("regular polygon", "circumradius", r);
    if (!std::isfinite(phase))
        throw InputError("regular polygon: phase must be finite");
    std::string label =
        n == 6 && phase == 0        ? fmt::format("hexagon(r={})", fmt_len(r))
        : n == 3 && phase == pi / 2 ? fmt::format("triangle(r={})", fmt_len(r))
        : n == 4 && phase == pi / 4
            ? fmt::format("square(r={})", fmt_len(r))
            : fmt::format("regular_polygon(n={}, r={}, phase={:g})", n, fmt_len(r), phase);
    Node node = primitive(ShapeKind::regular_polygon, 2, {double(n), r, phase}, std::move(label));
    for (int k = 0; k < n; ++k) {
        const double t = phase + 2 * pi * k / n;
        node.verts.push_back({r * std::cos(t), r * std::sin(t)});
    }
    return make(std::move(node));
}

Shape Shape::triangle(double r) {
    // Spec 2.5 lists (0, R), (-R cos30, -R sin30), (R cos30, -R sin30); exact values where exact.
    Shape s = regular_polygon(3, r, pi / 2);
    Node n = node_of(s);
    const double c30 = std::sqrt(3.0) / 2;
    n.verts = {{0, r}, {-r * c30, -0.5 * r}, {r * c30, -0.5 * r}};
    return make(std::move(n));
}

Shape Shape::square(double r) {
    return regular_polygon(4, r, pi / 4);
}
Shape Shape::hexagon(double r) {
    return regular_polygon(6, r, 0);
}

Shape Shape::rectangle(double lx, double ly) {
    require_length("rectangle", "lx", lx);
    require_length("rectangle", "ly", ly);
    Node n = primitive(ShapeKind::rectangle, 2, {lx, ly},
                       fmt::format("rectangle(lx={}, ly={})", fmt_len(lx), fmt_len(ly)));
    n.verts = {
        {-0.5 * lx, -0.5 * ly}, {0.5 * lx, -0.5 * ly}, {0.5 * lx, 0.5 * ly}, {-0.5 * lx, 0.5 * ly}};
    return make(std::move(n));
}

Shape Shape::rectangle_corners(double x0, double y0, double x1, double y1) {
    if (!(x1 > x0) || !(y1 > y0))
        throw InputError(fmt::format("rectangle: corners ({}, {}) and ({}, {}) need x1 > x0 and "
                                     "y1 > y0",
                                     x0, y0, x1, y1));
    return rectangle(x1 - x0, y1 - y0).translated(0.5 * (x0 + x1), 0.5 * (y0 + y1));
}

Shape Shape::drum2d(double r, double w) {
    require_length("drum2d", "radius", r);
    require_length("drum2d", "neck width", w);
    if (!(w < 2 * r))
        throw InputError(fmt::format("drum2d: neck width {} must be below 2 r = {}", w, 2 * r));
    Node n = primitive(ShapeKind::drum2d, 2, {r, w},
                       fmt::format("drum2d(r={}, w={})", fmt_len(r), fmt_len(w)));
    const double h = r * std::sqrt(3.0) / 2;
    n.verts = {{0.5 * w, 0},  {0.5 * r, h},   {-0.5 * r, h},
               {-0.5 * w, 0}, {-0.5 * r, -h}, {0.5 * r, -h}};
    return make(std::move(n));
}

Shape Shape::polygon(std::vector<Vec2> vertices) {
    if (vertices.size() > static_cast<std::size_t>(max_polygon_vertices))
        throw InputError(fmt::format("polygon: {} vertices, above the limit of {}", vertices.size(),
                                     max_polygon_vertices));
    Node n =
        primitive(ShapeKind::polygon, 2, {}, fmt::format("polygon({} vertices)", vertices.size()));
    // Validates (simple, non-degenerate) and fixes the orientation through a region.
    const Region check = Region::polygon(Ring(vertices.begin(), vertices.end()));
    if (polygon_moments(vertices).first < 0)
        std::reverse(vertices.begin(), vertices.end());
    n.verts = std::move(vertices);
    (void)check;
    return make(std::move(n));
}

namespace {
Shape csg(ShapeKind kind, std::vector<Shape> parts, const char* op) {
    std::vector<std::string> names;
    const int dim = parts.front().dimension();
    for (std::size_t i = 0; i < parts.size(); ++i) {
        if (parts[i].dimension() != dim)
            throw InputError(fmt::format("{}: operand 0 is {}D, operand {} ({}) is {}D", op, dim, i,
                                         parts[i].name(), parts[i].dimension()));
        names.push_back(parts[i].name());
    }
    Node n = primitive(kind, dim, {}, fmt::format("{}({})", op, fmt::join(names, ", ")));
    n.children = std::move(parts);
    return make(std::move(n));
}
} // namespace

Shape Shape::unite(std::vector<Shape> parts) {
    if (parts.size() < 2)
        throw InputError(fmt::format("unite: needs at least 2 shapes, got {}", parts.size()));
    return csg(ShapeKind::unite, std::move(parts), "unite");
}

Shape Shape::difference(Shape base, std::vector<Shape> tools) {
    if (tools.empty())
        throw InputError("difference: needs at least one shape to subtract");
    tools.insert(tools.begin(), std::move(base));
    return csg(ShapeKind::difference, std::move(tools), "difference");
}

Shape Shape::sphere(double r) {
    require_length("sphere", "radius", r);
    return make(primitive(ShapeKind::sphere, 3, {r}, fmt::format("sphere(r={})", fmt_len(r))));
}

Shape Shape::box(double lx, double ly, double lz) {
    require_length("box", "lx", lx);
    require_length("box", "ly", ly);
    require_length("box", "lz", lz);
    return make(
        primitive(ShapeKind::box, 3, {lx, ly, lz},
                  fmt::format("box(lx={}, ly={}, lz={})", fmt_len(lx), fmt_len(ly), fmt_len(lz))));
}

Shape Shape::cylinder(double r, double l) {
    require_length("cylinder", "radius", r);
    require_length("cylinder", "length", l);
    return make(primitive(ShapeKind::cylinder, 3, {r, l},
                          fmt::format("cylinder(r={}, l={})", fmt_len(r), fmt_len(l))));
}

Shape Shape::surface_mesh(const std::string& stl_path) {
    Node n = primitive(
        ShapeKind::surface_mesh, 3, {},
        fmt::format("surface_mesh({})", std::filesystem::path(stl_path).filename().string()));
    n.solid = std::make_shared<const Solid>(Solid::read_stl(stl_path));
    n.file = stl_path;
    return make(std::move(n));
}

// ------------------------------------------------------------------------------------------------
Shape Shape::translated(double dx, double dy, double dz) const {
    if (!std::isfinite(dx) || !std::isfinite(dy) || !std::isfinite(dz))
        throw InputError(fmt::format("{}: translation must be finite", name()));
    if (dimension() == 2 && dz != 0)
        throw InputError(
            fmt::format("{}: a 2D shape cannot be moved along z (dz = {})", name(), dz));
    Node n = *node_;
    n.place = Placement{0, {dx, dy, dz}}.compose(n.place);
    n.bounding_radius = farthest(n, n.place);
    n.box = bounds(n, n.place);
    return Shape(std::make_shared<const Node>(std::move(n)));
}

Shape Shape::rotated(double theta) const {
    if (!std::isfinite(theta))
        throw InputError(fmt::format("{}: rotation angle must be finite", name()));
    Node n = *node_;
    n.place = Placement{theta, {0, 0, 0}}.compose(n.place);
    n.bounding_radius = farthest(n, n.place);
    n.box = bounds(n, n.place);
    return Shape(std::make_shared<const Node>(std::move(n)));
}

Shape Shape::centered() const {
    const Vec3 c = centroid();
    return translated(-c[0], -c[1], -c[2]);
}

ShapeKind Shape::kind() const {
    return node_->kind;
}
int Shape::dimension() const {
    return node_->dim;
}

std::string Shape::name() const {
    const Placement& p = node_->place;
    if (p.is_identity())
        return node_->label;
    return fmt::format("{}@(t=({:g}, {:g}, {:g}), theta={:g})", node_->label, p.t[0], p.t[1],
                       p.t[2], p.theta);
}

double Shape::area_or_volume() const {
    return node_->measure;
}
Vec3 Shape::centroid() const {
    return node_->place.apply(node_->local_centroid);
}
double Shape::bounding_radius() const {
    return node_->bounding_radius;
}
std::array<double, 6> Shape::bounding_box() const {
    return node_->box;
}

bool Shape::contains(double x, double y, double z) const {
    const Vec3 X = node_->place.apply_inverse({x, y, node_->dim == 2 ? 0.0 : z});
    return classify(*node_, X) >= 0;
}

double Shape::clearance(double x, double y, double z) const {
    const Vec3 X = node_->place.apply_inverse({x, y, node_->dim == 2 ? 0.0 : z});
    return clearance_local(*node_, X);
}

const std::vector<double>& Shape::parameters() const {
    return node_->params;
}
const std::vector<Vec2>& Shape::vertices() const {
    return node_->verts;
}
const std::vector<Shape>& Shape::children() const {
    return node_->children;
}
const Placement& Shape::placement() const {
    return node_->place;
}

const std::vector<Vec3>& Shape::surface_vertices() const {
    static const std::vector<Vec3> none;
    return node_->solid ? node_->solid->vertices() : none;
}
const std::vector<std::array<std::int32_t, 3>>& Shape::surface_triangles() const {
    static const std::vector<std::array<std::int32_t, 3>> none;
    return node_->solid ? node_->solid->triangles() : none;
}
const std::string& Shape::source_file() const {
    return node_->file;
}

} // namespace pd::geometry
