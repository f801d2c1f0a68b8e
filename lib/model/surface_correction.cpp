// SPDX-License-Identifier: MIT
#include "model/surface_correction.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__SSE2__) && defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) &&       \
    !defined(PD_NO_AVX2)
#include <immintrin.h>
#define PD_POW4_AVX2 1
#endif

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

/// The unit directions of row a's bonds (node i, turn t), 3 per bond into u: direction()'s
/// operations, two bonds at a time in SSE2 lanes. The lanes round each difference, product,
/// sum, square root and quotient as the scalar code does (IEEE, no FMA), so the same bits, for
/// half the square roots and divisions issued (the divider bounds these passes).
void row_directions(const FamilyRows& f, std::size_t a, Turn t, std::vector<double>& u) {
    const auto i = static_cast<std::size_t>(f.rows[a]);
    const auto k0 = static_cast<std::size_t>(f.offsets[a]);
    const auto m = static_cast<std::size_t>(f.offsets[a + 1]) - k0;
    u.resize(3 * m);
    std::size_t b = 0;
#if defined(__SSE2__)
    const double* x = f.x0.data();
    const __m128d xi[3] = {_mm_set1_pd(x[3 * i]), _mm_set1_pd(x[3 * i + 1]),
                           _mm_set1_pd(x[3 * i + 2])};
    const __m128d co = _mm_set1_pd(t.co), so = _mm_set1_pd(t.so), mso = _mm_set1_pd(-t.so);
    for (; b + 1 < m; b += 2) {
        const double* pa = x + 3 * static_cast<std::size_t>(f.neighbor[k0 + b]);
        const double* pb = x + 3 * static_cast<std::size_t>(f.neighbor[k0 + b + 1]);
        __m128d dx[3];
        for (std::size_t c = 0; c < 3; ++c)
            dx[c] = _mm_sub_pd(_mm_set_pd(pb[c], pa[c]), xi[c]);
        // r2 = ((0 + dx0^2) + dx1^2) + dx2^2, as direction() sums it.
        __m128d r2 = _mm_setzero_pd();
        for (const auto& c : dx)
            r2 = _mm_add_pd(r2, _mm_mul_pd(c, c));
        const __m128d r = _mm_sqrt_pd(r2);
        const __m128d n[3] = {
            _mm_div_pd(_mm_add_pd(_mm_mul_pd(co, dx[0]), _mm_mul_pd(so, dx[1])), r),
            _mm_div_pd(_mm_add_pd(_mm_mul_pd(mso, dx[0]), _mm_mul_pd(co, dx[1])), r),
            _mm_div_pd(dx[2], r)};
        for (std::size_t c = 0; c < 3; ++c) {
            _mm_storel_pd(&u[3 * b + c], n[c]);
            _mm_storeh_pd(&u[3 * b + 3 + c], n[c]);
        }
    }
#endif
    for (; b < m; ++b) // the odd last bond (every bond without SSE2)
        direction(f, t, i, static_cast<std::size_t>(f.neighbor[k0 + b]), &u[3 * b]);
}

/// The bond factors G of row a's bonds (directions u from row_directions, node i's axis
/// factors gi) into G: surface_bond_factor's operations, two bonds at a time in SSE2 lanes
/// (the same bits, as row_directions).
void row_factors(const FamilyRows& f, std::size_t a, const std::vector<double>& u,
                 const std::array<double, 3>& gi, std::span<const double> g, int d, double* G) {
    const auto k0 = static_cast<std::size_t>(f.offsets[a]);
    const auto m = static_cast<std::size_t>(f.offsets[a + 1]) - k0;
    const auto gj = [&](std::size_t b) {
        const auto j = static_cast<std::size_t>(f.neighbor[k0 + b]);
        return std::array<double, 3>{g[3 * j], g[3 * j + 1], g[3 * j + 2]};
    };
    std::size_t b = 0;
#if defined(__SSE2__)
    const __m128d half = _mm_set1_pd(0.5), one = _mm_set1_pd(1.0);
    for (; b + 1 < m; b += 2) {
        const auto ga = gj(b), gb = gj(b + 1);
        __m128d s = _mm_setzero_pd();
        for (int c = 0; c < d; ++c) {
            const auto k = static_cast<std::size_t>(c);
            const __m128d gm =
                _mm_mul_pd(half, _mm_add_pd(_mm_set1_pd(gi[k]), _mm_set_pd(gb[k], ga[k])));
            const __m128d n = _mm_set_pd(u[3 * b + 3 + k], u[3 * b + k]);
            s = _mm_add_pd(s, _mm_div_pd(_mm_mul_pd(n, n), _mm_mul_pd(gm, gm)));
        }
        // s > 0 ? 1 / sqrt(s) : 1, lane by lane.
        const __m128d pos = _mm_cmpgt_pd(s, _mm_setzero_pd());
        const __m128d r = _mm_div_pd(one, _mm_sqrt_pd(s));
        _mm_storeu_pd(G + b, _mm_or_pd(_mm_and_pd(pos, r), _mm_andnot_pd(pos, one)));
    }
#endif
    for (; b < m; ++b)
        G[b] = surface_bond_factor(&u[3 * b], gi, gj(b), d);
}

/// pow4 of the values its fast check does not take (they go to std::pow, ~1 in 10 of the
/// components, ~20 ns each), remembered by their bits: a grid's bond directions take a few
/// thousand distinct values, repeated over every row. The same bits as pow4 by construction.
class Pow4Memo {
  public:
    double operator()(double u) {
        const auto bits = std::bit_cast<std::uint64_t>(u);
        auto& e = slots_[(bits * 0x9e3779b97f4a7c15ULL) >> (64 - log2_slots)];
        if (e.key != bits || !e.used) {
            e = {bits, pow4(u), true};
        }
        return e.value;
    }

  private:
    static constexpr int log2_slots = 14;
    struct Slot {
        std::uint64_t key = 0;
        double value = 0;
        bool used = false;
    };
    std::vector<Slot> slots_ = std::vector<Slot>(std::size_t{1} << log2_slots);
};

#if defined(PD_POW4_AVX2)
/// two_square's operations on four lanes.
__attribute__((target("avx2"))) inline void square4(__m256d a, __m256d& q, __m256d& e) {
    const __m256d split = _mm256_set1_pd(134217729.0), two = _mm256_set1_pd(2.0);
    q = _mm256_mul_pd(a, a);
    const __m256d t = _mm256_mul_pd(split, a);
    const __m256d hi = _mm256_sub_pd(t, _mm256_sub_pd(t, a)), lo = _mm256_sub_pd(a, hi);
    e = _mm256_add_pd(_mm256_add_pd(_mm256_sub_pd(_mm256_mul_pd(hi, hi), q),
                                    _mm256_mul_pd(_mm256_mul_pd(two, hi), lo)),
                      _mm256_mul_pd(lo, lo));
}

/// pow4_into's first count - count % 4 values four at a time in AVX2 lanes (no FMA: the same
/// operations, each rounded as in pow4, so the same bits; a lane its check does not pass goes
/// through the memo); returns how many it took.
__attribute__((target("avx2"))) std::size_t pow4_avx2(const double* u, double* p, std::size_t count,
                                                      Pow4Memo& memo) {
    const __m256d two = _mm256_set1_pd(2.0);
    const __m256d expo = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7ff0000000000000LL));
    const __m256d abs = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL));
    const __m256d tiny = _mm256_set1_pd(0x1p-800), ulp52 = _mm256_set1_pd(0x1p-52),
                  tol = _mm256_set1_pd(0.45);
    std::size_t k = 0;
    for (; k + 3 < count; k += 4) {
        const __m256d v = _mm256_loadu_pd(u + k);
        __m256d s, e, hi, r1;
        square4(v, s, e);
        square4(s, hi, r1);
        const __m256d lo = _mm256_add_pd(r1, _mm256_mul_pd(_mm256_mul_pd(two, s), e));
        const __m256d r = _mm256_add_pd(hi, lo);
        const __m256d d = _mm256_sub_pd(lo, _mm256_sub_pd(r, hi));
        const __m256d pow2 = _mm256_and_pd(r, expo);
        const __m256d ok = _mm256_and_pd(
            _mm256_and_pd(_mm256_cmp_pd(r, tiny, _CMP_GE_OQ), _mm256_cmp_pd(r, pow2, _CMP_NEQ_UQ)),
            _mm256_cmp_pd(_mm256_and_pd(d, abs), _mm256_mul_pd(tol, _mm256_mul_pd(pow2, ulp52)),
                          _CMP_LE_OQ));
        _mm256_storeu_pd(p + k, r);
        const int m = _mm256_movemask_pd(ok);
        for (int l = 0; l < 4; ++l)
            if (!(m & (1 << l)))
                p[k + static_cast<std::size_t>(l)] = memo(u[k + static_cast<std::size_t>(l)]);
    }
    return k;
}

bool have_avx2() {
    static const bool yes = __builtin_cpu_supports("avx2");
    return yes;
}
#endif

/// p[k] = pow4(u[k]) for k < count: pow4's operations four values at a time in AVX2 lanes where
/// the CPU has them (pow4_avx2), the rest two at a time in SSE2 lanes (the
/// same bits); a lane its check does not pass goes through pow4 itself (std::pow, or 0), by way
/// of the memo.
void pow4_into(const double* u, double* p, std::size_t count, Pow4Memo& memo) {
    std::size_t k = 0;
#if defined(PD_POW4_AVX2)
    if (have_avx2())
        k = pow4_avx2(u, p, count, memo);
#endif
#if defined(__SSE2__)
    const __m128d split = _mm_set1_pd(134217729.0), two = _mm_set1_pd(2.0);
    const __m128d expo = _mm_castsi128_pd(_mm_set1_epi64x(0x7ff0000000000000LL));
    const __m128d abs = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffffLL));
    const __m128d tiny = _mm_set1_pd(0x1p-800), ulp52 = _mm_set1_pd(0x1p-52),
                  tol = _mm_set1_pd(0.45);
    // two_square's operations on two lanes.
    const auto square = [&](__m128d a, __m128d& q, __m128d& e) {
        q = _mm_mul_pd(a, a);
        const __m128d t = _mm_mul_pd(split, a);
        const __m128d hi = _mm_sub_pd(t, _mm_sub_pd(t, a)), lo = _mm_sub_pd(a, hi);
        e = _mm_add_pd(
            _mm_add_pd(_mm_sub_pd(_mm_mul_pd(hi, hi), q), _mm_mul_pd(_mm_mul_pd(two, hi), lo)),
            _mm_mul_pd(lo, lo));
    };
    for (; k + 1 < count; k += 2) {
        const __m128d v = _mm_loadu_pd(u + k);
        __m128d s, e, hi, r1;
        square(v, s, e);
        square(s, hi, r1);
        const __m128d lo = _mm_add_pd(r1, _mm_mul_pd(_mm_mul_pd(two, s), e));
        const __m128d r = _mm_add_pd(hi, lo);
        const __m128d d = _mm_sub_pd(lo, _mm_sub_pd(r, hi));
        const __m128d pow2 = _mm_and_pd(r, expo); // r without its mantissa (r >= 0)
        const __m128d ok =
            _mm_and_pd(_mm_and_pd(_mm_cmpge_pd(r, tiny), _mm_cmpneq_pd(r, pow2)),
                       _mm_cmple_pd(_mm_and_pd(d, abs), _mm_mul_pd(tol, _mm_mul_pd(pow2, ulp52))));
        _mm_storeu_pd(p + k, r);
        const int m = _mm_movemask_pd(ok);
        if (!(m & 1))
            p[k] = memo(u[k]);
        if (!(m & 2))
            p[k + 1] = memo(u[k + 1]);
    }
#endif
    for (; k < count; ++k)
        p[k] = memo(u[k]);
}

/// family_axis_moments with bond k's weight scaled by its factor G_k for the axis factors g (3 per
/// node; empty: unscaled): the same products G_k w_k and sums in the same order as building the
/// array G w first, without the two per-bond arrays. The directions of a row are computed once
/// into a row-sized scratch array and shared by the factors and the moments.
std::vector<double> scaled_axis_moments(const FamilyRows& f, std::span<const double> weight,
                                        std::span<const double> g, int d, std::size_t n) {
    std::vector<double> out(3 * n, 0.0), u, G, p;
    Pow4Memo memo;
    for (std::size_t a = 0; a < f.rows.size(); ++a) {
        const auto i = static_cast<std::size_t>(f.rows[a]);
        const auto k0 = static_cast<std::size_t>(f.offsets[a]);
        const auto m = static_cast<std::size_t>(f.offsets[a + 1]) - k0;
        row_directions(f, a, row_turn(f, i), u);
        if (!g.empty()) {
            G.resize(m);
            row_factors(f, a, u, {g[3 * i], g[3 * i + 1], g[3 * i + 2]}, g, d, G.data());
        }
        p.resize(3 * m);
        pow4_into(u.data(), p.data(), 3 * m, memo);
        for (std::size_t b = 0; b < m; ++b) {
            const double w = g.empty() ? weight[k0 + b] : G[b] * weight[k0 + b];
            for (int c = 0; c < d; ++c)
                out[3 * i + static_cast<std::size_t>(c)] +=
                    w * p[3 * b + static_cast<std::size_t>(c)];
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
    std::vector<double> u;
    for (std::size_t a = 0; a < f.rows.size(); ++a) {
        const auto i = static_cast<std::size_t>(f.rows[a]);
        row_directions(f, a, row_turn(f, i), u);
        row_factors(f, a, u, {g[3 * i], g[3 * i + 1], g[3 * i + 2]}, g, d,
                    out.data() + f.offsets[a]);
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
