// SPDX-License-Identifier: MIT
// Issue 29 (start-up cost): model::pow4 returns the bits of std::pow(u, 4) for every bond
// direction component of grid families and for random components, and takes its own fast path
// for most of them (else it would save nothing).
#include "model/surface_correction.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace {

/// Counts the components where pow4's fast path could not have been taken (pow4 returned the
/// same bits, but the naive (u^2)^2 differs from std::pow: these show that the check matters).
struct Tally {
    std::int64_t n = 0, naive_differs = 0;
    void check(double u) {
        const double want = std::pow(u, 4);
        ASSERT_EQ(std::bit_cast<std::uint64_t>(pd::model::pow4(u)),
                  std::bit_cast<std::uint64_t>(want))
            << "u = " << u;
        const double u2 = u * u;
        naive_differs += u2 * u2 != want ? 1 : 0;
        ++n;
    }
};

} // namespace

TEST(SurfaceCorrection, Pow4EqualsStdPowOnGridDirections) {
    // Every lattice vector within 6 spacings, at three spacings and with an offset origin (the
    // rounding of x0_j - x0_i), in the units of a grid of h = 0.5 mm.
    Tally t;
    for (double h : {5e-4, 1e-3 / 3, 2.5e-5})
        for (int a = -6; a <= 6; ++a)
            for (int b = -6; b <= 6; ++b)
                for (int c = -6; c <= 6; ++c) {
                    if (a * a + b * b + c * c == 0 || a * a + b * b + c * c > 36)
                        continue;
                    const double o[3] = {0.0123, -0.0071, 0.0049};
                    const double dx[3] = {(o[0] + a * h) - o[0], (o[1] + b * h) - o[1],
                                          (o[2] + c * h) - o[2]};
                    const double r = std::sqrt(dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2]);
                    for (double x : dx)
                        t.check(x / r);
                }
    EXPECT_GT(t.n, 7000);
    EXPECT_GT(t.naive_differs, 0); // (u^2)^2 is not pow(u, 4): the careful path is needed
}

TEST(SurfaceCorrection, Pow4EqualsStdPowOnRandomComponents) {
    std::mt19937_64 gen(29);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    Tally t;
    for (int k = 0; k < 2000000; ++k)
        t.check(unit(gen));
    for (double u : {0.0, -0.0, 1.0, -1.0, 0.5, 1e-30, -1e-200, 1e-300, 0x1p-300, 0.75})
        t.check(u);
    EXPECT_GT(t.naive_differs, t.n / 20);
}

namespace {

using pd::model::FamilyRows;

/// The correction as it was written before its passes shared a row's directions and ran two
/// bonds per SSE2 lane (bond by bond, std::pow): the reference the fast passes must equal bit
/// for bit.
double ref_direction(const FamilyRows& f, std::size_t i, std::size_t j, double n[3]) {
    const double a = f.angle.empty() ? 0.0 : f.angle[i];
    const double co = a == 0 ? 1.0 : std::cos(a), so = a == 0 ? 0.0 : std::sin(a);
    double dx[3], r2 = 0;
    for (std::size_t c = 0; c < 3; ++c) {
        dx[c] = f.x0[3 * j + c] - f.x0[3 * i + c];
        r2 += dx[c] * dx[c];
    }
    const double r = std::sqrt(r2);
    n[0] = (co * dx[0] + so * dx[1]) / r;
    n[1] = (-so * dx[0] + co * dx[1]) / r;
    n[2] = dx[2] / r;
    return r;
}

std::array<double, 3> at(const std::vector<double>& g, std::size_t i) {
    return {g[3 * i], g[3 * i + 1], g[3 * i + 2]};
}

std::vector<double> ref_moments(const FamilyRows& f, const std::vector<double>& w,
                                const std::vector<double>& g, int d, std::size_t n) {
    std::vector<double> out(3 * n, 0.0);
    for (std::size_t a = 0; a < f.rows.size(); ++a) {
        const auto i = static_cast<std::size_t>(f.rows[a]);
        for (auto k = f.offsets[a]; k < f.offsets[a + 1]; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            const auto j = static_cast<std::size_t>(f.neighbor[kk]);
            double u[3];
            ref_direction(f, i, j, u);
            const double wk =
                g.empty() ? w[kk]
                          : pd::model::surface_bond_factor(u, at(g, i), at(g, j), d) * w[kk];
            for (int c = 0; c < d; ++c)
                out[3 * i + static_cast<std::size_t>(c)] += wk * std::pow(u[c], 4);
        }
    }
    return out;
}

std::vector<double> ref_factors(const FamilyRows& f, const std::vector<double>& w, int d,
                                std::size_t n) {
    auto update = [&](std::vector<double>& to, const std::vector<double>& m) {
        for (auto row : f.rows) {
            const auto i = static_cast<std::size_t>(row);
            const auto gi = pd::model::surface_axis_factors(
                at(m, i), 1.0, d, std::numeric_limits<double>::infinity());
            for (std::size_t c = 0; c < 3; ++c)
                to[3 * i + c] = std::clamp(to[3 * i + c] * gi[c], 0.25, 4.0);
        }
    };
    std::vector<double> g(3 * n, 1.0);
    update(g, ref_moments(f, w, {}, d, n));
    update(g, ref_moments(f, w, g, d, n));
    std::vector<double> out(w.size(), 1.0);
    for (std::size_t a = 0; a < f.rows.size(); ++a) {
        const auto i = static_cast<std::size_t>(f.rows[a]);
        for (auto k = f.offsets[a]; k < f.offsets[a + 1]; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            const auto j = static_cast<std::size_t>(f.neighbor[kk]);
            double u[3];
            ref_direction(f, i, j, u);
            out[kk] = pd::model::surface_bond_factor(u, at(g, i), at(g, j), d);
        }
    }
    return out;
}

/// A block of nx x ny x nz nodes at spacing h (jittered by `jitter` h), families to 3.2 h, each
/// row's bonds in increasing order; rows of odd and even length; `angle` per node.
void expect_bitwise_reference(int d, double jitter, double angle) {
    const int nx = 9, ny = 8, nz = d == 3 ? 7 : 1;
    const double h = 0.37e-3;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> U(-1, 1);
    std::vector<double> x0;
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                x0.push_back(-0.0011 + i * h + jitter * h * U(rng));
                x0.push_back(0.0023 + j * h + jitter * h * U(rng));
                x0.push_back(d == 3 ? 0.0007 + k * h + jitter * h * U(rng) : 0.0);
            }
    const std::size_t n = x0.size() / 3;
    std::vector<std::int64_t> offsets{0};
    std::vector<std::int32_t> neighbor, rows;
    std::vector<double> w;
    std::size_t odd = 0;
    for (std::size_t i = 0; i < n; ++i) {
        rows.push_back(static_cast<std::int32_t>(i));
        for (std::size_t j = 0; j < n; ++j) {
            double r2 = 0;
            for (std::size_t c = 0; c < 3; ++c)
                r2 += (x0[3 * j + c] - x0[3 * i + c]) * (x0[3 * j + c] - x0[3 * i + c]);
            if (j != i && r2 <= (3.2 * h) * (3.2 * h)) {
                neighbor.push_back(static_cast<std::int32_t>(j));
                w.push_back(std::sqrt(r2) / (h * 300.0) * (1 + 0.1 * U(rng)));
            }
        }
        offsets.push_back(static_cast<std::int64_t>(neighbor.size()));
        odd += (offsets.back() - offsets[offsets.size() - 2]) % 2;
    }
    ASSERT_GT(odd, 0u); // the odd last bond's scalar path is exercised
    std::vector<double> angles(n, 0.0);
    for (std::size_t i = n / 2; i < n; ++i)
        angles[i] = angle;
    const FamilyRows f{offsets, neighbor, rows, x0, angles};
    const auto want = ref_factors(f, w, d, n);
    const auto got = pd::model::surface_bond_factors(
        f, w, d, n, [](std::vector<double>&) {}, 1);
    ASSERT_EQ(got.size(), want.size());
    std::size_t not_one = 0;
    for (std::size_t k = 0; k < want.size(); ++k) {
        ASSERT_EQ(std::bit_cast<std::uint64_t>(got[k]), std::bit_cast<std::uint64_t>(want[k]))
            << "bond " << k;
        not_one += want[k] != 1.0 ? 1 : 0;
    }
    EXPECT_GT(not_one, want.size() / 2); // a correction that acts
}

} // namespace

// Issue 29 item 3: the passes compute each row's directions once and two bonds at a time in
// SSE2 lanes; the factors are the bits of the bond-by-bond formula (std::pow, no shared
// directions), on grids and jittered nodes, in 2D and 3D, turned and not.
TEST(SurfaceCorrection, FastPassesEqualTheBondByBondFormula) {
    expect_bitwise_reference(3, 0.0, 0.0);
    expect_bitwise_reference(3, 0.05, 0.4);
    expect_bitwise_reference(2, 0.0, 0.0);
    expect_bitwise_reference(2, 0.1, -1.1);
}
