// SPDX-License-Identifier: MIT
// The node behind a Shape (internal to lib/geometry/shapes.cpp and shape_node.cpp): its
// parameters, placement and derived measures, and the geometry evaluated on the CSG tree.
#pragma once

#include "geometry/region.hpp"
#include "geometry/shapes.hpp"
#include "geometry/solid.hpp"

#include <array>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace pd::geometry {

struct Shape::Node {
    ShapeKind kind = ShapeKind::circle;
    int dim = 2;
    std::vector<double> params;
    std::vector<Vec2> verts;
    std::vector<Shape> children;
    Placement place;
    std::string label;
    std::string file; ///< surface_mesh: the STL path
    // Derived, in the node's own frame.
    double measure = 0;
    Vec3 local_centroid{0, 0, 0};
    std::shared_ptr<const detail::Region>
        region;                                 ///< ellipse, polygonal kinds but rectangle, 2D CSG
    std::shared_ptr<const detail::Solid> solid; ///< surface_mesh
    double tol = 0; ///< how far the region's boundary may lie inside the true boundary, m
    // Derived, after placement.
    double bounding_radius = 0;
    std::array<double, 6> box{};
};

struct ShapeAccess {
    static const Shape::Node& node(const Shape& s) { return *s.node_; }
    static Shape make(std::shared_ptr<const Shape::Node> n) { return Shape(std::move(n)); }
};

namespace detail {

using Node = Shape::Node;
inline constexpr double pi = std::numbers::pi;

const Node& node_of(const Shape& s);

/// InputError unless v is a positive finite length.
void require_length(const std::string& shape, const char* what, double v);

/// Shoelace area and centroid of a CCW ring.
std::pair<double, Vec2> polygon_moments(const std::vector<Vec2>& v);

/// Largest |P(X)| over the points X of the node (P maps the node's own frame to the target).
double farthest(const Node& n, const Placement& P);

/// Axis-aligned bounding box of the node mapped by P.
std::array<double, 6> bounds(const Node& n, const Placement& P);

/// +1 inside, 0 on the boundary, -1 outside; X in the node's own frame.
int classify(const Node& n, const Vec3& X);

/// clearance() in the node's own frame.
double clearance_local(const Node& n, const Vec3& X);

/// A length for shape labels.
std::string fmt_len(double v);

/// A node of a primitive kind, derived fields unset.
Node primitive(ShapeKind kind, int dim, std::vector<double> params, std::string label);

/// The shape of node `n`, its derived fields filled.
Shape make(Node n);

} // namespace detail

} // namespace pd::geometry
