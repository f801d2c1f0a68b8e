// SPDX-License-Identifier: MIT
// The LPS bond kernel (spec 1.3): the dilatation pass, then the force pass, each in the two
// lanes of bond_kernels.hpp (portable, SSE2, or AVX2 four bonds at a time; same bits).
//
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
#include "solver/bond_forces.hpp"
#include "solver/bond_kernels.hpp"

#include <cmath>
#include <functional>

namespace pd::solver {

using kernels::ensure_constants;

namespace {

using namespace kernels;

/// The per-node arrays of the LPS law and the pass-1 work arrays per bond.
struct Lps {
    explicit Lps(BondData& b, BodyLaw& law)
        : dd(law.dimension)
        , half(law.dimension == 2)
        , theta(law.theta.data())
        , q(law.q.data())
        , mw(law.m.data())
        , bu(b.len.data())
        , bv(b.inv_len.data())
        , ap(law.lps_ap.data())
        , kt(law.lps_k.data()) {}
    double dd;
    bool half; // d = 2: theta / d as theta * 0.5 (exact: the bits of the division, one less)
    double *theta, *q;
    const double* mw;
    double* bu; // omega beta V_j e / l, pass 1 for pass 2
    double* bv; // omega beta V_j xi / l
    double* ap; // A_i, P_i side by side
    const double* kt;
    double A(std::int64_t i) const { return ap[2 * i]; }
    double P(std::int64_t i) const { return ap[2 * i + 1]; }
    /// t / d (2D: t * 0.5, exact, the bits of t / 2).
    double by_d(double t) const { return half ? t * 0.5 : t / dd; }
};

// ---- Pass 1: break bonds (tension, and compression when Comp; symmetric inputs), then
// dilatation, q and P; on observation steps the energy of the rows that stay whole ----

/// Pass 1's lanes: CheckedLanes (S: the dilatation sum) and, with energies, E = sum w e^2 and
/// M = sum w xi^2 (w = omega beta V_j), from which the row's deviatoric sum follows without a
/// second length per bond (pass1_finish).
template <class V>
struct Lanes1 : CheckedLanes<V> {
    Lanes1(const double* x_i, double op_, double ol_)
        : CheckedLanes<V>(x_i, op_, ol_)
        , E(zero<V>())
        , M(zero<V>()) {}
    V E, M;
};

/// Bonds k, k+1 of pass 1: u, v for pass 2 (no sqrt, division nor e there), theta's sum.
template <bool Comp, bool Energy, class V>
PD_INLINE void pass1_pair(Lanes1<V>& L, const Arrays& v, const Lps& w, offset_t k) {
    V d[3];
    gather2(v.x, v.nb[k], v.nb[k + 1], L.X, d);
    const V l = length(d);
    const V inv = div(splat(1.0, V{}), l);
    const V x0 = load2(v.xi + k, V{}), wk = load2(v.wv + k, V{});
    const V wx = mul(wk, x0), e = sub(l, x0), we = mul(wk, e);
    store2(w.bu + k, mul(we, inv));
    store2(w.bv + k, mul(wx, inv));
    L.S = add(L.S, mul(wx, e));
    if constexpr (Energy) {
        L.E = add(L.E, mul(we, e));
        L.M = add(L.M, mul(wx, x0));
    }
    L.B = flag(L.B, l, mul(x0, L.OP));
    if constexpr (Comp)
        L.B = flag(L.B, mul(x0, L.OL), l); // l < xi (1 - s0)
    L.bad |= not_intact<2>(v.alive + k);
}

/// What pass 1 sums over a row: the dilatation th; with energies (rows that stay whole) e2 =
/// sum w e^2 and m2 = sum w xi^2.
struct Row1 {
    double th = 0, e2 = 0, m2 = 0;
};

/// The rest of pass 1 from bond k on (pairs, the odd last bond in lane 0); false when a bond is
/// broken or breaking (the caller takes the general path), else r's sums.
template <bool Comp, bool Energy, class V>
PD_INLINE bool pass1_rest(Lanes1<V>& L, const Arrays& v, const Lps& w, std::int64_t i, offset_t k,
                          offset_t k1, Row1& r) {
    for (; k + 1 < k1; k += 2)
        pass1_pair<Comp, Energy>(L, v, w, k);
    double th0 = lane0(L.S), e0 = lane0(L.E), m0 = lane0(L.M);
    if (k < k1) {
        double d[3];
        const double l = bond_d(v.x, i, v.nb[k], d);
        const double inv = 1.0 / l, wx = v.wv[k] * v.xi[k], e = l - v.xi[k], we = v.wv[k] * e;
        w.bu[k] = we * inv;
        w.bv[k] = wx * inv;
        th0 += wx * e;
        if constexpr (Energy) {
            e0 += we * e;
            m0 += wx * v.xi[k];
        }
        L.bad |= static_cast<int>(l > v.xi[k] * L.op) | static_cast<int>(v.alive[k] != 1);
        if constexpr (Comp)
            L.bad |= static_cast<int>(l < v.xi[k] * L.ol);
    }
    r.th = th0 + lane1(L.S);
    if constexpr (Energy) {
        r.e2 = e0 + lane1(L.E);
        r.m2 = m0 + lane1(L.M);
    }
    return !(L.bad | any(L.B));
}

template <bool Comp, bool Energy, class V>
PD_INLINE bool pass1_hot(const Arrays& v, const Lps& w, std::int64_t i, double op, double ol,
                         offset_t k0, offset_t k1, Row1& r) {
    Lanes1<V> L(v.x + 3 * i, op, ol);
    return pass1_rest<Comp, Energy>(L, v, w, i, k0, k1, r);
}

#if defined(PD_KERNELS_AVX2)
/// pass1_hot with four bonds per step in front (AVX2).
template <bool Comp, bool Energy>
PD_AVX2 PD_INLINE bool pass1_hot_avx2(const Arrays& v, const Lps& w, std::int64_t i, double op,
                                      double ol, offset_t k, offset_t k1, Row1& r) {
    Lanes1<__m128d> L(v.x + 3 * i, op, ol);
    const Wide W(v.x + 3 * i);
    const __m256d OP = _mm256_set1_pd(op), OL = _mm256_set1_pd(ol), ONE = _mm256_set1_pd(1.0);
    __m256d B = _mm256_setzero_pd();
    for (; k + 3 < k1; k += 4) {
        __m256d d[3];
        gather4(v.x, v.nb + k, W.X, d);
        const __m256d l = length4(d);
        const __m256d inv = _mm256_div_pd(ONE, l);
        const __m256d x0 = _mm256_loadu_pd(v.xi + k), wk = _mm256_loadu_pd(v.wv + k);
        const __m256d wx = _mm256_mul_pd(wk, x0), e = _mm256_sub_pd(l, x0);
        const __m256d we = _mm256_mul_pd(wk, e);
        _mm256_storeu_pd(w.bu + k, _mm256_mul_pd(we, inv));
        _mm256_storeu_pd(w.bv + k, _mm256_mul_pd(wx, inv));
        L.S = fold(L.S, _mm256_mul_pd(wx, e));
        if constexpr (Energy) {
            L.E = fold(L.E, _mm256_mul_pd(we, e));
            L.M = fold(L.M, _mm256_mul_pd(wx, x0));
        }
        B = _mm256_or_pd(B, _mm256_cmp_pd(l, _mm256_mul_pd(x0, OP), _CMP_GT_OQ));
        if constexpr (Comp)
            B = _mm256_or_pd(B, _mm256_cmp_pd(l, _mm256_mul_pd(x0, OL), _CMP_LT_OQ));
        L.bad |= not_intact<4>(v.alive + k);
    }
    L.bad |= _mm256_movemask_pd(B);
    return pass1_rest<Comp, Energy>(L, v, w, i, k, k1, r);
}
#endif

/// Pass 1 of a row with broken or breaking bonds: breaks them (alive = 2: broken in this call),
/// r's sums and mi = the weighted volume of the intact bonds. hi = 1 + s0 of the row's body
/// (break_length); lo = 1 - s0 when Comp (bonds shorter than xi lo break too).
template <bool Breakable, bool Comp, bool Energy>
[[gnu::noinline]] void pass1_general(const Arrays& v, std::int64_t a, std::int64_t i, double lo,
                                     double hi, Row1& r, double& mi, bool& damaged,
                                     std::int64_t& broken) {
    r = Row1{};
    for (offset_t k = v.off[a]; k < v.off[a + 1]; ++k) {
        if (!v.alive[k]) {
            damaged = true;
            continue;
        }
        const index_t j = v.nb[k];
        double d[3];
        const double l = bond_d(v.x, i, j, d);
        if (Breakable && (l > break_length(v, k, hi) || (Comp && l < v.xi[k] * lo))) {
            v.alive[k] = 2;
            damaged = true;
            ++broken;
            continue;
        }
        mi += v.om[k] * v.xi[k] * v.xi[k] * beta_of(v, k, i) * v.vol[j];
        const double e = l - v.xi[k], wx = v.wv[k] * v.xi[k];
        r.th += wx * e;
        if constexpr (Energy) {
            r.e2 += v.wv[k] * e * e;
            r.m2 += wx * v.xi[k];
        }
    }
}

/// Row a of pass 1 is an LPS row of a moving node (else its theta, q, P are 0).
PD_INLINE bool pass1_owns(const Arrays& v, const Lps& w, const State& s, const BodyLaw& law,
                          std::int64_t a, std::int64_t& i, std::size_t& body) {
    i = v.rows[a];
    body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(i)]);
    if (law.lps[body] && s.moving[static_cast<std::size_t>(i)])
        return true;
    w.theta[i] = w.q[i] = w.ap[2 * i + 1] = 0;
    return false;
}

/// theta_i, q_i and P_i from the row's sums (in registers, stored once). With energies, a row
/// that stays whole adds its W_i V_i here (pass 2 then takes the hot path for it and skips the
/// energy: a whole row is exactly a row pass 2's hot loop accepts, every bond alive == 1).
/// Its deviatoric sum sum w (e - theta xi / d)^2 expanded: e2 - theta/d (2 th - theta/d m2).
/// The expansion rounds relative to e2, the scale of the dilatation energy k/2 theta^2 next to
/// it (about 1e-16 of W_i), not to the deviatoric sum itself.
template <bool Energy>
PD_INLINE void pass1_finish(const Lps& w, const BodyLaw& law, std::size_t body, std::int64_t i,
                            const Row1& r, double mi, bool damaged, const double* vol,
                            double& energy) {
    const double theta = w.dd * r.th / w.mw[i];
    const double td = w.by_d(theta);
    const double q = damaged ? td * (1.0 - mi / w.mw[i]) : 0.0;
    w.theta[i] = theta;
    w.q[i] = q;
    w.ap[2 * i + 1] = w.kt[i] * theta - w.A(i) * (td + q);
    if (Energy && !damaged) {
        const double wdev = r.e2 - td * (2.0 * r.th - td * r.m2);
        energy += (0.5 * law.kappa[body] * theta * theta + 0.5 * w.A(i) * wdev) * vol[i];
    }
}

/// Pass 1 of row a with the hot loop `hot` (a macro: see PD_PMB_ROW in bond_forces.cpp).
#define PD_PASS1_ROW(hot)                                                                          \
    [&](std::int64_t a, double& energy, double&, double&, std::int64_t& broken) PD_ROW_ATTR {      \
        std::int64_t i;                                                                            \
        std::size_t body;                                                                          \
        if (!pass1_owns(v, w, s, law, a, i, body))                                                 \
            return;                                                                                \
        Row1 r;                                                                                    \
        double mi = 0;                                                                             \
        bool damaged = false;                           /* breaks beyond xi (1 + s0), as b.lc */   \
        const double lo = Comp ? law.s0_lo[body] : 0.0; /* Comp: below xi (1 - s0) */              \
        if (!hot(v, w, i, v.op ? v.op[a] : 1.0 + law.s0[body], lo, v.off[a], v.off[a + 1], r))     \
            pass1_general<Breakable, Comp, Energy>(v, a, i, lo, 1.0 + law.s0[body], r, mi,         \
                                                   damaged, broken);                               \
        pass1_finish<Energy>(w, law, body, i, r, mi, damaged, v.vol, energy);                      \
    }

// ---- Pass 2: forces from both ends of every intact bond; the energy bonds broken in pass 1 held

/// A_j, P_j of the bonds to ja (lane 0) and jb (lane 1).
PD_INLINE void gather_ap(const double* ap, index_t ja, index_t jb, V2& a, V2& p) {
    a = {ap[2 * ja], ap[2 * jb]};
    p = {ap[2 * ja + 1], ap[2 * jb + 1]};
}
#if defined(__SSE2__)
PD_INLINE void gather_ap(const double* ap, index_t ja, index_t jb, __m128d& a, __m128d& p) {
    const __m128d x = _mm_loadu_pd(ap + 2 * static_cast<std::int64_t>(ja));
    const __m128d y = _mm_loadu_pd(ap + 2 * static_cast<std::int64_t>(jb));
    a = _mm_unpacklo_pd(x, y);
    p = _mm_unpackhi_pd(x, y);
}
#endif
#if defined(PD_KERNELS_AVX2)
/// A_j, P_j of the four bonds from nb[k] on (lane m = bond k + m): four 16-byte loads.
PD_AVX2 PD_INLINE void gather4_ap(const double* ap, const index_t* nb, __m256d& a, __m256d& p) {
    const auto at = [&](int m) { return _mm_loadu_pd(ap + 2 * static_cast<std::int64_t>(nb[m])); };
    const __m256d x = _mm256_insertf128_pd(_mm256_castpd128_pd256(at(0)), at(2), 1); // A0 P0 A2 P2
    const __m256d y = _mm256_insertf128_pd(_mm256_castpd128_pd256(at(1)), at(3), 1); // A1 P1 A3 P3
    a = _mm256_unpacklo_pd(x, y);
    p = _mm256_unpackhi_pd(x, y);
}
#endif

/// Pass 2's lanes of a row: the force, A_i, P_i.
template <class V>
struct Lanes2 : Lanes<V> {
    Lanes2(const double* x_i, double a_i, double p_i)
        : Lanes<V>(x_i)
        , AI(splat(a_i, V{}))
        , PI(splat(p_i, V{})) {}
    V AI, PI;
    int bad = 0;
};

/// Bonds k, k+1 of pass 2: omega t / l = (A_i + A_j) u + (P_i + P_j) v (no length: the
/// energies of whole rows come from pass 1).
template <class V>
PD_INLINE void pass2_pair(Lanes2<V>& L, const Arrays& v, const Lps& w, offset_t k) {
    const index_t ja = v.nb[k], jb = v.nb[k + 1];
    V d[3];
    gather2(v.x, ja, jb, L.X, d);
    V aj, pj;
    gather_ap(w.ap, ja, jb, aj, pj);
    const V ab =
        add(mul(add(L.AI, aj), load2(w.bu + k, V{})), mul(add(L.PI, pj), load2(w.bv + k, V{})));
    L.add_force(ab, d);
    L.bad |= not_intact<2>(v.alive + k);
}

/// The rest of pass 2 from bond k on; false when a bond is not intact (general path), else f_i
/// from the lanes.
template <class V>
PD_INLINE bool pass2_rest(Lanes2<V>& L, const Arrays& v, const Lps& w, std::int64_t i, offset_t k,
                          offset_t k1, double* fi) {
    for (; k + 1 < k1; k += 2)
        pass2_pair(L, v, w, k);
    if (k < k1) {
        const index_t j = v.nb[k];
        double d[3];
        bond_d(v.x, i, j, d);
        L.add_force0((lane0(L.AI) + w.A(j)) * w.bu[k] + (lane0(L.PI) + w.P(j)) * w.bv[k], d);
        L.bad |= static_cast<int>(v.alive[k] != 1);
    }
    L.sum(fi);
    return !L.bad;
}

template <class V>
PD_INLINE bool pass2_hot(const Arrays& v, const Lps& w, std::int64_t i, offset_t k0, offset_t k1,
                         double* fi) {
    Lanes2<V> L(v.x + 3 * i, w.A(i), w.P(i));
    return pass2_rest(L, v, w, i, k0, k1, fi);
}

#if defined(PD_KERNELS_AVX2)
/// pass2_hot with four bonds per step in front (AVX2).
PD_AVX2 PD_INLINE bool pass2_hot_avx2(const Arrays& v, const Lps& w, std::int64_t i, offset_t k,
                                      offset_t k1, double* fi) {
    const double a_i = w.A(i), p_i = w.P(i);
    Lanes2<__m128d> L(v.x + 3 * i, a_i, p_i);
    const Wide W(v.x + 3 * i);
    const __m256d AI = _mm256_set1_pd(a_i), PI = _mm256_set1_pd(p_i);
    for (; k + 3 < k1; k += 4) {
        __m256d d[3];
        gather4(v.x, v.nb + k, W.X, d);
        __m256d aj, pj;
        gather4_ap(w.ap, v.nb + k, aj, pj);
        const __m256d ab =
            _mm256_add_pd(_mm256_mul_pd(_mm256_add_pd(AI, aj), _mm256_loadu_pd(w.bu + k)),
                          _mm256_mul_pd(_mm256_add_pd(PI, pj), _mm256_loadu_pd(w.bv + k)));
        W.add_force(L, ab, d);
        L.bad |= not_intact<4>(v.alive + k);
    }
    return pass2_rest(L, v, w, i, k, k1, fi);
}
#endif

/// What pass 2's general path adds up for the energies of a row.
struct Row2 {
    double wdev = 0, e_rep = 0, th_new = 0;
    bool fresh = false;
};

/// Pass 2 of a row with bonds that are not intact: broken bonds (repulsion), bonds broken in
/// pass 1 (their share of the dilatation before, in th_new).
[[gnu::noinline]] inline void pass2_general(const Arrays& v, const Lps& w, const BodyLaw& law,
                                            std::size_t body, std::int64_t a, std::int64_t i,
                                            double* fi, Row2& r) {
    fi[0] = fi[1] = fi[2] = 0;
    r.wdev = 0;
    const double kr = law.krep[body], rr = law.rrep[body];
    for (offset_t k = v.off[a]; k < v.off[a + 1]; ++k) {
        const index_t j = v.nb[k];
        double d[3];
        const double l = bond_d(v.x, i, j, d);
        if (v.alive[k] != 1) {
            if (v.alive[k] == 2) { // broken in pass 1: its share of the dilatation before
                r.fresh = true;
                r.th_new += v.om[k] * v.xi[k] * (l - v.xi[k]) * beta_of(v, k, i) * v.vol[j];
            }
            if (l < rr) { // fragments repel across broken bonds (spec 4.7)
                const double ar = kr * (l - rr) * v.vol[j] / l;
                for (int c = 0; c < 3; ++c)
                    fi[c] += ar * d[c];
                r.e_rep += kr * (rr - l) * (rr - l) * v.vol[j];
            }
            continue;
        }
        const double e = l - v.xi[k];
        const double t = (w.A(i) + w.A(j)) * e + v.xi[k] * (w.P(i) + w.P(j));
        const double ab = v.wv[k] * t / l;
        for (int c = 0; c < 3; ++c)
            fi[c] += ab * d[c];
        const double ed_i = e - w.theta[i] * v.xi[k] / w.dd;
        r.wdev += v.wv[k] * ed_i * ed_i;
    }
}

/// The energy the bonds broken in pass 1 released at node i: W_i with them still intact, at
/// these positions, less half the work the change of node i's force state would have done over
/// this step (see the PMB kernel): released = W_before - W_after - dt/2 sum_k (t_before -
/// t_after) beta V_j de_k/dt, de_k/dt the extension rate of bond k. Marks them broken (0).
[[gnu::noinline]] inline double lps_released(const Arrays& v, const Lps& w, const BodyLaw& law,
                                             std::size_t body, std::int64_t a, std::int64_t i,
                                             double th_new, double w_after) {
    const double kap = law.kappa[body], a_i = w.A(i), dd = w.dd, mw = w.mw[i];
    const double th_b = w.theta[i] + dd * th_new / mw;
    double wdev_b = 0, mi_b = 0;
    for (offset_t k = v.off[a]; k < v.off[a + 1]; ++k) {
        if (!v.alive[k])
            continue;
        const index_t j = v.nb[k];
        double d[3];
        const double ed = bond_d(v.x, i, j, d) - v.xi[k] - th_b * v.xi[k] / dd;
        const double bk = beta_of(v, k, i);
        wdev_b += v.om[k] * ed * ed * bk * v.vol[j];
        mi_b += v.om[k] * v.xi[k] * v.xi[k] * bk * v.vol[j];
    }
    const double q_b = th_b / dd * (1.0 - mi_b / mw);
    const double p_i = w.kt[i] * w.theta[i];
    double pw = 0;
    for (offset_t k = v.off[a]; k < v.off[a + 1]; ++k) {
        if (!v.alive[k])
            continue;
        const index_t j = v.nb[k];
        double d[3];
        const double l = bond_d(v.x, i, j, d);
        const double e = l - v.xi[k];
        const double rate =
            (d[0] * (v.v[3 * j] - v.v[3 * i]) + d[1] * (v.v[3 * j + 1] - v.v[3 * i + 1]) +
             d[2] * (v.v[3 * j + 2] - v.v[3 * i + 2])) /
            l;
        const double t_b = v.om[k] * (dd * kap * th_b / mw * v.xi[k] +
                                      a_i * (e - th_b * v.xi[k] / dd - q_b * v.xi[k]));
        const double t_a =
            v.alive[k] == 1 ? v.om[k] * (p_i * v.xi[k] +
                                         a_i * (e - w.theta[i] * v.xi[k] / dd - w.q[i] * v.xi[k]))
                            : 0.0;
        pw += (t_b - t_a) * beta_of(v, k, i) * v.vol[j] * rate;
        if (v.alive[k] == 2)
            v.alive[k] = 0;
    }
    return (0.5 * kap * th_b * th_b + 0.5 * a_i * wdev_b - w_after - 0.5 * law.dt * pw) * v.vol[i];
}

/// Row a of pass 2 is an LPS row (f_i = 0 if its node does not move).
PD_INLINE bool pass2_owns(const Arrays& v, const State& s, const BodyLaw& law, std::int64_t a,
                          std::int64_t& i, std::size_t& body) {
    i = v.rows[a];
    body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(i)]);
    if (!law.lps[body])
        return false;
    if (!s.moving[static_cast<std::size_t>(i)]) {
        v.f[3 * i] = v.f[3 * i + 1] = v.f[3 * i + 2] = 0;
        return false;
    }
    return true;
}

/// Stores f_i; the energies of a row of the general path on observation steps or when bonds
/// broke (a row of the hot path is whole: pass 1 added its energy).
template <bool Breakable, bool Energy>
PD_INLINE void pass2_finish(const Arrays& v, const Lps& w, const BodyLaw& law, std::size_t body,
                            std::int64_t a, std::int64_t i, const double* fi, const Row2* r,
                            double& energy, double& released, double& repulsion) {
    v.f[3 * i] = fi[0];
    v.f[3 * i + 1] = fi[1];
    v.f[3 * i + 2] = fi[2];
    if (!r || (!Energy && !r->fresh))
        return;
    const double w_after = 0.5 * law.kappa[body] * w.theta[i] * w.theta[i] + 0.5 * w.A(i) * r->wdev;
    energy += w_after * v.vol[i];
    repulsion += 0.25 * r->e_rep * v.vol[i]; // each pair from both ends
    if (Breakable && r->fresh)
        released += lps_released(v, w, law, body, a, i, r->th_new, w_after);
}

/// Pass 2 of row a with the hot loop `hot`.
#define PD_PASS2_ROW(hot)                                                                          \
    [&](std::int64_t a, double& energy, double& released, double& repulsion, std::int64_t&)        \
        PD_ROW_ATTR {                                                                              \
            std::int64_t i;                                                                        \
            std::size_t body;                                                                      \
            if (!pass2_owns(v, s, law, a, i, body))                                                \
                return;                                                                            \
            double fi[3];                                                                          \
            Row2 r;                                                                                \
            const bool whole = hot(v, w, i, v.off[a], v.off[a + 1], fi);                           \
            if (!whole)                                                                            \
                pass2_general(v, w, law, body, a, i, fi, r);                                       \
            pass2_finish<Breakable, Energy>(v, w, law, body, a, i, fi, whole ? nullptr : &r,       \
                                            energy, released, repulsion);                          \
        }

/// Both passes over all rows with two lanes V (portable or SSE2); `between` in between.
#define PD_ROW_ATTR __attribute__((always_inline))
template <bool Breakable, bool Energy, bool Comp, class V>
Sums lps_rows(const Arrays& v, const Lps& w, const State& s, const BodyLaw& law,
              const std::function<void()>& between) {
    const Sums r1 = over_rows(v.n, PD_PASS1_ROW((pass1_hot<Comp, Energy, V>)));
    if (between)
        between(); // ghosts' dilatation and q
    Sums r = over_rows(v.n, PD_PASS2_ROW((pass2_hot<V>)));
    r.broken = r1.broken;
    r.energy += r1.energy;
    return r;
}
#undef PD_ROW_ATTR

#if defined(PD_KERNELS_AVX2)
#define PD_ROW_ATTR PD_AVX2 __attribute__((always_inline))
template <bool Breakable, bool Energy, bool Comp>
PD_AVX2 Sums lps_rows_avx2(const Arrays& v, const Lps& w, const State& s, const BodyLaw& law,
                           const std::function<void()>& between) {
    const Sums r1 = over_rows_avx2(v.n, PD_PASS1_ROW((pass1_hot_avx2<Comp, Energy>)));
    if (between)
        between();
    Sums r = over_rows_avx2(v.n, PD_PASS2_ROW(pass2_hot_avx2));
    r.broken = r1.broken;
    r.energy += r1.energy;
    return r;
}
#undef PD_ROW_ATTR
#endif

/// Comp: some body breaks bonds in compression too (its own instantiation: the default pays
/// nothing).
template <bool Breakable, bool Energy, bool Comp>
BondResult lps_kernel(State& s, BondData& b, BodyLaw& law, const std::function<void()>& between) {
    const Arrays v(s, b, &law);
    const Lps w(b, law);
    Sums r;
    switch (kernels::isa()) {
#if defined(PD_KERNELS_AVX2)
    case Isa::avx2:
        r = lps_rows_avx2<Breakable, Energy, Comp>(v, w, s, law, between);
        break;
#endif
#if defined(__SSE2__)
    case Isa::sse2:
        r = lps_rows<Breakable, Energy, Comp, __m128d>(v, w, s, law, between);
        break;
#endif
    default:
        r = lps_rows<Breakable, Energy, Comp, V2>(v, w, s, law, between);
    }
    return {Energy ? r.energy : 0.0, r.broken, r.released, Energy ? r.repulsion : 0.0};
}

} // namespace

BondResult lps_bond_forces(State& s, BondData& b, BodyLaw& law,
                           const std::function<void()>& between) {
    ensure_constants(s, b, law);
    if (law.any_breakable && law.any_compressive)
        return law.energy ? lps_kernel<true, true, true>(s, b, law, between)
                          : lps_kernel<true, false, true>(s, b, law, between);
    if (law.energy)
        return law.any_breakable ? lps_kernel<true, true, false>(s, b, law, between)
                                 : lps_kernel<false, true, false>(s, b, law, between);
    return law.any_breakable ? lps_kernel<true, false, false>(s, b, law, between)
                             : lps_kernel<false, false, false>(s, b, law, between);
}

} // namespace pd::solver
