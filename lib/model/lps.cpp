// SPDX-License-Identifier: MIT
#include "model/lps.hpp"

#include "core/errors.hpp"

#include <limits>
#include <numbers>

namespace pd::model {

LpsConstants lps_constants(const Material& m, double delta, int dimension, Planar planar) {
    using std::numbers::pi;
    const double E = m.youngs_modulus, nu = m.poisson_ratio;
    PD_CHECK(delta > 0 && E > 0 && nu > -1 && nu < 0.5, "LPS constants need E > 0, -1 < nu < 1/2");
    const double mu = E / (2 * (1 + nu));
    const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
    LpsConstants k;
    k.mu = mu;
    double denom = 0;
    if (dimension == 3) {
        k.kappa = E / (3 * (1 - 2 * nu));
        k.alpha = 15;
        denom = 3 * mu + std::pow(0.75, 4) * (k.kappa - 5 * mu / 3);
    } else {
        const double lam =
            planar == Planar::plane_stress ? 2 * lambda * mu / (lambda + 2 * mu) : lambda;
        k.kappa = lam + mu;
        k.alpha = 8;
        denom = 6 * mu / pi + 16 / (9 * pi * pi) * (k.kappa - 2 * mu);
    }
    k.s0 = m.breakable() ? std::sqrt(m.fracture_energy / (denom * delta))
                         : std::numeric_limits<double>::infinity();
    return k;
}

} // namespace pd::model
