// SPDX-License-Identifier: MIT
#include "solver/stability.hpp"

#include "core/errors.hpp"
#include "solver/bond_kernels.hpp"
#include "solver/contact.hpp"
#include "solver/detail.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace pd::solver {

namespace {

/// Deterministic pseudo-random number in [-1, 1) from an integer (splitmix64).
double hash_unit(std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1p-52 - 1.0;
}

#if defined(PD_KERNELS_AVX2)
/// BondOperator::pmb_row_force four bonds at a time in AVX2 lanes: f += sum c (d . dw) d over
/// the first m - m % 4 of the row's m bonds (neighbours nb, c from `coef`, 4 B each); returns
/// how many it took. The sums' order differs from the SSE2 path's, as between rank counts.
PD_AVX2 std::size_t pmb_compact_avx2(const double* X, const double* w, const index_t* nb,
                                     const char* coef, std::size_t i, std::size_t m, double f[3]) {
    const __m256d xi[3] = {_mm256_set1_pd(X[3 * i]), _mm256_set1_pd(X[3 * i + 1]),
                           _mm256_set1_pd(X[3 * i + 2])};
    const __m256d wi[3] = {_mm256_set1_pd(w[3 * i]), _mm256_set1_pd(w[3 * i + 1]),
                           _mm256_set1_pd(w[3 * i + 2])};
    __m256d acc[3] = {_mm256_setzero_pd(), _mm256_setzero_pd(), _mm256_setzero_pd()};
    std::size_t b = 0;
    for (; b + 3 < m; b += 4) {
        __m256d d[3], dw[3];
        kernels::gather4(X, nb + b, xi, d);
        kernels::gather4(w, nb + b, wi, dw);
        const __m256d dd =
            _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(d[0], dw[0]), _mm256_mul_pd(d[1], dw[1])),
                          _mm256_mul_pd(d[2], dw[2]));
        const __m256d c = _mm256_cvtps_pd(
            _mm_castsi128_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(coef + 4 * b))));
        const __m256d t = _mm256_mul_pd(c, dd);
        for (int e = 0; e < 3; ++e)
            acc[e] = _mm256_add_pd(acc[e], _mm256_mul_pd(t, d[e]));
    }
    for (int e = 0; e < 3; ++e) {
        const __m128d h =
            _mm_add_pd(_mm256_castpd256_pd128(acc[e]), _mm256_extractf128_pd(acc[e], 1));
        f[e] += kernels::lane0(h) + kernels::lane1(h);
    }
    return b;
}
#endif

/// The linearised bond operator y = D^-1/2 K D^-1/2 x over this rank's rows (3 per node, full
/// length 3n; ghosts of x must be current).
class BondOperator {
  public:
    BondOperator(const State& s, BondData& b, const BodyLaw& law, Domain& dom, bool compact)
        : s_(s)
        , b_(b)
        , xi_(b.xi)
        , law_(law)
        , dom_(dom) {
        PD_CHECK(b.kb.size() == (keeps_kb(law) ? b.xi.size() : 0), "bond_constants first");
        const std::size_t n = s.n;
        scale_.assign(n, 0.0);
        for (auto row : s.rows) {
            const auto i = static_cast<std::size_t>(row);
            if (s.moving[i] && s.rho[i] > 0 && s.vol[i] > 0)
                scale_[i] = 1.0 / std::sqrt(s.rho[i] * s.vol[i]);
        }
        dom_.exchange({&scale_}, 1);
        mask_.assign(3 * n, 0);
        for (auto row : s.rows) {
            const auto i = static_cast<std::size_t>(row);
            for (int d = 0; d < law.dimension; ++d)
                mask_[3 * i + static_cast<std::size_t>(d)] =
                    scale_[i] > 0 && !(s.fixed_dof[i] & (1u << d)) ? 1 : 0;
        }
        if (law.any_lps) {
            // LPS: q_i = theta_i / d (1 - m_intact / m_i) on damaged families (bond_forces.cpp).
            g_.assign(n, 0.0);
            for (std::size_t a = 0; a < s.rows.size(); ++a) {
                const auto i = static_cast<std::size_t>(s.rows[a]);
                if (!law.lps[static_cast<std::size_t>(s.body[i])])
                    continue;
                bool damaged = false;
                const double mi = intact_weighted_volume(s, b, law, a, damaged);
                g_[i] = damaged ? 1.0 - mi / law.m[i] : 0.0;
            }
            dth_.assign(n, 0.0);
            dq_.assign(n, 0.0);
        }
        w_.assign(3 * n, 0.0);
        // No PMB kernel (keeps_kb): no moving PMB row, every c 0 and margin 0 (the same bits).
        if (compact && keeps_kb(law))
            compact_coefficients();
    }
    BondOperator(const BondOperator&) = delete;
    BondOperator& operator=(const BondOperator&) = delete;
    /// xi back in its storage, if compact_coefficients borrowed it.
    ~BondOperator() { restore_xi(b_.offsets[s_.rows.size()]); }

    bool active(std::size_t dof) const { return mask_[dof] != 0; }

    /// The bound m of |lambda_max(A') - lambda_max(A)| for the compact coefficients A' (0 on
    /// the reference path).
    double margin() const { return margin_; }

    /// y = A x (owned rows; x's ghosts current). x and y full length.
    void apply(const std::vector<double>& x, std::vector<double>& y) {
        const std::size_t n = s_.n;
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t d = 0; d < 3; ++d)
                w_[3 * i + d] = x[3 * i + d] * scale_[i];
        const std::size_t nr = s_.rows.size();
        if (law_.any_lps)
            dilatation_change(nr);
        const double* vol = s_.vol.data();
        for (std::size_t a = 0; a < nr; ++a) {
            const auto i = static_cast<std::size_t>(s_.rows[a]);
            double f[3] = {0, 0, 0};
            const auto body = static_cast<std::size_t>(s_.body[i]);
            if (scale_[i] > 0 && coef_ && !law_.rnp[body] && !law_.lps[body])
                pmb_row_force(a, i, f);
            else if (scale_[i] > 0)
                row_force(a, i, f);
            // Nodal force V_i f_i, scaled by D^-1/2; minus: K = -df/du is positive.
            const double sc = -vol[i] * scale_[i];
            for (std::size_t c = 0; c < 3; ++c)
                y[3 * i + c] = mask_[3 * i + c] ? sc * f[c] : 0.0;
        }
    }

  private:
    /// Unit vector e from i to j in the current positions, and the length l.
    void dir(std::size_t i, std::size_t j, double e[3], double& l) const {
        const double* X = s_.x.data();
        double sq = 0;
        for (std::size_t c = 0; c < 3; ++c) {
            e[c] = X[3 * j + c] - X[3 * i + c];
            sq += e[c] * e[c];
        }
        l = std::sqrt(sq);
        for (std::size_t c = 0; c < 3; ++c)
            e[c] /= l;
    }
    /// The relative displacement w_j - w_i along e.
    double proj(std::size_t i, std::size_t j, const double e[3]) const {
        const double* w = w_.data();
        return e[0] * (w[3 * j] - w[3 * i]) + e[1] * (w[3 * j + 1] - w[3 * i + 1]) +
               e[2] * (w[3 * j + 2] - w[3 * i + 2]);
    }
    /// Pass 1: the dilatation change of every LPS row, then its ghosts.
    void dilatation_change(std::size_t nr) {
        const double* vol = s_.vol.data();
        const double dd = law_.dimension;
        for (std::size_t a = 0; a < nr; ++a) {
            const auto i = static_cast<std::size_t>(s_.rows[a]);
            const auto bd = static_cast<std::size_t>(s_.body[i]); // bond_beta's body
            if (!law_.lps[bd] || scale_[i] == 0) {
                dth_[i] = dq_[i] = 0;
                continue;
            }
            double th = 0;
            for (auto k = b_.offsets[a]; k < b_.offsets[a + 1]; ++k) {
                const auto kk = static_cast<std::size_t>(k);
                if (!b_.alive[kk])
                    continue;
                const auto j = static_cast<std::size_t>(b_.neighbor[kk]);
                double e[3], l;
                dir(i, j, e, l);
                th +=
                    b_.omega[kk] * b_.xi[kk] * proj(i, j, e) * bond_beta(b_, law_, bd, kk) * vol[j];
            }
            dth_[i] = dd * th / law_.m[i];
            dq_[i] = g_[i] * dth_[i] / dd;
        }
        dom_.exchange({&dth_, &dq_}, 1);
    }
    /// The force density f of row a (node i) for the displacement w.
    void row_force(std::size_t a, std::size_t i, double f[3]) const {
        const double* vol = s_.vol.data();
        const auto body = static_cast<std::size_t>(s_.body[i]);
        for (auto k = b_.offsets[a]; k < b_.offsets[a + 1]; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            const auto j = static_cast<std::size_t>(b_.neighbor[kk]);
            double e[3], l, t = 0;
            if (law_.rnp[body]) {
                // Reference direction (rnp kernel: f = a X, S = X . eta / r^2); at S = 0.
                double sq = 0;
                for (std::size_t c = 0; c < 3; ++c) {
                    e[c] = s_.x0[3 * j + c] - s_.x0[3 * i + c];
                    sq += e[c] * e[c];
                }
                l = std::sqrt(sq);
                for (double& c : e)
                    c /= l;
                t = 4.0 * b_.omega[kk] * law_.rnp_c[body] * law_.rnp_beta[body] /
                    law_.rnp_inv[body] * b_.beta[kk] * vol[j] / b_.xi[kk] * proj(i, j, e);
            } else {
                dir(i, j, e, l);
                t = pair_stiffness(i, j, kk, body, proj(i, j, e));
            }
            f[0] += t * e[0];
            f[1] += t * e[1];
            f[2] += t * e[2];
        }
    }
    /// Per PMB bond the float c = kb' / |d|^2 (d = x_j - x_i, kb' the stiffness row_force
    /// gives the bond: kb, or for a broken bond its repulsion's): what the Lanczos steps stream
    /// is then the neighbour index and c, 8 B a bond instead of 13 (index, kb, alive flag), and
    /// no division. The rounding of c to float is a relative error of at most u = 2^-24 per
    /// term of A, so A' = A + E with |E| <= u T entrywise, T the bonds' terms of A in absolute
    /// value (symmetric, nonnegative), and |lambda_max(A') - lambda_max(A)| <= ||E||_2 <= u
    /// ||T||_2 <= u R, R the largest row sum of T. A row (i, e) of T sums V_i s_i |c| |d_e|
    /// |d|_1 (s_i + s_j) <= sqrt(3) V_i s_i |kb'| (s_i + s_j) over its bonds (|d_e| |d|_1 <=
    /// sqrt(3) |d|^2). margin_ = 4 u max_i V_i s_i sum_j |kb'| (s_i + s_j) >= 2 sqrt(3) u R
    /// (the second u for A's own roundings), which bond_spectrum adds to both ends of its
    /// bracket. No compact path (margin_ 0) when a c is not a normal float. Memory: with no LPS
    /// or RNP body (nothing reads xi here) the c, two per double, take xi's storage, and
    /// ~BondOperator recomputes xi with bond_length (the same bits: each xi is checked against
    /// it before it is overwritten; at a mismatch xi is restored, the c get their own array).
    void compact_coefficients() {
        const auto nb = b_.kb.size();
        int bad = 2;
        if (!law_.any_lps && !law_.any_rnp && xi_.size() == nb) {
            store_ = xi_.data();
            bad = fill_coefficients(true);
            if (bad == 0)
                return;
            restore_xi(nb);
        }
        if (bad == 2) { // xi's storage not borrowed: an array of their own
            own_.assign((nb + 1) / 2, 0.0);
            store_ = own_.data();
            bad = fill_coefficients(false);
        }
        if (bad != 0)
            store_ = nullptr;
    }
    /// compact_coefficients' pass into store_ (collective): 0, or 1 at a c that is not a normal
    /// float, or 2 at an xi that bond_length does not give (`check`; xi's storage borrowed up to
    /// the row before it).
    int fill_coefficients(bool check) {
        const double* X = s_.x.data();
        const double* vol = s_.vol.data();
        auto* out = reinterpret_cast<char*>(store_);
        double r_max = 0;
        bool ok = true, same = true;
        for (std::size_t a = 0; a < s_.rows.size() && ok && same; ++a) {
            const auto i = static_cast<std::size_t>(s_.rows[a]);
            const auto body = static_cast<std::size_t>(s_.body[i]);
            const bool pmb = scale_[i] > 0 && !law_.rnp[body] && !law_.lps[body];
            double rs = 0;
            for (auto k = b_.offsets[a]; k < b_.offsets[a + 1]; ++k) {
                const auto kk = static_cast<std::size_t>(k);
                const auto j = static_cast<std::size_t>(b_.neighbor[kk]);
                if (check && xi_[kk] != detail::bond_length(s_.x0, i, j)) {
                    same = false;
                    borrowed_ = kk;
                    break;
                }
                float cf = 0;
                if (pmb) {
                    double l2 = 0;
                    for (std::size_t c = 0; c < 3; ++c)
                        l2 += (X[3 * j + c] - X[3 * i + c]) * (X[3 * j + c] - X[3 * i + c]);
                    const double kp = pmb_stiffness(kk, j, body);
                    cf = static_cast<float>(kp / l2);
                    ok = ok && (std::isnormal(cf) || kp == 0);
                    rs += std::abs(kp) * (scale_[i] + scale_[j]);
                }
                std::memcpy(out + 4 * kk, &cf, 4); // xi[kk / 2] was checked at kk / 2 <= kk
            }
            r_max = std::max(r_max, vol[i] * scale_[i] * rs);
            if (check && same)
                borrowed_ = static_cast<std::size_t>(b_.offsets[a + 1]);
        }
        const int bad = static_cast<int>(dom_.max(!same ? 2.0 : !ok ? 1.0 : 0.0));
        if (bad != 0)
            return bad;
        margin_ = 0x1p-22 * dom_.max(r_max);
        coef_ = true;
        return 0;
    }
    /// xi of the bonds below `end` from x0 where compact_coefficients borrowed its storage.
    void restore_xi(std::size_t end) {
        end = std::min(end, borrowed_);
        for (std::size_t a = 0; a < s_.rows.size(); ++a) {
            const auto i = static_cast<std::size_t>(s_.rows[a]);
            for (auto k = b_.offsets[a]; k < b_.offsets[a + 1]; ++k) {
                const auto kk = static_cast<std::size_t>(k);
                if (kk >= end)
                    break;
                xi_[kk] = detail::bond_length(s_.x0, i, static_cast<std::size_t>(b_.neighbor[kk]));
            }
        }
        borrowed_ = 0;
    }
    /// The compact c of bond k (compact_coefficients' store, 4 B each).
    float coefficient(std::size_t k) const {
        float c;
        std::memcpy(&c, reinterpret_cast<const char*>(store_) + 4 * k, 4);
        return c;
    }
    /// The force density f of the PMB row a (node i): per bond c (d . dw) d with d = x_j - x_i
    /// and the compact c = kb / |d|^2 (compact_coefficients), four bonds at a time in AVX2 lanes
    /// where the CPU has them (pmb_compact_avx2), then two at a time in SSE2 lanes.
    /// The same operator as row_force's kb (e . dw) e (e = d / |d|) to the rounding of c.
    void pmb_row_force(std::size_t a, std::size_t i, double f[3]) const {
        auto k = b_.offsets[a];
        const auto end = b_.offsets[a + 1];
        const double* X = s_.x.data();
        const double* w = w_.data();
        const char* coef = reinterpret_cast<const char*>(store_);
#if defined(PD_KERNELS_AVX2)
        if (avx2_)
            k += static_cast<offset_t>(pmb_compact_avx2(X, w, b_.neighbor.data() + k,
                                                        coef + 4 * static_cast<std::size_t>(k), i,
                                                        static_cast<std::size_t>(end - k), f));
#endif
#if defined(__SSE2__)
        using V = __m128d;
        const V xi[3] = {_mm_set1_pd(X[3 * i]), _mm_set1_pd(X[3 * i + 1]),
                         _mm_set1_pd(X[3 * i + 2])};
        const V wi[3] = {_mm_set1_pd(w[3 * i]), _mm_set1_pd(w[3 * i + 1]),
                         _mm_set1_pd(w[3 * i + 2])};
        V acc[3] = {_mm_setzero_pd(), _mm_setzero_pd(), _mm_setzero_pd()};
        for (; k + 1 < end; k += 2) {
            const auto ka = static_cast<std::size_t>(k);
            const index_t ja = b_.neighbor[ka], jb = b_.neighbor[ka + 1];
            V d[3], dw[3];
            kernels::gather2(X, ja, jb, xi, d);
            kernels::gather2(w, ja, jb, wi, dw);
            const V dd = _mm_add_pd(_mm_add_pd(_mm_mul_pd(d[0], dw[0]), _mm_mul_pd(d[1], dw[1])),
                                    _mm_mul_pd(d[2], dw[2]));
            const V c = _mm_cvtps_pd(
                _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(coef + 4 * ka))));
            const V t = _mm_mul_pd(c, dd);
            for (int e = 0; e < 3; ++e)
                acc[e] = _mm_add_pd(acc[e], _mm_mul_pd(t, d[e]));
        }
        for (int e = 0; e < 3; ++e)
            f[e] += kernels::lane0(acc[e]) + kernels::lane1(acc[e]);
#endif
        for (; k < end; ++k) { // the odd last bond (every bond without SSE2)
            const auto kk = static_cast<std::size_t>(k);
            const auto j = static_cast<std::size_t>(b_.neighbor[kk]);
            double d[3], dd = 0;
            for (std::size_t c = 0; c < 3; ++c) {
                d[c] = X[3 * j + c] - X[3 * i + c];
                dd += d[c] * (w[3 * j + c] - w[3 * i + c]);
            }
            const double t = static_cast<double>(coefficient(kk)) * dd;
            for (std::size_t c = 0; c < 3; ++c)
                f[c] += t * d[c];
        }
    }
    /// A PMB bond's stiffness: pair_stiffness(...) = pmb_stiffness(...) de.
    double pmb_stiffness(std::size_t kk, std::size_t j, std::size_t body) const {
        return b_.alive[kk] ? b_.kb[kk] : std::max(law_.krep[body] * s_.vol[j], b_.kb[kk]);
    }
    /// The bond's force for the relative displacement de along it (PMB, LPS, or the broken-bond
    /// repulsion).
    double pair_stiffness(std::size_t i, std::size_t j, std::size_t kk, std::size_t body,
                          double de) const {
        const double* vol = s_.vol.data();
        const double dd = law_.dimension;
        if (!b_.alive[kk]) {
            // The broken-bond repulsion (spec 4.7) once the pair comes closer
            // than r_rep; a PMB bond counts at the larger of the two stiffnesses
            // (bonds may still break during the run).
            double k_pair = law_.krep[body] * vol[j];
            if (!law_.lps[body])
                k_pair = std::max(k_pair, bond_kb(b_, law_, body, kk, vol[j]));
            return k_pair * de;
        }
        if (law_.lps[body]) {
            const double kap = law_.kappa[body], mu = law_.mu[body];
            const double xi = b_.xi[kk];
            const double t_ij = b_.omega[kk] * (dd * kap * dth_[i] / law_.m[i] * xi +
                                                law_.alpha * mu / law_.m[i] *
                                                    (de - dth_[i] * xi / dd - dq_[i] * xi));
            const double t_ji = b_.omega[kk] * (dd * kap * dth_[j] / law_.m[j] * xi +
                                                law_.alpha * mu / law_.m[j] *
                                                    (de - dth_[j] * xi / dd - dq_[j] * xi));
            return (t_ij + t_ji) * bond_beta(b_, law_, body, kk) * vol[j];
        }
        // kb = c stiff V_j / xi, evaluated in this order by bond_constants: the same bits as
        // the expression, without its division per bond and Lanczos step.
        return b_.kb[kk] * de;
    }

  public:
    double dot(const std::vector<double>& p, const std::vector<double>& q) const {
        double sum = 0;
        for (auto row : s_.rows) {
            const auto i = 3 * static_cast<std::size_t>(row);
            sum += p[i] * q[i] + p[i + 1] * q[i + 1] + p[i + 2] * q[i + 2];
        }
        return dom_.sum(sum);
    }

    void exchange(std::vector<double>& x) {
        dom_.exchange({&x}, 3);
    }

  private:
    const State& s_;
    const BondData& b_;
    const BodyLaw& law_;
    Domain& dom_;
    std::vector<double> scale_; ///< 1 / sqrt(rho V), 0 for nodes that do not move
    std::vector<std::uint8_t> mask_;
    std::vector<double> g_, dth_, dq_, w_;
    std::vector<double>& xi_;  ///< b_.xi, whose storage compact_coefficients may borrow
    std::vector<double> own_;  ///< the c's storage when xi's is not borrowed
    double* store_ = nullptr;  ///< the c, 4 B each (xi's storage or own_)
    std::size_t borrowed_ = 0; ///< bonds below it hold c in xi's storage
    bool coef_ = false;        ///< the PMB rows run on the c
    bool avx2_ = kernels::best_isa() == kernels::Isa::avx2; ///< pmb_compact_avx2 for them
    double margin_ = 0;
};

} // namespace

double round_step(double dt, int digits) {
    if (!std::isfinite(dt) || !(dt > 0))
        return dt;
    const double unit = std::pow(10.0, std::floor(std::log10(dt)) - (digits - 1));
    return std::floor(dt / unit * (1 + 1e-9)) * unit;
}

BondSpectrum bond_spectrum(const State& s, BondData& b, const BodyLaw& law, Domain& dom,
                           int max_iterations, double tolerance, int step_digits, bool compact) {
    BondSpectrum r;
    BondOperator A(s, b, law, dom, compact);
    const double m = A.margin();
    const std::size_t n3 = 3 * s.n;
    std::vector<double> q(n3, 0.0), q_prev(n3, 0.0), w(n3, 0.0);
    for (auto row : s.rows) {
        const auto i = static_cast<std::size_t>(row);
        for (std::size_t d = 0; d < 3; ++d)
            if (A.active(3 * i + d))
                q[3 * i + d] = hash_unit(3 * static_cast<std::uint64_t>(row) + d);
    }
    double norm = std::sqrt(A.dot(q, q));
    if (!(norm > 0)) {
        // Every dof prescribed: no dynamics of its own. The row-sum bound of the bonds keeps
        // the step the conditions are sampled at finite (and as it was before issue 11).
        double k_max = 0;
        for (std::size_t a = 0; a < s.rows.size(); ++a) {
            const auto i = static_cast<std::size_t>(s.rows[a]);
            if (!s.moving[i])
                continue;
            k_max = std::max(k_max, 2.0 * row_kb_sum(s, b, law, a) / s.rho[i]);
        }
        r.ritz = dom.max(k_max);
        return r;
    }
    for (auto& v : q)
        v /= norm;
    std::vector<double> alpha, beta;
    double beta_prev = 0, last = 0;
    int settled = 0;
    for (int it = 0; it < max_iterations; ++it) {
        A.exchange(q);
        A.apply(q, w);
        const double al = A.dot(q, w);
        for (auto row : s.rows) {
            const auto i = 3 * static_cast<std::size_t>(row);
            for (std::size_t d = 0; d < 3; ++d)
                w[i + d] -= al * q[i + d] + beta_prev * q_prev[i + d];
        }
        const double be = std::sqrt(A.dot(w, w));
        alpha.push_back(al);
        const auto k = static_cast<Eigen::Index>(alpha.size());
        Eigen::VectorXd diag = Eigen::Map<Eigen::VectorXd>(alpha.data(), k);
        Eigen::VectorXd sub =
            k > 1 ? Eigen::Map<Eigen::VectorXd>(beta.data(), k - 1).eval() : Eigen::VectorXd();
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es;
        es.computeFromTridiagonal(diag, sub, Eigen::ComputeEigenvectors);
        // The bracket of A's lambda_max: A''s, widened by the compact path's margin.
        r.ritz = es.eigenvalues()(k - 1) - m;
        r.residual = be * std::abs(es.eigenvectors()(k - 1, k - 1)) + 2 * m;
        r.iterations = it + 1;
        beta.push_back(be);
        // Converged: the top Ritz value is steady and its residual small.
        settled = std::abs(r.ritz - last) <= tolerance * r.ritz ? settled + 1 : 0;
        // The step decided: both ends of lambda_max's bracket round to the same step.
        const bool decided = step_digits > 0 && it > 0 && std::abs(r.ritz - last) <= r.residual &&
                             round_step(critical_dt(r.ritz), step_digits) ==
                                 round_step(critical_dt(r.lambda()), step_digits);
        last = r.ritz;
        if (!(be > 1e-14 * std::abs(r.ritz)) ||
            (settled >= 3 && r.residual <= 10 * tolerance * r.ritz) || decided)
            break;
        q_prev.swap(q);
        for (auto row : s.rows) {
            const auto i = 3 * static_cast<std::size_t>(row);
            for (std::size_t d = 0; d < 3; ++d)
                q[i + d] = w[i + d] / be;
        }
        beta_prev = be;
    }
    return r;
}

double contact_lambda_bound(const model::Model& m, const State& s) {
    double lambda = 0;
    int ng = 0;
    for (auto g : m.bodies.group)
        ng = std::max(ng, g + 1);
    for (const auto& w : m.walls)
        ng = std::max(ng, w.group + 1);
    const auto G = static_cast<std::size_t>(ng);
    std::vector<int> bodies(G, 0), moving(G, 0), walls(G, 0);
    std::vector<double> hmin(G, std::numeric_limits<double>::infinity()), vmax(G, 0.0),
        rho_min(G, std::numeric_limits<double>::infinity());
    for (std::size_t b = 0; b < m.bodies.num(); ++b) {
        const auto g = static_cast<std::size_t>(m.bodies.group[b]);
        ++bodies[g];
        moving[g] += m.bodies.fixed[b] ? 0 : 1;
        hmin[g] = std::min(hmin[g], m.bodies.mesh_size[b]);
        for (auto i = m.bodies.begin(b); i < m.bodies.end(b); ++i) {
            const auto ii = static_cast<std::size_t>(i);
            vmax[g] = std::max(vmax[g], s.vol[ii]);
            if (!m.bodies.fixed[b])
                rho_min[g] = std::min(rho_min[g], s.rho[ii]);
        }
    }
    for (const auto& w : m.walls)
        ++walls[static_cast<std::size_t>(w.group)];
    for (const auto& p : m.contact) {
        const double kn = contact_max_stiffness(p);
        if (kn <= 0 || p.radius <= 0 || p.group_a >= ng || p.group_b >= ng)
            continue;
        const auto a = static_cast<std::size_t>(p.group_a), b = static_cast<std::size_t>(p.group_b);
        // Can this law act at all?
        const bool pair = a == b ? bodies[a] >= 2 && moving[a] >= 1
                                 : bodies[a] >= 1 && bodies[b] >= 1 && moving[a] + moving[b] >= 1;
        const bool wall = (walls[b] > 0 && moving[a] > 0) || (walls[a] > 0 && moving[b] > 0);
        if (!pair && !wall)
            continue;
        if (p.law == model::ContactLaw::surface) {
            // A node inside a boundary: c V_i on itself and on the facet's nodes (weights
            // summing to 1), twice as a node is both inside one boundary and a facet node of
            // another (Gershgorin: 2 x (c + c) / rho), and that for each other body it can touch
            // at once: in a pack, grains meet at a point in threes (2D) and fours (3D), so a
            // node there is inside, and a facet node for, `dimension` other bodies. At 4 c / rho
            // a 2D box of 78 circles and hexagons blew up at such a triple junction after 36 ms
            // (one node at 8.9 m/s, the balance 16 % off at 0.85 x the estimate).
            // Against a rigid wall only: c on the node itself; with the node's own bonds, 2 c
            // (the smaller step of bonds and contact is taken, not their sum: see
            // Solver::stable_dt).
            const double rho = std::min(rho_min[a], rho_min[b]);
            if (std::isfinite(rho))
                lambda = std::max(lambda, (pair ? 4.0 * m.dimension : 2.0) * kn / rho);
            continue;
        }
        const double h = std::min(hmin[a], hmin[b]);
        const double v = std::max(vmax[a], vmax[b]);
        const double rho = std::min(rho_min[a], rho_min[b]);
        if (!std::isfinite(h) || !std::isfinite(rho) || !(v > 0))
            continue;
        const double reach = m.dimension == 3 ? 4.0 / 3.0 * M_PI * std::pow(p.radius, 3)
                                              : M_PI * p.radius * p.radius;
        // Node count within R_c (at least 1; a wall acts as one mirror node) times the largest
        // nodal volume; twice the row sum (Gershgorin).
        const double nodes_in = std::max(1.0, reach / std::pow(h, m.dimension));
        lambda = std::max(lambda, 2.0 * kn * nodes_in * v / rho);
    }
    return lambda;
}

double critical_dt(double lambda) {
    return lambda > 0 ? 2.0 / std::sqrt(lambda) : std::numeric_limits<double>::infinity();
}

} // namespace pd::solver
