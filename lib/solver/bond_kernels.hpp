// SPDX-License-Identifier: MIT
// What the bond kernels of bond_forces.cpp (PMB, RNP) and lps_kernel.cpp (LPS) share: the
// pointers of the arrays, the row loop with its reductions, the two-lane arithmetic (SSE2 or
// portable, chosen at run time, with a four-bond AVX2 step in front), the lazy constants.
// Private to lib/solver.
//
// Bitwise contract: bond k0 + 2m + L of a row is summed in lane L, the odd last bond in lane 0,
// the row's sum is lane 0 + lane 1. The per-bond operations (IEEE +, -, *, /, sqrt, no FMA) are
// the same on every path, so the portable, SSE2 and AVX2 paths give the same bits; the AVX2 step
// computes four bonds at once and adds bonds k, k+1 to the lanes before k+2, k+3.
#pragma once

#include "solver/bond_forces.hpp"

#include <cstdint>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__SSE2__) && defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) &&       \
    !defined(PD_NO_AVX2)
#include <immintrin.h>
#define PD_KERNELS_AVX2 1
/// Code generated for AVX2 (no FMA: the products and sums round as on the other paths).
#define PD_AVX2 __attribute__((target("avx2")))
#else
#define PD_AVX2
#endif
#define PD_INLINE inline __attribute__((always_inline))
// __m128d as a template argument (Lanes<__m128d>): GCC notes that its alignment attribute is not
// part of the type's identity, which does not matter here.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wignored-attributes"
#endif

namespace pd::solver::kernels {

/// The arithmetic the bond kernels run on: chosen once from the CPU, settable for tests.
enum class Isa : int { portable, sse2, avx2 };

inline Isa best_isa() {
#if defined(PD_KERNELS_AVX2)
    if (__builtin_cpu_supports("avx2"))
        return Isa::avx2;
#endif
#if defined(__SSE2__)
    return Isa::sse2;
#else
    return Isa::portable;
#endif
}
/// The path the kernels take (best_isa() unless a test set another one that the CPU has).
inline Isa& isa() {
    static Isa v = best_isa();
    return v;
}

/// The arrays of a kernel, set up once per call; `law` for beta_of (the LPS kernel).
struct Arrays {
    explicit Arrays(State& s, BondData& b, const BodyLaw* law = nullptr)
        : n(static_cast<std::int64_t>(s.rows.size()))
        , rows(s.rows.data())
        , x(s.x.data())
        , v(s.v.data())
        , vol(s.vol.data())
        , f(s.f.data())
        , off(b.offsets.data())
        , nb(b.neighbor.data())
        , xi(b.xi.data())
        , beta(b.beta.empty() ? nullptr : b.beta.data())
        , om(b.omega.data())
        , kb(b.kb.data())
        , wv(b.wv.data())
        , lc(b.lc.empty() ? nullptr : b.lc.data())
        , op(b.op.empty() ? nullptr : b.op.data())
        , alive(b.alive.data())
        , body(s.body.data())
        , delta(law ? law->delta.data() : nullptr)
        , h(law ? law->h.data() : nullptr) {}
    std::int64_t n;
    const index_t* rows;
    const double *x, *v, *vol;
    double* f;
    const offset_t* off;
    const index_t* nb;
    /// beta: BondData::beta, nullptr when not kept (bond_beta recomputes it); kb, wv: empty
    /// when not kept (keeps_kb, an LPS body).
    const double *xi, *beta, *om, *kb, *wv;
    const double* lc; ///< BondData::lc (nullptr: no flaws, xi (1 + s0) of the body)
    const double* op; ///< BondData::op (nullptr: no flaws, 1 + s0 of the body)
    std::uint8_t* alive;
    const std::int32_t* body; ///< State::body
    const double *delta, *h;  ///< BodyLaw::delta, h (bond_beta's), when given
};

/// Bond k's partial volume, k a bond of node i's row, as bond_beta: the stored factor, or
/// model::partial_volume of its xi in i's body (the bits build_bonds computed).
PD_INLINE double beta_of(const Arrays& v, offset_t k, std::int64_t i) {
    if (v.beta)
        return v.beta[k];
    const auto b = static_cast<std::size_t>(v.body[i]);
    return model::partial_volume(v.xi[k], v.delta[b], v.h[b]);
}

/// The length at which bond k breaks: its own with flaws, else xi hi (hi = 1 + s0 of the row's
/// body; inf when unbreakable), the product bond_constants once stored.
PD_INLINE double break_length(const Arrays& v, offset_t k, double hi) {
    return v.lc ? v.lc[k] : v.xi[k] * hi;
}

/// The sums of a kernel over its rows.
struct Sums {
    double energy = 0, released = 0, repulsion = 0;
    std::int64_t broken = 0;
};

/// Runs row(a, acc...) for every row a in [0, n), on the OpenMP team when the loop is long
/// enough (threaded()), else serially without entering a parallel region. over_rows_avx2 is
/// the same loop compiled for AVX2, so that an AVX2 row inlines into it (and into its OpenMP
/// region).
// clang-format off
#if defined(_OPENMP)
#define PD_OMP_ROWS \
    _Pragma("omp parallel for schedule(static) reduction(+ : energy, broken, released, repulsion)")
#else
#define PD_OMP_ROWS
#endif
// clang-format on
#define PD_OVER_ROWS(NAME, ATTR)                                                                   \
    template <class Row>                                                                           \
    ATTR Sums NAME(std::int64_t n, Row&& row) {                                                    \
        double energy = 0, released = 0, repulsion = 0;                                            \
        std::int64_t broken = 0;                                                                   \
        if (threaded(n, parallel_min_bonds)) {                                                     \
            PD_OMP_ROWS                                                                            \
            for (std::int64_t a = 0; a < n; ++a)                                                   \
                row(a, energy, released, repulsion, broken);                                       \
        } else {                                                                                   \
            for (std::int64_t a = 0; a < n; ++a)                                                   \
                row(a, energy, released, repulsion, broken);                                       \
        }                                                                                          \
        return {energy, released, repulsion, broken};                                              \
    }
PD_OVER_ROWS(over_rows, )
#if defined(PD_KERNELS_AVX2)
PD_OVER_ROWS(over_rows_avx2, PD_AVX2)
#endif
#undef PD_OVER_ROWS
#undef PD_OMP_ROWS

// ---- Two lanes: V2 (portable) and __m128d (SSE2) with the same operations ----

struct V2 {
    double a, b;
};
PD_INLINE V2 add(V2 x, V2 y) {
    return {x.a + y.a, x.b + y.b};
}
PD_INLINE V2 sub(V2 x, V2 y) {
    return {x.a - y.a, x.b - y.b};
}
PD_INLINE V2 mul(V2 x, V2 y) {
    return {x.a * y.a, x.b * y.b};
}
PD_INLINE V2 div(V2 x, V2 y) {
    return {x.a / y.a, x.b / y.b};
}
PD_INLINE V2 root(V2 x) {
    return {__builtin_sqrt(x.a), __builtin_sqrt(x.b)};
}
PD_INLINE V2 load2(const double* p, V2) {
    return {p[0], p[1]};
}
PD_INLINE void store2(double* p, V2 x) {
    p[0] = x.a;
    p[1] = x.b;
}
PD_INLINE V2 pair(double lane0, double lane1, V2) {
    return {lane0, lane1};
}
PD_INLINE V2 splat(double x, V2) {
    return {x, x};
}
/// The bond-breaking flags of V2 lanes: an int.
PD_INLINE int flag(int acc, V2 l, V2 lim) {
    return acc | static_cast<int>(l.a > lim.a) | static_cast<int>(l.b > lim.b);
}
PD_INLINE double lane0(V2 x) {
    return x.a;
}
PD_INLINE double lane1(V2 x) {
    return x.b;
}
PD_INLINE V2 add0(V2 x, double y) {
    return {x.a + y, x.b};
}
template <class V>
struct Mask {
    using type = int;
};

#if defined(__SSE2__)
PD_INLINE __m128d add(__m128d x, __m128d y) {
    return _mm_add_pd(x, y);
}
PD_INLINE __m128d sub(__m128d x, __m128d y) {
    return _mm_sub_pd(x, y);
}
PD_INLINE __m128d mul(__m128d x, __m128d y) {
    return _mm_mul_pd(x, y);
}
PD_INLINE __m128d div(__m128d x, __m128d y) {
    return _mm_div_pd(x, y);
}
PD_INLINE __m128d root(__m128d x) {
    return _mm_sqrt_pd(x);
}
PD_INLINE __m128d load2(const double* p, __m128d) {
    return _mm_loadu_pd(p);
}
PD_INLINE void store2(double* p, __m128d x) {
    _mm_storeu_pd(p, x);
}
PD_INLINE __m128d pair(double lane0, double lane1, __m128d) {
    return _mm_set_pd(lane1, lane0);
}
PD_INLINE __m128d splat(double x, __m128d) {
    return _mm_set1_pd(x);
}
/// The bond-breaking flags of SSE2 lanes: a mask register, read once per row.
PD_INLINE __m128d flag(__m128d acc, __m128d l, __m128d lim) {
    return _mm_or_pd(acc, _mm_cmpgt_pd(l, lim));
}
PD_INLINE int any(__m128d m) {
    return _mm_movemask_pd(m);
}
PD_INLINE double lane0(__m128d x) {
    return _mm_cvtsd_f64(x);
}
PD_INLINE double lane1(__m128d x) {
    return _mm_cvtsd_f64(_mm_unpackhi_pd(x, x));
}
PD_INLINE __m128d add0(__m128d x, double y) {
    return _mm_add_sd(x, _mm_set_sd(y));
}
template <>
struct Mask<__m128d> {
    using type = __m128d;
};
#endif
PD_INLINE int any(int m) {
    return m;
}
template <class V>
PD_INLINE V zero() {
    return splat(0.0, V{});
}
template <>
PD_INLINE int zero<int>() {
    return 0;
}

/// d = x_j - x_i of the bonds to ja (lane 0) and jb (lane 1), component by component.
PD_INLINE void gather2(const double* x, index_t ja, index_t jb, const V2* X, V2* d) {
    const double* pa = x + 3 * static_cast<std::int64_t>(ja);
    const double* pb = x + 3 * static_cast<std::int64_t>(jb);
    for (int c = 0; c < 3; ++c)
        d[c] = {pa[c] - X[c].a, pb[c] - X[c].b};
}
#if defined(__SSE2__)
PD_INLINE void gather2(const double* x, index_t ja, index_t jb, const __m128d* X, __m128d* d) {
    const double* pa = x + 3 * static_cast<std::int64_t>(ja);
    const double* pb = x + 3 * static_cast<std::int64_t>(jb);
    const __m128d xa = _mm_loadu_pd(pa), xb = _mm_loadu_pd(pb);
    d[0] = _mm_sub_pd(_mm_unpacklo_pd(xa, xb), X[0]);
    d[1] = _mm_sub_pd(_mm_unpackhi_pd(xa, xb), X[1]);
    d[2] = _mm_sub_pd(_mm_loadh_pd(_mm_load_sd(pa + 2), pb + 2), X[2]);
}
#endif

/// |d| of two lanes: sqrt((d0 d0 + d1 d1) + d2 d2).
template <class V>
PD_INLINE V length(const V* d) {
    return root(add(add(mul(d[0], d[0]), mul(d[1], d[1])), mul(d[2], d[2])));
}

/// 1 unless the `count` alive flags from p on are all 1 (intact).
template <int count>
PD_INLINE int not_intact(const std::uint8_t* p) {
    if constexpr (count == 2) {
        std::uint16_t a;
        std::memcpy(&a, p, 2);
        return static_cast<int>(a != 0x0101);
    } else {
        std::uint32_t a;
        std::memcpy(&a, p, 4);
        return static_cast<int>(a != 0x01010101u);
    }
}

/// x_i of a row in both lanes, and the three sums of a force in lanes.
template <class V>
struct Lanes {
    explicit Lanes(const double* xi_) {
        for (int c = 0; c < 3; ++c) {
            X[c] = splat(xi_[c], V{});
            F[c] = zero<V>();
        }
    }
    V X[3], F[3];
    /// F += a d, lane by lane.
    PD_INLINE void add_force(V a, const V* d) {
        for (int c = 0; c < 3; ++c)
            F[c] = add(F[c], mul(a, d[c]));
    }
    /// The odd last bond into lane 0.
    PD_INLINE void add_force0(double a, const double* d) {
        for (int c = 0; c < 3; ++c)
            F[c] = add0(F[c], a * d[c]);
    }
    /// f_i = lane 0 + lane 1.
    PD_INLINE void sum(double* fi) const {
        for (int c = 0; c < 3; ++c)
            fi[c] = lane0(F[c]) + lane1(F[c]);
    }
};

/// The lanes of a hot loop that also tests its bonds: the force (Lanes), one more sum S (PMB:
/// the energy; LPS pass 1: the dilatation), the flags of bonds reaching xi (1 + s0) (`op` =
/// 1 + s0 of the row's body) and of bonds not intact; `ol` = 1 - s0 for the kernels that also
/// break bonds compressed below xi (1 - s0) (the `Comp` instantiations; unused otherwise).
template <class V>
struct CheckedLanes : Lanes<V> {
    CheckedLanes(const double* x_i, double op_, double ol_)
        : Lanes<V>(x_i)
        , op(op_)
        , ol(ol_)
        , OP(splat(op_, V{}))
        , OL(splat(ol_, V{}))
        , S(zero<V>())
        , B(zero<typename Mask<V>::type>()) {}
    double op, ol;
    V OP, OL, S;
    typename Mask<V>::type B;
    int bad = 0;
};

/// d = x_j - x_i and |d| of one bond (the odd last one of a row, the general paths).
PD_INLINE double bond_d(const double* x, std::int64_t i, std::int64_t j, double* d) {
    d[0] = x[3 * j] - x[3 * i];
    d[1] = x[3 * j + 1] - x[3 * i + 1];
    d[2] = x[3 * j + 2] - x[3 * i + 2];
    return __builtin_sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

#if defined(PD_KERNELS_AVX2)
/// d = x_j - x_i of the four bonds from nb[k] on (lane m = bond k + m).
PD_AVX2 PD_INLINE void gather4(const double* x, const index_t* nb, const __m256d* X, __m256d* d) {
    const double* p0 = x + 3 * static_cast<std::int64_t>(nb[0]);
    const double* p1 = x + 3 * static_cast<std::int64_t>(nb[1]);
    const double* p2 = x + 3 * static_cast<std::int64_t>(nb[2]);
    const double* p3 = x + 3 * static_cast<std::int64_t>(nb[3]);
    const __m256d a = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p0)),
                                           _mm_loadu_pd(p2), 1); // x0 y0 x2 y2
    const __m256d b = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p1)),
                                           _mm_loadu_pd(p3), 1); // x1 y1 x3 y3
    const __m128d z01 = _mm_loadh_pd(_mm_load_sd(p0 + 2), p1 + 2);
    const __m128d z23 = _mm_loadh_pd(_mm_load_sd(p2 + 2), p3 + 2);
    d[0] = _mm256_sub_pd(_mm256_unpacklo_pd(a, b), X[0]);
    d[1] = _mm256_sub_pd(_mm256_unpackhi_pd(a, b), X[1]);
    d[2] = _mm256_sub_pd(_mm256_insertf128_pd(_mm256_castpd128_pd256(z01), z23, 1), X[2]);
}
/// v[nb[k + m]] in lane m.
PD_AVX2 PD_INLINE __m256d gather4(const double* v, const index_t* nb) {
    const __m128i j = _mm_loadu_si128(reinterpret_cast<const __m128i*>(nb));
    const __m256d all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    return _mm256_mask_i32gather_pd(_mm256_setzero_pd(), v, j, all, 8);
}
PD_AVX2 PD_INLINE __m256d length4(const __m256d* d) {
    return _mm256_sqrt_pd(
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(d[0], d[0]), _mm256_mul_pd(d[1], d[1])),
                      _mm256_mul_pd(d[2], d[2])));
}
/// acc += bonds k, k+1 (low half), then += bonds k+2, k+3: the order of two SSE2 steps.
PD_AVX2 PD_INLINE __m128d fold(__m128d acc, __m256d v) {
    return _mm_add_pd(_mm_add_pd(acc, _mm256_castpd256_pd128(v)), _mm256_extractf128_pd(v, 1));
}
/// The lanes' x_i and force of a row, four wide for the AVX2 step.
struct Wide {
    explicit PD_AVX2 Wide(const double* xi_) {
        for (int c = 0; c < 3; ++c)
            X[c] = _mm256_set1_pd(xi_[c]);
    }
    __m256d X[3];
    PD_AVX2 PD_INLINE void add_force(Lanes<__m128d>& L, __m256d a, const __m256d* d) const {
        for (int c = 0; c < 3; ++c)
            L.F[c] = fold(L.F[c], _mm256_mul_pd(a, d[c]));
    }
};
#endif

/// Callers that fill BondData and BodyLaw by hand (tests) get the constants on the first call.
inline void ensure_constants(const State& s, BondData& b, const BodyLaw& law) {
    const bool lps = !b.omega.empty() && law.m.size() == s.n; // as bond_constants
    if (b.kb.size() != (keeps_kb(law) ? b.xi.size() : 0) ||
        b.lc.size() != (law.any_flaws ? b.xi.size() : 0) ||
        (lps && (b.wv.size() != b.xi.size() || b.len.size() != b.xi.size())) ||
        (law.m.size() == s.n && law.lps_ap.size() != 2 * s.n))
        bond_constants(s, b, const_cast<BodyLaw&>(law));
}

} // namespace pd::solver::kernels
