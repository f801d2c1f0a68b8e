// SPDX-License-Identifier: MIT
// The geometry of a Shape evaluated on its CSG tree: region, bounds, farthest point,
// classification, clearance, and the derived fields filled once when a node is made (shapes.cpp
// has the factories and queries).
#include "geometry/shape_node.hpp"

#include "core/errors.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pd::geometry::detail {

double sagitta(double r) {
    return r * (1 - std::cos(pi / curve_segments));
}
double hypot2(double x, double y) {
    return std::sqrt(x * x + y * y);
}
const Node& node_of(const Shape& s) {
    return ShapeAccess::node(s);
}

void require_length(const std::string& shape, const char* what, double v) {
    if (!(v > 0) || !std::isfinite(v))
        throw InputError(
            fmt::format("{}: {} must be a positive finite length in m, got {}", shape, what, v));
}

bool is_polygonal(ShapeKind k) {
    return k == ShapeKind::regular_polygon || k == ShapeKind::rectangle || k == ShapeKind::drum2d ||
           k == ShapeKind::polygon;
}

/// Shoelace area and centroid of a CCW ring.
std::pair<double, Vec2> polygon_moments(const std::vector<Vec2>& v) {
    double a = 0, mx = 0, my = 0;
    for (std::size_t i = 0; i < v.size(); ++i) {
        const auto& p = v[i];
        const auto& q = v[(i + 1) % v.size()];
        const double c = p[0] * q[1] - q[0] * p[1];
        a += c;
        mx += (p[0] + q[0]) * c;
        my += (p[1] + q[1]) * c;
    }
    return {0.5 * a, {mx / (3 * a), my / (3 * a)}};
}

/// The 2D node as a polygonal region in the frame reached by P (P maps the node's own frame
/// there). Curves become inscribed polygons with curve_segments vertices.
Region build_region(const Node& n, const Placement& P) {
    auto mapped = [&](double x, double y) {
        const Vec3 q = P.apply({x, y, 0});
        return std::array<double, 2>{q[0], q[1]};
    };
    Ring ring;
    switch (n.kind) {
    case ShapeKind::circle:
    case ShapeKind::ellipse: {
        const double a = n.params[0], b = n.kind == ShapeKind::circle ? a : n.params[1];
        for (int k = 0; k < curve_segments; ++k) {
            const double t = 2 * pi * k / curve_segments;
            ring.push_back(mapped(a * std::cos(t), b * std::sin(t)));
        }
        return Region::polygon(ring);
    }
    case ShapeKind::unite:
    case ShapeKind::difference: {
        auto part = [&](std::size_t i) {
            const Node& c = node_of(n.children[i]);
            return build_region(c, P.compose(c.place));
        };
        Region r = part(0);
        for (std::size_t i = 1; i < n.children.size(); ++i)
            r = n.kind == ShapeKind::unite ? Region::unite(r, part(i))
                                           : Region::subtract(r, part(i));
        return r;
    }
    default:
        PD_CHECK(is_polygonal(n.kind), "build_region: not a 2D shape");
        for (const auto& v : n.verts)
            ring.push_back(mapped(v[0], v[1]));
        return Region::polygon(ring);
    }
}

/// Largest |P(X)| over the points X of the node (P maps the node's own frame to the target).
double farthest(const Node& n, const Placement& P) {
    const Vec3 c = P.apply({0, 0, 0});
    const double cxy = hypot2(c[0], c[1]);
    auto max_over = [&](const std::vector<Vec2>& pts, double extra) {
        double r = 0;
        for (const auto& v : pts) {
            const Vec3 q = P.apply({v[0], v[1], 0});
            r = std::max(r, hypot2(q[0], q[1]));
        }
        return r + extra;
    };
    switch (n.kind) {
    case ShapeKind::circle:
        return cxy + n.params[0];
    case ShapeKind::ellipse: {
        if (cxy == 0)
            return std::max(n.params[0], n.params[1]);
        std::vector<Vec2> pts;
        for (const auto& ring : n.region->rings())
            pts.insert(pts.end(), ring.begin(), ring.end());
        return max_over(pts, n.tol);
    }
    case ShapeKind::unite: {
        double r = 0;
        for (const auto& ch : n.children)
            r = std::max(r, farthest(node_of(ch), P.compose(node_of(ch).place)));
        return r;
    }
    case ShapeKind::difference: {
        const Node& base = node_of(n.children[0]);
        if (n.dim == 3)
            return farthest(base, P.compose(base.place));
        std::vector<Vec2> pts;
        for (const auto& ring : n.region->rings())
            pts.insert(pts.end(), ring.begin(), ring.end());
        return std::min(farthest(base, P.compose(base.place)), max_over(pts, n.tol));
    }
    case ShapeKind::sphere:
        return std::sqrt(cxy * cxy + c[2] * c[2]) + n.params[0];
    case ShapeKind::box: {
        double r = 0;
        for (int k = 0; k < 8; ++k) {
            const Vec3 q =
                P.apply({(k & 1 ? 0.5 : -0.5) * n.params[0], (k & 2 ? 0.5 : -0.5) * n.params[1],
                         (k & 4 ? 0.5 : -0.5) * n.params[2]});
            r = std::max(r, std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]));
        }
        return r;
    }
    case ShapeKind::cylinder: {
        const double a = cxy + n.params[0], b = std::abs(c[2]) + 0.5 * n.params[1];
        return std::sqrt(a * a + b * b);
    }
    case ShapeKind::surface_mesh: {
        double r = 0;
        for (const auto& v : n.solid->vertices()) {
            const Vec3 q = P.apply(v);
            r = std::max(r, std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]));
        }
        return r;
    }
    default:
        return max_over(n.verts, 0);
    }
}

/// Axis-aligned bounding box of the node mapped by P.
std::array<double, 6> bounds(const Node& n, const Placement& P) {
    const double inf = std::numeric_limits<double>::infinity();
    std::array<double, 6> b{inf, inf, inf, -inf, -inf, -inf};
    auto grow = [&](const Vec3& q) {
        for (int i = 0; i < 3; ++i) {
            b[i] = std::min(b[i], q[i]);
            b[i + 3] = std::max(b[i + 3], q[i]);
        }
    };
    const Vec3 c = P.apply({0, 0, 0});
    switch (n.kind) {
    case ShapeKind::circle:
    case ShapeKind::ellipse: {
        const double a = n.params[0], bb = n.kind == ShapeKind::circle ? a : n.params[1];
        const double co = std::cos(P.theta), si = std::sin(P.theta);
        const double hx = std::sqrt(a * a * co * co + bb * bb * si * si);
        const double hy = std::sqrt(a * a * si * si + bb * bb * co * co);
        grow({c[0] - hx, c[1] - hy, c[2]});
        grow({c[0] + hx, c[1] + hy, c[2]});
        break;
    }
    case ShapeKind::unite:
        for (const auto& ch : n.children) {
            const auto cb = bounds(node_of(ch), P.compose(node_of(ch).place));
            grow({cb[0], cb[1], cb[2]});
            grow({cb[3], cb[4], cb[5]});
        }
        break;
    case ShapeKind::difference:
        return bounds(node_of(n.children[0]), P.compose(node_of(n.children[0]).place));
    case ShapeKind::sphere:
        grow({c[0] - n.params[0], c[1] - n.params[0], c[2] - n.params[0]});
        grow({c[0] + n.params[0], c[1] + n.params[0], c[2] + n.params[0]});
        break;
    case ShapeKind::box:
        for (int k = 0; k < 8; ++k)
            grow(P.apply({(k & 1 ? 0.5 : -0.5) * n.params[0], (k & 2 ? 0.5 : -0.5) * n.params[1],
                          (k & 4 ? 0.5 : -0.5) * n.params[2]}));
        break;
    case ShapeKind::cylinder:
        grow({c[0] - n.params[0], c[1] - n.params[0], c[2] - 0.5 * n.params[1]});
        grow({c[0] + n.params[0], c[1] + n.params[0], c[2] + 0.5 * n.params[1]});
        break;
    case ShapeKind::surface_mesh:
        for (const auto& v : n.solid->vertices())
            grow(P.apply(v));
        break;
    default:
        for (const auto& v : n.verts)
            grow(P.apply({v[0], v[1], 0}));
    }
    return b;
}

int compare(double a, double b) {
    return a < b ? 1 : (a == b ? 0 : -1);
}

/// +1 inside, 0 on the boundary, -1 outside; X in the node's own frame.
int classify(const Node& n, const Vec3& X) {
    const double x = X[0], y = X[1], z = X[2];
    const auto& p = n.params;
    switch (n.kind) {
    case ShapeKind::circle:
        return compare(x * x + y * y, p[0] * p[0]);
    case ShapeKind::ellipse:
        return compare(x * x / (p[0] * p[0]) + y * y / (p[1] * p[1]), 1.0);
    case ShapeKind::rectangle:
        return std::min(compare(std::abs(x), 0.5 * p[0]), compare(std::abs(y), 0.5 * p[1]));
    case ShapeKind::unite: {
        int best = -1;
        for (const auto& ch : n.children)
            best = std::max(best, classify(node_of(ch), node_of(ch).place.apply_inverse(X)));
        return best;
    }
    case ShapeKind::difference: {
        const Node& base = node_of(n.children[0]);
        int result = classify(base, base.place.apply_inverse(X));
        for (std::size_t i = 1; i < n.children.size() && result >= 0; ++i) {
            const Node& tool = node_of(n.children[i]);
            const int t = classify(tool, tool.place.apply_inverse(X));
            if (t > 0)
                result = -1;
            else if (t == 0)
                result = 0;
        }
        return result;
    }
    case ShapeKind::sphere:
        return compare(x * x + y * y + z * z, p[0] * p[0]);
    case ShapeKind::box:
        return std::min({compare(std::abs(x), 0.5 * p[0]), compare(std::abs(y), 0.5 * p[1]),
                         compare(std::abs(z), 0.5 * p[2])});
    case ShapeKind::cylinder:
        return std::min(compare(x * x + y * y, p[0] * p[0]), compare(std::abs(z), 0.5 * p[1]));
    case ShapeKind::surface_mesh:
        return n.solid->classify(X);
    default:
        return n.region->classify(x, y);
    }
}

/// Signed distance of an axis-aligned box with half sides h to a point q (negative inside).
double box_sdf(const double* q, const double* h, int dim) {
    double outside = 0, inside = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < dim; ++i) {
        const double d = std::abs(q[i]) - h[i];
        outside += d > 0 ? d * d : 0;
        inside = std::max(inside, d);
    }
    return inside > 0 ? std::sqrt(outside) : inside;
}

/// clearance() in the node's own frame.
double clearance_local(const Node& n, const Vec3& X) {
    const auto& p = n.params;
    switch (n.kind) {
    case ShapeKind::circle:
        return p[0] - hypot2(X[0], X[1]);
    case ShapeKind::rectangle: {
        const double h[2] = {0.5 * p[0], 0.5 * p[1]};
        return -box_sdf(X.data(), h, 2);
    }
    case ShapeKind::sphere:
        return p[0] - std::sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
    case ShapeKind::box: {
        const double h[3] = {0.5 * p[0], 0.5 * p[1], 0.5 * p[2]};
        return -box_sdf(X.data(), h, 3);
    }
    case ShapeKind::cylinder: {
        const double q[2] = {hypot2(X[0], X[1]), X[2]};
        const double dr = q[0] - p[0], dz = std::abs(q[1]) - 0.5 * p[1];
        const double inside = std::min(std::max(dr, dz), 0.0);
        const double outside = hypot2(std::max(dr, 0.0), std::max(dz, 0.0));
        return -(inside + outside);
    }
    case ShapeKind::surface_mesh: {
        const int c = n.solid->classify(X);
        const double d = n.solid->surface_distance(X);
        return c > 0 ? d : (c == 0 ? 0 : -d);
    }
    case ShapeKind::unite:
    case ShapeKind::difference:
        if (n.dim == 3) {
            // max (union) / min (difference, tools negated) of the parts' signed distances: the
            // same sign as the CSG and never larger in magnitude than the true distance.
            auto part = [&](std::size_t i) {
                const Node& ch = node_of(n.children[i]);
                return clearance_local(ch, ch.place.apply_inverse(X));
            };
            double f = part(0);
            for (std::size_t i = 1; i < n.children.size(); ++i)
                f = n.kind == ShapeKind::unite ? std::max(f, part(i)) : std::min(f, -part(i));
            return f;
        }
        [[fallthrough]];
    default: {
        const int c = classify(n, X);
        const double d = n.region->boundary_distance(X[0], X[1]);
        return (c > 0 ? d : (c == 0 ? 0 : -d)) - n.tol;
    }
    }
}

std::string fmt_len(double v) {
    return fmt::format("{:g}", v);
}

/// Volume and centroid of a 3D node (own frame) by adaptive octree quadrature (csg_octree_depth).
std::pair<double, Vec3> octree_moments(const Node& n) {
    const auto b = bounds(n, Placement{});
    const double side = std::max({b[3] - b[0], b[4] - b[1], b[5] - b[2]}) * (1 + 1e-9);
    double v = 0, m[3] = {0, 0, 0};
    const double sqrt3 = std::sqrt(3.0);
    auto visit = [&](auto&& self, const Vec3& c, double h, int depth) -> void {
        const double f = clearance_local(n, c), vol = 8 * h * h * h;
        double w = 0;
        if (f >= sqrt3 * h) {
            w = vol;
        } else if (f <= -sqrt3 * h) {
            return;
        } else if (depth > 0) {
            const double q = 0.5 * h;
            for (int k = 0; k < 8; ++k)
                self(
                    self,
                    Vec3{c[0] + (k & 1 ? q : -q), c[1] + (k & 2 ? q : -q), c[2] + (k & 4 ? q : -q)},
                    q, depth - 1);
            return;
        } else {
            w = vol * std::clamp(0.5 + f / (2 * h), 0.0, 1.0);
        }
        v += w;
        for (int i = 0; i < 3; ++i)
            m[i] += w * c[static_cast<std::size_t>(i)];
    };
    visit(visit, Vec3{0.5 * (b[0] + b[3]), 0.5 * (b[1] + b[4]), 0.5 * (b[2] + b[5])}, 0.5 * side,
          csg_octree_depth);
    if (!(v > 0))
        return {0, {0, 0, 0}};
    return {v, {m[0] / v, m[1] / v, m[2] / v}};
}

/// Fills the derived fields of a node whose kind, parameters, vertices and children are set.
std::shared_ptr<const Node> finish(Node n) {
    switch (n.kind) {
    case ShapeKind::circle:
        n.measure = pi * n.params[0] * n.params[0];
        break;
    case ShapeKind::ellipse:
        n.measure = pi * n.params[0] * n.params[1];
        n.tol = sagitta(std::max(n.params[0], n.params[1]));
        n.region = std::make_shared<const Region>(build_region(n, Placement{}));
        break;
    case ShapeKind::unite:
    case ShapeKind::difference: {
        if (n.dim == 3) {
            const auto [v, c] = octree_moments(n);
            if (!(v > 0))
                throw InputError(fmt::format("{}: the result is empty", n.label));
            n.measure = v;
            n.local_centroid = c;
            break;
        }
        for (const auto& ch : n.children)
            n.tol = std::max(n.tol, node_of(ch).tol);
        auto r = std::make_shared<const Region>(build_region(n, Placement{}));
        if (r->empty())
            throw InputError(fmt::format("{}: the result is empty", n.label));
        n.measure = r->area();
        n.local_centroid = {r->centroid()[0], r->centroid()[1], 0};
        n.region = std::move(r);
        break;
    }
    case ShapeKind::sphere:
        n.measure = 4.0 / 3.0 * pi * std::pow(n.params[0], 3);
        break;
    case ShapeKind::box:
        n.measure = n.params[0] * n.params[1] * n.params[2];
        break;
    case ShapeKind::cylinder:
        n.measure = pi * n.params[0] * n.params[0] * n.params[1];
        break;
    case ShapeKind::surface_mesh:
        n.measure = n.solid->volume();
        n.local_centroid = n.solid->centroid();
        break;
    default: { // polygonal
        if (n.kind != ShapeKind::rectangle)
            n.region = std::make_shared<const Region>(Region::polygon(n.verts));
        const auto [a, c] = polygon_moments(n.verts);
        n.measure = a;
        n.local_centroid = {c[0], c[1], 0};
    }
    }
    n.bounding_radius = farthest(n, n.place);
    n.box = bounds(n, n.place);
    return std::make_shared<const Node>(std::move(n));
}

Node primitive(ShapeKind kind, int dim, std::vector<double> params, std::string label) {
    Node n;
    n.kind = kind;
    n.dim = dim;
    n.params = std::move(params);
    n.label = std::move(label);
    return n;
}

Shape make(Node n) {
    return ShapeAccess::make(finish(std::move(n)));
}

} // namespace pd::geometry::detail
