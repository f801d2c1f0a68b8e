// SPDX-License-Identifier: MIT
#include "core/errors.hpp"
#include "pipeline/scene/build.hpp"

namespace pd::pipeline::scene {

void parse_solver(SceneBuild& s) {
    const json& root = s.root;
    model::Model& m = s.m;
    // Solver settings.
    if (!root.contains("solver"))
        throw ConfigError("solver", "missing: give at least final_time");
    const json& sv = root["solver"];
    check_keys(sv, "solver",
               {"final_time", "dt", "dt_safety", "output_interval", "observe_every", "integrator",
                "contact_skin", "checkpoint_interval", "surface_correction",
                "quadrature_calibration", "fields", "dt_above_estimate", "penetration"});
    auto& S = m.solver;
    S.final_time = positive(sv, "solver", "final_time", 0, true);
    if (!(S.final_time <= 1e6)) // 11 days of explicit dynamics: a typo or an overflow
        throw ConfigError("solver.final_time", fmt::format("{:g} s: above 1e6 s", S.final_time));
    if (sv.contains("dt") && sv["dt"].is_string())
        text(sv, "solver", "dt", "auto", {"auto"});
    else
        S.dt = sv.contains("dt") ? positive(sv, "solver", "dt", 0) : 0.0;
    S.dt_above_estimate_warns =
        text(sv, "solver", "dt_above_estimate", "refuse", {"refuse", "warn"}) == "warn";
    S.penetration_warns = text(sv, "solver", "penetration", "stop", {"stop", "warn"}) == "warn";
    S.dt_safety = positive(sv, "solver", "dt_safety", 0.85);
    if (S.dt_safety > 1)
        throw ConfigError("solver.dt_safety", "must be in (0, 1]");
    S.output_interval = number(sv, "solver", "output_interval", 0);
    if (S.output_interval < 0)
        throw ConfigError("solver.output_interval", "must be >= 0");
    // Observables every 10 steps unless asked (1 = every step): a row costs a pass over the
    // nodes, the bond energies, reductions and an HDF5 append, about as much as the bond loop
    // of a small grain. Integrals over time (external work, dissipation) are summed at every
    // step and the wall and body reactions are averaged over the interval, so a row loses
    // nothing but the instantaneous values between rows (issue 15).
    S.observe_every = static_cast<std::int64_t>(positive(sv, "solver", "observe_every", 10));
    S.checkpoint_interval = number(sv, "solver", "checkpoint_interval", 0);
    S.surface_correction = boolean(sv, "solver", "surface_correction", true);
    S.quadrature_calibration = boolean(sv, "solver", "quadrature_calibration", true);
    if (sv.contains("fields")) {
        if (!sv["fields"].is_array())
            throw ConfigError("solver.fields", "expected a list of frame fields");
        S.fields.clear();
        for (const auto& x : sv["fields"]) {
            const std::string n = x.is_string() ? x.get<std::string>() : "";
            if (n != "velocity" && n != "displacement" && n != "force" && n != "damage" &&
                n != "damage_z" && n != "fragment" && n != "broken_bonds")
                throw ConfigError(
                    "solver.fields",
                    "'" + x.dump() +
                        "' is not one of velocity, "
                        "displacement, force, damage, damage_z, fragment, broken_bonds "
                        "(position is always written)");
            S.fields.push_back(n);
        }
    }
    if (S.checkpoint_interval < 0)
        throw ConfigError("solver.checkpoint_interval", "must be >= 0 (0 = at the end only)");
    S.integrator = text(sv, "solver", "integrator", "velocity_verlet",
                        {"velocity_verlet", "symplectic_euler"}) == "velocity_verlet"
                       ? model::Integrator::velocity_verlet
                       : model::Integrator::symplectic_euler;
    S.contact_skin = number(sv, "solver", "contact_skin", 0);
    if (S.contact_skin < 0)
        throw ConfigError("solver.contact_skin", "must be >= 0 (0 = automatic)");
}

} // namespace pd::pipeline::scene
