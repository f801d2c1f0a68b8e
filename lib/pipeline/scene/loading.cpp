// SPDX-License-Identifier: MIT
#include "core/errors.hpp"
#include "pipeline/scene/build.hpp"

#include <algorithm>
#include <cmath>

namespace pd::pipeline::scene {

namespace {

/// The time and space functions of condition `c` (spec 5.7).
void time_and_space(const json& cj, const std::string& w, const model::Model& m,
                    model::NodeCondition& c) {
    const auto tf = text(
        cj, w, "time_function", "constant",
        {"constant", "linear", "quadratic", "sine", "rotation", "linear_step", "linear_slow_fast"});
    c.time_fn = tf == "constant"      ? model::TimeFn::constant
                : tf == "linear"      ? model::TimeFn::linear
                : tf == "quadratic"   ? model::TimeFn::quadratic
                : tf == "sine"        ? model::TimeFn::sine
                : tf == "rotation"    ? model::TimeFn::rotation
                : tf == "linear_step" ? model::TimeFn::linear_step
                                      : model::TimeFn::linear_slow_fast;
    if ((c.time_fn == model::TimeFn::linear_step || c.time_fn == model::TimeFn::linear_slow_fast) &&
        !c.is_force)
        throw ConfigError(w + ".time_function", tf + " applies to force_density (spec 5.7)");
    if (c.time_fn == model::TimeFn::rotation) {
        // value = angular velocity (rad/s) about rotation_center, in the xy plane.
        if (c.is_force)
            throw ConfigError(w + ".time_function", "rotation applies to displacements");
        c.centre = vec(cj, w, "rotation_center", m.dimension, {0, 0, 0}, true);
    } else if (cj.contains("rotation_center")) {
        throw ConfigError(w + ".rotation_center", "only with time_function rotation");
    }
    const auto sf = text(cj, w, "space_function", "constant",
                         {"constant", "linear_x", "linear_y", "sine_x", "hat_x", "hat_y"});
    c.space_fn = sf == "constant"   ? model::SpaceFn::constant
                 : sf == "linear_x" ? model::SpaceFn::linear_x
                 : sf == "linear_y" ? model::SpaceFn::linear_y
                 : sf == "sine_x"   ? model::SpaceFn::sine_x
                 : sf == "hat_x"    ? model::SpaceFn::hat_x
                                    : model::SpaceFn::hat_y;
    c.params = {number(cj, w, "space_parameter", 1.0), number(cj, w, "time_parameter", 0.0), 0.0,
                0.0};
    if (cj.contains("time_parameters")) {
        const auto& tp = cj["time_parameters"];
        if (!tp.is_array() || tp.empty() || tp.size() > 3 || cj.contains("time_parameter"))
            throw ConfigError(w + ".time_parameters",
                              "expected [p1, p2, p3] (instead of time_parameter)");
        for (std::size_t q = 0; q < tp.size(); ++q)
            c.params[q + 1] = tp[q].get<double>();
    }
}

/// The displacement / force components of condition `c`.
void components(const json& cj, const std::string& w, const model::Model& m,
                model::NodeCondition& c) {
    if (!cj.contains("components") || !cj["components"].is_array() || cj["components"].empty())
        throw ConfigError(w + ".components", "missing: a list of \"x\", \"y\", \"z\"");
    for (const auto& comp : cj["components"]) {
        const std::string cs = comp.is_string() ? comp.get<std::string>() : "";
        if (cs == "x")
            c.dofs |= 1;
        else if (cs == "y")
            c.dofs |= 2;
        else if (cs == "z" && m.dimension == 3)
            c.dofs |= 4;
        else
            throw ConfigError(w + ".components",
                              "entries must be \"x\", \"y\"" +
                                  std::string(m.dimension == 3 ? " or \"z\"" : ""));
    }
}

/// The nodes condition `c` acts on: of the listed particles, in the region.
void select_nodes(const json& cj, const std::string& w, const model::Model& m,
                  model::NodeCondition& c) {
    const auto& B = m.bodies;
    std::vector<std::uint8_t> take_body(B.num(), 1);
    if (cj.contains("particles")) {
        if (!cj["particles"].is_array())
            throw ConfigError(w + ".particles", "expected a list of particle indices");
        std::fill(take_body.begin(), take_body.end(), 0);
        for (const auto& id : cj["particles"]) {
            if (!id.is_number_integer() || id.get<long>() < 0 ||
                static_cast<std::size_t>(id.get<long>()) >= B.num())
                throw ConfigError(
                    w + ".particles",
                    fmt::format("{} is not a particle index in [0, {})", id.dump(), B.num()));
            take_body[id.get<std::size_t>()] = 1;
        }
    }
    std::array<double, 3> lo{-1e300, -1e300, -1e300}, hi{1e300, 1e300, 1e300};
    if (cj.contains("region")) {
        const json& r = cj["region"];
        check_keys(r, w + ".region", {"min", "max"});
        lo = vec(r, w + ".region", "min", m.dimension, {0, 0, 0}, true);
        hi = vec(r, w + ".region", "max", m.dimension, {0, 0, 0}, true);
        if (m.dimension == 2) {
            lo[2] = -1e300;
            hi[2] = 1e300;
        }
    }
    if (!cj.contains("particles") && !cj.contains("region"))
        throw ConfigError(w, "select nodes with \"particles\" and/or \"region\"");
    for (std::size_t i = 0; i < m.nodes.num(); ++i) {
        if (!take_body[static_cast<std::size_t>(m.nodes.body[i])])
            continue;
        bool in = true;
        for (std::size_t d = 0; d < 3; ++d)
            in = in && m.nodes.x0[3 * i + d] >= lo[d] && m.nodes.x0[3 * i + d] <= hi[d];
        if (in)
            c.nodes.push_back(static_cast<model::index_t>(i));
    }
    if (c.nodes.empty())
        throw ConfigError(w, "selects no node (check region and particles)");
}

/// loading.conditions[k].
model::NodeCondition parse_condition(const json& cj, std::size_t k, const model::Model& m) {
    const std::string w = fmt::format("loading.conditions[{}]", k);
    check_keys(cj, w,
               {"name", "kind", "particles", "region", "components", "value", "time_function",
                "time_parameter", "space_function", "space_parameter", "rotation_center",
                "time_parameters"});
    model::NodeCondition c;
    c.name = text(cj, w, "name", fmt::format("condition_{}", k));
    c.is_force = text(cj, w, "kind", "", {"displacement", "force_density"}) == "force_density";
    if (!cj.contains("kind"))
        throw ConfigError(w + ".kind", "missing: displacement or force_density");
    c.amplitude = number(cj, w, "value", 0, true);
    time_and_space(cj, w, m, c);
    components(cj, w, m, c);
    select_nodes(cj, w, m, c);
    return c;
}

} // namespace

void parse_loading(SceneBuild& s) {
    const json& root = s.root;
    model::Model& m = s.m;
    const json empty = json::object();
    // Loading.
    const json& ld = root.contains("loading") ? root["loading"] : empty;
    check_keys(ld, "loading", {"gravity", "viscous_damping", "conditions"});
    m.loading.gravity = vec(ld, "loading", "gravity", m.dimension, {0, 0, 0});
    for (double g : m.loading.gravity)
        if (!(std::fabs(g) <= 1e8)) // 1e7 g: beyond any centrifuge, a typo or an overflow
            throw ConfigError("loading.gravity", fmt::format("{:g} m/s^2: above 1e8", g));
    m.loading.viscous_damping = number(ld, "loading", "viscous_damping", 0);
    if (m.loading.viscous_damping < 0)
        throw ConfigError("loading.viscous_damping", "must be >= 0");
    if (ld.contains("conditions")) {
        if (!ld["conditions"].is_array())
            throw ConfigError("loading.conditions", "expected a list");
        for (std::size_t k = 0; k < ld["conditions"].size(); ++k) {
            const json& cj = ld["conditions"][k];
            m.loading.conditions.push_back(parse_condition(cj, k, m));
        }
    }
}

} // namespace pd::pipeline::scene
