// SPDX-License-Identifier: MIT
// Time functions T(t) of conditions and wall motions (spec 5.6-5.7): value and rate dT/dt.
// p = {p0 (space), p1, p2, p3}: the time functions use p1..p3.
#pragma once

#include "model/model.hpp"

#include <array>
#include <cmath>

namespace pd::model {

/// T(t); *rate receives dT/dt.
inline double time_function(TimeFn f, const std::array<double, 4>& p, double t, double* rate) {
    const double p1 = p[1], p2 = p[2], p3 = p[3];
    switch (f) {
    case TimeFn::constant:
        *rate = 0;
        return 1;
    case TimeFn::linear:
        *rate = 1;
        return t;
    case TimeFn::quadratic:
        *rate = 1 + 2 * p1 * t;
        return t + p1 * t * t;
    case TimeFn::sine:
        *rate = M_PI * p1 * std::cos(M_PI * p1 * t);
        return std::sin(M_PI * p1 * t);
    case TimeFn::rotation:
        *rate = 1; // the angle grows as amplitude * t (the solver handles the rotation itself)
        return t;
    case TimeFn::linear_step: {
        // Staircase (spec 5.7): ramps of duration p1 separated by plateaus of duration p2.
        const double P = p1 + p2;
        const double k = std::floor(t / P);
        if (t < k * P + p1) {
            *rate = 1;
            return t - k * p2;
        }
        *rate = 0;
        return (k + 1) * p1;
    }
    case TimeFn::linear_slow_fast:
        *rate = t <= p1 ? p2 : p3;
        return *rate * t;
    }
    return 0;
}

} // namespace pd::model
