// SPDX-License-Identifier: MIT
#include "model/rnp.hpp"

#include "core/errors.hpp"
#include "model/lps.hpp"

#include <cmath>
#include <numbers>

namespace pd::model {

double influence_moment(Influence f, int d) {
    // Composite Simpson on [0, 1]: exact for constant and linear J, 1e-12 for the Gaussian.
    const int n = 2000;
    double s = 0;
    for (int k = 0; k <= n; ++k) {
        const double q = static_cast<double>(k) / n;
        const double w = (k == 0 || k == n) ? 1 : (k % 2 ? 4 : 2);
        s += w * influence(f, q) * std::pow(q, d);
    }
    return s / (3.0 * n);
}

RnpConstants rnp_constants(const Material& m, double delta, int dimension) {
    using std::numbers::pi;
    if (!m.breakable())
        throw InputError(fmt::format("material '{}': the RNP law needs fracture_energy > 0 (it "
                                     "sets the potential's scale)",
                                     m.name));
    const double nu = 0.25, E = m.youngs_modulus;
    const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
    const double M = influence_moment(m.influence, dimension);
    RnpConstants k;
    if (dimension == 2) {
        k.C = pi * m.fracture_energy / (4 * M);
        k.beta = 4 * lambda / (k.C * M);
        k.inv_factor = std::pow(delta, 3) * pi;
    } else {
        k.C = 2 * m.fracture_energy / (3 * M);
        k.beta = 5 * lambda / (k.C * M);
        k.inv_factor = std::pow(delta, 4) * 4 * pi / 3;
    }
    k.rbar = std::sqrt(0.5 / k.beta);
    return k;
}

} // namespace pd::model
