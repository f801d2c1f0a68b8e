// SPDX-License-Identifier: MIT
// The geometry module's CGAL translation unit for 3D: STL reading (CGAL::IO, ASCII and binary),
// manifold / closed / self-intersection checks and orientation (Polygon_mesh_processing),
// containment (Side_of_triangle_mesh) and distances (AABB tree), all on EPICK: exact predicates,
// double constructions. Volume and centroid are sums over the triangles (divergence theorem).
#include "geometry/solid.hpp"

#include "core/errors.hpp"
#include "core/files.hpp"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/STL.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace pd::geometry::detail {

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
using Inside = CGAL::Side_of_triangle_mesh<Mesh, K, CGAL::Default, Tree>;
namespace PMP = CGAL::Polygon_mesh_processing;
} // namespace

struct Solid::Impl {
    Mesh mesh;
    Tree tree;
    std::unique_ptr<Inside> inside;
    std::vector<Point3> vertices;
    std::vector<Triangle> triangles;
    double volume = 0;
    Point3 centroid{0, 0, 0};

    explicit Impl(Mesh m)
        : mesh(std::move(m)) {
        std::vector<std::int32_t> index(mesh.number_of_vertices(), -1);
        for (auto v : mesh.vertices()) {
            index[v.idx()] = static_cast<std::int32_t>(vertices.size());
            const Point& p = mesh.point(v);
            vertices.push_back({p.x(), p.y(), p.z()});
        }
        const Point3& o = vertices.front(); // reference point: fewer cancellations than (0,0,0)
        double v6 = 0, mx = 0, my = 0, mz = 0;
        for (auto f : mesh.faces()) {
            Triangle t{};
            int k = 0;
            for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
                t[static_cast<std::size_t>(k++)] = index[v.idx()];
            triangles.push_back(t);
            const Point3 &a = vertices[static_cast<std::size_t>(t[0])],
                         &b = vertices[static_cast<std::size_t>(t[1])],
                         &c = vertices[static_cast<std::size_t>(t[2])];
            const double u[3] = {a[0] - o[0], a[1] - o[1], a[2] - o[2]};
            const double w[3] = {b[0] - o[0], b[1] - o[1], b[2] - o[2]};
            const double z[3] = {c[0] - o[0], c[1] - o[1], c[2] - o[2]};
            const double det = u[0] * (w[1] * z[2] - w[2] * z[1]) -
                               u[1] * (w[0] * z[2] - w[2] * z[0]) +
                               u[2] * (w[0] * z[1] - w[1] * z[0]);
            v6 += det; // 6 x signed volume of the tetrahedron (o, a, b, c)
            mx += det * (u[0] + w[0] + z[0]);
            my += det * (u[1] + w[1] + z[1]);
            mz += det * (u[2] + w[2] + z[2]);
        }
        volume = v6 / 6;
        if (v6 > 0)
            centroid = {o[0] + mx / (4 * v6), o[1] + my / (4 * v6), o[2] + mz / (4 * v6)};
        tree.insert(faces(mesh).first, faces(mesh).second, mesh);
        tree.build();
        tree.accelerate_distance_queries();
        inside = std::make_unique<Inside>(tree, K());
    }
    Impl(const Impl&) = delete;
    Impl& operator=(const Impl&) = delete;
};

Solid Solid::from_triangles(std::vector<Point3> vertices, std::vector<Triangle> triangles,
                            const std::string& what) {
    if (triangles.empty())
        throw InputError(fmt::format("{}: no triangles", what));
    std::vector<Point> points;
    points.reserve(vertices.size());
    for (const auto& v : vertices) {
        if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
            throw InputError(fmt::format("{}: vertex coordinates must be finite", what));
        points.emplace_back(v[0], v[1], v[2]);
    }
    std::vector<std::vector<std::size_t>> soup;
    soup.reserve(triangles.size());
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        const auto& t = triangles[i];
        for (auto k : t)
            if (k < 0 || static_cast<std::size_t>(k) >= points.size())
                throw InputError(fmt::format("{}: triangle {} uses vertex {}, only {} vertices",
                                             what, i, k, points.size()));
        const auto &a = points[static_cast<std::size_t>(t[0])],
                   &b = points[static_cast<std::size_t>(t[1])],
                   &c = points[static_cast<std::size_t>(t[2])];
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || CGAL::collinear(a, b, c))
            throw InputError(fmt::format("{}: triangle {} is degenerate (zero area, vertices "
                                         "({}, {}, {}), ({}, {}, {}), ({}, {}, {}))",
                                         what, i, a.x(), a.y(), a.z(), b.x(), b.y(), b.z(), c.x(),
                                         c.y(), c.z()));
        soup.push_back({static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]),
                        static_cast<std::size_t>(t[2])});
    }
    const std::size_t npoints = points.size();
    // Consistent orientation; points are duplicated (-> false) where the soup is not a manifold.
    if (!PMP::orient_polygon_soup(points, soup) || points.size() != npoints ||
        !PMP::is_polygon_soup_a_polygon_mesh(soup))
        throw InputError(fmt::format("{}: the surface is not a 2-manifold (an edge is shared by "
                                     "more than two triangles, or triangles meet at a vertex "
                                     "only)",
                                     what));
    Mesh mesh;
    PMP::polygon_soup_to_polygon_mesh(points, soup, mesh);
    std::size_t border = 0;
    for (auto h : mesh.halfedges())
        border += mesh.is_border(h) ? 1 : 0;
    if (border > 0)
        throw InputError(fmt::format("{}: the surface is open ({} border edges); a surface_mesh "
                                     "must be closed (watertight)",
                                     what, border));
    if (PMP::does_self_intersect(mesh)) {
        std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
        PMP::self_intersections(mesh, std::back_inserter(pairs));
        throw InputError(fmt::format("{}: the surface intersects itself ({} pairs of triangles, "
                                     "e.g. triangles {} and {})",
                                     what, pairs.size(), pairs.empty() ? 0 : pairs[0].first.idx(),
                                     pairs.empty() ? 0 : pairs[0].second.idx()));
    }
    PMP::orient_to_bound_a_volume(mesh);
    auto impl = std::make_shared<Impl>(std::move(mesh));
    if (!(impl->volume > 0))
        throw InputError(fmt::format("{}: the surface bounds no volume", what));
    return Solid(std::move(impl));
}

Solid Solid::read_stl(const std::string& path) {
    note_input("STL file", path);
    if (!std::filesystem::is_regular_file(path) || !std::ifstream(path))
        throw InputError(fmt::format("cannot open STL file '{}'", path));
    std::vector<Point> points;
    std::vector<std::array<std::size_t, 3>> tris;
    if (!CGAL::IO::read_STL(path, points, tris) || tris.empty())
        throw InputError(fmt::format("'{}': not a readable STL file (ASCII or binary) with "
                                     "triangles",
                                     path));
    std::vector<Point3> v;
    v.reserve(points.size());
    for (const auto& p : points)
        v.push_back({p.x(), p.y(), p.z()});
    std::vector<Triangle> t;
    t.reserve(tris.size());
    for (const auto& q : tris)
        t.push_back({static_cast<std::int32_t>(q[0]), static_cast<std::int32_t>(q[1]),
                     static_cast<std::int32_t>(q[2])});
    return from_triangles(std::move(v), std::move(t), fmt::format("STL file '{}'", path));
}

double Solid::volume() const {
    return impl_->volume;
}
Point3 Solid::centroid() const {
    return impl_->centroid;
}
const std::vector<Point3>& Solid::vertices() const {
    return impl_->vertices;
}
const std::vector<Triangle>& Solid::triangles() const {
    return impl_->triangles;
}

int Solid::classify(const Point3& p) const {
    switch ((*impl_->inside)(Point(p[0], p[1], p[2]))) {
    case CGAL::ON_BOUNDED_SIDE:
        return 1;
    case CGAL::ON_BOUNDARY:
        return 0;
    default:
        return -1;
    }
}

double Solid::surface_distance(const Point3& p) const {
    return std::sqrt(impl_->tree.squared_distance(Point(p[0], p[1], p[2])));
}

} // namespace pd::geometry::detail
