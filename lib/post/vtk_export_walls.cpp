// SPDX-License-Identifier: MIT
// Rigid-wall outlines (see vtk_export_walls.hpp). No VTK here: xdmf.cpp uses them too.
#include "post/vtk_export_walls.hpp"

#include "model/functions.hpp"
#include "model/wall_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace pd::post {

namespace {

using V3 = std::array<double, 3>;

V3 cross(const V3& a, const V3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const V3& a, const V3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
V3 unit(const V3& a) {
    const double n = std::sqrt(dot(a, a));
    return n > 0 ? V3{a[0] / n, a[1] / n, a[2] / n} : a;
}

/// Rotation of v by the rotation vector theta (Rodrigues), as solver/walls.cpp.
V3 rotate(const V3& v, const V3& theta) {
    const double a = std::sqrt(dot(theta, theta));
    if (a == 0)
        return v;
    const V3 k{theta[0] / a, theta[1] / a, theta[2] / a};
    const double c = std::cos(a), s = std::sin(a), kv = dot(k, v);
    const V3 kxv = cross(k, v);
    V3 r;
    for (int d = 0; d < 3; ++d)
        r[d] = v[d] * c + kxv[d] * s + k[d] * kv * (1 - c);
    return r;
}

/// The wall's pose at time t: as solver::wall_pose (kept equal by a unit test).
struct Pose {
    V3 point, normal, centre, velocity, omega, theta;
};
Pose pose(const model::Wall& w, double t) {
    Pose p;
    double rate = 0;
    const double T = model::wall_time(w, t, &rate); // at rest before its start_time
    for (int d = 0; d < 3; ++d) {
        p.theta[d] = w.angular_velocity[d] * T;
        p.centre[d] = w.centre[d] + w.velocity[d] * T;
        p.velocity[d] = w.velocity[d] * rate;
        p.omega[d] = w.angular_velocity[d] * rate;
    }
    const V3 rel = rotate(
        {w.point[0] - w.centre[0], w.point[1] - w.centre[1], w.point[2] - w.centre[2]}, p.theta);
    for (int d = 0; d < 3; ++d)
        p.point[d] = p.centre[d] + rel[d];
    p.normal = rotate(w.normal, p.theta);
    return p;
}

void add_point(WallOutline& o, const Pose& p, const V3& x) {
    const V3 r{x[0] - p.centre[0], x[1] - p.centre[1], x[2] - p.centre[2]};
    const V3 wr = cross(p.omega, r);
    for (int d = 0; d < 3; ++d) {
        o.points.push_back(x[d]);
        o.velocity.push_back(p.velocity[d] + wr[d]);
    }
}

} // namespace

WallExtent wall_extent(const model::Nodes& nodes) {
    WallExtent e;
    const std::size_t n = nodes.x0.size() / 3;
    if (n == 0)
        return e;
    V3 lo, hi;
    lo.fill(std::numeric_limits<double>::max());
    hi.fill(std::numeric_limits<double>::lowest());
    for (std::size_t i = 0; i < n; ++i)
        for (int d = 0; d < 3; ++d) {
            lo[d] = std::min(lo[d], nodes.x0[3 * i + d]);
            hi[d] = std::max(hi[d], nodes.x0[3 * i + d]);
        }
    double diag = 0;
    for (int d = 0; d < 3; ++d) {
        e.centre[d] = 0.5 * (lo[d] + hi[d]);
        diag += (hi[d] - lo[d]) * (hi[d] - lo[d]);
    }
    diag = std::sqrt(diag);
    e.half = diag > 0 ? 0.6 * diag : 1e-3;
    return e;
}

namespace {

/// The part of convex polygon `poly` on the free side of plane pose `q` (Sutherland-Hodgman).
std::vector<V3> clip(const std::vector<V3>& poly, const Pose& q) {
    auto side = [&](const V3& x) {
        return (x[0] - q.point[0]) * q.normal[0] + (x[1] - q.point[1]) * q.normal[1] +
               (x[2] - q.point[2]) * q.normal[2];
    };
    std::vector<V3> out;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const V3& a = poly[i];
        const V3& b = poly[(i + 1) % poly.size()];
        const double da = side(a), db = side(b);
        if (da >= 0)
            out.push_back(a);
        if ((da >= 0) != (db >= 0)) {
            const double f = da / (da - db);
            out.push_back(
                {a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])});
        }
    }
    return out;
}

/// A segment (2D) of half-size extent.half on the plane of wall `wall`, or in 3D a square patch
/// of that half side clipped to the free side of the `others` planes (each clip that would leave
/// nothing is skipped), both centred on the extent's centre projected onto the plane.
void plane_outline(WallOutline& o, const Pose& p, int dimension, const WallExtent& extent,
                   std::int32_t wall, const std::vector<Pose>& others) {
    const auto first = static_cast<std::int64_t>(o.num_points());
    const V3 n = unit(p.normal);
    const V3 rel{extent.centre[0] - p.point[0], extent.centre[1] - p.point[1],
                 extent.centre[2] - p.point[2]};
    const double h = dot(rel, n);
    const V3 c{extent.centre[0] - h * n[0], extent.centre[1] - h * n[1],
               extent.centre[2] - h * n[2]};
    const double s = extent.half;
    if (dimension != 3) {
        const V3 e{-n[1], n[0], 0};
        add_point(o, p, {c[0] - s * e[0], c[1] - s * e[1], c[2]});
        add_point(o, p, {c[0] + s * e[0], c[1] + s * e[1], c[2]});
        o.cells.insert(o.cells.end(), {first, first + 1});
        o.wall.push_back(wall);
        return;
    }
    // Tangents: n x (the axis least aligned with n), then n x e1.
    V3 a{0, 0, 0};
    int m = 0;
    for (int d = 1; d < 3; ++d)
        if (std::abs(n[d]) < std::abs(n[m]))
            m = d;
    a[m] = 1;
    const V3 e1 = unit(cross(n, a)), e2 = cross(n, e1);
    std::vector<V3> poly;
    for (const auto& [u, v] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}})
        poly.push_back({c[0] + s * (u * e1[0] + v * e2[0]), c[1] + s * (u * e1[1] + v * e2[1]),
                        c[2] + s * (u * e1[2] + v * e2[2])});
    // Bounded by the other planes: a box of walls around the grains is drawn as a box.
    for (const auto& q : others) {
        auto cut = clip(poly, q);
        if (cut.size() >= 3)
            poly = std::move(cut);
    }
    for (const auto& x : poly)
        add_point(o, p, x);
    // A fan of quadrilaterals (the last one with a repeated corner when the count is odd).
    const auto np = static_cast<std::int64_t>(poly.size());
    for (std::int64_t i = 1; i + 1 < np; i += 2) {
        o.cells.insert(o.cells.end(),
                       {first, first + i, first + i + 1, first + std::min(i + 2, np - 1)});
        o.wall.push_back(wall);
    }
}

/// A circle of 128 segments about the current point, turned with the wall (2D).
void circle_outline(WallOutline& o, const Pose& p, double r, std::int32_t wall) {
    constexpr double two_pi = 2 * std::numbers::pi;
    constexpr int segments = 128;
    const auto first = static_cast<std::int64_t>(o.num_points());
    for (int i = 0; i < segments; ++i) {
        const double phi = two_pi * i / segments;
        const V3 local = rotate({r * std::cos(phi), r * std::sin(phi), 0}, p.theta);
        add_point(o, p, {p.point[0] + local[0], p.point[1] + local[1], p.point[2]});
    }
    for (int i = 0; i < segments; ++i) {
        o.cells.insert(o.cells.end(), {first + i, first + (i + 1) % segments});
        o.wall.push_back(wall);
    }
}

/// A latitude-longitude sphere (16 x 32 quads) about the current point, turned with the wall.
void sphere_outline(WallOutline& o, const Pose& p, double r, std::int32_t wall) {
    constexpr double two_pi = 2 * std::numbers::pi;
    constexpr int lat = 16, lon = 32;
    const auto first = static_cast<std::int64_t>(o.num_points());
    for (int i = 0; i <= lat; ++i) {
        const double th = std::numbers::pi * i / lat;
        for (int j = 0; j < lon; ++j) {
            const double phi = two_pi * j / lon;
            const V3 local = rotate({r * std::sin(th) * std::cos(phi),
                                     r * std::sin(th) * std::sin(phi), r * std::cos(th)},
                                    p.theta);
            add_point(o, p, {p.point[0] + local[0], p.point[1] + local[1], p.point[2] + local[2]});
        }
    }
    for (int i = 0; i < lat; ++i)
        for (int j = 0; j < lon; ++j) {
            const auto a = first + i * lon + j, b = first + i * lon + (j + 1) % lon;
            o.cells.insert(o.cells.end(), {a, b, b + lon, a + lon});
            o.wall.push_back(wall);
        }
}

/// A triangulated wall's cells in their pose at t: x = c(t) + R(theta) (X - c0). In 3D each
/// triangle is a quadrilateral with its last corner repeated (the outline's one cell type).
void mesh_outline(WallOutline& o, const model::Wall& w, const Pose& p, std::int32_t wall) {
    const auto first = static_cast<std::int64_t>(o.num_points());
    const auto& X = w.mesh->points();
    for (std::size_t i = 0; i + 2 < X.size(); i += 3) {
        const V3 rel =
            rotate({X[i] - w.centre[0], X[i + 1] - w.centre[1], X[i + 2] - w.centre[2]}, p.theta);
        add_point(o, p, {p.centre[0] + rel[0], p.centre[1] + rel[1], p.centre[2] + rel[2]});
    }
    const auto& c = w.mesh->cells();
    const auto per = static_cast<std::size_t>(w.mesh->dim());
    for (std::size_t k = 0; k + per <= c.size(); k += per) {
        if (per == 3)
            o.cells.insert(o.cells.end(),
                           {first + c[k], first + c[k + 1], first + c[k + 2], first + c[k + 2]});
        else
            o.cells.insert(o.cells.end(), {first + c[k], first + c[k + 1]});
        o.wall.push_back(wall);
    }
}

} // namespace

WallOutline wall_outline(const std::vector<model::Wall>& walls, int dimension,
                         const WallExtent& extent, double t) {
    WallOutline o;
    o.points_per_cell = dimension == 3 ? 4 : 2;
    for (std::size_t k = 0; k < walls.size(); ++k) {
        const auto& w = walls[k];
        const Pose p = pose(w, t);
        const auto wall = static_cast<std::int32_t>(k);
        std::vector<Pose> others; // the other planes present at t
        for (std::size_t j = 0; j < walls.size() && dimension == 3; ++j)
            if (j != k && walls[j].shape == model::WallShape::plane &&
                model::wall_present(walls[j], t))
                others.push_back(pose(walls[j], t));
        if (w.shape == model::WallShape::plane)
            plane_outline(o, p, dimension, extent, wall, others);
        else if (w.shape == model::WallShape::mesh)
            mesh_outline(o, w, p, wall);
        else if (dimension != 3) // circles (2D) and spheres (3D) about the current point
            circle_outline(o, p, w.radius, wall);
        else
            sphere_outline(o, p, w.radius, wall);
    }
    return o;
}

} // namespace pd::post
