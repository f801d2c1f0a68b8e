// SPDX-License-Identifier: MIT
// Issue 31: the flaw factors of one grain's bonds follow the Weibull law of modulus m and median 1
// (fitted modulus within 10 %), and depend only on (seed, body, unordered node pair).
#include "core/log.hpp"
#include "model/flaws.hpp"
#include "model/pmb.hpp"
#include "pipeline/scene.hpp"
#include "solver/solver.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace {

/// The factors of the bonds of a grain of 3000 nodes, each bonded to its next 20 (60000 bonds).
std::vector<double> grain_factors(double m, std::int64_t seed) {
    std::vector<double> w;
    for (std::int64_t i = 0; i < 3000; ++i)
        for (std::int64_t j = i + 1; j <= i + 20; ++j)
            w.push_back(pd::model::flaw_factor(m, seed, 7, i, j));
    std::sort(w.begin(), w.end());
    return w;
}

/// Least-squares slope of ln(-ln(1 - F)) against ln w (Weibull plot), F = (k + 0.5) / N.
double fitted_modulus(const std::vector<double>& w) {
    const double n = static_cast<double>(w.size());
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (std::size_t k = 0; k < w.size(); ++k) {
        const double F = (static_cast<double>(k) + 0.5) / n;
        const double x = std::log(w[k]), y = std::log(-std::log1p(-F));
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

/// Calls fn(model, a, j, s_c / s0) for every bond a -> j of a one-disc scene, after the
/// solver's setup (1 rank: row a is node a).
template <class Fn>
void each_bond(const std::string& scene, Fn fn) {
    const pd::Log quiet("test", 0, pd::Verbosity::quiet);
    const auto m = pd::pipeline::build_scene(scene, "disc", quiet);
    pd::solver::Solver s(m);
    s.initialize();
    const auto& b = s.bonds();
    const double s0 = pd::model::pmb_constants(m.materials[0], m.bodies.horizon[0], 2, m.planar).s0;
    for (std::size_t a = 0; a + 1 < b.offsets.size(); ++a)
        for (auto k = b.offsets[a]; k < b.offsets[a + 1]; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            fn(m, a, static_cast<std::size_t>(b.neighbor[kk]), (b.lc[kk] / b.xi[kk] - 1) / s0);
        }
}

} // namespace

TEST(Flaws, OneGrainFitsTheWeibullModulusAndMedian) {
    for (const double m : {3.0, 6.0, 12.0}) {
        const auto w = grain_factors(m, 1);
        const double fit = fitted_modulus(w);
        const double median = w[w.size() / 2];
        std::printf("m = %g: fitted %.4f (%.2f %%), median %.4f, least %.3f\n", m, fit,
                    100 * (fit / m - 1), median, w.front());
        EXPECT_NEAR(fit / m, 1.0, 0.10);
        EXPECT_NEAR(median, 1.0, 0.02);
    }
}

TEST(Flaws, SymmetricPerBondAndSeeded) {
    using pd::model::flaw_factor;
    EXPECT_EQ(flaw_factor(6, 1, 3, 10, 25), flaw_factor(6, 1, 3, 25, 10));
    EXPECT_NE(flaw_factor(6, 1, 3, 10, 25), flaw_factor(6, 2, 3, 10, 25));
    EXPECT_NE(flaw_factor(6, 1, 3, 10, 25), flaw_factor(6, 1, 4, 10, 25));
    EXPECT_NE(flaw_factor(6, 1, 3, 10, 25), flaw_factor(6, 1, 3, 10, 26));
    const double u = pd::model::flaw_uniform(0, 0, 0, 0);
    EXPECT_GT(u, 0.0);
    EXPECT_LT(u, 1.0);
}

TEST(Flaws, TheBondsOfOneDiscFitTheWeibullLawAroundS0) {
    // A PMB disc of 1 mm at h = 0.025 mm (about 5000 nodes, 70 000 bonds): the solver's
    // per-bond critical stretch lc / xi - 1 over its own s0.
    const std::string sc = R"({"dimension": 2,
      "materials": {"m": {"density": 1000, "youngs_modulus": 1e8, "fracture_energy": 10,
                          "flaws": {"law": "weibull", "modulus": 6, "seed": 1}}},
      "discretization": {"mesh_size": 2.5e-5, "horizon_factor": 3},
      "particles": [{"radius": 1e-3, "center": [0, 0], "material": "m"}],
      "solver": {"final_time": 1e-6}})";
    std::vector<double> w;
    double s0 = 0;
    each_bond(sc, [&](const pd::model::Model& m, std::size_t a, std::size_t j, double r) {
        s0 = pd::model::pmb_constants(m.materials[0], m.bodies.horizon[0], 2, m.planar).s0;
        if (j > a)
            w.push_back(r);
    });
    std::sort(w.begin(), w.end());
    const double fit = fitted_modulus(w);
    std::printf("disc: %zu bonds, s0 = %.4g, fitted modulus %.4f (m = 6), median s_c / s0 %.4f, "
                "least %.3f\n",
                w.size(), s0, fit, w[w.size() / 2], w.front());
    EXPECT_GT(w.size(), 20000u);
    EXPECT_NEAR(fit / 6, 1.0, 0.10);
    EXPECT_NEAR(w[w.size() / 2], 1.0, 0.02);
}

TEST(Flaws, PatchesShareOneFactorAndFitTheWeibullLaw) {
    // Correlated flaws ("length" L): the solver gives every bond whose midpoint lies in one L x L
    // cell (body frame) the same critical stretch, and the cells' factors follow the Weibull law
    // (modulus within 10 %, median 1) over 4096 cells.
    using pd::model::flaw_cell_factor;
    EXPECT_NE(flaw_cell_factor(4, 1, 0, 2, 3, 0), flaw_cell_factor(4, 1, 0, 3, 2, 0));
    EXPECT_NE(flaw_cell_factor(4, 1, 0, 2, 3, 0), flaw_cell_factor(4, 2, 0, 2, 3, 0));
    std::vector<double> cells;
    for (int i = 0; i < 64; ++i)
        for (int j = 0; j < 64; ++j)
            cells.push_back(flaw_cell_factor(4, 1, 0, i - 32, j - 32, 0));
    std::sort(cells.begin(), cells.end());
    EXPECT_NEAR(fitted_modulus(cells) / 4, 1.0, 0.10);
    EXPECT_NEAR(cells[cells.size() / 2], 1.0, 0.05);
    const std::string sc = R"({"dimension": 2,
      "materials": {"m": {"density": 1000, "youngs_modulus": 1e8, "fracture_energy": 10,
                          "flaws": {"law": "weibull", "modulus": 4, "seed": 3, "length": 2.5e-4}}},
      "discretization": {"mesh_size": 5e-5, "horizon_factor": 3},
      "particles": [{"radius": 1e-3, "center": [2e-3, 1e-3], "material": "m"}],
      "solver": {"final_time": 1e-6}})";
    std::size_t checked = 0;
    each_bond(sc, [&](const pd::model::Model& m, std::size_t a, std::size_t j, double r) {
        std::int64_t c[2];
        for (std::size_t d = 0; d < 2; ++d)
            c[d] = static_cast<std::int64_t>(std::floor(
                (0.5 * (m.nodes.x0[3 * a + d] + m.nodes.x0[3 * j + d]) - m.bodies.center[d]) /
                2.5e-4));
        EXPECT_NEAR(r, flaw_cell_factor(4, 3, 0, c[0], c[1], 0), 1e-9);
        ++checked;
    });
    EXPECT_GT(checked, 10000u);
}
