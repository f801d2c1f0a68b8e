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
    double energy = 0, released = 0, repulsion = 0;
    std::int64_t broken = 0;
#pragma omp parallel for schedule(static) reduction(+ : energy, broken, released, repulsion) if (n > parallel_min)
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
        double e_i = 0, e_rel = 0, e_rep = 0;
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
                    e_rep += kr * (rr - l) * (rr - l) * vol[j];
                }
                continue;
            }
            const double st = (l - xi[k]) / xi[k];
            if constexpr (Breakable) {
                if (st > s0) { // tension only; i->j and j->i see identical l, xi: symmetric
                    alive[k] = 0;
                    ++broken;
                    // The energy it held, less half the work its force would have done over
                    // the step that broke it: the trapezoid the integrator applied to the
                    // step lacks that half, so the balance closes to O(dt^2), not O(dt).
                    const double* v = s.v.data();
                    const double dv = d0 * (v[3 * j] - v[3 * i]) +
                                      d1 * (v[3 * j + 1] - v[3 * i + 1]) +
                                      d2 * (v[3 * j + 2] - v[3 * i + 2]);
                    e_rel += c * st * beta[k] * vol[j] * (st * xi[k] - law.dt * dv / l);
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
        released += 0.25 * e_rel * vol[i];
        repulsion += 0.25 * e_rep * vol[i];
    }
    return {energy, broken, released, repulsion};
}

template <bool Breakable>
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
    std::int64_t broken = 0;
    // Pass 1: break bonds (tension only, symmetric inputs), then dilatation and q.
#pragma omp parallel for schedule(static) reduction(+ : broken) if (n > parallel_min)
    for (std::int64_t a = 0; a < n; ++a) {
        const std::int64_t i = rows[a];
        const auto body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(i)]);
        if (!law.lps[body] || !s.moving[static_cast<std::size_t>(i)]) {
            theta[i] = 0;
            q[i] = 0;
            continue;
        }
        const double s0 = law.s0[body];
        double th = 0, mi = 0;
        bool damaged = false;
        for (offset_t k = off[a]; k < off[a + 1]; ++k) {
            if (Breakable && !alive[k]) {
                damaged = true;
                continue;
            }
            const index_t j = nb[k];
            const double d0 = x[3 * j] - x[3 * i], d1 = x[3 * j + 1] - x[3 * i + 1],
                         d2 = x[3 * j + 2] - x[3 * i + 2];
            const double e = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2) - xi[k];
            if constexpr (Breakable) {
                if (e / xi[k] > s0) {
                    alive[k] = 2;
                    damaged = true;
                    ++broken;
                    continue;
                }
                mi += om[k] * xi[k] * xi[k] * beta[k] * vol[j];
            }
            th += om[k] * xi[k] * e * beta[k] * vol[j];
        }
        theta[i] = dd * th / mw[i];
        q[i] = damaged ? theta[i] / dd * (1.0 - mi / mw[i]) : 0.0;
    }
    if (between)
        between(); // ghosts' dilatation and q
    // Pass 2: forces from both ends of every intact bond; the energy bonds broken in pass 1 held.
    double energy = 0, released = 0, repulsion = 0;
#pragma omp parallel for schedule(static) reduction(+ : energy, released, repulsion) if (n > parallel_min)
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
        double fi[3] = {0, 0, 0}, wdev = 0, e_rep = 0, th_new = 0;
        bool fresh = false;
        const double kr = law.krep[body], rr = law.rrep[body];
        for (offset_t k = off[a]; k < off[a + 1]; ++k) {
            const index_t j = nb[k];
            const double d0 = x[3 * j] - x[3 * i], d1 = x[3 * j + 1] - x[3 * i + 1],
                         d2 = x[3 * j + 2] - x[3 * i + 2];
            const double l = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
            if (Breakable && alive[k] != 1) {
                if (alive[k] == 2) { // broken in pass 1: its share of the dilatation before
                    fresh = true;
                    th_new += om[k] * xi[k] * (l - xi[k]) * beta[k] * vol[j];
                }
                if (l < rr) { // fragments repel across broken bonds (spec 4.7)
                    const double a = kr * (l - rr) * vol[j] / l;
                    fi[0] += a * d0;
                    fi[1] += a * d1;
                    fi[2] += a * d2;
                    e_rep += kr * (rr - l) * (rr - l) * vol[j];
                }
                continue;
            }
            const double e = l - xi[k];
            const double ed_i = e - theta[i] * xi[k] / dd;
            const double ed_j = e - theta[j] * xi[k] / dd;
            const double t_ij = om[k] * (p_i * xi[k] + a_i * (ed_i - q[i] * xi[k]));
            const double t_ji = om[k] * (dd * kap * theta[j] / mw[j] * xi[k] +
                                         law.alpha * mu / mw[j] * (ed_j - q[j] * xi[k]));
            const double a = (t_ij + t_ji) * beta[k] * vol[j] / l;
            fi[0] += a * d0;
            fi[1] += a * d1;
            fi[2] += a * d2;
            wdev += om[k] * ed_i * ed_i * beta[k] * vol[j];
        }
        f[3 * i] = fi[0];
        f[3 * i + 1] = fi[1];
        f[3 * i + 2] = fi[2];
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
    }
    return {energy, broken, released, repulsion};
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
    double energy = 0, released = 0;
    std::int64_t broken = 0;
#pragma omp parallel for schedule(static) reduction(+ : energy, broken, released) if (n > parallel_min)
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
    }
    return {energy, broken, released, 0.0};
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
