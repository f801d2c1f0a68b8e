// SPDX-License-Identifier: MIT
#include "solver/bond_forces.hpp"

#include "solver/bond_kernels.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace pd::solver {

using kernels::ensure_constants;
using kernels::over_rows;
using kernels::Sums;
#if defined(__SSE2__)
using kernels::gather2;
using kernels::lanes;
#endif

namespace {

/// The reference loop of the PMB kernel as it was before issue 15 (stretch, two divisions per
/// bond), kept for solver_bench's side-by-side: same forces to rounding.
template <bool Breakable>
BondResult naive_kernel(State& s, BondData& b, const BodyLaw& law) {
    const auto n = static_cast<std::int64_t>(s.rows.size());
    const index_t* rows = s.rows.data();
    const double* x = s.x.data();
    const double* vol = s.vol.data();
    double* f = s.f.data();
    const offset_t* off = b.offsets.data();
    const index_t* nb = b.neighbor.data();
    const double* xi = b.xi.data();
    const double* beta = b.stiff.data();
    std::uint8_t* alive = b.alive.data();
    double energy = 0;
    std::int64_t broken = 0;
    for (std::int64_t a = 0; a < n; ++a) {
        const std::int64_t i = rows[a];
        const auto body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(i)]);
        if (law.lps[body] || law.rnp[body] || !s.moving[static_cast<std::size_t>(i)])
            continue;
        const double c = law.c[body], s0 = law.s0[body];
        double fi[3] = {0, 0, 0}, e_i = 0;
        for (offset_t k = off[a]; k < off[a + 1]; ++k) {
            const index_t j = nb[k];
            const double d0 = x[3 * j] - x[3 * i], d1 = x[3 * j + 1] - x[3 * i + 1],
                         d2 = x[3 * j + 2] - x[3 * i + 2];
            const double l = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
            if (Breakable && !alive[k])
                continue;
            const double st = (l - xi[k]) / xi[k];
            if (Breakable && st > s0) {
                alive[k] = 0;
                ++broken;
                continue;
            }
            const double w = beta[k] * vol[j];
            const double a = c * st * w / l;
            fi[0] += a * d0;
            fi[1] += a * d1;
            fi[2] += a * d2;
            e_i += c * st * st * xi[k] * w;
        }
        f[3 * i] = fi[0];
        f[3 * i + 1] = fi[1];
        f[3 * i + 2] = fi[2];
        energy += 0.25 * e_i * vol[i];
    }
    return {energy, broken, 0.0, 0.0};
}

/// PMB force of one row whose bonds are all intact, none breaking: the hot loop. Per bond one
/// sqrt and one division, no branch; returns false (and leaves f_i alone) when a bond is broken
/// or reaches its critical length xi (1 + s0) (`op` = 1 + s0 of the row's body: the product
/// b.lc holds, without its load), so the caller takes the general path.
/// Two lanes: bond k0 + 2m + L is summed in lane L, the odd last bond in lane 0, f_i is lane 0
/// plus lane 1. With SSE2 the lanes are one 16-byte register (sqrtpd, divpd: the divider is the
/// loop's bottleneck); elsewhere the same operations in the same order, so the force does not
/// depend on the CPU (nor on the rank: a row is summed whole on one rank).
template <bool Energy>
inline bool pmb_row_intact(const double* x, std::int64_t i, const index_t* nb, const double* xi,
                           const double* kb, double op, const std::uint8_t* alive, offset_t k0,
                           offset_t k1, double* fi, double& e_i) {
    const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2];
    double f[2][3] = {{0, 0, 0}, {0, 0, 0}}, e[2] = {0, 0};
    int bad = 0;
    // One bond into lane L, the operations of the SSE2 loop one lane at a time.
    auto bond = [&](offset_t k, int L) {
        const std::int64_t j = nb[k];
        const double d0 = x[3 * j] - xi0, d1 = x[3 * j + 1] - xi1, d2 = x[3 * j + 2] - xi2;
        const double l = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
        const double ext = l - xi[k];
        const double ke = kb[k] * ext;
        const double a = ke / l;
        f[L][0] += a * d0;
        f[L][1] += a * d1;
        f[L][2] += a * d2;
        if constexpr (Energy)
            e[L] += ke * ext;
        bad |= static_cast<int>(l > xi[k] * op) | static_cast<int>(alive[k] != 1);
    };
    offset_t k = k0;
#if defined(__SSE2__)
    {
        __m128d F0 = _mm_setzero_pd(), F1 = _mm_setzero_pd(), F2 = _mm_setzero_pd();
        __m128d E = _mm_setzero_pd(), B = _mm_setzero_pd();
        const __m128d X0 = _mm_set1_pd(xi0), X1 = _mm_set1_pd(xi1), X2 = _mm_set1_pd(xi2);
        const __m128d OP = _mm_set1_pd(op);
        for (; k + 1 < k1; k += 2) {
            const double* pa = x + 3 * static_cast<std::int64_t>(nb[k]);
            const double* pb = x + 3 * static_cast<std::int64_t>(nb[k + 1]);
            const __m128d xa = _mm_loadu_pd(pa), xb = _mm_loadu_pd(pb);
            const __m128d d0 = _mm_sub_pd(_mm_unpacklo_pd(xa, xb), X0);
            const __m128d d1 = _mm_sub_pd(_mm_unpackhi_pd(xa, xb), X1);
            const __m128d d2 = _mm_sub_pd(_mm_loadh_pd(_mm_load_sd(pa + 2), pb + 2), X2);
            const __m128d r2 =
                _mm_add_pd(_mm_add_pd(_mm_mul_pd(d0, d0), _mm_mul_pd(d1, d1)), _mm_mul_pd(d2, d2));
            const __m128d l = _mm_sqrt_pd(r2);
            const __m128d x0 = _mm_loadu_pd(xi + k);
            const __m128d ext = _mm_sub_pd(l, x0);
            const __m128d ke = _mm_mul_pd(_mm_loadu_pd(kb + k), ext);
            const __m128d a = _mm_div_pd(ke, l);
            F0 = _mm_add_pd(F0, _mm_mul_pd(a, d0));
            F1 = _mm_add_pd(F1, _mm_mul_pd(a, d1));
            F2 = _mm_add_pd(F2, _mm_mul_pd(a, d2));
            if constexpr (Energy)
                E = _mm_add_pd(E, _mm_mul_pd(ke, ext));
            B = _mm_or_pd(B, _mm_cmpgt_pd(l, _mm_mul_pd(x0, OP)));
            std::uint16_t al;
            std::memcpy(&al, alive + k, 2);
            bad |= static_cast<int>(al != 0x0101);
        }
        alignas(16) double t[2];
        _mm_store_pd(t, F0);
        f[0][0] = t[0], f[1][0] = t[1];
        _mm_store_pd(t, F1);
        f[0][1] = t[0], f[1][1] = t[1];
        _mm_store_pd(t, F2);
        f[0][2] = t[0], f[1][2] = t[1];
        _mm_store_pd(t, E);
        e[0] = t[0], e[1] = t[1];
        bad |= _mm_movemask_pd(B);
    }
#else
    for (; k + 1 < k1; k += 2) {
        bond(k, 0);
        bond(k + 1, 1);
    }
#endif
    if (k < k1)
        bond(k, 0);
    if (bad)
        return false;
    fi[0] = f[0][0] + f[1][0];
    fi[1] = f[0][1] + f[1][1];
    fi[2] = f[0][2] + f[1][2];
    e_i = e[0] + e[1];
    return true;
}

template <bool Breakable, bool Energy>
BondResult kernel(State& s, BondData& b, const BodyLaw& law) {
    const auto n = static_cast<std::int64_t>(s.rows.size());
    const index_t* rows = s.rows.data();
    const double* x = s.x.data();
    const double* vol = s.vol.data();
    double* f = s.f.data();
    const offset_t* off = b.offsets.data();
    const index_t* nb = b.neighbor.data();
    const double* xi = b.xi.data();
    const double* kb = b.kb.data();
    const double* lc = b.lc.data();
    std::uint8_t* alive = b.alive.data();
    auto row = [&](std::int64_t a, double& energy, double& released, double& repulsion,
                   std::int64_t& broken) {
        const std::int64_t i = rows[a];
        const auto body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(i)]);
        if (law.lps[body] || law.rnp[body])
            return; // the LPS or RNP kernel owns this row
        if (!s.moving[static_cast<std::size_t>(i)]) {
            f[3 * i] = f[3 * i + 1] = f[3 * i + 2] = 0;
            return;
        }
        double fi[3] = {0, 0, 0};
        double e_i = 0, e_rel = 0, e_rep = 0;
        if (!pmb_row_intact<Energy>(x, i, nb, xi, kb, 1.0 + law.s0[body], alive, off[a], off[a + 1],
                                    fi, e_i)) {
            // General path: broken bonds (repulsion), bonds breaking now.
            fi[0] = fi[1] = fi[2] = e_i = 0;
            const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2];
            const double kr = law.krep[body], rr = law.rrep[body];
            for (offset_t k = off[a]; k < off[a + 1]; ++k) {
                const index_t j = nb[k];
                const double d0 = x[3 * j] - xi0, d1 = x[3 * j + 1] - xi1, d2 = x[3 * j + 2] - xi2;
                const double l = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
                if (!alive[k]) {
                    // Fragments of one grain repel across broken bonds (spec 4.7).
                    if (l < rr) {
                        const double ar = kr * (l - rr) * vol[j] / l;
                        fi[0] += ar * d0;
                        fi[1] += ar * d1;
                        fi[2] += ar * d2;
                        if constexpr (Energy)
                            e_rep += kr * (rr - l) * (rr - l) * vol[j];
                    }
                    continue;
                }
                const double ext = l - xi[k];
                if (Breakable && l > lc[k]) {
                    // Tension only; i->j and j->i see identical l, xi: symmetric. The energy it
                    // held, less half the work its force would have done over the step that
                    // broke it: the trapezoid the integrator applied to the step lacks that
                    // half, so the balance closes to O(dt^2), not O(dt).
                    alive[k] = 0;
                    ++broken;
                    const double* v = s.v.data();
                    const double dv = d0 * (v[3 * j] - v[3 * i]) +
                                      d1 * (v[3 * j + 1] - v[3 * i + 1]) +
                                      d2 * (v[3 * j + 2] - v[3 * i + 2]);
                    e_rel += kb[k] * ext * (ext - law.dt * dv / l);
                    continue;
                }
                const double ab = kb[k] * ext / l;
                fi[0] += ab * d0;
                fi[1] += ab * d1;
                fi[2] += ab * d2;
                if constexpr (Energy)
                    e_i += kb[k] * ext * ext;
            }
        }
        f[3 * i] = fi[0];
        f[3 * i + 1] = fi[1];
        f[3 * i + 2] = fi[2];
        // Bond energy density 1/2 c s^2 xi per pair = 1/2 kb ext^2; the full list counts each
        // pair twice.
        if constexpr (Energy) {
            energy += 0.25 * e_i * vol[i];
            repulsion += 0.25 * e_rep * vol[i];
        }
        released += 0.25 * e_rel * vol[i];
    };
    const Sums r = over_rows(n, row);
    return {r.energy, r.broken, r.released, r.repulsion};
}

template <bool Breakable>
BondResult rnp_kernel(State& s, BondData& b, const BodyLaw& law) {
    const auto n = static_cast<std::int64_t>(s.rows.size());
    const index_t* rows = s.rows.data();
    const double* x = s.x.data();
    const double* x0 = s.x0.data();
    const double* vol = s.vol.data();
    double* f = s.f.data();
    const offset_t* off = b.offsets.data();
    const index_t* nb = b.neighbor.data();
    const double* xi = b.xi.data();
    const double* beta = b.beta.data();
    const double* om = b.omega.data();
    std::uint8_t* alive = b.alive.data();
    auto row = [&](std::int64_t a, double& energy, double& released, double&,
                   std::int64_t& broken) {
        const std::int64_t i = rows[a];
        const auto body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(i)]);
        if (!law.rnp[body])
            return;
        if (!s.moving[static_cast<std::size_t>(i)]) {
            f[3 * i] = f[3 * i + 1] = f[3 * i + 2] = 0;
            return;
        }
        const double C = law.rnp_c[body], bt = law.rnp_beta[body], rb = law.rnp_rbar[body];
        const double inv = 1.0 / law.rnp_inv[body];
        double fi[3] = {0, 0, 0}, e_i = 0, e_rel = 0;
        for (offset_t k = off[a]; k < off[a + 1]; ++k) {
            const index_t j = nb[k];
            if (Breakable && !alive[k]) {
                e_i += C * inv * beta[k] * vol[j]; // a broken bond keeps C / invF
                continue;
            }
            double X[3], eta[3], dot = 0;
            for (int d = 0; d < 3; ++d) {
                X[d] = x0[3 * j + d] - x0[3 * i + d];
                eta[d] = (x[3 * j + d] - x0[3 * j + d]) - (x[3 * i + d] - x0[3 * i + d]);
                dot += eta[d] * X[d];
            }
            const double r = xi[k];
            const double S = dot / (r * r);
            if constexpr (Breakable) {
                if (S > rb / std::sqrt(r)) {
                    alive[k] = 0;
                    ++broken;
                    e_i += C * inv * beta[k] * vol[j];
                    // Energy before minus after: the bond's potential jumps to its broken value.
                    e_rel +=
                        (om[k] * (1 - std::exp(-bt * r * S * S)) - 1) * C * inv * beta[k] * vol[j];
                    continue;
                }
            }
            const double ex = std::exp(-bt * r * S * S);
            const double a = 4.0 * om[k] * S * C * bt * ex * inv * beta[k] * vol[j] / r;
            fi[0] += a * X[0];
            fi[1] += a * X[1];
            fi[2] += a * X[2];
            e_i += om[k] * C * (1 - ex) * inv * beta[k] * vol[j];
        }
        f[3 * i] = fi[0];
        f[3 * i + 1] = fi[1];
        f[3 * i + 2] = fi[2];
        energy += e_i * vol[i];
        released += e_rel * vol[i];
    };
    const Sums r = over_rows(n, row);
    return {r.energy, r.broken, r.released, 0.0};
}

} // namespace

void bond_constants(const State& s, BondData& b, BodyLaw& law) {
    const auto nbond = b.xi.size();
    b.kb.resize(nbond);
    b.lc.resize(nbond);
    b.wv.assign(b.omega.empty() ? 0 : nbond, 0.0);
    b.len.assign(b.wv.size(), 0.0);
    b.inv_len.assign(b.wv.size(), 0.0);
    for (std::size_t a = 0; a + 1 < b.offsets.size(); ++a) {
        const auto body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(s.rows[a])]);
        const double s0 = law.s0[body];
        for (auto k = b.offsets[a]; k < b.offsets[a + 1]; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            const double vj = s.vol[static_cast<std::size_t>(b.neighbor[kk])];
            b.kb[kk] = law.c[body] * b.stiff[kk] * vj / b.xi[kk];
            b.lc[kk] =
                std::isfinite(s0) ? b.xi[kk] * (1.0 + s0) : std::numeric_limits<double>::infinity();
            if (!b.wv.empty())
                b.wv[kk] = b.omega[kk] * b.beta[kk] * vj;
        }
    }
    if (law.m.size() != s.n)
        return; // no LPS body
    law.lps_p.assign(s.n, 0.0);
    law.lps_a.assign(s.n, 0.0);
    law.lps_k.assign(s.n, 0.0);
    for (std::size_t i = 0; i < s.n; ++i) {
        const auto body = static_cast<std::size_t>(s.body[i]);
        const double mi = law.m[i];
        if (!law.lps[body] || !(mi > 0))
            continue; // (nodes neither owned nor ghosts have m = 0)
        law.lps_a[i] = law.alpha * law.mu[body] / mi;
        law.lps_k[i] = law.dimension * law.kappa[body] / mi;
    }
}

BondResult rnp_bond_forces(State& s, BondData& b, const BodyLaw& law) {
    ensure_constants(s, b, law);
    return law.any_breakable ? rnp_kernel<true>(s, b, law) : rnp_kernel<false>(s, b, law);
}

BondResult pmb_bond_forces(State& s, BondData& b, const BodyLaw& law) {
    ensure_constants(s, b, law);
    if (law.energy)
        return law.any_breakable ? kernel<true, true>(s, b, law) : kernel<false, true>(s, b, law);
    return law.any_breakable ? kernel<true, false>(s, b, law) : kernel<false, false>(s, b, law);
}

BondResult pmb_bond_forces_reference(State& s, BondData& b, const BodyLaw& law) {
    return law.any_breakable ? naive_kernel<true>(s, b, law) : naive_kernel<false>(s, b, law);
}

void damage_phi(const State& s, const BondData& b, std::vector<double>& phi) {
    phi.assign(s.n, 0.0);
    const auto n = static_cast<std::int64_t>(s.rows.size());
    const index_t* rows = s.rows.data();
#pragma omp parallel for schedule(static) if (n > parallel_min)
    for (std::int64_t a = 0; a < n; ++a) {
        const std::int64_t i = rows[a];
        double all = 0, br = 0;
        for (offset_t k = b.offsets[a]; k < b.offsets[a + 1]; ++k) {
            const double w = b.beta[k] * s.vol[b.neighbor[k]];
            all += w;
            if (!b.alive[k])
                br += w;
        }
        phi[i] = all > 0 ? br / all : 0.0;
    }
}

} // namespace pd::solver
