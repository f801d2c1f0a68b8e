// SPDX-License-Identifier: MIT
// Displacement and force conditions (spec 5.6) as the integrator needs them: the condition
// boxes, the prescribed motion, the external power; and the pre-cracks.
#include "model/functions.hpp"
#include "model/slots.hpp"
#include "solver/detail.hpp"

#include <cmath>

namespace pd::solver::detail {

using model::space_value; // `box`: xmin, xmax, ymin, ymax of the condition's nodes

void condition_boxes(Forces& f) {
    for (const auto& c : f.m.loading.conditions) {
        std::array<double, 4> box{1e300, -1e300, 1e300, -1e300};
        for (auto i : c.nodes) {
            const auto ii = static_cast<std::size_t>(i);
            box[0] = std::min(box[0], f.s.x0[3 * ii]);
            box[1] = std::max(box[1], f.s.x0[3 * ii]);
            box[2] = std::min(box[2], f.s.x0[3 * ii + 1]);
            box[3] = std::max(box[3], f.s.x0[3 * ii + 1]);
        }
        f.cond_box.push_back(box);
        if (!c.is_force) {
            for (auto i : c.nodes)
                f.s.fixed_dof[static_cast<std::size_t>(i)] |= c.dofs;
            f.has_prescribed = true;
        } else {
            f.fbc.assign(3 * f.s.n, 0.0);
        }
    }
}

void apply_displacements(Forces& f) {
    const double t = f.s.time;
    for (const auto& c : f.m.loading.conditions) {
        if (c.is_force)
            continue;
        if (c.time_fn == model::TimeFn::rotation) {
            // u = R(w t)(X - c) - (X - c), v = w R'(w t)(X - c), in the xy plane.
            const double th = c.amplitude * t, cs = std::cos(th), sn = std::sin(th);
            for (auto i : c.nodes) {
                const auto ii = static_cast<std::size_t>(i);
                const double rx = f.s.x0[3 * ii] - c.centre[0],
                             ry = f.s.x0[3 * ii + 1] - c.centre[1];
                const double u[2] = {cs * rx - sn * ry - rx, sn * rx + cs * ry - ry};
                const double v[2] = {c.amplitude * (-sn * rx - cs * ry),
                                     c.amplitude * (cs * rx - sn * ry)};
                for (std::size_t d = 0; d < 2; ++d)
                    if (c.dofs & (1u << d)) {
                        f.s.u[3 * ii + d] = u[d];
                        f.s.v[3 * ii + d] = v[d];
                        f.s.x[3 * ii + d] = f.s.x0[3 * ii + d] + u[d];
                    }
            }
            continue;
        }
        double rate = 0;
        const double T = model::time_function(c.time_fn, c.params, t, &rate);
        const auto& box = f.cond_box[static_cast<std::size_t>(&c - f.m.loading.conditions.data())];
        for (auto i : c.nodes) {
            const auto ii = static_cast<std::size_t>(i);
            const double S = space_value(c.space_fn, c.params[0], &f.s.x0[3 * ii], box);
            for (std::size_t d = 0; d < 3; ++d)
                if (c.dofs & (1u << d)) {
                    f.s.u[3 * ii + d] = c.amplitude * T * S;
                    f.s.v[3 * ii + d] = c.amplitude * rate * S;
                    f.s.x[3 * ii + d] = f.s.x0[3 * ii + d] + f.s.u[3 * ii + d];
                }
        }
    }
}

void break_precracks(Forces& f) {
    for (const auto& c : f.m.cracks)
        for (std::size_t a = 0; a < f.s.rows.size(); ++a) {
            const auto i = static_cast<std::size_t>(f.s.rows[a]);
            for (auto k = f.b.offsets[a]; k < f.b.offsets[a + 1]; ++k) {
                const auto kk = static_cast<std::size_t>(k);
                const auto j = static_cast<std::size_t>(f.b.neighbor[kk]);
                if (f.b.alive[kk] && model::segments_cross(&f.s.x0[3 * i], &f.s.x0[3 * j],
                                                           c.p0.data(), c.p1.data())) {
                    f.b.alive[kk] = 0;
                    ++f.precracked;
                }
            }
        }
    f.broken_total += f.precracked;
}

double external_power(const Forces& f) {
    // Power of gravity and force conditions on every component, of the reactions that impose
    // prescribed displacements (minus the internal force there), and of moving walls.
    double pw = 0;
    if (node_power_needed(f))
        pw = sum_rows(
            static_cast<std::int64_t>(f.s.rows.size()), parallel_min_nodes,
            [&](std::int64_t a) { return node_power(f, static_cast<std::size_t>(f.s.rows[a])); });
    return external_power(f, pw);
}

double external_power(const Forces& f, double nodes) {
    double pw = nodes;
    for (std::size_t w = 0; w < f.m.walls.size(); ++w) {
        const auto p = wall_pose(f.m.walls[w], f.s.time);
        for (std::size_t d = 0; d < 3; ++d)
            pw -= f.wall_load.force[3 * w + d] * p.velocity[d] +
                  f.wall_load.moment[3 * w + d] * p.omega[d];
    }
    return pw;
}

} // namespace pd::solver::detail
