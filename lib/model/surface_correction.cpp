// SPDX-License-Identifier: MIT
#include "model/surface_correction.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace pd::model {

namespace {

/// The rotation of node i's body frame about z (cos, sin of f.angle[i]): computed once per row,
/// not per bond; cos 0 = 1 and sin 0 = 0 exactly, so an angle 0 skips the two calls and gives
/// the same bits.
struct Turn {
    double co = 1, so = 0;
};

Turn row_turn(const FamilyRows& f, std::size_t i) {
    const double a = f.angle.empty() ? 0.0 : f.angle[i];
    if (a == 0)
        return {};
    return {std::cos(a), std::sin(a)};
}

/// Unit direction from node i to node j in the body frame (t: node i's turn); returns the
/// distance.
double direction(const FamilyRows& f, Turn t, std::size_t i, std::size_t j, double n[3]) {
    double dx[3];
    double r2 = 0;
    for (std::size_t c = 0; c < 3; ++c) {
        dx[c] = f.x0[3 * j + c] - f.x0[3 * i + c];
        r2 += dx[c] * dx[c];
    }
    const double r = std::sqrt(r2);
    n[0] = (t.co * dx[0] + t.so * dx[1]) / r;
    n[1] = (-t.so * dx[0] + t.co * dx[1]) / r;
    n[2] = dx[2] / r;
    return r;
}

/// a * a = p + e exactly (Dekker's product with Veltkamp's split, no FMA; |a| in [2^-400, 2^500]).
void two_square(double a, double& p, double& e) {
    p = a * a;
    const double t = 134217729.0 * a; // 2^27 + 1
    const double hi = t - (t - a), lo = a - hi;
    e = ((hi * hi - p) + 2.0 * hi * lo) + lo * lo;
}

} // namespace

double pow4(double u) {
    if (u == 0)
        return 0.0;
    double s, e, hi, r1;
    two_square(u, s, e);   // u^2 = s + e
    two_square(s, hi, r1); // s^2 = hi + r1
    // u^4 = hi + lo + e^2 to within 2^-49 ulp(hi): |e| <= 2^-53 s, so e^2 < 2^-52 ulp, and the
    // two roundings of lo are below 2^-50 ulp.
    const double lo = r1 + 2.0 * s * e;
    const double r = hi + lo;
    const double d = lo - (r - hi); // hi + lo = r + d exactly (Fast2Sum, |lo| < 3 ulp(hi))
    const auto bits = std::bit_cast<std::uint64_t>(r);
    const double ulp = std::bit_cast<double>(bits & 0x7ff0000000000000ULL) * 0x1p-52;
    // |u^4 - r| < 0.451 ulp: every other double is more than 0.549 ulp away (r not a power of 2:
    // both neighbours are 1 ulp away), and std::pow (glibc >= 2.28: at most 0.54 ulp) must
    // return r. Otherwise, and near underflow, ask std::pow itself.
    if (r >= 0x1p-800 && (bits & 0xfffffffffffffULL) != 0 && std::abs(d) <= 0.45 * ulp)
        return r;
    return std::pow(u, 4);
}

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

namespace {

/// family_axis_moments with bond k's weight scaled by its factor G_k for the axis factors g (3 per
/// node; empty: unscaled): the same products G_k w_k and sums in the same order as building the
/// array G w first, without the two per-bond arrays and with one direction per bond.
std::vector<double> scaled_axis_moments(const FamilyRows& f, std::span<const double> weight,
                                        std::span<const double> g, int d, std::size_t n) {
    std::vector<double> out(3 * n, 0.0);
    for (std::size_t a = 0; a < f.rows.size(); ++a) {
        const auto i = static_cast<std::size_t>(f.rows[a]);
        const Turn t = row_turn(f, i);
        std::array<double, 3> gi{1, 1, 1};
        if (!g.empty())
            gi = {g[3 * i], g[3 * i + 1], g[3 * i + 2]};
        for (auto k = f.offsets[a]; k < f.offsets[a + 1]; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            const auto j = static_cast<std::size_t>(f.neighbor[kk]);
            double u[3];
            direction(f, t, i, j, u);
            const double w =
                g.empty() ? weight[kk]
                          : surface_bond_factor(u, gi, {g[3 * j], g[3 * j + 1], g[3 * j + 2]}, d) *
                                weight[kk];
            for (int c = 0; c < d; ++c)
                out[3 * i + static_cast<std::size_t>(c)] += w * pow4(u[c]);
        }
    }
    return out;
}

} // namespace

std::vector<double> family_axis_moments(const FamilyRows& f, std::span<const double> weight, int d,
                                        std::size_t n) {
    return scaled_axis_moments(f, weight, {}, d, n);
}

namespace {
/// The bond factors of g into out (one per bond).
void bond_factors_into(const FamilyRows& f, std::span<const double> g, int d,
                       std::span<double> out) {
    for (std::size_t a = 0; a < f.rows.size(); ++a) {
        const auto i = static_cast<std::size_t>(f.rows[a]);
        const std::array<double, 3> gi{g[3 * i], g[3 * i + 1], g[3 * i + 2]};
        const Turn t = row_turn(f, i);
        for (auto k = f.offsets[a]; k < f.offsets[a + 1]; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            const auto j = static_cast<std::size_t>(f.neighbor[kk]);
            double u[3];
            direction(f, t, i, j, u);
            out[kk] = surface_bond_factor(u, gi, {g[3 * j], g[3 * j + 1], g[3 * j + 2]}, d);
        }
    }
}
} // namespace

std::vector<double> surface_bond_factors(const FamilyRows& f, std::span<const double> g, int d) {
    std::vector<double> out(f.neighbor.size(), 1.0);
    bond_factors_into(f, g, d, out);
    return out;
}

std::vector<double> surface_bond_factors(const FamilyRows& f, std::vector<double> weight, int d,
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
    std::vector<double> ones(3 * n, 1.0);
    update(ones, g);
    g = ones;
    for (int it = 0; it < iterations; ++it) // the moments weighted by the bond factors of g
        update(g, scaled_axis_moments(f, weight, g, d, n));
    std::fill(weight.begin(), weight.end(), 1.0); // the factors in the weights' place
    bond_factors_into(f, g, d, weight);
    return weight;
}

} // namespace pd::model
