// SPDX-License-Identifier: MIT
#include "model/pmb.hpp"

#include "core/errors.hpp"

#include <limits>
#include <numbers>

namespace pd::model {

double pmb_poisson_ratio(int dimension, Planar planar) {
    return dimension == 2 && planar == Planar::plane_stress ? 1.0 / 3.0 : 0.25;
}

PmbConstants pmb_constants(const Material& m, double delta, int dimension, Planar planar) {
    using std::numbers::pi;
    PD_CHECK(delta > 0, "horizon must be positive");
    const double E = m.youngs_modulus, G = m.fracture_energy;
    PmbConstants k;
    double s0_sq = 0;
    if (dimension == 3) {
        const double K = E / (3.0 * (1.0 - 2.0 * 0.25));
        k.c = 18.0 * K / (pi * std::pow(delta, 4));
        s0_sq = 5.0 * G / (9.0 * K * delta);
    } else if (planar == Planar::plane_stress) {
        k.c = 9.0 * E / (pi * std::pow(delta, 3));
        s0_sq = 4.0 * pi * G / (9.0 * E * delta);
    } else {
        k.c = 48.0 * E / (5.0 * pi * std::pow(delta, 3));
        s0_sq = 5.0 * pi * G / (12.0 * E * delta);
    }
    k.s0 = m.breakable() ? std::sqrt(s0_sq) : std::numeric_limits<double>::infinity();
    return k;
}

} // namespace pd::model
