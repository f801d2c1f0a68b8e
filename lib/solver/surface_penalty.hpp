// SPDX-License-Identifier: MIT
// The surface contact law's penalty (model::ContactLaw::surface) as a function of a node's
// depth d >= 0 behind a boundary (another grain's facet or a rigid wall), per unit volume of the
// node: stiffness c (N m-5), so the force density is U'(d) along the outward normal.
//
//   U(d) = c d^3 / (6 d0)                       0 <= d <= d0   (the onset: stiffness c d / d0)
//   U(d) = c (d^2 / 2 - d0 d / 2 + d0^2 / 6)    d0 <= d        (linear: force c (d - d0 / 2))
//
// Why the onset: with a stiffness that jumps from 0 to c as a node crosses the boundary, velocity
// Verlet makes an energy error at every crossing, and a grain resting on a wall or on another
// grain crosses it at every vibration (its static depth under gravity is ~1e-10 m against
// ~1e-9 - 1e-7 m of undamped vibration). Those errors do not average out: a 2 mm block dropped
// 0.25 mm on a floor at 0.85 x the stable step (restitution 0.3) gained 3.4e-5 J, three times
// the drop energy, in 35 ms, and a block set down at rest with no damping blew up after 2 ms;
// the same block at 0.4 x the step, or with a force whose stiffness rises continuously, is
// stable. Ramping the stiffness up over d0 = onset_share x h makes the force C1: the block comes
// to rest (its vibration energy falls from 4e-7 to 4e-11 J in 35 ms) and the balance holds to
// 1e-7 J. The ramp shifts the linear branch by d0 / 2 = 0.005 h, a compliance far below the
// law's own (its pressure c h / 2 at d = h / 2), and vanishes with h.
#pragma once

namespace pd::solver {

/// d0 / h of the surface law's onset (h: the pair's or the wall's body mesh size).
inline constexpr double onset_share = 0.01;

/// The penalty at depth d >= 0: U(d) (J m-3) and U'(d) (N m-3), for stiffness c and onset d0.
struct Penalty {
    double energy;
    double force;
};

inline Penalty surface_penalty(double c, double d, double d0) {
    if (d <= 0)
        return {0.0, 0.0};
    if (d < d0)
        return {c * d * d * d / (6 * d0), c * d * d / (2 * d0)};
    return {c * (0.5 * d * d - 0.5 * d0 * d + d0 * d0 / 6), c * (d - 0.5 * d0)};
}

} // namespace pd::solver
