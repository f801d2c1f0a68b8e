// SPDX-License-Identifier: MIT
#include "model/quadrature.hpp"

#include "model/lps.hpp"
#include "model/pmb.hpp"
#include "model/rnp.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace pd::model {

namespace {

using std::numbers::pi;

/// Young's modulus along an axis of a cubic-symmetric stiffness with components c11, c12.
double axis_modulus(double c11, double c12, int d) {
    return d == 2 ? c11 - c12 * c12 / c11 : (c11 - c12) * (c11 + 2 * c12) / (c11 + c12);
}

/// Per sample: family volume, and the moments (body frame, axis averages)
///   PMB/RNP: M = sum J r n^4 beta V;  LPS: Q = sum J r^2 n^4 beta V, P = sum J r^2 n n beta V.
struct Sample {
    double vol = 0, m11 = 0, m12 = 0, q11 = 0, q12 = 0, p11 = 0, mw = 0;
    double boundary = 1e300; ///< distance to the boundary (support-function bound)
};

/// What a family sum needs of body b: its node range, cut-off, frame and influence.
struct Body {
    std::size_t i0 = 0, i1 = 0;
    int d = 2;
    double delta = 0, h = 0, reach = 0;
    double co = 1, so = 0; ///< the body's orientation about z
    Influence inf = Influence::constant;
};

/// The cut-off the bond list used (not stored: pd-pack chose it): compare a node's row length
/// with the neighbour counts within delta and within delta + h/2. True: delta + h/2 with linear
/// partial volumes; false: PeriDEM's strict < delta.
bool partial_cutoff(const Model& m, std::size_t i0, std::size_t i1, double delta, double h) {
    if (m.bonds.offsets.size() != m.nodes.num() + 1)
        return true;
    const std::size_t i = i0 + (i1 - i0) / 2;
    std::int64_t strict = 0, wide = 0;
    for (std::size_t j = i0; j < i1; ++j) {
        double r2 = 0;
        for (std::size_t k = 0; k < 3; ++k)
            r2 += std::pow(m.nodes.x0[3 * j + k] - m.nodes.x0[3 * i + k], 2);
        if (j == i)
            continue;
        strict += r2 < delta * delta ? 1 : 0;
        wide += r2 < std::pow(delta + 0.5 * h, 2) ? 1 : 0;
    }
    const auto row = m.bonds.offsets[i + 1] - m.bonds.offsets[i];
    return !(row == strict && row != wide);
}

/// The body's extent along a fan of directions (its support function): a node's distance to the
/// boundary is at least min over u of (extent(u) - u . x), exactly so for a convex body up to the
/// fan's resolution (a concave notch can hide; the volume test of complete_average remains).
struct Fan {
    std::vector<std::array<double, 3>> dir;
    std::vector<double> extent;
};

Fan support_fan(const Model& m, const Body& B) {
    Fan f;
    if (B.d == 2) {
        for (int k = 0; k < 24; ++k)
            f.dir.push_back({std::cos(k * pi / 12), std::sin(k * pi / 12), 0});
    } else {
        for (int a = -1; a <= 1; ++a)
            for (int c = -1; c <= 1; ++c)
                for (int e = -1; e <= 1; ++e)
                    if (a || c || e) {
                        const double l = std::sqrt(a * a + c * c + e * e);
                        f.dir.push_back({a / l, c / l, e / l});
                    }
    }
    for (auto& u : f.dir) // in the body frame: a grid's faces are then among the fan's normals
        u = {B.co * u[0] - B.so * u[1], B.so * u[0] + B.co * u[1], u[2]};
    f.extent.assign(f.dir.size(), -1e300);
    for (std::size_t j = B.i0; j < B.i1; ++j)
        for (std::size_t u = 0; u < f.dir.size(); ++u) {
            const double* x = &m.nodes.x0[3 * j];
            f.extent[u] =
                std::max(f.extent[u], f.dir[u][0] * x[0] + f.dir[u][1] * x[1] + f.dir[u][2] * x[2]);
        }
    return f;
}

/// Node i's family sums (Sample) and its distance to the boundary.
Sample family_sample(const Model& m, const Body& B, const Fan& f, std::size_t i) {
    const int d = B.d;
    const double* xi = &m.nodes.x0[3 * i];
    Sample S;
    for (std::size_t u = 0; u < f.dir.size(); ++u)
        S.boundary = std::min(S.boundary, f.extent[u] - (f.dir[u][0] * xi[0] + f.dir[u][1] * xi[1] +
                                                         f.dir[u][2] * xi[2]));
    for (std::size_t j = B.i0; j < B.i1; ++j) {
        if (j == i)
            continue;
        double dx[3];
        double r2 = 0;
        for (int k = 0; k < 3; ++k) {
            dx[k] = m.nodes.x0[3 * j + static_cast<std::size_t>(k)] - xi[k];
            r2 += dx[k] * dx[k];
        }
        if (!(r2 < B.reach * B.reach))
            continue;
        const double r = std::sqrt(r2);
        const double w = partial_volume(r, B.delta, B.h) * m.nodes.volume[j];
        const double J = influence(B.inf, r / B.delta);
        // Direction in the body frame.
        const double n[3] = {(B.co * dx[0] + B.so * dx[1]) / r, (-B.so * dx[0] + B.co * dx[1]) / r,
                             dx[2] / r};
        double a4 = 0, a22 = 0, a2 = 0, pairs = 0;
        for (int a = 0; a < d; ++a) {
            a4 += std::pow(n[a], 4);
            a2 += n[a] * n[a];
            for (int c = a + 1; c < d; ++c) {
                a22 += n[a] * n[a] * n[c] * n[c];
                pairs += 1;
            }
        }
        a4 /= d;
        a22 /= pairs;
        S.vol += w;
        S.m11 += J * r * a4 * w;
        S.m12 += J * r * a22 * w;
        S.q11 += J * r2 * a4 * w;
        S.q12 += J * r2 * a22 * w;
        S.p11 += J * r2 * (a2 / d) * w; // P_aa averaged over the axes
        S.mw += J * r2 * w;
    }
    return S;
}

/// Sum of the complete families' samples (count in `n`): the outermost nodes at least the reach
/// away (a grid family one layer short of it misses 1.5 % of its volume in 3D and would pass a
/// volume test), and the volume of a whole horizon (within 3 % of the best sample, 95 % of the
/// ball).
Sample complete_sum(const std::vector<Sample>& samples, const Body& B, double ball, int& n) {
    double best = 0;
    for (const auto& S : samples)
        best = std::max(best, S.vol);
    Sample avg;
    for (const auto& S : samples) {
        const bool clear = S.boundary >= B.reach - 1e-9 * B.h;
        if (!clear || S.vol < 0.97 * best || S.vol < 0.95 * ball)
            continue;
        avg.m11 += S.m11;
        avg.m12 += S.m12;
        avg.q11 += S.q11;
        avg.q12 += S.q12;
        avg.p11 += S.p11;
        avg.mw += S.mw;
        ++n;
    }
    return avg;
}

/// LPS: kappa and mu solved from C_1111 and C_1122 of the discrete family (factors on out).
void lps_factors(const Model& m, const Material& mat, const Body& B, const Sample& avg,
                 QuadratureFactors& out) {
    const int d = B.d;
    // C = kappa A + mu B with A = (d/m)^2 P P, B = (alpha/m) (Q - P P / m) (see lps.hpp);
    // every term is invariant to scaling all the sums, so they need no division by samples.
    const double alpha = d == 3 ? 15.0 : 8.0;
    const double mw = avg.mw, p = avg.p11; // P_aa (~ m/d); P_ab = 0 by symmetry of a family
    const double A11 = std::pow(d / mw, 2) * p * p, A12 = A11;
    const double B11 = alpha / mw * (avg.q11 - p * p / mw);
    const double B12 = alpha / mw * (avg.q12 - p * p / mw);
    const auto k = lps_constants(mat, B.delta, d, m.planar);
    // Continuum: A = I I, B = alpha / (d (d + 2)) iso - alpha / d^2 I I.
    const double t11 = k.kappa + k.mu * (3 * alpha / (d * (d + 2)) - alpha / (d * d));
    const double t12 = k.kappa + k.mu * (alpha / (d * (d + 2)) - alpha / (d * d));
    const double det = A11 * B12 - A12 * B11;
    if (!(std::abs(det) > 0))
        return;
    const double kap = (t11 * B12 - t12 * B11) / det;
    const double mu = (A11 * t12 - A12 * t11) / det;
    if (kap > 0 && mu > 0) {
        out.kappa = kap / k.kappa;
        out.mu = mu / k.mu;
    }
}

} // namespace

QuadratureFactors quadrature_factors(const Model& m, std::size_t b, int max_samples) {
    QuadratureFactors out;
    Body B;
    B.d = m.dimension;
    B.i0 = static_cast<std::size_t>(m.bodies.begin(b));
    B.i1 = static_cast<std::size_t>(m.bodies.end(b));
    if (B.i1 <= B.i0)
        return out;
    const int d = B.d;
    const auto& mat = m.materials[static_cast<std::size_t>(m.bodies.material[b])];
    B.delta = m.bodies.horizon[b];
    B.h = m.bodies.mesh_size[b];
    B.reach = B.delta + (partial_cutoff(m, B.i0, B.i1, B.delta, B.h) ? 0.5 * B.h : 0.0);
    const double ball = d == 3 ? 4.0 / 3.0 * pi * std::pow(B.delta, 3) : pi * B.delta * B.delta;
    // Body frame: the reference mesh's axes turned by the body's orientation about z.
    B.co = std::cos(m.bodies.orientation[b]);
    B.so = std::sin(m.bodies.orientation[b]);
    B.inf = mat.law == Law::pmb ? Influence::constant : mat.influence;
    const std::size_t nb = B.i1 - B.i0;
    const std::size_t ns = std::min<std::size_t>(nb, static_cast<std::size_t>(max_samples));
    const Fan fan = support_fan(m, B);
    std::vector<Sample> samples(ns);
    for (std::size_t s = 0; s < ns; ++s) // spread over the body (the middle of ns index ranges)
        samples[s] = family_sample(m, B, fan, B.i0 + (2 * s + 1) * nb / (2 * ns));
    const Sample avg = complete_sum(samples, B, ball, out.samples);
    // Continuum moments: int J r^k n^4 dV = (int J r^k dV) iso / (d (d + 2)), iso_1111 = 3,
    // iso_1122 = 1, and int J r^k dV = omega_d' delta^(d+k) int_0^1 J q^(d-1+k) dq (2 pi | 4 pi).
    const double shell = d == 3 ? 4 * pi : 2 * pi;
    const int p = mat.law == Law::lps ? 2 : 1;
    if (out.samples == 0) {
        out.axis_moment = 3 * shell * std::pow(B.delta, d + p) *
                          influence_moment(B.inf, d - 1 + p) / (d * (d + 2));
        return out;
    }
    out.axis_moment = (p == 2 ? avg.q11 : avg.m11) / out.samples;
    if (mat.law == Law::lps) {
        lps_factors(m, mat, B, avg, out);
        return out;
    }
    // PMB and RNP: stiffness proportional to M; the factor makes the axis modulus the continuum's.
    const double cont =
        shell * std::pow(B.delta, d + 1) * influence_moment(B.inf, d) / (d * (d + 2));
    const double e_cont = axis_modulus(3 * cont, cont, d);
    const double e_disc = axis_modulus(avg.m11 / out.samples, avg.m12 / out.samples, d);
    out.pmb = e_disc > 0 ? e_cont / e_disc : 1.0;
    return out;
}

} // namespace pd::model
