// SPDX-License-Identifier: MIT
// Closest point of a triangulated (3D) or polyline (2D) wall and its signed distance; see
// wall_mesh.hpp. Closest point on a triangle: Ericson, Real-Time Collision Detection (2005) 5.1.5.
#include "model/wall_mesh.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>

namespace pd::model {

namespace {

using V3 = std::array<double, 3>;

V3 sub(const double* a, const double* b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
double dot(const V3& a, const V3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
V3 cross(const V3& a, const V3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const V3& a) {
    return std::sqrt(dot(a, a));
}

/// Closest point q of triangle (a, b, c) to p; returns the feature (0 face, 1 + edge k with
/// edges (a,b), (b,c), (c,a), 4 + vertex k).
int closest_on_triangle(const double* p, const double* a, const double* b, const double* c,
                        double* q) {
    const V3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
    auto at = [&](const double* o, const V3& e, double t, int f) {
        for (int k = 0; k < 3; ++k)
            q[k] = o[k] + t * e[k];
        return f;
    };
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0)
        return at(a, ab, 0, 4);
    const V3 bp = sub(p, b);
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3)
        return at(b, ab, 0, 5);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0)
        return at(a, ab, d1 / (d1 - d3), 1);
    const V3 cp = sub(p, c);
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6)
        return at(c, ab, 0, 6);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0)
        return at(a, ac, d2 / (d2 - d6), 3);
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return at(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)), 2);
    const double den = 1 / (va + vb + vc), v = vb * den, w = vc * den;
    for (int k = 0; k < 3; ++k)
        q[k] = a[k] + ab[k] * v + ac[k] * w;
    return 0;
}

/// Closest point q of segment (a, b) to p: 0 interior, 4 + end k.
int closest_on_segment(const double* p, const double* a, const double* b, double* q) {
    const V3 ab = sub(b, a), ap = sub(p, a);
    const double t = dot(ab, ap) / dot(ab, ab);
    const double tc = std::clamp(t, 0.0, 1.0);
    for (int k = 0; k < 3; ++k)
        q[k] = a[k] + tc * ab[k];
    return t <= 0 ? 4 : t >= 1 ? 5 : 0;
}

/// Edge (or 2D vertex) key -> the cells using it, with the direction they run it in.
using EdgeUse = std::map<std::pair<std::int32_t, std::int32_t>, std::vector<std::pair<int, int>>>;

EdgeUse edge_uses(int dim, const std::vector<std::int32_t>& cells) {
    EdgeUse uses;
    const auto nc = static_cast<int>(cells.size() / static_cast<std::size_t>(dim));
    for (int c = 0; c < nc; ++c) {
        const auto* v = &cells[static_cast<std::size_t>(dim * c)];
        if (dim == 2) { // a 2D "edge" is a vertex: +1 where a segment ends, -1 where it starts
            uses[{v[0], v[0]}].push_back({c, -1});
            uses[{v[1], v[1]}].push_back({c, +1});
            continue;
        }
        for (int k = 0; k < 3; ++k) {
            const auto a = v[k], b = v[(k + 1) % 3];
            uses[{std::min(a, b), std::max(a, b)}].push_back({c, a < b ? +1 : -1});
        }
    }
    return uses;
}

} // namespace

std::string check_wall_mesh(int dim, const std::vector<double>& points,
                            const std::vector<std::int32_t>& cells) {
    const auto per = static_cast<std::size_t>(dim);
    const std::size_t nc = cells.size() / per, np = points.size() / 3;
    if (nc == 0 || cells.size() % per != 0 || points.size() % 3 != 0)
        return fmt::format("has no {} (or a partial one)", dim == 3 ? "triangle" : "segment");
    if (nc > max_wall_mesh_cells)
        return fmt::format("has {} {}, more than the {} a wall may have", nc,
                           dim == 3 ? "triangles" : "segments", max_wall_mesh_cells);
    V3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!std::isfinite(points[i]) || std::abs(points[i]) > 1e6)
            return fmt::format("point {} has a coordinate {} (finite, |x| <= 1e6 m expected)",
                               i / 3, points[i]);
        lo[i % 3] = std::min(lo[i % 3], points[i]);
        hi[i % 3] = std::max(hi[i % 3], points[i]);
    }
    for (auto v : cells)
        if (v < 0 || static_cast<std::size_t>(v) >= np)
            return fmt::format("refers to point {}; it has {} points", v, np);
    const double L = norm(sub(hi.data(), lo.data()));
    for (std::size_t c = 0; c < nc; ++c) {
        const auto* v = &cells[per * c];
        const double* a = &points[3 * static_cast<std::size_t>(v[0])];
        const double* b = &points[3 * static_cast<std::size_t>(v[1])];
        const double size =
            dim == 2 ? norm(sub(b, a))
                     : norm(cross(sub(b, a), sub(&points[3 * static_cast<std::size_t>(v[2])], a)));
        if (!(size > (dim == 2 ? 1e-9 * L : 1e-12 * L * L)))
            return fmt::format("{} {} is degenerate ({} {:.3g})", dim == 3 ? "triangle" : "segment",
                               c, dim == 3 ? "twice its area" : "length", size);
    }
    for (const auto& [key, use] : edge_uses(dim, cells)) {
        if (use.size() > 2)
            return fmt::format("{} {} is shared by {} {} (at most 2)",
                               dim == 3 ? "the edge of points" : "point", key.first, use.size(),
                               dim == 3 ? "triangles" : "segments");
        if (use.size() == 2 && use[0].second == use[1].second)
            return fmt::format("{} {} and {} have opposite orientations: their normals must all "
                               "point into the free side",
                               dim == 3 ? "triangles" : "segments", use[0].first, use[1].first);
    }
    return "";
}

void weld_triangles(const std::vector<double>& soup, std::vector<double>& points,
                    std::vector<std::int32_t>& cells) {
    std::map<V3, std::int32_t> index;
    points.clear();
    cells.clear();
    for (std::size_t i = 0; i + 2 < soup.size(); i += 3) {
        const V3 p{soup[i], soup[i + 1], soup[i + 2]};
        auto [it, fresh] = index.try_emplace(p, static_cast<std::int32_t>(points.size() / 3));
        if (fresh)
            points.insert(points.end(), p.begin(), p.end());
        cells.push_back(it->second);
    }
}

WallMesh::WallMesh(int dim, std::vector<double> points, std::vector<std::int32_t> cells)
    : dim_(dim)
    , points_(std::move(points))
    , cells_(std::move(cells)) {
    build_normals();
    build_grid();
}

void WallMesh::build_normals() {
    const std::size_t nc = num_cells(), per = static_cast<std::size_t>(dim_);
    face_n_.assign(3 * nc, 0.0);
    edge_n_.assign(9 * nc, 0.0);
    vertex_n_.assign(points_.size(), 0.0);
    auto P = [&](std::size_t c, int k) {
        return &points_[3 *
                        static_cast<std::size_t>(cells_[per * c + static_cast<std::size_t>(k)])];
    };
    for (std::size_t c = 0; c < nc; ++c) {
        V3 n = dim_ == 3 ? cross(sub(P(c, 1), P(c, 0)), sub(P(c, 2), P(c, 0)))
                         : V3{-(P(c, 1)[1] - P(c, 0)[1]), P(c, 1)[0] - P(c, 0)[0], 0};
        const double l = norm(n);
        for (int k = 0; k < 3; ++k)
            face_n_[3 * c + static_cast<std::size_t>(k)] = n[static_cast<std::size_t>(k)] / l;
        for (int k = 0; k < dim_; ++k) { // vertex pseudo-normal: angle-weighted (2D: sum)
            double angle = 1;
            if (dim_ == 3) {
                const V3 e1 = sub(P(c, (k + 1) % 3), P(c, k)), e2 = sub(P(c, (k + 2) % 3), P(c, k));
                angle = std::acos(std::clamp(dot(e1, e2) / (norm(e1) * norm(e2)), -1.0, 1.0));
            }
            const auto v = static_cast<std::size_t>(cells_[per * c + static_cast<std::size_t>(k)]);
            for (std::size_t q = 0; q < 3; ++q)
                vertex_n_[3 * v + q] += angle * face_n_[3 * c + q];
        }
    }
    // Open rims: an edge (2D: a vertex) of one cell; its vertices have no pseudo-normal either.
    std::vector<std::uint8_t> rim(points_.size() / 3, 0);
    for (const auto& [key, use] : edge_uses(dim_, cells_)) {
        if (use.size() == 2) {
            if (dim_ == 3)
                for (const auto& [c, dir] : use)
                    for (int k = 0; k < 3; ++k) {
                        const auto a = cells_[3 * static_cast<std::size_t>(c) +
                                              static_cast<std::size_t>(k)],
                                   b = cells_[3 * static_cast<std::size_t>(c) +
                                              static_cast<std::size_t>((k + 1) % 3)];
                        if (std::min(a, b) != key.first || std::max(a, b) != key.second)
                            continue;
                        for (std::size_t q = 0; q < 3; ++q)
                            edge_n_[9 * static_cast<std::size_t>(c) + 3 * k + q] =
                                face_n_[3 * static_cast<std::size_t>(use[0].first) + q] +
                                face_n_[3 * static_cast<std::size_t>(use[1].first) + q];
                    }
            continue;
        }
        rim[static_cast<std::size_t>(key.first)] = rim[static_cast<std::size_t>(key.second)] = 1;
    }
    for (std::size_t v = 0; v < rim.size(); ++v)
        if (rim[v])
            for (std::size_t q = 0; q < 3; ++q)
                vertex_n_[3 * v + q] = 0;
}

void WallMesh::build_grid() {
    const std::size_t nc = num_cells(), per = static_cast<std::size_t>(dim_);
    double hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (int k = 0; k < 3; ++k)
        lo_[k] = HUGE_VAL;
    for (std::size_t i = 0; i < points_.size(); ++i) {
        lo_[i % 3] = std::min(lo_[i % 3], points_[i]);
        hi[i % 3] = std::max(hi[i % 3], points_[i]);
    }
    // Cell side: the mean extent of the mesh cells, at least 1/128 of the box.
    double mean = 0, L = 0;
    for (std::size_t c = 0; c < nc; ++c)
        for (int k = 0; k < 3; ++k) {
            double a = HUGE_VAL, b = -HUGE_VAL;
            for (std::size_t j = 0; j < per; ++j) {
                const double x = points_[3 * static_cast<std::size_t>(cells_[per * c + j]) +
                                         static_cast<std::size_t>(k)];
                a = std::min(a, x);
                b = std::max(b, x);
            }
            mean += (b - a) / (3.0 * static_cast<double>(nc));
        }
    for (int k = 0; k < 3; ++k)
        L = std::max(L, hi[k] - lo_[k]);
    size_ = std::max({mean, L / 128, 1e-12});
    auto count = [&] {
        std::int64_t total = 1;
        for (int k = 0; k < 3; ++k) {
            n_[k] = std::max<std::int64_t>(
                1, static_cast<std::int64_t>(std::ceil((hi[k] - lo_[k]) / size_)));
            total *= n_[k];
        }
        return total;
    };
    while (count() > 4 * static_cast<std::int64_t>(nc) + 64)
        size_ *= 1.5;
    // CSR: count, then fill.
    const std::int64_t total = n_[0] * n_[1] * n_[2];
    offsets_.assign(static_cast<std::size_t>(total) + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<std::int64_t> fill(offsets_.begin(), offsets_.end() - 1);
        for (std::size_t c = 0; c < nc; ++c) {
            std::int64_t a[3], b[3];
            for (int k = 0; k < 3; ++k) {
                double x0 = HUGE_VAL, x1 = -HUGE_VAL;
                for (std::size_t j = 0; j < per; ++j) {
                    const double x = points_[3 * static_cast<std::size_t>(cells_[per * c + j]) +
                                             static_cast<std::size_t>(k)];
                    x0 = std::min(x0, x);
                    x1 = std::max(x1, x);
                }
                auto idx = [&](double x) {
                    const double t = std::clamp(std::floor((x - lo_[k]) / size_), 0.0,
                                                static_cast<double>(n_[k] - 1));
                    return static_cast<std::int64_t>(t);
                };
                a[k] = idx(x0);
                b[k] = idx(x1);
            }
            for (auto i = a[0]; i <= b[0]; ++i)
                for (auto j = a[1]; j <= b[1]; ++j)
                    for (auto k = a[2]; k <= b[2]; ++k) {
                        const auto g = static_cast<std::size_t>((i * n_[1] + j) * n_[2] + k);
                        if (pass == 0)
                            ++offsets_[g + 1];
                        else
                            items_[static_cast<std::size_t>(fill[g]++)] =
                                static_cast<std::int32_t>(c);
                    }
        }
        if (pass == 0) {
            for (std::size_t g = 0; g < static_cast<std::size_t>(total); ++g)
                offsets_[g + 1] += offsets_[g];
            items_.assign(static_cast<std::size_t>(offsets_.back()), 0);
        }
    }
}

void WallMesh::test_cell(std::size_t c, const double* X, Hit& best) const {
    const std::size_t per = static_cast<std::size_t>(dim_);
    auto P = [&](std::size_t k) {
        return &points_[3 * static_cast<std::size_t>(cells_[per * c + k])];
    };
    double q[3];
    const int f = dim_ == 3 ? closest_on_triangle(X, P(0), P(1), P(2), q)
                            : closest_on_segment(X, P(0), P(1), q);
    const V3 r = sub(X, q);
    const double d2 = dot(r, r);
    const auto ci = static_cast<std::int64_t>(c);
    if (d2 < best.d2 || (d2 == best.d2 && ci < best.cell))
        best = {d2, ci, f, {q[0], q[1], q[2]}};
}

bool WallMesh::finish(const Hit& best, const double* X, double rmax, double& d, double n[3]) const {
    if (best.cell < 0 || !(best.d2 <= rmax * rmax))
        return false;
    const auto c = static_cast<std::size_t>(best.cell);
    const double* N = best.feature == 0 ? &face_n_[3 * c]
                      : best.feature < 4
                          ? &edge_n_[9 * c + 3 * static_cast<std::size_t>(best.feature - 1)]
                          : &vertex_n_[3 * static_cast<std::size_t>(
                                               cells_[static_cast<std::size_t>(dim_) * c +
                                                      static_cast<std::size_t>(best.feature - 4)])];
    const V3 r = sub(X, best.q);
    const double dist = std::sqrt(best.d2);
    const V3 pn{N[0], N[1], N[2]};
    const double sgn = dot(r, pn) < 0 ? -1.0 : 1.0; // an open rim (pn = 0) counts as outside
    d = sgn * dist;
    if (dist > 0) {
        for (std::size_t k = 0; k < 3; ++k)
            n[k] = sgn * r[k] / dist;
        return true;
    }
    const double l = norm(pn);
    for (std::size_t k = 0; k < 3; ++k)
        n[k] = l > 0 ? pn[k] / l : face_n_[3 * c + k];
    return true;
}

bool WallMesh::closest_brute(const double* X, double rmax, double& d, double n[3]) const {
    Hit best{HUGE_VAL, -1, 0, {0, 0, 0}};
    for (std::size_t c = 0; c < num_cells(); ++c)
        test_cell(c, X, best);
    return finish(best, X, rmax, d, n);
}

bool WallMesh::closest(const double* X, double rmax, double& d, double n[3]) const {
    if (!(rmax < HUGE_VAL)) {
        // Unbounded: growing searches (each exact within its radius) until one finds a cell;
        // every cell lies within the distance to the grid's box plus its diagonal.
        double out2 = 0, diag2 = 0;
        for (int k = 0; k < 3; ++k) {
            const double top = lo_[k] + static_cast<double>(n_[k]) * size_;
            const double e = std::max({lo_[k] - X[k], X[k] - top, 0.0});
            out2 += e * e;
            diag2 += (top - lo_[k]) * (top - lo_[k]);
        }
        const double limit = std::sqrt(out2) + std::sqrt(diag2);
        for (double r = std::max(size_, std::sqrt(out2)); r < limit; r *= 2)
            if (closest(X, r, d, n))
                return true;
        return closest_brute(X, rmax, d, n);
    }
    std::int64_t a[3], b[3];
    for (int k = 0; k < 3; ++k) {
        const double top = lo_[k] + static_cast<double>(n_[k]) * size_;
        if (X[k] + rmax < lo_[k] || X[k] - rmax > top)
            return false; // the query box misses the grid: no cell within rmax
        auto idx = [&](double x) {
            const double t =
                std::clamp(std::floor((x - lo_[k]) / size_), 0.0, static_cast<double>(n_[k] - 1));
            return static_cast<std::int64_t>(t);
        };
        a[k] = idx(X[k] - rmax);
        b[k] = idx(X[k] + rmax);
    }
    Hit best{HUGE_VAL, -1, 0, {0, 0, 0}};
    for (auto i = a[0]; i <= b[0]; ++i)
        for (auto j = a[1]; j <= b[1]; ++j)
            for (auto k = a[2]; k <= b[2]; ++k) {
                const auto g = static_cast<std::size_t>((i * n_[1] + j) * n_[2] + k);
                for (auto e = offsets_[g]; e < offsets_[g + 1]; ++e)
                    test_cell(static_cast<std::size_t>(items_[static_cast<std::size_t>(e)]), X,
                              best);
            }
    return finish(best, X, rmax, d, n);
}

} // namespace pd::model
