// SPDX-License-Identifier: MIT
// PMB (prototype microelastic brittle) bond law, bond-based peridynamics with a constant
// influence function J = 1. Constants calibrated so that the PD strain energy density of a
// homogeneous deformation equals the classical one (Silling & Askari 2005; 2D: Ha & Bobaru 2010):
//   3D:                  c = 18K/(pi delta^4),     s0 = sqrt(5 Gc / (9 K delta)),       nu = 1/4
//   2D plane stress:     c = 9E/(pi delta^3),      s0 = sqrt(4 pi Gc / (9 E delta)),    nu = 1/3
//   2D plane strain:     c = 48E/(5 pi delta^3),   s0 = sqrt(5 pi Gc / (12 E delta)),   nu = 1/4
// In 2D, volumes are areas times a unit thickness (1 m). Force density on node i of an intact
// bond: f_i += c s beta_ij V_j (y_j - y_i)/|y_j - y_i| with s = (|y_j - y_i| - |xi|)/|xi| and
// beta the linear partial-volume factor of spec 1.3.
#pragma once

#include "model/model.hpp"

#include <cmath>

namespace pd::model {

struct PmbConstants {
    double c = 0;  ///< micromodulus, N m-6
    double s0 = 0; ///< critical stretch (tension only); +inf if unbreakable
};

/// PMB constants of `m` for horizon `delta` in `dimension` D (planar assumption for 2D).
PmbConstants pmb_constants(const Material& m, double delta, int dimension, Planar planar);

/// Poisson ratio a bond-based law implies.
double pmb_poisson_ratio(int dimension, Planar planar);

/// Linear partial-volume factor of a neighbour at reference distance r (spec 1.3): 1 inside
/// delta - h/2, then (delta + h/2 - r)/h.
inline double partial_volume(double r, double delta, double h) {
    return r <= delta - 0.5 * h ? 1.0 : (delta + 0.5 * h - r) / h;
}

/// Scalar PMB bond force per unit volume squared: c * s (force density = this * beta * V_j).
inline double pmb_bond_force(double c, double stretch) {
    return c * stretch;
}

} // namespace pd::model
