// SPDX-License-Identifier: MIT
#include "solver/bond_forces.hpp"

#include <cmath>
#include <functional>

namespace pd::solver {

namespace {

template <bool Breakable>
BondResult kernel(State& s, BondData& b, const BodyLaw& law) {
    const auto n = static_cast<std::int64_t>(s.rows.size());
    const index_t* rows = s.rows.data();
    const double* x = s.x.data();
    const double* vol = s.vol.data();
    double* f = s.f.data();
    const offset_t* off = b.offsets.data();
    const index_t* nb = b.neighbor.data();
    const double* xi = b.xi.data();
    const double* beta = b.stiff.data(); // partial volume x quadrature correction
    std::uint8_t* alive = b.alive.data();
    double energy = 0;
    std::int64_t broken = 0;
#pragma omp parallel for schedule(static) reduction(+ : energy, broken) if (n > parallel_min)
    for (std::int64_t a = 0; a < n; ++a) {
        const std::int64_t i = rows[a];
        double fi[3] = {0, 0, 0};
        const auto body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(i)]);
        if (law.lps[body] || law.rnp[body])
            continue; // the LPS or RNP kernel owns this row
        if (!s.moving[static_cast<std::size_t>(i)]) {
            f[3 * i] = f[3 * i + 1] = f[3 * i + 2] = 0;
            continue;
        }
        const double c = law.c[body];
        const double s0 = law.s0[body];
        const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2];
        double e_i = 0;
        const double kr = law.krep[body], rr = law.rrep[body];
        for (offset_t k = off[a]; k < off[a + 1]; ++k) {
            const index_t j = nb[k];
            const double d0 = x[3 * j] - xi0, d1 = x[3 * j + 1] - xi1, d2 = x[3 * j + 2] - xi2;
            const double l = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
            if (Breakable && !alive[k]) {
                // Fragments of one grain repel across broken bonds (spec 4.7).
                if (l < rr) {
                    const double a = kr * (l - rr) * vol[j] / l;
                    fi[0] += a * d0;
                    fi[1] += a * d1;
                    fi[2] += a * d2;
                }
                continue;
            }
            const double st = (l - xi[k]) / xi[k];
            if constexpr (Breakable) {
                if (st > s0) { // tension only; i->j and j->i see identical l, xi: symmetric
                    alive[k] = 0;
                    ++broken;
                    continue;
                }
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
        // Bond energy density 1/2 c s^2 xi per pair; the full list counts each pair twice.
        energy += 0.25 * e_i * vol[i];
    }
    return {energy, broken};
}

template <bool Breakable>
BondResult lps_kernel(State& s, BondData& b, BodyLaw& law, const std::function<void()>& between) {
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
    std::uint8_t* alive = b.alive.data();
    const double dd = law.dimension;
    double* theta = law.theta.data();
    const double* mw = law.m.data();
    std::int64_t broken = 0;
    // Pass 1: break bonds (tension only, symmetric inputs), then dilatation.
#pragma omp parallel for schedule(static) reduction(+ : broken) if (n > parallel_min)
    for (std::int64_t a = 0; a < n; ++a) {
        const std::int64_t i = rows[a];
        const auto body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(i)]);
        if (!law.lps[body] || !s.moving[static_cast<std::size_t>(i)]) {
            theta[i] = 0;
            continue;
        }
        const double s0 = law.s0[body];
        double th = 0;
        for (offset_t k = off[a]; k < off[a + 1]; ++k) {
            if (Breakable && !alive[k])
                continue;
            const index_t j = nb[k];
            const double d0 = x[3 * j] - x[3 * i], d1 = x[3 * j + 1] - x[3 * i + 1],
                         d2 = x[3 * j + 2] - x[3 * i + 2];
            const double e = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2) - xi[k];
            if constexpr (Breakable) {
                if (e / xi[k] > s0) {
                    alive[k] = 0;
                    ++broken;
                    continue;
                }
            }
            th += om[k] * xi[k] * e * beta[k] * vol[j];
        }
        theta[i] = dd * th / mw[i];
    }
    if (between)
        between(); // ghosts' dilatation
    // Pass 2: forces from both ends of every intact bond.
    double energy = 0;
#pragma omp parallel for schedule(static) reduction(+ : energy) if (n > parallel_min)
    for (std::int64_t a = 0; a < n; ++a) {
        const std::int64_t i = rows[a];
        const auto body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(i)]);
        if (!law.lps[body])
            continue;
        if (!s.moving[static_cast<std::size_t>(i)]) {
            f[3 * i] = f[3 * i + 1] = f[3 * i + 2] = 0;
            continue;
        }
        const double kap = law.kappa[body], mu = law.mu[body];
        const double a_i = law.alpha * mu / mw[i];
        const double p_i = dd * kap * theta[i] / mw[i];
        double fi[3] = {0, 0, 0}, wdev = 0;
        const double kr = law.krep[body], rr = law.rrep[body];
        for (offset_t k = off[a]; k < off[a + 1]; ++k) {
            const index_t j = nb[k];
            const double d0 = x[3 * j] - x[3 * i], d1 = x[3 * j + 1] - x[3 * i + 1],
                         d2 = x[3 * j + 2] - x[3 * i + 2];
            const double l = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
            if (Breakable && !alive[k]) {
                if (l < rr) { // fragments repel across broken bonds (spec 4.7)
                    const double a = kr * (l - rr) * vol[j] / l;
                    fi[0] += a * d0;
                    fi[1] += a * d1;
                    fi[2] += a * d2;
                }
                continue;
            }
            const double e = l - xi[k];
            const double ed_i = e - theta[i] * xi[k] / dd;
            const double ed_j = e - theta[j] * xi[k] / dd;
            const double t_ij = om[k] * (p_i * xi[k] + a_i * ed_i);
            const double t_ji =
                om[k] * (dd * kap * theta[j] / mw[j] * xi[k] + law.alpha * mu / mw[j] * ed_j);
            const double a = (t_ij + t_ji) * beta[k] * vol[j] / l;
            fi[0] += a * d0;
            fi[1] += a * d1;
            fi[2] += a * d2;
            wdev += om[k] * ed_i * ed_i * beta[k] * vol[j];
        }
        f[3 * i] = fi[0];
        f[3 * i + 1] = fi[1];
        f[3 * i + 2] = fi[2];
        energy += (0.5 * kap * theta[i] * theta[i] + 0.5 * a_i * wdev) * vol[i];
    }
    return {energy, broken};
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
    double energy = 0;
    std::int64_t broken = 0;
#pragma omp parallel for schedule(static) reduction(+ : energy, broken) if (n > parallel_min)
    for (std::int64_t a = 0; a < n; ++a) {
        const std::int64_t i = rows[a];
        const auto body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(i)]);
        if (!law.rnp[body])
            continue;
        if (!s.moving[static_cast<std::size_t>(i)]) {
            f[3 * i] = f[3 * i + 1] = f[3 * i + 2] = 0;
            continue;
        }
        const double C = law.rnp_c[body], bt = law.rnp_beta[body], rb = law.rnp_rbar[body];
        const double inv = 1.0 / law.rnp_inv[body];
        double fi[3] = {0, 0, 0}, e_i = 0;
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
    }
    return {energy, broken};
}

} // namespace

BondResult rnp_bond_forces(State& s, BondData& b, const BodyLaw& law) {
    return law.any_breakable ? rnp_kernel<true>(s, b, law) : rnp_kernel<false>(s, b, law);
}

BondResult lps_bond_forces(State& s, BondData& b, BodyLaw& law,
                           const std::function<void()>& between) {
    return law.any_breakable ? lps_kernel<true>(s, b, law, between)
                             : lps_kernel<false>(s, b, law, between);
}

BondResult pmb_bond_forces(State& s, BondData& b, const BodyLaw& law) {
    return law.any_breakable ? kernel<true>(s, b, law) : kernel<false>(s, b, law);
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
