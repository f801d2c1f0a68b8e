// SPDX-License-Identifier: MIT
#include "pipeline/peridem/geometry.hpp"

#include "core/errors.hpp"
#include "mesh/discretize.hpp"
#include "mesh/shape_mesher.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace pd::pipeline::peridem {

std::optional<std::array<double, 4>> rectangle_box(const std::vector<double>& p) {
    if (p.size() == 6)
        return std::array<double, 4>{std::min(p[0], p[3]), std::min(p[1], p[4]),
                                     std::max(p[0], p[3]), std::max(p[1], p[4])};
    if (p.size() == 5)
        return std::array<double, 4>{p[2] - p[0] / 2, p[3] - p[1] / 2, p[2] + p[0] / 2,
                                     p[3] + p[1] / 2};
    if (p.size() == 2)
        return std::array<double, 4>{-p[0] / 2, -p[1] / 2, p[0] / 2, p[1] / 2};
    return std::nullopt;
}

json corners(const std::array<double, 4>& b) {
    return json{{"type", "rectangle"}, {"corners", {{b[0], b[1]}, {b[2], b[3]}}}};
}

std::optional<ZoneShape> deck_shape(const std::string& type, std::vector<double> p,
                                    const std::string& key, double r) {
    if (p.empty())
        return std::nullopt;
    if (r > 0) {
        const double f = r / p[0];
        p[0] = r;
        if (type == "drum2d" || type == "ellipse")
            p[1] *= f;
    }
    const double R = p[0];
    auto offset = [&](ZoneShape z, std::size_t at) {
        if (p.size() > at + 1 && (p[at] != 0 || p[at + 1] != 0)) {
            z.spec["offset"] = {p[at], p[at + 1]};
            z.shape = z.shape.translated(p[at], p[at + 1]);
        }
        return z;
    };
    try {
        if (type == "circle")
            return offset({json{{"type", "circle"}, {"radius", R}}, geometry::Shape::circle(R), R},
                          1);
        if (type == "hexagon")
            return offset(
                {json{{"type", "hexagon"}, {"radius", R}}, geometry::Shape::hexagon(R), R}, 1);
        if (type == "triangle")
            return offset(
                {json{{"type", "triangle"}, {"radius", R}}, geometry::Shape::triangle(R), R}, 1);
        if (type == "square")
            return offset({json{{"type", "square"}, {"radius", R}}, geometry::Shape::square(R), R},
                          1);
        if (type == "sphere")
            return offset({json{{"type", "sphere"}, {"radius", R}}, geometry::Shape::sphere(R), R},
                          1);
        if (type == "drum2d" && p.size() >= 2)
            return offset({json{{"type", "drum2d"}, {"radius", R}, {"neck_width", p[1]}},
                           geometry::Shape::drum2d(R, p[1]), R},
                          2);
        if (type == "ellipse" && p.size() >= 2)
            return offset({json{{"type", "ellipse"}, {"semi_axes", {p[0], p[1]}}},
                           geometry::Shape::ellipse(p[0], p[1]), R},
                          2);
        if (type == "rectangle") {
            auto b = rectangle_box(p);
            if (!b)
                return std::nullopt;
            return ZoneShape{corners(*b),
                             geometry::Shape::rectangle_corners((*b)[0], (*b)[1], (*b)[2], (*b)[3]),
                             R};
        }
        if (type == "rectangle_minus_rectangle" && p.size() == 12) {
            std::vector<double> o(p.begin(), p.begin() + 6), i(p.begin() + 6, p.end());
            auto bo = *rectangle_box(o), bi = *rectangle_box(i);
            return ZoneShape{
                json{{"type", "difference"}, {"base", corners(bo)}, {"minus", {corners(bi)}}},
                geometry::Shape::difference(
                    geometry::Shape::rectangle_corners(bo[0], bo[1], bo[2], bo[3]),
                    {geometry::Shape::rectangle_corners(bi[0], bi[1], bi[2], bi[3])}),
                R};
        }
    } catch (const InputError& e) {
        throw ConfigError(key, e.what());
    }
    return std::nullopt;
}

/// The boundary edges of a 2D mesh, each cell oriented counter-clockwise: next[a] = b for the
/// edge a -> b; nullopt if the boundary is not manifold.
std::optional<std::map<int, int>> boundary_next(const model::RefMesh& m) {
    const int npc = m.nodes_per_cell;
    std::map<std::pair<int, int>, int> count;
    std::vector<std::pair<int, int>> directed;
    const std::size_t nc = m.cells.size() / static_cast<std::size_t>(npc);
    auto X = [&](int i) { return std::array<double, 2>{m.nodes[3 * i], m.nodes[3 * i + 1]}; };
    for (std::size_t c = 0; c < nc; ++c) {
        const int* v = &m.cells[c * static_cast<std::size_t>(npc)];
        // Orient every cell counter-clockwise so boundary edges chain consistently.
        double a2 = 0;
        for (int k = 0; k < npc; ++k) {
            auto p = X(v[k]), q = X(v[(k + 1) % npc]);
            a2 += p[0] * q[1] - q[0] * p[1];
        }
        for (int k = 0; k < npc; ++k) {
            int a = v[k], b = v[(k + 1) % npc];
            if (a2 < 0)
                std::swap(a, b);
            ++count[{std::min(a, b), std::max(a, b)}];
            directed.emplace_back(a, b);
        }
    }
    std::map<int, int> next;
    for (auto [a, b] : directed)
        if (count[{std::min(a, b), std::max(a, b)}] == 1) {
            if (next.count(a))
                return std::nullopt; // non-manifold boundary
            next[a] = b;
        }
    return next;
}

std::optional<ZoneShape> mesh_outline(const model::RefMesh& m) {
    auto X = [&](int i) { return std::array<double, 2>{m.nodes[3 * i], m.nodes[3 * i + 1]}; };
    auto boundary = boundary_next(m);
    if (!boundary)
        return std::nullopt;
    auto& next = *boundary;
    std::vector<std::vector<geometry::Vec2>> loops;
    std::vector<double> areas;
    std::set<int> seen;
    for (auto [start, unused] : next) {
        if (seen.count(start))
            continue;
        std::vector<int> loop;
        int v = start;
        while (!seen.count(v)) {
            seen.insert(v);
            loop.push_back(v);
            if (!next.count(v))
                return std::nullopt;
            v = next[v];
        }
        // Drop collinear vertices.
        std::vector<geometry::Vec2> poly;
        const std::size_t n = loop.size();
        for (std::size_t k = 0; k < n; ++k) {
            auto a = X(loop[(k + n - 1) % n]), b = X(loop[k]), c = X(loop[(k + 1) % n]);
            const double cr = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
            const double l =
                std::hypot(b[0] - a[0], b[1] - a[1]) * std::hypot(c[0] - b[0], c[1] - b[1]);
            if (std::abs(cr) > 1e-9 * l)
                poly.push_back({b[0], b[1]});
        }
        if (poly.size() < 3)
            continue;
        double a2 = 0;
        for (std::size_t k = 0; k < poly.size(); ++k) {
            const auto& p = poly[k];
            const auto& q = poly[(k + 1) % poly.size()];
            a2 += p[0] * q[1] - q[0] * p[1];
        }
        loops.push_back(std::move(poly));
        areas.push_back(std::abs(a2) / 2);
    }
    if (loops.empty())
        return std::nullopt;
    const auto outer =
        static_cast<std::size_t>(std::max_element(areas.begin(), areas.end()) - areas.begin());
    auto polygon = [](const std::vector<geometry::Vec2>& v) {
        json j{{"type", "polygon"}, {"vertices", json::array()}};
        for (const auto& p : v)
            j["vertices"].push_back({p[0], p[1]});
        return j;
    };
    ZoneShape z{polygon(loops[outer]), geometry::Shape::polygon(loops[outer]), 0};
    std::vector<geometry::Shape> holes;
    json minus = json::array();
    for (std::size_t k = 0; k < loops.size(); ++k)
        if (k != outer) {
            holes.push_back(geometry::Shape::polygon(loops[k]));
            minus.push_back(polygon(loops[k]));
        }
    if (!holes.empty()) {
        z.shape = geometry::Shape::difference(z.shape, holes);
        z.spec = json{{"type", "difference"}, {"base", z.spec}, {"minus", minus}};
    }
    return z;
}

/// Does the shape describe the mesh: every node inside (to 1e-6 R) and the mesh area within 3%?
bool fits(const geometry::Shape& s, const model::RefMesh& m, int dim) {
    const double tol = 1e-6 * s.bounding_radius();
    for (std::size_t i = 0; i < m.nodes.size() / 3; ++i)
        if (s.clearance(m.nodes[3 * i], m.nodes[3 * i + 1], m.nodes[3 * i + 2]) < -tol)
            return false;
    double v = 0;
    for (double x : mesh::nodal_volumes(m, dim))
        v += x;
    return std::abs(v / s.area_or_volume() - 1) < 0.03;
}

} // namespace pd::pipeline::peridem
