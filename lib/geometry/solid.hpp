// SPDX-License-Identifier: MIT
// Closed triangle surfaces (3D solids bounded by a surface mesh, e.g. an STL file) for the
// geometry module: validation, exact volume and centroid (divergence theorem), containment and
// distance to the surface. Doubles in, doubles out; CGAL (Surface_mesh, Polygon_mesh_processing,
// AABB tree) lives only in solid.cpp. Internal to pd::geometry: other modules use Shape.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pd::geometry::detail {

using Point3 = std::array<double, 3>;
using Triangle = std::array<std::int32_t, 3>;

/// A solid bounded by a closed, 2-manifold, non-self-intersecting triangle surface (several
/// components and cavities allowed). Immutable, cheap to copy.
class Solid {
  public:
    /// Reads an ASCII or binary STL file (identical vertices are merged). Throws InputError naming
    /// `path` if it cannot be read, holds no triangles, degenerate triangles, is not a 2-manifold
    /// (an edge shared by more than two triangles, inconsistent orientation), is open (border
    /// edges), intersects itself or bounds no volume.
    static Solid read_stl(const std::string& path);
    /// The same checks on an indexed triangle soup; `what` names it in messages.
    static Solid from_triangles(std::vector<Point3> vertices, std::vector<Triangle> triangles,
                                const std::string& what);

    double volume() const;   ///< m3, exact for the polyhedron (sum of signed tetrahedra)
    Point3 centroid() const; ///< m, exact for the polyhedron
    /// +1 inside, 0 on the surface, -1 outside (CGAL Side_of_triangle_mesh: ray casting with
    /// exact predicates on the double vertices).
    int classify(const Point3& p) const;
    /// Unsigned distance from p to the nearest surface triangle, m (AABB tree).
    double surface_distance(const Point3& p) const;
    /// Vertices and outward-oriented triangles (after merging, orientation fixed).
    const std::vector<Point3>& vertices() const;
    const std::vector<Triangle>& triangles() const;

  private:
    struct Impl;
    explicit Solid(std::shared_ptr<const Impl> impl)
        : impl_(std::move(impl)) {}
    std::shared_ptr<const Impl> impl_;
};

} // namespace pd::geometry::detail
