// SPDX-License-Identifier: MIT
// RNP: regularised nonlinear peridynamic bond potential (Lipton 2014/2016; PeriDEM's RNPBond,
// spec 1.4). With S = (eta . xi) / |xi|^2 (linearised strain), J = J(|xi| / delta) and
// invF = delta^(d+1) omega_d (omega_2 = pi, omega_3 = 4 pi / 3):
//   bond energy  J C (1 - exp(-beta |xi| S^2)) / invF     (total: sum_i V_i sum_j . V_j)
//   force        f_i += 4 J S C beta exp(-beta |xi| S^2) / invF  V_j  xi / |xi|   (reference dir.)
// Critical strain S_c(r) = rbar / sqrt(r), rbar = sqrt(0.5 / beta) (the inflection point); a bond
// breaks when S > S_c (tension only by default). From classical constants (nu = 1/4 forced,
// M = int_0^1 J(q) q^d dq): 2D C = pi Gc / (4 M), beta = 4 lambda / (C M); 3D C = 2 Gc / (3 M),
// beta = 5 lambda / (C M).
#pragma once

#include "model/model.hpp"

namespace pd::model {

struct RnpConstants {
    double C = 0;          ///< J m-1 (2D per unit thickness)
    double beta = 0;       ///< m-1
    double rbar = 0;       ///< sqrt(0.5 / beta), m^(1/2)
    double inv_factor = 0; ///< delta^(d+1) omega_d
};

RnpConstants rnp_constants(const Material& m, double delta, int dimension);

/// M_d = integral over [0, 1] of J(q) q^d dq.
double influence_moment(Influence f, int d);

} // namespace pd::model
