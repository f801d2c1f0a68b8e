// SPDX-License-Identifier: MIT
#include "model/surface_correction.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pd::model {

namespace {

/// Unit direction from node i to node j in the body frame; returns the distance.
double direction(const FamilyRows& f, std::size_t i, std::size_t j, double n[3]) {
    double dx[3];
    double r2 = 0;
    for (std::size_t c = 0; c < 3; ++c) {
        dx[c] = f.x0[3 * j + c] - f.x0[3 * i + c];
        r2 += dx[c] * dx[c];
    }
    const double r = std::sqrt(r2);
    const double a = f.angle.empty() ? 0.0 : f.angle[i];
    const double co = std::cos(a), so = std::sin(a);
    n[0] = (co * dx[0] + so * dx[1]) / r;
    n[1] = (-so * dx[0] + co * dx[1]) / r;
    n[2] = dx[2] / r;
    return r;
}

} // namespace

std::array<double, 3> surface_axis_factors(const std::array<double, 3>& family, double bulk, int d,
                                           double limit) {
    std::array<double, 3> g{1, 1, 1};
    for (int a = 0; a < d; ++a) {
        const auto k = static_cast<std::size_t>(a);
        if (family[k] > 0 && bulk > 0)
            g[k] = std::clamp(bulk / family[k], 1.0 / limit, limit);
    }
    return g;
}

double surface_bond_factor(const double* n, const std::array<double, 3>& gi,
                           const std::array<double, 3>& gj, int d) {
    double s = 0;
    for (int a = 0; a < d; ++a) {
        const auto k = static_cast<std::size_t>(a);
        const double g = 0.5 * (gi[k] + gj[k]);
        s += n[k] * n[k] / (g * g);
    }
    return s > 0 ? 1.0 / std::sqrt(s) : 1.0;
}

std::vector<double> family_axis_moments(const FamilyRows& f, std::span<const double> weight, int d,
                                        std::size_t n) {
    std::vector<double> out(3 * n, 0.0);
    for (std::size_t a = 0; a < f.rows.size(); ++a) {
        const auto i = static_cast<std::size_t>(f.rows[a]);
        for (auto k = f.offsets[a]; k < f.offsets[a + 1]; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            double u[3];
            direction(f, i, static_cast<std::size_t>(f.neighbor[kk]), u);
            for (int c = 0; c < d; ++c)
                out[3 * i + static_cast<std::size_t>(c)] += weight[kk] * std::pow(u[c], 4);
        }
    }
    return out;
}

std::vector<double> surface_bond_factors(const FamilyRows& f, std::span<const double> g, int d) {
    std::vector<double> out(f.neighbor.size(), 1.0);
    for (std::size_t a = 0; a < f.rows.size(); ++a) {
        const auto i = static_cast<std::size_t>(f.rows[a]);
        const std::array<double, 3> gi{g[3 * i], g[3 * i + 1], g[3 * i + 2]};
        for (auto k = f.offsets[a]; k < f.offsets[a + 1]; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            const auto j = static_cast<std::size_t>(f.neighbor[kk]);
            double u[3];
            direction(f, i, j, u);
            out[kk] = surface_bond_factor(u, gi, {g[3 * j], g[3 * j + 1], g[3 * j + 2]}, d);
        }
    }
    return out;
}

std::vector<double> surface_bond_factors(const FamilyRows& f, std::span<const double> weight, int d,
                                         std::size_t n,
                                         const std::function<void(std::vector<double>&)>& exchange,
                                         int iterations) {
    auto g = family_axis_moments(f, weight, d, n);
    auto update = [&](std::vector<double>& to, const std::vector<double>& moments) {
        for (auto row : f.rows) {
            const auto i = static_cast<std::size_t>(row);
            const auto gi =
                surface_axis_factors({moments[3 * i], moments[3 * i + 1], moments[3 * i + 2]}, 1.0,
                                     d, std::numeric_limits<double>::infinity());
            for (std::size_t a = 0; a < 3; ++a)
                to[3 * i + a] = std::clamp(to[3 * i + a] * gi[a], 0.25, 4.0);
        }
        exchange(to);
    };
    std::vector<double> ones(3 * n, 1.0), gw(weight.size());
    update(ones, g);
    g = ones;
    for (int it = 0; it < iterations; ++it) {
        const auto G = surface_bond_factors(f, g, d);
        for (std::size_t k = 0; k < gw.size(); ++k)
            gw[k] = G[k] * weight[k];
        update(g, family_axis_moments(f, gw, d, n));
    }
    return surface_bond_factors(f, g, d);
}

} // namespace pd::model
