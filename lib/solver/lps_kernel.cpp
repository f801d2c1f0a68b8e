// SPDX-License-Identifier: MIT
// The LPS bond kernel (spec 1.3): the dilatation pass, then the force pass, two bonds per SSE2
// step like the PMB row of bond_forces.cpp (a portable path does the same operations in order).
#include "solver/bond_forces.hpp"
#include "solver/bond_kernels.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>

namespace pd::solver {

using kernels::ensure_constants;
using kernels::over_rows;
using kernels::Sums;
#if defined(__SSE2__)
using kernels::gather2;
using kernels::lanes;
#endif

namespace {

template <bool Breakable, bool Energy>
BondResult lps_kernel(State& s, BondData& b, BodyLaw& law, const std::function<void()>& between) {
    // Energy of node i (spec 1.3, reference weighted volume m_i fixed for the whole run):
    //   W_i = k/2 theta_i^2 + alpha mu / (2 m_i) sum_intact w (e^d_ij)^2 beta V_j,
    //   theta_i = d / m_i sum_intact w xi e beta V_j,   e^d = e - theta xi / d.
    // The force is its exact derivative: t_ij = w (d k theta_i / m_i xi + alpha mu / m_i
    // (e^d_ij - q_i xi)), q_i = theta_i / d (1 - m_i^intact / m_i). q_i = 0 for a whole family;
    // once bonds break it is the term the usual formula drops, and without it the force is not
    // conservative: a damaged family pumps energy in (issue 10: a hollow ellipse on a tip gained
    // 0.17 J of kinetic energy). With m_i fixed, W_i stays a bounded positive quadratic form of
    // the intact bonds' extensions, so losing bonds never stiffens a node (recomputing m_i from
    // the intact bonds would: 1/m_i grows without bound as the family empties).
    const auto n = static_cast<std::int64_t>(s.rows.size());
    const index_t* rows = s.rows.data();
    const double* x = s.x.data();
    const double* vol = s.vol.data();
    double* f = s.f.data();
    const offset_t* off = b.offsets.data();
    const index_t* nb = b.neighbor.data();
    const double* xi = b.xi.data();
    const double* beta = b.beta.data();
    const double* om = b.omega.data();
    std::uint8_t* alive = b.alive.data(); // 2 = broken in this call (pass 1), 0 after pass 2
    const double dd = law.dimension;
    double* theta = law.theta.data();
    double* q = law.q.data();
    const double* mw = law.m.data();
    const double* wv = b.wv.data();
    const double* lc = b.lc.data();
    double* bu = b.len.data();     // omega beta V_j e / l, pass 1 for pass 2
    double* bv = b.inv_len.data(); // omega beta V_j xi / l
    double* pshare = law.lps_p.data();
    const double* ka = law.lps_a.data();
    const double* kt = law.lps_k.data();
    // Pass 1: break bonds (tension only, symmetric inputs), then dilatation, q and P.
    auto pass1 = [&](std::int64_t a, double&, double&, double&, std::int64_t& broken) {
        const std::int64_t i = rows[a];
        const auto body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(i)]);
        if (!law.lps[body] || !s.moving[static_cast<std::size_t>(i)]) {
            theta[i] = 0;
            q[i] = 0;
            pshare[i] = 0;
            return;
        }
        const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2];
        // Hot loop: every bond intact, none breaking (no branch). Two lanes as in the PMB row:
        // bond k0 + 2m + L summed in lane L, the odd last one in lane 0.
        double th2[2] = {0, 0};
        int bad = 0;
        const double op = 1.0 + law.s0[body]; // breaks beyond xi (1 + s0), as b.lc
        auto bond1 = [&](offset_t k, int L) {
            const index_t j = nb[k];
            const double d0 = x[3 * j] - xi0, d1 = x[3 * j + 1] - xi1, d2 = x[3 * j + 2] - xi2;
            const double l = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
            const double inv = 1.0 / l, wx = wv[k] * xi[k], e = l - xi[k];
            bu[k] = wv[k] * e * inv; // for pass 2: no sqrt, division, nor e there
            bv[k] = wx * inv;
            th2[L] += wx * e;
            bad |= static_cast<int>(l > xi[k] * op) | static_cast<int>(alive[k] != 1);
        };
        offset_t k = off[a];
        const offset_t k1 = off[a + 1];
#if defined(__SSE2__)
        {
            const __m128d X0 = _mm_set1_pd(xi0), X1 = _mm_set1_pd(xi1), X2 = _mm_set1_pd(xi2);
            const __m128d OP = _mm_set1_pd(op), ONE = _mm_set1_pd(1.0);
            __m128d TH = _mm_setzero_pd(), B = _mm_setzero_pd();
            for (; k + 1 < k1; k += 2) {
                __m128d d0, d1, d2;
                gather2(x, nb[k], nb[k + 1], X0, X1, X2, d0, d1, d2);
                const __m128d l = _mm_sqrt_pd(_mm_add_pd(
                    _mm_add_pd(_mm_mul_pd(d0, d0), _mm_mul_pd(d1, d1)), _mm_mul_pd(d2, d2)));
                const __m128d inv = _mm_div_pd(ONE, l);
                const __m128d x0 = _mm_loadu_pd(xi + k), w = _mm_loadu_pd(wv + k);
                const __m128d wx = _mm_mul_pd(w, x0), e = _mm_sub_pd(l, x0);
                _mm_storeu_pd(bu + k, _mm_mul_pd(_mm_mul_pd(w, e), inv));
                _mm_storeu_pd(bv + k, _mm_mul_pd(wx, inv));
                TH = _mm_add_pd(TH, _mm_mul_pd(wx, e));
                B = _mm_or_pd(B, _mm_cmpgt_pd(l, _mm_mul_pd(x0, OP)));
                std::uint16_t al;
                std::memcpy(&al, alive + k, 2);
                bad |= static_cast<int>(al != 0x0101);
            }
            lanes(TH, th2[0], th2[1]);
            bad |= _mm_movemask_pd(B);
        }
#else
        for (; k + 1 < k1; k += 2) {
            bond1(k, 0);
            bond1(k + 1, 1);
        }
#endif
        if (k < k1)
            bond1(k, 0);
        double th = th2[0] + th2[1];
        bool damaged = false;
        double mi = 0;
        if (bad) {
            th = 0;
            for (offset_t k = off[a]; k < off[a + 1]; ++k) {
                if (!alive[k]) {
                    damaged = true;
                    continue;
                }
                const index_t j = nb[k];
                const double d0 = x[3 * j] - xi0, d1 = x[3 * j + 1] - xi1, d2 = x[3 * j + 2] - xi2;
                const double l = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
                if (Breakable && l > lc[k]) {
                    alive[k] = 2;
                    damaged = true;
                    ++broken;
                    continue;
                }
                mi += om[k] * xi[k] * xi[k] * beta[k] * vol[j];
                th += wv[k] * xi[k] * (l - xi[k]);
            }
        }
        theta[i] = dd * th / mw[i];
        q[i] = damaged ? theta[i] / dd * (1.0 - mi / mw[i]) : 0.0;
        pshare[i] = kt[i] * theta[i] - ka[i] * (theta[i] / dd + q[i]);
    };
    const std::int64_t broken = over_rows(n, pass1).broken;
    if (between)
        between(); // ghosts' dilatation and q
    // Pass 2: forces from both ends of every intact bond; the energy bonds broken in pass 1 held.
    auto pass2 = [&](std::int64_t a, double& energy, double& released, double& repulsion,
                     std::int64_t&) {
        const std::int64_t i = rows[a];
        const auto body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(i)]);
        if (!law.lps[body])
            return;
        if (!s.moving[static_cast<std::size_t>(i)]) {
            f[3 * i] = f[3 * i + 1] = f[3 * i + 2] = 0;
            return;
        }
        const double kap = law.kappa[body];
        const double a_i = ka[i];
        const double p_i = kt[i] * theta[i];
        const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2];
        double fi[3] = {0, 0, 0}, wdev = 0, e_rep = 0, th_new = 0;
        bool fresh = false;
        // Hot loop (no branch): t_ij + t_ji = omega ((A_i + A_j) e + xi (P_i + P_j)). Two lanes
        // as in pass 1.
        const double pi = pshare[i], ti = theta[i] / dd;
        double f2[2][3] = {{0, 0, 0}, {0, 0, 0}}, w2[2] = {0, 0};
        int bad = 0;
        auto bond2 = [&](offset_t k, int L) {
            const index_t j = nb[k];
            const double d0 = x[3 * j] - xi0, d1 = x[3 * j + 1] - xi1, d2 = x[3 * j + 2] - xi2;
            // omega t / l = (A_i + A_j) omega e / l + (P_i + P_j) omega xi / l
            const double ab = (a_i + ka[j]) * bu[k] + (pi + pshare[j]) * bv[k];
            f2[L][0] += ab * d0;
            f2[L][1] += ab * d1;
            f2[L][2] += ab * d2;
            if constexpr (Energy) { // e again, bitwise as in pass 1 (observation steps only)
                const double ed = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2) - xi[k] - ti * xi[k];
                w2[L] += wv[k] * ed * ed;
            }
            bad |= static_cast<int>(alive[k] != 1);
        };
        offset_t k = off[a];
        const offset_t k1 = off[a + 1];
#if defined(__SSE2__)
        {
            const __m128d X0 = _mm_set1_pd(xi0), X1 = _mm_set1_pd(xi1), X2 = _mm_set1_pd(xi2);
            const __m128d AI = _mm_set1_pd(a_i), PI = _mm_set1_pd(pi), TI = _mm_set1_pd(ti);
            __m128d F0 = _mm_setzero_pd(), F1 = _mm_setzero_pd(), F2 = _mm_setzero_pd();
            __m128d W = _mm_setzero_pd();
            for (; k + 1 < k1; k += 2) {
                const index_t ja = nb[k], jb = nb[k + 1];
                __m128d d0, d1, d2;
                gather2(x, ja, jb, X0, X1, X2, d0, d1, d2);
                const __m128d ab = _mm_add_pd(
                    _mm_mul_pd(_mm_add_pd(AI, _mm_set_pd(ka[jb], ka[ja])), _mm_loadu_pd(bu + k)),
                    _mm_mul_pd(_mm_add_pd(PI, _mm_set_pd(pshare[jb], pshare[ja])),
                               _mm_loadu_pd(bv + k)));
                F0 = _mm_add_pd(F0, _mm_mul_pd(ab, d0));
                F1 = _mm_add_pd(F1, _mm_mul_pd(ab, d1));
                F2 = _mm_add_pd(F2, _mm_mul_pd(ab, d2));
                if constexpr (Energy) {
                    const __m128d x0 = _mm_loadu_pd(xi + k);
                    const __m128d l = _mm_sqrt_pd(_mm_add_pd(
                        _mm_add_pd(_mm_mul_pd(d0, d0), _mm_mul_pd(d1, d1)), _mm_mul_pd(d2, d2)));
                    const __m128d ed = _mm_sub_pd(_mm_sub_pd(l, x0), _mm_mul_pd(TI, x0));
                    W = _mm_add_pd(W, _mm_mul_pd(_mm_mul_pd(_mm_loadu_pd(wv + k), ed), ed));
                }
                std::uint16_t al;
                std::memcpy(&al, alive + k, 2);
                bad |= static_cast<int>(al != 0x0101);
            }
            lanes(F0, f2[0][0], f2[1][0]);
            lanes(F1, f2[0][1], f2[1][1]);
            lanes(F2, f2[0][2], f2[1][2]);
            lanes(W, w2[0], w2[1]);
        }
#else
        for (; k + 1 < k1; k += 2) {
            bond2(k, 0);
            bond2(k + 1, 1);
        }
#endif
        if (k < k1)
            bond2(k, 0);
        fi[0] = f2[0][0] + f2[1][0];
        fi[1] = f2[0][1] + f2[1][1];
        fi[2] = f2[0][2] + f2[1][2];
        wdev = w2[0] + w2[1];
        if (bad) { // general path: broken bonds (repulsion), bonds broken in pass 1
            fi[0] = fi[1] = fi[2] = wdev = 0;
            const double kr = law.krep[body], rr = law.rrep[body];
            for (offset_t k = off[a]; k < off[a + 1]; ++k) {
                const index_t j = nb[k];
                const double d0 = x[3 * j] - xi0, d1 = x[3 * j + 1] - xi1, d2 = x[3 * j + 2] - xi2;
                const double l = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
                if (alive[k] != 1) {
                    if (alive[k] == 2) { // broken in pass 1: its share of the dilatation before
                        fresh = true;
                        th_new += om[k] * xi[k] * (l - xi[k]) * beta[k] * vol[j];
                    }
                    if (l < rr) { // fragments repel across broken bonds (spec 4.7)
                        const double ar = kr * (l - rr) * vol[j] / l;
                        fi[0] += ar * d0;
                        fi[1] += ar * d1;
                        fi[2] += ar * d2;
                        e_rep += kr * (rr - l) * (rr - l) * vol[j];
                    }
                    continue;
                }
                const double e = l - xi[k];
                const double t = (a_i + ka[j]) * e + xi[k] * (pshare[i] + pshare[j]);
                const double ab = wv[k] * t / l;
                fi[0] += ab * d0;
                fi[1] += ab * d1;
                fi[2] += ab * d2;
                const double ed_i = e - theta[i] * xi[k] / dd;
                wdev += wv[k] * ed_i * ed_i;
            }
        }
        f[3 * i] = fi[0];
        f[3 * i + 1] = fi[1];
        f[3 * i + 2] = fi[2];
        if (!Energy && !fresh)
            return;
        const double w_after = 0.5 * kap * theta[i] * theta[i] + 0.5 * a_i * wdev;
        energy += w_after * vol[i];
        repulsion += 0.25 * e_rep * vol[i]; // each pair from both ends
        if (Breakable && fresh) {
            // W_i with the bonds broken in this call still intact, at these positions, less half
            // the work the change of node i's force state would have done over this step (see
            // the PMB kernel): released = W_before - W_after - dt/2 sum_k (t_before - t_after)
            // beta V_j de_k/dt, de_k/dt the extension rate of bond k.
            const double th_b = theta[i] + dd * th_new / mw[i];
            const double* v = s.v.data();
            double wdev_b = 0, mi_b = 0;
            for (offset_t k = off[a]; k < off[a + 1]; ++k) {
                if (!alive[k])
                    continue;
                const index_t j = nb[k];
                const double d0 = x[3 * j] - x[3 * i], d1 = x[3 * j + 1] - x[3 * i + 1],
                             d2 = x[3 * j + 2] - x[3 * i + 2];
                const double ed =
                    std::sqrt(d0 * d0 + d1 * d1 + d2 * d2) - xi[k] - th_b * xi[k] / dd;
                wdev_b += om[k] * ed * ed * beta[k] * vol[j];
                mi_b += om[k] * xi[k] * xi[k] * beta[k] * vol[j];
            }
            const double q_b = th_b / dd * (1.0 - mi_b / mw[i]);
            double pw = 0;
            for (offset_t k = off[a]; k < off[a + 1]; ++k) {
                if (!alive[k])
                    continue;
                const index_t j = nb[k];
                const double d0 = x[3 * j] - x[3 * i], d1 = x[3 * j + 1] - x[3 * i + 1],
                             d2 = x[3 * j + 2] - x[3 * i + 2];
                const double l = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
                const double e = l - xi[k];
                const double rate =
                    (d0 * (v[3 * j] - v[3 * i]) + d1 * (v[3 * j + 1] - v[3 * i + 1]) +
                     d2 * (v[3 * j + 2] - v[3 * i + 2])) /
                    l;
                const double t_b = om[k] * (dd * kap * th_b / mw[i] * xi[k] +
                                            a_i * (e - th_b * xi[k] / dd - q_b * xi[k]));
                const double t_a =
                    alive[k] == 1
                        ? om[k] * (p_i * xi[k] + a_i * (e - theta[i] * xi[k] / dd - q[i] * xi[k]))
                        : 0.0;
                pw += (t_b - t_a) * beta[k] * vol[j] * rate;
                if (alive[k] == 2)
                    alive[k] = 0;
            }
            released +=
                (0.5 * kap * th_b * th_b + 0.5 * a_i * wdev_b - w_after - 0.5 * law.dt * pw) *
                vol[i];
        }
    };
    const Sums r = over_rows(n, pass2);
    return {Energy ? r.energy : 0.0, broken, r.released, Energy ? r.repulsion : 0.0};
}

} // namespace

BondResult lps_bond_forces(State& s, BondData& b, BodyLaw& law,
                           const std::function<void()>& between) {
    ensure_constants(s, b, law);
    if (law.energy)
        return law.any_breakable ? lps_kernel<true, true>(s, b, law, between)
                                 : lps_kernel<false, true>(s, b, law, between);
    return law.any_breakable ? lps_kernel<true, false>(s, b, law, between)
                             : lps_kernel<false, false>(s, b, law, between);
}

} // namespace pd::solver
