// SPDX-License-Identifier: MIT
#include "solver/bond_forces.hpp"

#include <cmath>

namespace pd::solver {

namespace {

template <bool Breakable>
BondResult kernel(State& s, BondData& b, const BodyLaw& law) {
    const auto n = static_cast<std::int64_t>(s.n);
    const double* x = s.x.data();
    const double* vol = s.vol.data();
    double* f = s.f.data();
    const offset_t* off = b.offsets.data();
    const index_t* nb = b.neighbor.data();
    const double* xi = b.xi.data();
    const double* beta = b.beta.data();
    std::uint8_t* alive = b.alive.data();
    double energy = 0;
    std::int64_t broken = 0;
#pragma omp parallel for schedule(static) reduction(+ : energy, broken) if (n > parallel_min)
    for (std::int64_t i = 0; i < n; ++i) {
        double fi[3] = {0, 0, 0};
        if (!s.moving[static_cast<std::size_t>(i)]) {
            f[3 * i] = f[3 * i + 1] = f[3 * i + 2] = 0;
            continue;
        }
        const auto body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(i)]);
        const double c = law.c[body];
        const double s0 = law.s0[body];
        const double xi0 = x[3 * i], xi1 = x[3 * i + 1], xi2 = x[3 * i + 2];
        double e_i = 0;
        for (offset_t k = off[i]; k < off[i + 1]; ++k) {
            if (Breakable && !alive[k])
                continue;
            const index_t j = nb[k];
            const double d0 = x[3 * j] - xi0, d1 = x[3 * j + 1] - xi1, d2 = x[3 * j + 2] - xi2;
            const double l = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
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

} // namespace

BondResult pmb_bond_forces(State& s, BondData& b, const BodyLaw& law) {
    return law.any_breakable ? kernel<true>(s, b, law) : kernel<false>(s, b, law);
}

void damage_phi(const State& s, const BondData& b, std::vector<double>& phi) {
    phi.assign(s.n, 0.0);
    const auto n = static_cast<std::int64_t>(s.n);
#pragma omp parallel for schedule(static) if (n > parallel_min)
    for (std::int64_t i = 0; i < n; ++i) {
        double all = 0, br = 0;
        for (offset_t k = b.offsets[i]; k < b.offsets[i + 1]; ++k) {
            const double w = b.beta[k] * s.vol[b.neighbor[k]];
            all += w;
            if (!b.alive[k])
                br += w;
        }
        phi[i] = all > 0 ? br / all : 0.0;
    }
}

} // namespace pd::solver
