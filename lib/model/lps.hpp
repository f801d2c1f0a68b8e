// SPDX-License-Identifier: MIT
// LPS (linear peridynamic solid, Silling et al. 2007; PeriDEM's PDState, spec 1.3) in d = 2 or 3
// dimensions with consistent constants. With w = J(r/delta), m_i = sum_j w xi^2 beta V_j and
// e = |y_j - y_i| - xi:
//   theta_i = (d / m_i) sum_j w xi e beta V_j
//   t_ij = (d kappa theta_i / m_i) w xi + (a mu / m_i) w (e - theta_i xi / d),  a = 15 (3D), 8 (2D)
//   f_i = sum_j (t_ij + t_ji) beta V_j (y_j - y_i)/|y_j - y_i|
// kappa is the bulk modulus of the d-dimensional problem: K in 3D, lambda + mu in 2D plane
// strain, lambda* + mu with lambda* = 2 lambda mu / (lambda + 2 mu) in plane stress. These match
// the classical strain energy for every homogeneous deformation (3D: the spec's form exactly).
// Critical stretch (Madenci & Oterkus 2014): 3D s0 = sqrt(Gc / ((3 mu + (3/4)^4 (kappa -
// 5 mu / 3)) delta)) (the spec's formula), 2D s0 = sqrt(Gc / ((6 mu / pi + 16 / (9 pi^2) (kappa -
// 2 mu)) delta)).
#pragma once

#include "model/model.hpp"

#include <cmath>

namespace pd::model {

struct LpsConstants {
    double kappa = 0; ///< Pa, bulk modulus of the d-dimensional problem
    double mu = 0;    ///< Pa, shear modulus
    double s0 = 0;    ///< critical stretch (inf = unbreakable)
    double alpha = 0; ///< 15 (3D) or 8 (2D)
};

LpsConstants lps_constants(const Material& m, double delta, int dimension, Planar planar);

/// J(q), q = r / delta in [0, 1); bonds of the partial-volume shell (q up to 1 + h / (2 delta))
/// get J(min(q, 1)): the linear J would be negative there, and negative weights make the LPS
/// energy indefinite (a damaged family left with its outer bonds had W_i < 0: two brittle LPS
/// discs at 2 x 5 m/s gained 80 % kinetic energy while the elastic energy fell to -0.08 J).
inline double influence(Influence f, double q) {
    switch (f) {
    case Influence::constant:
        return 1.0;
    case Influence::linear:
        return q < 1.0 ? 1.0 - q : 0.0;
    case Influence::gaussian:
        return std::exp(-q * q / 0.2);
    }
    return 1.0;
}

} // namespace pd::model
