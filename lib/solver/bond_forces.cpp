// SPDX-License-Identifier: MIT
#include "solver/bond_forces.hpp"

#include "core/errors.hpp"
#include "model/flaws.hpp"
#include "solver/bond_kernels.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>

namespace pd::solver {

using kernels::ensure_constants;

namespace {

using namespace kernels;

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
    const double* kb = b.kb.data(); // c beta G V_j / xi: the stiffness the loop once built
    std::uint8_t* alive = b.alive.data();
    double energy = 0;
    std::int64_t broken = 0;
    for (std::int64_t a = 0; a < n; ++a) {
        const std::int64_t i = rows[a];
        const auto body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(i)]);
        if (law.lps[body] || law.rnp[body] || !s.moving[static_cast<std::size_t>(i)])
            continue;
        const double s0 = law.s0[body];
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
            const double w = kb[k] * xi[k]; // c beta V_j, to rounding
            const double a = st * w / l;
            fi[0] += a * d0;
            fi[1] += a * d1;
            fi[2] += a * d2;
            e_i += st * st * xi[k] * w;
        }
        f[3 * i] = fi[0];
        f[3 * i + 1] = fi[1];
        f[3 * i + 2] = fi[2];
        energy += 0.25 * e_i * vol[i];
    }
    return {energy, broken, 0.0, 0.0};
}

/// Bonds k, k+1 of a PMB row into the two lanes.
template <bool Energy, bool Comp, class V>
PD_INLINE void pmb_pair(CheckedLanes<V>& L, const Arrays& v, offset_t k) {
    V d[3];
    gather2(v.x, v.nb[k], v.nb[k + 1], L.X, d);
    const V l = length(d);
    const V x0 = load2(v.xi + k, V{});
    const V ext = sub(l, x0);
    const V ke = mul(load2(v.kb + k, V{}), ext);
    L.add_force(div(ke, l), d);
    if constexpr (Energy)
        L.S = add(L.S, mul(ke, ext));
    L.B = flag(L.B, l, mul(x0, L.OP));
    if constexpr (Comp)
        L.B = flag(L.B, mul(x0, L.OL), l); // l < xi (1 - s0)
    L.bad |= not_intact<2>(v.alive + k);
}

/// The rest of a PMB row from bond k on: pairs, the odd last bond in lane 0, then f_i and the
/// energy from the lanes; false (f_i left alone) when a bond is broken or reaches its critical
/// length xi (1 + s0) (`op` = 1 + s0 of the row's body: the product b.lc holds, without its
/// load), or, when Comp, falls below xi (1 - s0), so the caller takes the general path.
template <bool Energy, bool Comp, class V>
PD_INLINE bool pmb_rest(CheckedLanes<V>& L, const Arrays& v, std::int64_t i, offset_t k,
                        offset_t k1, double* fi, double& e_i) {
    for (; k + 1 < k1; k += 2)
        pmb_pair<Energy, Comp>(L, v, k);
    double e0 = lane0(L.S);
    if (k < k1) {
        double d[3];
        const double l = bond_d(v.x, i, v.nb[k], d);
        const double ext = l - v.xi[k], ke = v.kb[k] * ext;
        L.add_force0(ke / l, d);
        if constexpr (Energy)
            e0 += ke * ext;
        L.bad |= static_cast<int>(l > v.xi[k] * L.op) | static_cast<int>(v.alive[k] != 1);
        if constexpr (Comp)
            L.bad |= static_cast<int>(l < v.xi[k] * L.ol);
    }
    if (L.bad | any(L.B))
        return false;
    L.sum(fi);
    e_i = e0 + lane1(L.S);
    return true;
}

/// PMB force of one row whose bonds are all intact, none breaking: the hot loop, one sqrt and
/// one division per bond, no branch. Two lanes: V2 (portable) or __m128d (SSE2).
template <bool Energy, bool Comp, class V>
PD_INLINE bool pmb_hot(const Arrays& v, std::int64_t i, double op, double ol, offset_t k0,
                       offset_t k1, double* fi, double& e_i) {
    CheckedLanes<V> L(v.x + 3 * i, op, ol);
    return pmb_rest<Energy, Comp>(L, v, i, k0, k1, fi, e_i);
}

#if defined(PD_KERNELS_AVX2)
/// pmb_hot with four bonds per step in front (AVX2), then the SSE2 pair and odd bond.
template <bool Energy, bool Comp>
PD_AVX2 PD_INLINE bool pmb_hot_avx2(const Arrays& v, std::int64_t i, double op, double ol,
                                    offset_t k, offset_t k1, double* fi, double& e_i) {
    CheckedLanes<__m128d> L(v.x + 3 * i, op, ol);
    const kernels::Wide W(v.x + 3 * i);
    const __m256d OP = _mm256_set1_pd(op), OL = _mm256_set1_pd(ol);
    __m256d B = _mm256_setzero_pd();
    for (; k + 3 < k1; k += 4) {
        __m256d d[3];
        kernels::gather4(v.x, v.nb + k, W.X, d);
        const __m256d l = kernels::length4(d);
        const __m256d x0 = _mm256_loadu_pd(v.xi + k);
        const __m256d ext = _mm256_sub_pd(l, x0);
        const __m256d ke = _mm256_mul_pd(_mm256_loadu_pd(v.kb + k), ext);
        W.add_force(L, _mm256_div_pd(ke, l), d);
        if constexpr (Energy)
            L.S = kernels::fold(L.S, _mm256_mul_pd(ke, ext));
        B = _mm256_or_pd(B, _mm256_cmp_pd(l, _mm256_mul_pd(x0, OP), _CMP_GT_OQ));
        if constexpr (Comp)
            B = _mm256_or_pd(B, _mm256_cmp_pd(l, _mm256_mul_pd(x0, OL), _CMP_LT_OQ));
        L.bad |= not_intact<4>(v.alive + k);
    }
    L.bad |= _mm256_movemask_pd(B);
    return pmb_rest<Energy, Comp>(L, v, i, k, k1, fi, e_i);
}
#endif

/// PMB row with broken bonds (repulsion) or bonds breaking now: f_i and the row's sums.
template <bool Breakable, bool Energy, bool Comp>
[[gnu::noinline]] void pmb_general_row(const Arrays& v, const BodyLaw& law, std::size_t body,
                                       std::int64_t a, std::int64_t i, double& energy,
                                       double& released, double& repulsion, std::int64_t& broken) {
    double fi[3] = {0, 0, 0};
    double e_i = 0, e_rel = 0, e_rep = 0;
    const double kr = law.krep[body], rr = law.rrep[body];
    const double lo = Comp ? law.s0_lo[body] : 0.0, hi = 1.0 + law.s0[body];
    for (offset_t k = v.off[a]; k < v.off[a + 1]; ++k) {
        const index_t j = v.nb[k];
        double d[3];
        const double l = bond_d(v.x, i, j, d);
        if (!v.alive[k]) {
            // Fragments of one grain repel across broken bonds (spec 4.7).
            if (l < rr) {
                const double ar = kr * (l - rr) * v.vol[j] / l;
                for (int c = 0; c < 3; ++c)
                    fi[c] += ar * d[c];
                if constexpr (Energy)
                    e_rep += kr * (rr - l) * (rr - l) * v.vol[j];
            }
            continue;
        }
        const double ext = l - v.xi[k];
        if (Breakable && (l > break_length(v, k, hi) || (Comp && l < v.xi[k] * lo))) {
            // Tension (and, when Comp, compression beyond xi (1 - s0), PeriDEM's |s| > s0);
            // i->j and j->i see identical l, xi and body: symmetric. The energy it held,
            // less half the work its force would have done over the step that broke it: the
            // trapezoid the integrator applied to the step lacks that half, so the balance
            // closes to O(dt^2), not O(dt).
            v.alive[k] = 0;
            ++broken;
            const double dv = d[0] * (v.v[3 * j] - v.v[3 * i]) +
                              d[1] * (v.v[3 * j + 1] - v.v[3 * i + 1]) +
                              d[2] * (v.v[3 * j + 2] - v.v[3 * i + 2]);
            e_rel += v.kb[k] * ext * (ext - law.dt * dv / l);
            continue;
        }
        const double ab = v.kb[k] * ext / l;
        for (int c = 0; c < 3; ++c)
            fi[c] += ab * d[c];
        if constexpr (Energy)
            e_i += v.kb[k] * ext * ext;
    }
    for (int c = 0; c < 3; ++c)
        v.f[3 * i + c] = fi[c];
    if constexpr (Energy) {
        energy += 0.25 * e_i * v.vol[i];
        repulsion += 0.25 * e_rep * v.vol[i];
    }
    released += 0.25 * e_rel * v.vol[i];
}

/// Row a's node i and body, false if the PMB kernel has no force to compute there (f_i = 0 for
/// a node that does not move; LPS and RNP rows belong to their kernels).
PD_INLINE bool pmb_owns(const Arrays& v, const State& s, const BodyLaw& law, std::int64_t a,
                        std::int64_t& i, std::size_t& body) {
    i = v.rows[a];
    body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(i)]);
    if (law.lps[body] || law.rnp[body])
        return false;
    if (!s.moving[static_cast<std::size_t>(i)]) {
        v.f[3 * i] = v.f[3 * i + 1] = v.f[3 * i + 2] = 0;
        return false;
    }
    return true;
}

/// One PMB row: the hot loop (`hot`, portable, SSE2 or AVX2) when every bond is intact and none
/// breaks, else the general path. Bond energy density 1/2 c s^2 xi per pair = 1/2 kb ext^2;
/// the full list counts each pair twice. A macro, so that the AVX2 hot loop inlines into the
/// AVX2 row loop (a function compiled without AVX2 cannot take it inline).
#define PD_PMB_ROW(hot)                                                                            \
    [&](std::int64_t a, double& energy, double& released, double& repulsion, std::int64_t& broken) \
        PD_ROW_ATTR {                                                                              \
            std::int64_t i;                                                                        \
            std::size_t body;                                                                      \
            if (!pmb_owns(v, s, law, a, i, body))                                                  \
                return;                                                                            \
            double fi[3], e_i = 0;                                                                 \
            if (!hot(v, i, v.op ? v.op[a] : 1.0 + law.s0[body], Comp ? law.s0_lo[body] : 0.0,      \
                     v.off[a], v.off[a + 1], fi, e_i)) {                                           \
                pmb_general_row<Breakable, Energy, Comp>(v, law, body, a, i, energy, released,     \
                                                         repulsion, broken);                       \
                return;                                                                            \
            }                                                                                      \
            for (int c = 0; c < 3; ++c)                                                            \
                v.f[3 * i + c] = fi[c];                                                            \
            if constexpr (Energy)                                                                  \
                energy += 0.25 * e_i * v.vol[i];                                                   \
        }

/// All PMB rows with the hot loop of portable or SSE2 lanes (V).
#define PD_ROW_ATTR __attribute__((always_inline))
template <bool Breakable, bool Energy, bool Comp, class V>
Sums pmb_rows(const Arrays& v, const State& s, const BodyLaw& law) {
    return over_rows(v.n, PD_PMB_ROW((pmb_hot<Energy, Comp, V>)));
}
#undef PD_ROW_ATTR

#if defined(PD_KERNELS_AVX2)
/// All PMB rows, compiled for AVX2 (the row and its hot loop inlined into the row loop).
#define PD_ROW_ATTR PD_AVX2 __attribute__((always_inline))
template <bool Breakable, bool Energy, bool Comp>
PD_AVX2 Sums pmb_rows_avx2(const Arrays& v, const State& s, const BodyLaw& law) {
    return over_rows_avx2(v.n, PD_PMB_ROW((pmb_hot_avx2<Energy, Comp>)));
}
#undef PD_ROW_ATTR
#endif
#undef PD_PMB_ROW

/// Comp: some body breaks bonds in compression too (an instantiation of its own, so that the
/// default, tension only, pays nothing for it).
template <bool Breakable, bool Energy, bool Comp>
BondResult kernel(State& s, BondData& b, const BodyLaw& law) {
    const Arrays v(s, b);
    Sums r;
    switch (kernels::isa()) {
#if defined(PD_KERNELS_AVX2)
    case Isa::avx2:
        r = pmb_rows_avx2<Breakable, Energy, Comp>(v, s, law);
        break;
#endif
#if defined(__SSE2__)
    case Isa::sse2:
        r = pmb_rows<Breakable, Energy, Comp, __m128d>(v, s, law);
        break;
#endif
    default:
        r = pmb_rows<Breakable, Energy, Comp, kernels::V2>(v, s, law);
    }
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
        // PeriDEM breaks in compression too (|S| > S_c) when the material asks for it.
        const bool comp = law.any_compressive && law.s0_lo[body] != 0;
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
                if (S > rb / std::sqrt(r) || (comp && S < -rb / std::sqrt(r))) {
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

/// Flaws (model/flaws.hpp) of row a: each bond breaks at xi (1 + s0 w), w its Weibull factor;
/// op[a] = 1 + the row's least critical stretch (1 + s0 without flaws).
void flaw_row(const State& s, BondData& b, const BodyLaw& law, std::size_t a, std::size_t body) {
    const double s0 = law.s0[body];
    b.op[a] = 1.0 + s0;
    if (!(law.flaw_m[body] > 0))
        return;
    const std::int64_t i0 = law.first_node[body];
    const std::int64_t i = s.rows[a] - i0;
    const double L = law.flaw_len[body];
    double least = std::numeric_limits<double>::infinity();
    for (auto k = b.offsets[a]; k < b.offsets[a + 1]; ++k) {
        const auto kk = static_cast<std::size_t>(k);
        double sc = 0;
        if (L > 0) { // the patch of the bond's midpoint (the same from both ends)
            std::int64_t c[3];
            const auto p = static_cast<std::size_t>(s.rows[a]);
            const auto q = static_cast<std::size_t>(b.neighbor[kk]);
            for (std::size_t d = 0; d < 3; ++d)
                c[d] = static_cast<std::int64_t>(std::floor(
                    (0.5 * (s.x0[3 * p + d] + s.x0[3 * q + d]) - law.centre[3 * body + d]) / L));
            sc = s0 * model::flaw_cell_factor(law.flaw_m[body], law.flaw_seed[body],
                                              static_cast<std::int64_t>(body), c[0], c[1], c[2]);
        } else
            sc = s0 * model::flaw_factor(law.flaw_m[body], law.flaw_seed[body],
                                         static_cast<std::int64_t>(body), i, b.neighbor[kk] - i0);
        b.lc[kk] = b.xi[kk] * (1.0 + sc);
        least = std::min(least, sc);
    }
    if (b.offsets[a + 1] > b.offsets[a])
        b.op[a] = 1.0 + least;
}

} // namespace

void bond_constants(const State& s, BondData& b, BodyLaw& law, std::vector<double> stiff) {
    const auto nbond = b.xi.size();
    const bool kb = keeps_kb(law), lps = !b.omega.empty() && law.m.size() == s.n;
    if (stiff.empty() && kb) {
        stiff.resize(nbond);
        for (std::size_t a = 0; a + 1 < b.offsets.size(); ++a) {
            const auto body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(s.rows[a])]);
            for (auto k = b.offsets[a]; k < b.offsets[a + 1]; ++k)
                stiff[static_cast<std::size_t>(k)] =
                    bond_beta(b, law, body, static_cast<std::size_t>(k));
        }
    }
    if (!kb) { // freed before the LPS arrays are made: one per-bond array fewer at the peak
        stiff.clear();
        stiff.shrink_to_fit();
    }
    PD_CHECK(stiff.size() == (kb ? nbond : 0), "bond_constants: a stiffness factor per bond");
    b.kb.clear(); // stiff becomes kb in place
    b.kb.shrink_to_fit();
    b.lc.assign(law.any_flaws ? nbond : 0, 0.0);
    b.wv.assign(lps ? nbond : 0, 0.0);
    b.wv.shrink_to_fit();
    b.len.assign(b.wv.size(), 0.0); // the LPS kernel's work arrays (their values are not read)
    b.len.shrink_to_fit();
    b.inv_len.assign(b.wv.size(), 0.0);
    b.inv_len.shrink_to_fit();
    b.op.assign(law.any_flaws ? b.offsets.size() - 1 : 0, 0.0);
    for (std::size_t a = 0; a + 1 < b.offsets.size(); ++a) {
        const auto body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(s.rows[a])]);
        const double s0 = law.s0[body];
        for (auto k = b.offsets[a]; k < b.offsets[a + 1]; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            const double vj = s.vol[static_cast<std::size_t>(b.neighbor[kk])];
            if (kb)
                stiff[kk] = law.c[body] * stiff[kk] * vj / b.xi[kk];
            if (law.any_flaws)
                b.lc[kk] = std::isfinite(s0) ? b.xi[kk] * (1.0 + s0)
                                             : std::numeric_limits<double>::infinity();
            if (lps)
                b.wv[kk] = b.omega[kk] * bond_beta(b, law, body, kk) * vj;
        }
        if (law.any_flaws)
            flaw_row(s, b, law, a, body);
    }
    b.kb = std::move(stiff);
    if (law.m.size() != s.n)
        return; // no LPS body
    law.lps_ap.assign(2 * s.n, 0.0);
    law.lps_k.assign(s.n, 0.0);
    for (std::size_t i = 0; i < s.n; ++i) {
        const auto body = static_cast<std::size_t>(s.body[i]);
        const double mi = law.m[i];
        if (!law.lps[body] || !(mi > 0))
            continue; // (nodes neither owned nor ghosts have m = 0)
        law.lps_ap[2 * i] = law.alpha * law.mu[body] / mi;
        law.lps_k[i] = law.dimension * law.kappa[body] / mi;
    }
}

BondResult rnp_bond_forces(State& s, BondData& b, const BodyLaw& law) {
    ensure_constants(s, b, law);
    return law.any_breakable ? rnp_kernel<true>(s, b, law) : rnp_kernel<false>(s, b, law);
}

BondResult pmb_bond_forces(State& s, BondData& b, const BodyLaw& law) {
    ensure_constants(s, b, law);
    if (law.any_breakable && law.any_compressive)
        return law.energy ? kernel<true, true, true>(s, b, law)
                          : kernel<true, false, true>(s, b, law);
    if (law.energy)
        return law.any_breakable ? kernel<true, true, false>(s, b, law)
                                 : kernel<false, true, false>(s, b, law);
    return law.any_breakable ? kernel<true, false, false>(s, b, law)
                             : kernel<false, false, false>(s, b, law);
}

BondResult pmb_bond_forces_reference(State& s, BondData& b, const BodyLaw& law) {
    return law.any_breakable ? naive_kernel<true>(s, b, law) : naive_kernel<false>(s, b, law);
}

void damage_phi(const State& s, const BondData& b, const BodyLaw& law, std::vector<double>& phi) {
    phi.assign(s.n, 0.0);
    const auto n = static_cast<std::int64_t>(s.rows.size());
    const index_t* rows = s.rows.data();
#pragma omp parallel for schedule(static) if (n > parallel_min)
    for (std::int64_t a = 0; a < n; ++a) {
        const std::int64_t i = rows[a];
        // A row with no broken bond: br = 0 and phi = 0 / all or 0, +0.0 either way (the value
        // assigned above), without its pass over the weights.
        const auto k0 = static_cast<std::size_t>(b.offsets[a]);
        const auto len = static_cast<std::size_t>(b.offsets[a + 1]) - k0;
        if (len == 0 || std::memchr(b.alive.data() + k0, 0, len) == nullptr)
            continue;
        const auto body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(i)]);
        double all = 0, br = 0;
        for (offset_t k = b.offsets[a]; k < b.offsets[a + 1]; ++k) {
            const double w =
                bond_beta(b, law, body, static_cast<std::size_t>(k)) * s.vol[b.neighbor[k]];
            all += w;
            if (!b.alive[k])
                br += w;
        }
        phi[i] = all > 0 ? br / all : 0.0;
    }
}

} // namespace pd::solver
