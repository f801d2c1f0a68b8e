// SPDX-License-Identifier: MIT
// Polygonal regions (polygons with holes) for the geometry module: Boolean union/difference,
// area, centroid, containment and distance to the boundary. Doubles in, doubles out; CGAL lives
// only in region.cpp (the module's 2D CGAL translation unit, STYLE 2.1 "inside.cpp"; 3D:
// solid.cpp). Internal to pd::geometry: other modules use Shape.
#pragma once

#include <array>
#include <memory>
#include <vector>

namespace pd::geometry::detail {

using Ring = std::vector<std::array<double, 2>>;

/// A closed polygonal region, possibly several components with holes. Immutable, cheap to copy.
class Region {
  public:
    /// The region bounded by a simple polygon (CW or CCW). Throws InputError if it has fewer than
    /// 3 vertices, repeated vertices, zero area or self-intersections.
    static Region polygon(const Ring& vertices);
    /// Exact Boolean union / difference (CGAL, exact constructions).
    static Region unite(const Region& a, const Region& b);
    static Region subtract(const Region& a, const Region& b);

    bool empty() const;
    double area() const;                    ///< m2
    std::array<double, 2> centroid() const; ///< m; (0, 0) if empty
    /// +1 inside, 0 on the boundary, -1 outside (exact predicates on the double vertices).
    int classify(double x, double y) const;
    /// Unsigned distance from (x, y) to the nearest boundary edge, m (O(edges)).
    double boundary_distance(double x, double y) const;
    /// Every boundary ring (outer boundaries CCW, holes CW), vertices as doubles.
    const std::vector<Ring>& rings() const;

  private:
    struct Impl;
    explicit Region(std::shared_ptr<const Impl> impl)
        : impl_(std::move(impl)) {}
    std::shared_ptr<const Impl> impl_;
};

} // namespace pd::geometry::detail
