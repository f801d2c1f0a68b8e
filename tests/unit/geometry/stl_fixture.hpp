// SPDX-License-Identifier: MIT
// Small closed triangle surfaces for the surface_mesh tests (refined icosahedron, cube,
// tetrahedron), their exact polyhedron volume and centroid computed here independently of the
// library, and ASCII / binary STL writers.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace pd_test {

using V3 = std::array<double, 3>;
using T3 = std::array<std::int32_t, 3>;

struct Surface {
    std::vector<V3> v;
    std::vector<T3> t; ///< outward (counter-clockwise seen from outside)
};

/// Icosahedron refined `levels` times, vertices projected on the sphere of radius r about c.
inline Surface icosphere(double r, int levels, V3 c = {0, 0, 0}) {
    const double g = (1 + std::sqrt(5.0)) / 2;
    Surface s;
    s.v = {{-1, g, 0},  {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
           {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
    s.t = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
           {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
           {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    auto unit = [](V3 p) {
        const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        return V3{p[0] / n, p[1] / n, p[2] / n};
    };
    for (auto& p : s.v)
        p = unit(p);
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<int, int>, int> mid;
        auto middle = [&](int a, int b) {
            const auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end())
                return it->second;
            const V3 &p = s.v[static_cast<std::size_t>(a)], &q = s.v[static_cast<std::size_t>(b)];
            s.v.push_back(unit({p[0] + q[0], p[1] + q[1], p[2] + q[2]}));
            const int k = static_cast<int>(s.v.size()) - 1;
            mid.emplace(key, k);
            return k;
        };
        std::vector<T3> next;
        for (const auto& t : s.t) {
            const int a = middle(t[0], t[1]), b = middle(t[1], t[2]), d = middle(t[2], t[0]);
            next.push_back({t[0], a, d});
            next.push_back({t[1], b, a});
            next.push_back({t[2], d, b});
            next.push_back({a, b, d});
        }
        s.t = std::move(next);
    }
    for (auto& p : s.v)
        p = {c[0] + r * p[0], c[1] + r * p[1], c[2] + r * p[2]};
    return s;
}

/// Axis-aligned cube [x0, x0 + a]^3 (x0 the same on every axis), 12 triangles.
inline Surface cube(double a, V3 lo = {0, 0, 0}) {
    Surface s;
    for (int k = 0; k < 8; ++k)
        s.v.push_back({lo[0] + (k & 1 ? a : 0), lo[1] + (k & 2 ? a : 0), lo[2] + (k & 4 ? a : 0)});
    s.t = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
           {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    return s;
}

/// Tetrahedron with the given vertices (any order; triangles made outward).
inline Surface tetrahedron(V3 a, V3 b, V3 c, V3 d) {
    Surface s{{a, b, c, d}, {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}}};
    const V3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v{c[0] - a[0], c[1] - a[1], c[2] - a[2]},
        w{d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    const double det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                       u[2] * (v[0] * w[1] - v[1] * w[0]);
    if (det < 0)
        for (auto& t : s.t)
            std::swap(t[1], t[2]);
    return s;
}

/// Exact volume and centroid of the polyhedron (tetrahedra from the first vertex).
inline std::pair<double, V3> moments(const Surface& s) {
    const V3 o = s.v[0];
    double v6 = 0;
    V3 m{0, 0, 0};
    for (const auto& t : s.t) {
        V3 p[3];
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < 3; ++i)
                p[k][static_cast<std::size_t>(i)] =
                    s.v[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])]
                       [static_cast<std::size_t>(i)] -
                    o[static_cast<std::size_t>(i)];
        const double det = p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) -
                           p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
                           p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0]);
        v6 += det;
        for (std::size_t i = 0; i < 3; ++i)
            m[i] += det * (p[0][i] + p[1][i] + p[2][i]) / 4;
    }
    return {v6 / 6, {o[0] + m[0] / v6, o[1] + m[1] / v6, o[2] + m[2] / v6}};
}

inline V3 normal(const Surface& s, const T3& t) {
    const V3 &a = s.v[static_cast<std::size_t>(t[0])], &b = s.v[static_cast<std::size_t>(t[1])],
             &c = s.v[static_cast<std::size_t>(t[2])];
    const V3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    V3 n{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    const double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    return {n[0] / l, n[1] / l, n[2] / l};
}

inline void write_ascii_stl(const std::string& path, const Surface& s) {
    std::ofstream f(path);
    f.precision(17);
    f << "solid test\n";
    for (const auto& t : s.t) {
        const V3 n = normal(s, t);
        f << "  facet normal " << n[0] << ' ' << n[1] << ' ' << n[2] << "\n    outer loop\n";
        for (auto k : t) {
            const V3& p = s.v[static_cast<std::size_t>(k)];
            f << "      vertex " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
        }
        f << "    endloop\n  endfacet\n";
    }
    f << "endsolid test\n";
}

/// Binary STL (float32 coordinates: use coordinates exact in float for exact comparisons).
/// `header` (at most 80 characters): exporters often start it with "solid", as ASCII files do.
inline void write_binary_stl(const std::string& path, const Surface& s,
                             const std::string& header_text = "binary STL, pdgrain tests") {
    std::ofstream f(path, std::ios::binary);
    char header[80] = {};
    std::memcpy(header, header_text.data(), std::min<std::size_t>(80, header_text.size()));
    f.write(header, 80);
    const auto n = static_cast<std::uint32_t>(s.t.size());
    f.write(reinterpret_cast<const char*>(&n), 4);
    for (const auto& t : s.t) {
        const V3 nn = normal(s, t);
        float rec[12];
        for (int i = 0; i < 3; ++i)
            rec[i] = static_cast<float>(nn[static_cast<std::size_t>(i)]);
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < 3; ++i)
                rec[3 + 3 * k + i] =
                    static_cast<float>(s.v[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])]
                                          [static_cast<std::size_t>(i)]);
        f.write(reinterpret_cast<const char*>(rec), sizeof rec);
        const std::uint16_t attr = 0;
        f.write(reinterpret_cast<const char*>(&attr), 2);
    }
}

/// A fresh directory per test (ctest may run tests in parallel processes), removed at the end.
class StlDir : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = std::filesystem::temp_directory_path() /
               (std::string("pd_test_stl_") +
                ::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name() + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(dir_);
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    std::filesystem::path dir_;
};

} // namespace pd_test
