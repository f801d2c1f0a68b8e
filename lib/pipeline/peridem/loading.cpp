// SPDX-License-Identifier: MIT
#include "core/errors.hpp"
#include "pipeline/peridem/import.hpp"

#include <optional>
#include <set>

namespace pd::pipeline::peridem {

namespace {

/// Displacement_BC and Force_BC sets -> scene conditions.
struct LoadingReader {
    Import& im;
    std::vector<std::uint8_t> driven; ///< particles moved by a non-zero condition
    const std::vector<std::string> comp = {"x", "y", "z"};

    /// The particles (Particle_List, Wall_List, Particle_Exclude_List) and region of set `s`.
    void selection(const YAML::Node& s, const std::string& w, json& c,
                   std::vector<std::size_t>* ids, bool& whole) const {
        const int dim = im.dim;
        const auto& parts = im.parts;
        const auto& wall_ids = im.wall_ids;
        std::set<std::size_t> take;
        bool listed = false;
        for (const char* key : {"Particle_List", "Wall_List"}) {
            if (!child(s, key))
                continue;
            listed = true;
            for (long id : ints(s, w, key)) {
                const bool wall = std::string(key) == "Wall_List";
                const std::size_t n = wall ? wall_ids.size() : parts.size();
                if (id < 0 || static_cast<std::size_t>(id) >= n)
                    throw ConfigError(dot(w, key), fmt::format("{} is not a {} id in [0, {})", id,
                                                               wall ? "wall" : "particle", n));
                take.insert(wall ? wall_ids[static_cast<std::size_t>(id)]
                                 : static_cast<std::size_t>(id));
            }
        }
        if (child(s, "Particle_Exclude_List")) {
            if (!listed)
                for (std::size_t k = 0; k < parts.size(); ++k)
                    take.insert(k);
            listed = true;
            for (long id : ints(s, w, "Particle_Exclude_List"))
                take.erase(static_cast<std::size_t>(id));
        }
        whole = !child(s, "Region");
        if (auto rg = child(s, "Region")) {
            const YAML::Node g = child(rg, "Geometry");
            const std::string gw = w + ".Region.Geometry";
            const auto type = str_or(g, gw, "Type", "");
            const auto p = nums(g, gw, "Parameters");
            std::optional<std::array<double, 4>> b;
            if (type == "rectangle")
                b = rectangle_box(p);
            if (!b || dim == 3)
                throw ConfigError(gw, fmt::format("'{}' with {} parameters: only 2D rectangle "
                                                  "regions can be imported",
                                                  type, p.size()));
            c["region"] = {{"min", {(*b)[0], (*b)[1]}}, {"max", {(*b)[2], (*b)[3]}}};
        } else if (!listed)
            throw ConfigError(w, "selects nothing: give Particle_List or Region");
        if (listed) {
            c["particles"] = json::array();
            for (auto id : take) {
                c["particles"].push_back(id);
                if (ids)
                    ids->push_back(id);
            }
        }
    }

    void sets(const char* block, bool force) {
        const YAML::Node& R = im.R;
        const YAML::Node b = R[block];
        if (!b)
            return;
        const int n = int_or(b, block, "Sets", 0, 0, 100000);
        for (int k = 1; k <= n; ++k)
            one_set(b, block, force, k);
    }

    /// {block}.Set_{k}.
    void one_set(const YAML::Node& b, const char* block, bool force, int k) {
        const int dim = im.dim;
        const auto& zones = im.zones;
        auto& parts = im.parts;
        json& conditions = im.conditions;
        const int n = int_or(b, block, "Sets", 0, 0, 100000);
        const std::string w = fmt::format("{}.Set_{}", block, k);
        const YAML::Node s = b[fmt::format("Set_{}", k)];
        if (!s)
            throw ConfigError(w, fmt::format("missing ({}.Sets = {})", block, n));
        json c{{"name", fmt::format("{}_set_{}", force ? "force" : "displacement", k)},
               {"kind", force ? "force_density" : "displacement"}};
        std::vector<std::size_t> ids;
        bool whole = false;
        selection(s, w, c, &ids, whole);
        c["components"] = json::array();
        std::set<long> dofs;
        for (long dof : ints(s, w, "Direction")) {
            if (dof < 1 || dof > dim)
                throw ConfigError(w + ".Direction",
                                  fmt::format("{} is not a dof in [1, {}]", dof, dim));
            dofs.insert(dof);
            c["components"].push_back(comp[static_cast<std::size_t>(dof - 1)]);
        }
        if (dofs.empty())
            throw ConfigError(w + ".Direction", "missing: the list of dofs (1-based)");
        const YAML::Node tf = child(s, "Time_Function");
        const auto tt = str_or(tf, w + ".Time_Function", "Type", "constant");
        const auto tp = nums(tf, w + ".Time_Function", "Parameters");
        const double a = tp.empty() ? 0.0 : tp[0];
        const bool zero =
            !force && (flag_or(s, w, "Zero_Displacement", false) || (tt == "constant" && a == 0));
        time_function(w, force, tt, tp, a, c);
        const double amplitude = spatial_function(s, w, force, a, c);
        c["value"] = zero ? 0.0 : amplitude;
        // Whole particles held at zero in every dof: a fixed obstacle.
        if (zero && whole && static_cast<int>(dofs.size()) == dim) {
            for (auto id : ids)
                parts[id].fixed = true;
            return;
        }
        if (!force && !zero)
            for (auto id : ids)
                driven[id] = 1;
        if (!force && !zero && whole)
            // A constrained wall driven in some dofs is held in the others.
            for (auto id : ids)
                if (zones[static_cast<std::size_t>(parts[id].zone - 1)].constrained &&
                    static_cast<int>(dofs.size()) < dim) {
                    json h{{"name", fmt::format("hold_{}_particle_{}", k, id)},
                           {"kind", "displacement"},
                           {"particles", {id}},
                           {"components", json::array()},
                           {"value", 0.0}};
                    for (int q = 1; q <= dim; ++q)
                        if (!dofs.count(q))
                            h["components"].push_back(comp[static_cast<std::size_t>(q - 1)]);
                    conditions.push_back(h);
                }
        conditions.push_back(c);
    }

    /// The Spatial_Function of a set into `c`; returns the amplitude (PeriDEM's forces scale
    /// by the space parameter).
    double spatial_function(const YAML::Node& s, const std::string& w, bool force, double a,
                            json& c) const {
        const YAML::Node sf = child(s, "Spatial_Function");
        const auto st = str_or(sf, w + ".Spatial_Function", "Type", "constant");
        const auto sp = nums(sf, w + ".Spatial_Function", "Parameters");
        double amplitude = a;
        if (st == "linear_x" || st == "linear_y" || st == "sin_x") {
            c["space_function"] = st == "sin_x" ? "sine_x" : st;
            c["space_parameter"] = sp.empty() ? 1.0 : sp[0];
            if (force) // PeriDEM's forces: p_s0 sin(pi p_s0 x), p_s0 p_s0 x
                amplitude = a * (sp.empty() ? 1.0 : sp[0]);
        } else if (st == "sin_y" || (force && (st == "hat_x" || st == "hat_y"))) {
            throw ConfigError(w + ".Spatial_Function.Type",
                              "'" + st +
                                  "' cannot be expressed (constant, linear_x, linear_y, "
                                  "sin_x)");
        } else if (st != "constant") {
            // PeriDEM 0.2.1 computes every other type (the drum decks' 'rotation') as S = 1:
            // displacements evaluate sin_x/y and linear_x/y, forces also hat_x/y.
            im.log.info("{}.Spatial_Function.Type '{}': constant, as PeriDEM computes it (its "
                        "{} evaluate {} only)",
                        w, st, force ? "forces" : "displacements",
                        force ? "hat_x/y, sin_x/y, linear_x/y" : "sin_x/y, linear_x/y");
        }
        return amplitude;
    }

    /// The Time_Function of a set.
    void time_function(const std::string& w, bool force, const std::string& tt,
                       const std::vector<double>& tp, double a, json& c) const {
        const Log& log = im.log;
        const int dim = im.dim;
        if (tt == "constant" || (force && tt == "none")) {
            c["time_function"] = "constant";
        } else if (tt == "linear") {
            c["time_function"] = "linear";
        } else if (tt == "quadratic" && !force) {
            // PeriDEM: u = a t + p1 t^2; pdgrain: u = a (t + p t^2).
            c["time_function"] = "quadratic";
            c["time_parameter"] = tp.size() > 1 && a != 0 ? tp[1] / a : 0.0;
            log.warn("{}.Time_Function: quadratic velocity is a + 2 p1 t in pdgrain (PeriDEM: "
                     "a + p1 t)",
                     w);
        } else if (tt == "sin") {
            c["time_function"] = "sine";
            c["time_parameter"] = tp.size() > 1 ? tp[1] : 0.0;
        } else if (tt == "rotation" && !force) {
            // Attrition drums (spec 5.6, 5.9): [omega, x0, y0, z0], a rigid-body rotation of
            // the reference positions about (x0, y0), counter-clockwise for omega > 0.
            if (tp.size() < 3)
                throw ConfigError(w + ".Time_Function.Parameters",
                                  "rotation needs [omega, x0, y0(, z0)]");
            if (dim != 2)
                throw ConfigError(w + ".Time_Function.Type",
                                  "rotation is an in-plane (2D) motion in PeriDEM 0.2");
            c["time_function"] = "rotation";
            c["rotation_center"] = json{tp[1], tp[2]};
            log.info("{}: rotation at {:.4g} rad/s about ({:.4g}, {:.4g}) m, prescribed on "
                     "every node of the selection (a rigid-body displacement)",
                     w, tp[0], tp[1], tp[2]);
        } else
            throw ConfigError(w + ".Time_Function.Type",
                              fmt::format("'{}' cannot be expressed in a pdgrain scene ({})", tt,
                                          force ? "constant, linear, sin"
                                                : "constant, linear, quadratic, sin, "
                                                  "rotation"));
    }
};

} // namespace

void read_loading(Import& im) {
    const YAML::Node& R = im.R;
    const Log& log = im.log;
    const int dim = im.dim;
    const bool single = im.single;
    const auto& zones = im.zones;
    auto& parts = im.parts;
    LoadingReader loading{im, std::vector<std::uint8_t>(parts.size(), 0)};
    auto sets = [&](const char* block, bool force) { loading.sets(block, force); };
    auto& driven = loading.driven;
    sets("Displacement_BC", false);
    sets("Force_BC", true);
    // Constrained zones not driven by a condition are fixed obstacles (spec 4.8).
    for (const auto& z : zones)
        if (z.constrained)
            for (auto id : z.particles)
                if (!driven[id])
                    parts[id].fixed = true;
    if (auto cv = child(R["IC"], "Constant_Velocity")) {
        const auto v = nums(cv, "IC.Constant_Velocity", "Velocity_Vector");
        if (v.size() < static_cast<std::size_t>(dim))
            throw ConfigError("IC.Constant_Velocity.Velocity_Vector",
                              fmt::format("expected {} components", dim));
        std::vector<long> ids =
            single ? std::vector<long>{0} : ints(cv, "IC.Constant_Velocity", "Particle_List");
        for (long id : ids) {
            if (id < 0 || static_cast<std::size_t>(id) >= parts.size())
                throw ConfigError(
                    "IC.Constant_Velocity.Particle_List",
                    fmt::format("{} is not a particle id in [0, {})", id, parts.size()));
            parts[static_cast<std::size_t>(id)].v = {v[0], v[1], dim == 3 ? v[2] : 0.0};
        }
    }
    if (auto ct = child(R["Particle"], "Compressive_Test"))
        log.info("Particle.Compressive_Test: pdgrain records the contact force every fixed or "
                 "driven body receives (/observables/body_force; pd-post walls.csv, "
                 "plot_wall_reaction.py --body B); examples/compressive_n500 is this test with "
                 "a rigid plate that enters the settled pack (walls[].start_time)");
    if (auto oc = child(R["Output"], "Output_Criteria"))
        log.warn("Output.Output_Criteria ({}): not imported (pdgrain stops only on blow-up or "
                 "NaN)",
                 str_or(oc, "Output.Output_Criteria", "Type", "?"));
}

} // namespace pd::pipeline::peridem
