// SPDX-License-Identifier: MIT
// Issue 29 (start-up cost): model::pow4 returns the bits of std::pow(u, 4) for every bond
// direction component of grid families and for random components, and takes its own fast path
// for most of them (else it would save nothing).
#include "model/surface_correction.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>

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
