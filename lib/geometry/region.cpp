// SPDX-License-Identifier: MIT
// The geometry module's only CGAL translation unit. Boolean operations use the exact-constructions
// kernel (EPECK): with EPICK, CGAL's Boolean set operations abort on inputs as ordinary as an
// annulus joined with a bar (inexact intersection points break the arrangement's preconditions).
// Queries (containment, distances) run on double copies with EPICK's exact predicates.
#include "geometry/region.hpp"

#include "core/errors.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_2_algorithms.h>
#include <CGAL/Polygon_set_2.h>
#include <CGAL/Polygon_with_holes_2.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

namespace pd::geometry::detail {

namespace {
using EK = CGAL::Exact_predicates_exact_constructions_kernel;
using IK = CGAL::Exact_predicates_inexact_constructions_kernel;
using ExactSet = CGAL::Polygon_set_2<EK>;
using ExactPolygon = CGAL::Polygon_2<EK>;
using ExactPwh = CGAL::Polygon_with_holes_2<EK>;
using Point = IK::Point_2;

/// One component as double rings: outer (CCW) and holes (CW).
struct Component {
    std::vector<Point> outer;
    std::vector<std::vector<Point>> holes;
    CGAL::Bbox_2 bbox;
};

std::vector<Point> to_points(const Ring& r) {
    std::vector<Point> p;
    p.reserve(r.size());
    for (const auto& v : r)
        p.emplace_back(v[0], v[1]);
    return p;
}

Ring to_ring(const ExactPolygon& poly) {
    Ring r;
    r.reserve(poly.size());
    for (auto v = poly.vertices_begin(); v != poly.vertices_end(); ++v)
        r.push_back({CGAL::to_double(v->x()), CGAL::to_double(v->y())});
    return r;
}

CGAL::Bounded_side side(const std::vector<Point>& ring, const Point& p) {
    return CGAL::bounded_side_2(ring.begin(), ring.end(), p, IK());
}
} // namespace

struct Region::Impl {
    ExactSet set;
    std::vector<Ring> rings;
    std::vector<Component> components;
    std::vector<IK::Segment_2> edges;
    double area = 0;
    std::array<double, 2> centroid{0, 0};

    explicit Impl(ExactSet s)
        : set(std::move(s)) {
        std::vector<ExactPwh> pwh;
        set.polygons_with_holes(std::back_inserter(pwh));
        double a = 0, mx = 0, my = 0; // shoelace sums: 2A and 6 A c
        auto add_ring = [&](const Ring& r) {
            rings.push_back(r);
            for (std::size_t i = 0; i < r.size(); ++i) {
                const auto& p = r[i];
                const auto& q = r[(i + 1) % r.size()];
                const double cross = p[0] * q[1] - q[0] * p[1];
                a += cross;
                mx += (p[0] + q[0]) * cross;
                my += (p[1] + q[1]) * cross;
                edges.emplace_back(Point(p[0], p[1]), Point(q[0], q[1]));
            }
        };
        for (const auto& c : pwh) {
            Component comp;
            Ring outer = to_ring(c.outer_boundary());
            add_ring(outer);
            comp.outer = to_points(outer);
            comp.bbox = CGAL::bbox_2(comp.outer.begin(), comp.outer.end());
            for (auto h = c.holes_begin(); h != c.holes_end(); ++h) {
                Ring hole = to_ring(*h);
                add_ring(hole);
                comp.holes.push_back(to_points(hole));
            }
            components.push_back(std::move(comp));
        }
        area = 0.5 * a;
        if (area > 0)
            centroid = {mx / (3 * a), my / (3 * a)};
    }
};

Region Region::polygon(const Ring& vertices) {
    if (vertices.size() < 3)
        throw InputError(
            fmt::format("polygon: needs at least 3 vertices, got {}", vertices.size()));
    for (const auto& v : vertices)
        if (!std::isfinite(v[0]) || !std::isfinite(v[1]))
            throw InputError("polygon: vertex coordinates must be finite");
    const std::vector<Point> pts = to_points(vertices);
    for (std::size_t i = 0; i < vertices.size(); ++i)
        if (vertices[i] == vertices[(i + 1) % vertices.size()])
            throw InputError(fmt::format("polygon: vertex {} repeats vertex {} ({}, {})",
                                         (i + 1) % vertices.size(), i, vertices[i][0],
                                         vertices[i][1]));
    const IK traits{};
    if (!CGAL::is_simple_2(pts.begin(), pts.end(), traits))
        throw InputError(fmt::format("polygon: the {} vertices do not form a simple polygon "
                                     "(edges cross, touch or overlap)",
                                     vertices.size()));
    if (CGAL::orientation_2(pts.begin(), pts.end(), traits) == CGAL::COLLINEAR)
        throw InputError("polygon: vertices are collinear (zero area)");
    ExactPolygon poly;
    for (const auto& v : vertices)
        poly.push_back(EK::Point_2(v[0], v[1]));
    if (poly.is_clockwise_oriented())
        poly.reverse_orientation();
    return Region(std::make_shared<const Impl>(ExactSet(poly)));
}

Region Region::unite(const Region& a, const Region& b) {
    ExactSet s = a.impl_->set;
    s.join(b.impl_->set);
    return Region(std::make_shared<const Impl>(std::move(s)));
}

Region Region::subtract(const Region& a, const Region& b) {
    ExactSet s = a.impl_->set;
    s.difference(b.impl_->set);
    return Region(std::make_shared<const Impl>(std::move(s)));
}

bool Region::empty() const {
    return impl_->components.empty();
}
double Region::area() const {
    return impl_->area;
}
std::array<double, 2> Region::centroid() const {
    return impl_->centroid;
}
const std::vector<Ring>& Region::rings() const {
    return impl_->rings;
}

int Region::classify(double x, double y) const {
    const Point p(x, y);
    int best = -1;
    for (const auto& c : impl_->components) {
        if (x < c.bbox.xmin() || x > c.bbox.xmax() || y < c.bbox.ymin() || y > c.bbox.ymax())
            continue;
        const auto s = side(c.outer, p);
        if (s == CGAL::ON_UNBOUNDED_SIDE)
            continue;
        int here = s == CGAL::ON_BOUNDARY ? 0 : 1;
        for (const auto& h : c.holes) {
            const auto sh = side(h, p);
            if (sh == CGAL::ON_BOUNDED_SIDE) {
                here = -1;
                break;
            }
            if (sh == CGAL::ON_BOUNDARY)
                here = 0;
        }
        best = std::max(best, here);
        if (best == 1)
            break;
    }
    return best;
}

double Region::boundary_distance(double x, double y) const {
    const Point p(x, y);
    double d2 = std::numeric_limits<double>::infinity();
    for (const auto& e : impl_->edges)
        d2 = std::min(d2, CGAL::squared_distance(p, e));
    return std::sqrt(d2);
}

} // namespace pd::geometry::detail
