// SPDX-License-Identifier: MIT
// The surface law's automatic stiffness follows the speeds the scene can produce (issue 26
// items 3 and 8).
//
// The rule of contact.cpp, c = kappa / h^2, makes a node at depth d behind a boundary push with
// the pressure p = c d h (force density c d on a node of volume ~ h^dim, one node per h^(dim - 1)
// of boundary): kappa d / h, a fixed share of kappa whatever h. A node deeper than h / 2 is let
// go (surface_contact.cpp) and the guard stops the run. What an impact at speed V asks of the
// contact is its peak pressure: Hertz's, for grains (curved) against anything,
//
//   p0 = (2 / pi) E* sqrt(delta_max / R) = 0.84 E* (V / c*)^(2/5),   c* = sqrt(E* / rho),
//
// (3D sphere on a rigid flat, delta_max = R (5 pi rho V^2 / 4 E*)^(2/5): R cancels, so p0 needs
// no grain size), E* = E / (1 - nu^2); and for flat faces the acoustic rho c* V, smaller below
// Mach ~0.7. Against a rigid wall the depth the penalty reaches is d = p0 / (c h) (measured: a
// 2D PMB disc at 5 m/s on a wall, h = 0.1 / 0.05 mm, reaches 0.44 / 0.49 h/2 against 0.46
// predicted); between two grains both pass and it is about half. So p0 is held at h / 4, half
// the guard's bound, when c h^2 / 4 >= p0. Faster, the nodes arriving at the boundary bounce on
// the penalty before the grain behind them slows: the depth then falls only as 1 / sqrt(c),
// about 3.3 M h / sqrt(c h^2 / kappa), M = V / sqrt(kappa / rho) (a 2D disc on a wall at 20 and
// 50 m/s, M = 0.12 and 0.30, h = 0.05 mm, c = 1, 2.3, 4 and 8 kappa / h^2: 0.89, 0.56, 0.35,
// 0.26 and -, 1.06, 0.82, 0.64 h/2), so holding it at h / 4 asks c h^2 >= 178 rho V^2. Hence
//
//   c = max(kappa, speed_margin p0, bounce_margin rho V^2) / h^2,
//   speed_margin = 4, bounce_margin = 200,
//
// p0 of the softer material of the pair (E* the smallest E / (1 - nu^2) of the two groups'
// bodies, rho the largest density), kappa the pair's (contact.cpp), V the largest approach speed
// of the scene (below). The Hertz term governs up to M ~ 0.1, the bounce term above it. Scenes
// with M below ~2 % (a 1 mm disc of E = 32 MPa at 5 m/s: 3 %; a pack settling under gravity:
// < 1 %) keep c = kappa / h^2 and their step. The step falls as 1 / sqrt(c) where c rises (the
// contact bound of stability.cpp takes the raised c).
//
// V is the largest approach speed the scene can produce: the grains' initial speeds; the rigid
// walls' surface speeds (translation plus angular velocity times the farthest node from the
// rotation centre, times the largest rate of the wall's time function up to the final time);
// the prescribed displacements' speeds (a rotation's angular velocity times the farthest
// condition node from its centre, else the amplitude times the time function's largest rate
// times the space function at the condition's nodes); all with a free fall under gravity over the
// scene's height H along g added, sqrt(V^2 + 2 g H). Force conditions are left out: their speed
// is the dynamics', not prescribed. V counts up to the pair's sqrt(kappa / rho) (c at most 200
// kappa / h^2).
#include "model/functions.hpp"
#include "pipeline/scene/build.hpp"

#include <algorithm>
#include <cmath>

namespace pd::pipeline::scene {

namespace {

/// c h^2 / p0: the impact's peak pressure is held at depth h / speed_margin (see above).
constexpr double speed_margin = 4.0;
/// c h^2 / (rho V^2): the nodes' bounce on the penalty stays within h / 4 (measured, see above).
constexpr double bounce_margin = 200.0;

/// The largest |dT/dt| of a time function over [0, t_end] (its rate at the ends and, for the
/// sine, its amplitude).
double max_rate(model::TimeFn f, const std::array<double, 4>& p, double t_end) {
    switch (f) {
    case model::TimeFn::constant:
        return 0;
    case model::TimeFn::quadratic:
        return std::max(1.0, std::abs(1 + 2 * p[1] * t_end));
    case model::TimeFn::sine:
        return std::abs(M_PI * p[1]);
    case model::TimeFn::linear_slow_fast:
        return std::max(std::abs(p[2]), std::abs(p[3]));
    default: // linear, rotation, linear_step
        return 1;
    }
}

double norm3(const double* v) {
    return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/// The farthest node of the scene from point c (m).
double farthest_node(const model::Model& m, const double* c) {
    double r = 0;
    for (std::size_t i = 0; i < m.nodes.num(); ++i) {
        const double d[3] = {m.nodes.x0[3 * i] - c[0], m.nodes.x0[3 * i + 1] - c[1],
                             m.nodes.x0[3 * i + 2] - c[2]};
        r = std::max(r, norm3(d));
    }
    return r;
}

/// The largest speed a displacement condition prescribes at its nodes (m s-1).
double condition_speed(const model::NodeCondition& c, const model::Model& m, double t_end) {
    if (c.is_force || c.nodes.empty())
        return 0;
    std::array<double, 4> box{HUGE_VAL, -HUGE_VAL, HUGE_VAL, -HUGE_VAL};
    for (auto i : c.nodes) {
        const double* X = &m.nodes.x0[3 * static_cast<std::size_t>(i)];
        box = {std::min(box[0], X[0]), std::max(box[1], X[0]), std::min(box[2], X[1]),
               std::max(box[3], X[1])};
    }
    const double rate = max_rate(c.time_fn, c.params, t_end);
    double v = 0;
    for (auto i : c.nodes) {
        const double* X = &m.nodes.x0[3 * static_cast<std::size_t>(i)];
        if (c.time_fn == model::TimeFn::rotation)
            v = std::max(v, std::abs(c.amplitude) *
                                std::hypot(X[0] - c.centre[0], X[1] - c.centre[1]));
        else
            v = std::max(v, std::abs(c.amplitude) * rate *
                                std::abs(model::space_value(c.space_fn, c.params[0], X, box)));
    }
    return v;
}

/// The largest approach speed the scene can produce (m s-1), as the file's header says.
double scene_speed(const model::Model& m) {
    const auto& B = m.bodies;
    const double t_end = m.solver.final_time;
    double v = 0;
    for (std::size_t b = 0; b < B.num(); ++b)
        if (!B.fixed[b])
            v = std::max(v, norm3(&B.initial_velocity[3 * b]));
    for (const auto& w : m.walls) {
        const double rate = max_rate(w.motion, w.motion_params, t_end);
        v = std::max(v, rate * (norm3(w.velocity.data()) + norm3(w.angular_velocity.data()) *
                                                               farthest_node(m, w.centre.data())));
    }
    for (const auto& c : m.loading.conditions)
        v = std::max(v, condition_speed(c, m, t_end));
    const double g = norm3(m.loading.gravity.data());
    if (g > 0 && m.nodes.num() > 0) {
        double lo = HUGE_VAL, hi = -HUGE_VAL;
        for (std::size_t i = 0; i < m.nodes.num(); ++i) {
            double s = 0;
            for (std::size_t d = 0; d < 3; ++d)
                s += m.nodes.x0[3 * i + d] * m.loading.gravity[d] / g;
            lo = std::min(lo, s);
            hi = std::max(hi, s);
        }
        v = std::sqrt(v * v + 2 * g * (hi - lo));
    }
    return v;
}

/// The materials of a contact pair that the rule reads: kappa as contact.cpp's (the harmonic
/// mean of the groups' largest bulk moduli; a group of rigid walls takes the other's), the
/// smallest E* = E / (1 - nu^2) of the two groups' bodies and their largest density.
struct PairMaterials {
    double kappa = 0, e_star = HUGE_VAL, rho = 0;
};

PairMaterials pair_materials(const model::Model& m, const model::ContactPair& p) {
    const auto& B = m.bodies;
    PairMaterials r;
    double ka = 0, kb = 0;
    for (std::size_t b = 0; b < B.num(); ++b) {
        const auto g = B.group[b];
        if (g != p.group_a && g != p.group_b)
            continue;
        const auto& mat = m.materials[static_cast<std::size_t>(B.material[b])];
        if (g == p.group_a)
            ka = std::max(ka, mat.bulk_modulus());
        if (g == p.group_b)
            kb = std::max(kb, mat.bulk_modulus());
        const double nu = mat.poisson_ratio;
        r.e_star = std::min(r.e_star, mat.youngs_modulus / (1 - nu * nu));
        r.rho = std::max(r.rho, mat.density);
    }
    if (ka == 0)
        ka = kb;
    if (kb == 0)
        kb = ka;
    r.kappa = ka > 0 ? 2 * ka * kb / (ka + kb) : 0;
    return r;
}

/// The peak pressure of an impact at speed v (Pa): Hertz's, or the acoustic one if larger.
double impact_pressure(const PairMaterials& pm, double v) {
    const double cs = std::sqrt(pm.e_star / pm.rho);
    return std::max(0.84 * pm.e_star * std::pow(v / cs, 0.4), pm.rho * cs * v);
}

/// c h^2 (Pa) that holds an impact at speed v within h / 4 (see above).
double needed_modulus(const PairMaterials& pm, double v) {
    return std::max(speed_margin * impact_pressure(pm, v), bounce_margin * pm.rho * v * v);
}

} // namespace

void raise_for_speed(SceneBuild& s) {
    auto& m = s.m;
    double v = -1, f_max = 0;
    for (std::size_t q = 0; q < m.contact.size(); ++q) {
        auto& p = m.contact[q];
        if (q >= s.contact_auto.size() || !s.contact_auto[q] ||
            p.law != model::ContactLaw::surface || !(p.stiffness > 0))
            continue;
        if (v < 0)
            v = scene_speed(m);
        const auto pm = pair_materials(m, p);
        if (!(v > 0) || !(pm.kappa > 0) || !(pm.rho > 0) || !std::isfinite(pm.e_star))
            continue;
        // Capped at Mach 1: faster, a grain cannot slow its nodes before they arrive and no
        // stiffness holds the impact (the grains shatter); the run's "too fast for contact"
        // check stays the judge (a disc at 1e8 m/s raised c 1e13 x and ran at dt 4e-14 s).
        const double f = needed_modulus(pm, std::min(v, std::sqrt(pm.kappa / pm.rho))) / pm.kappa;
        f_max = std::max(f_max, f);
        if (f > 1) {
            p.stiffness *= f;
            s.log.info("contact groups {}-{}: surface law stiffness x {:.3g} for impacts up to "
                       "{:.3g} m/s (Mach {:.3g} of sqrt(kappa / rho)): c {:.4g} N m-5",
                       p.group_a, p.group_b, f, v, v / std::sqrt(pm.kappa / pm.rho), p.stiffness);
        }
    }
    if (f_max > 0 && f_max <= 1)
        s.log.info("surface law: impacts up to {:.3g} m/s ask at most {:.3g} x kappa / h^2: the "
                   "stiffness stays kappa / h^2",
                   v, f_max);
}

} // namespace pd::pipeline::scene
