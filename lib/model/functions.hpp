// SPDX-License-Identifier: MIT
// Time functions T(t) of conditions and wall motions (spec 5.6-5.7): value and rate dT/dt;
// space functions S(X) of conditions; the displacement a condition prescribes.
// p = {p0 (space), p1, p2, p3}: the time functions use p1..p3.
#pragma once

#include "model/model.hpp"
#include "model/wall_mesh.hpp"

#include <algorithm>
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

/// T of a wall's motion at time t: 0 (at rest at its t = 0 pose) before its start_time, then
/// its time function of t - start_time.
inline double wall_time(const Wall& w, double t, double* rate) {
    if (t < w.start_time) {
        *rate = 0;
        return 0;
    }
    return time_function(w.motion, w.motion_params, t - w.start_time, rate);
}

/// Whether a wall takes part in contact at time t.
inline bool wall_present(const Wall& w, double t) {
    return t >= w.start_time;
}

/// Signed distance of x from a wall at its t = 0 pose (positive on the free side): where a wall
/// with a start_time enters.
inline double wall_distance(const Wall& w, const double* x) {
    if (w.shape == WallShape::plane) {
        double d = 0;
        for (std::size_t q = 0; q < 3; ++q)
            d += (x[q] - w.point[q]) * w.normal[q];
        return d;
    }
    if (w.shape == WallShape::mesh) {
        double d = HUGE_VAL, n[3];
        w.mesh->closest(x, HUGE_VAL, d, n);
        return d;
    }
    const double r = std::hypot(x[0] - w.point[0], x[1] - w.point[1], x[2] - w.point[2]);
    return w.shape == WallShape::circle_inside ? w.radius - r : r - w.radius;
}

/// above_grains: how far along its normal the surface of plane wall `w` may come towards node x
/// of contact group `group`: x.n less the reach of their law (R_c of the node law, 0 for the
/// surface law) and the wall's gap; +infinity when the wall does not touch that group.
inline double entry_level(const Model& m, const Wall& w, std::int32_t group, const double* x) {
    const auto* p = m.contact_between(group, w.group);
    if (p == nullptr || !(p->stiffness > 0))
        return HUGE_VAL;
    return x[0] * w.normal[0] + x[1] * w.normal[1] + x[2] * w.normal[2] - p->offset() - w.gap;
}

/// above_grains: moves plane wall `w` rigidly (point and rotation centre) along its normal so
/// that its surface lies at `level` along it (the smallest entry_level of the grains' nodes).
inline void place_wall(Wall& w, double level) {
    double s = level;
    for (std::size_t d = 0; d < 3; ++d)
        s -= w.point[d] * w.normal[d];
    for (std::size_t d = 0; d < 3; ++d) {
        w.point[d] += s * w.normal[d];
        w.centre[d] += s * w.normal[d];
    }
}

/// S(X) of a condition's space function at reference position X; `box` = x and y range of the
/// condition's nodes (the hat functions).
inline double space_value(SpaceFn f, double p0, const double* X, const std::array<double, 4>& box) {
    auto hat = [&](double x, double lo, double hi) {
        const double L = hi - lo;
        return L > 0 ? p0 * std::max(0.0, 1 - std::abs(2 * (x - 0.5 * (lo + hi)) / L)) : p0;
    };
    switch (f) {
    case SpaceFn::constant:
        return 1;
    case SpaceFn::linear_x:
        return p0 * X[0];
    case SpaceFn::linear_y:
        return p0 * X[1];
    case SpaceFn::sine_x:
        return std::sin(M_PI * p0 * X[0]);
    case SpaceFn::hat_x:
        return hat(X[0], box[0], box[1]);
    case SpaceFn::hat_y:
        return hat(X[1], box[2], box[3]);
    }
    return 0;
}

/// Adds to u (3) the displacement that condition c (not a force) prescribes at time t on a node
/// of reference position X, for the components it prescribes (spec 5.6; a rotation in the xy
/// plane about c.centre).
inline void prescribed_displacement(const NodeCondition& c, const double* X,
                                    const std::array<double, 4>& box, double t, double* u) {
    if (c.time_fn == TimeFn::rotation) {
        const double th = c.amplitude * t, cs = std::cos(th), sn = std::sin(th);
        const double rx = X[0] - c.centre[0], ry = X[1] - c.centre[1];
        const double d[2] = {cs * rx - sn * ry - rx, sn * rx + cs * ry - ry};
        for (std::size_t k = 0; k < 2; ++k)
            if (c.dofs & (1u << k))
                u[k] = d[k];
        return;
    }
    double rate = 0;
    const double T = time_function(c.time_fn, c.params, t, &rate);
    const double S = space_value(c.space_fn, c.params[0], X, box);
    for (std::size_t k = 0; k < 3; ++k)
        if (c.dofs & (1u << k))
            u[k] = c.amplitude * T * S;
}

} // namespace pd::model
