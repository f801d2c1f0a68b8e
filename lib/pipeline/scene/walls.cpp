// SPDX-License-Identifier: MIT
#include "core/errors.hpp"
#include "model/functions.hpp"
#include "pipeline/scene/build.hpp"

#include <algorithm>
#include <cmath>

namespace pd::pipeline::scene {

namespace {

/// walls[k].
model::Wall parse_wall(const json& wj, std::size_t k, const model::Model& m, const Folder& base) {
    const std::string w = fmt::format("walls[{}]", k);
    check_keys(wj, w,
               {"name", "type", "point", "normal", "center", "radius", "velocity",
                "angular_velocity", "rotation_center", "group", "time_function", "time_parameters",
                "start_time", "enter", "gap", "file", "polyline", "closed", "flip"});
    model::Wall wall;
    wall.name = text(wj, w, "name", fmt::format("wall_{}", k));
    const auto type =
        text(wj, w, "type", "plane", {"plane", "circle_inside", "circle_outside", "mesh"});
    wall.shape = type == "plane"           ? model::WallShape::plane
                 : type == "circle_inside" ? model::WallShape::circle_inside
                 : type == "mesh"          ? model::WallShape::mesh
                                           : model::WallShape::circle_outside;
    for (const char* key : {"file", "polyline", "closed", "flip"})
        if (wj.contains(key) && wall.shape != model::WallShape::mesh)
            throw ConfigError(w + "." + key, "only a wall of \"type\": \"mesh\" has it");
    if (wall.shape == model::WallShape::mesh) {
        parse_wall_mesh(wj, w, wall, m.dimension, base);
    } else if (wall.shape == model::WallShape::plane) {
        wall.point = vec(wj, w, "point", m.dimension, {0, 0, 0}, true);
        wall.normal = vec(wj, w, "normal", m.dimension, {0, 0, 0}, true);
        const double nn = std::hypot(wall.normal[0], wall.normal[1], wall.normal[2]);
        if (!(nn > 0))
            throw ConfigError(w + ".normal", "must be a non-zero vector");
        for (double& c : wall.normal)
            c /= nn;
    } else {
        wall.point = vec(wj, w, "center", m.dimension, {0, 0, 0}, true);
        wall.radius = positive(wj, w, "radius", 0, true);
    }
    wall.velocity = vec(wj, w, "velocity", m.dimension, {0, 0, 0});
    if (wj.contains("angular_velocity")) {
        if (m.dimension == 2)
            wall.angular_velocity = {0, 0, number(wj, w, "angular_velocity", 0)};
        else
            wall.angular_velocity = vec(wj, w, "angular_velocity", 3, {0, 0, 0});
    }
    wall.centre = vec(wj, w, "rotation_center", m.dimension, wall.point);
    // Motion in time: displacement velocity T(t), angle angular_velocity T(t).
    const auto tf = text(wj, w, "time_function", "linear",
                         {"linear", "quadratic", "sine", "linear_step", "linear_slow_fast"});
    wall.motion = tf == "linear"        ? model::TimeFn::linear
                  : tf == "quadratic"   ? model::TimeFn::quadratic
                  : tf == "sine"        ? model::TimeFn::sine
                  : tf == "linear_step" ? model::TimeFn::linear_step
                                        : model::TimeFn::linear_slow_fast;
    if (wj.contains("time_parameters")) {
        const auto& tp = wj["time_parameters"];
        if (!tp.is_array() || tp.empty() || tp.size() > 3)
            throw ConfigError(w + ".time_parameters", "expected [p1, p2, p3]");
        for (std::size_t q = 0; q < tp.size(); ++q)
            wall.motion_params[q + 1] = tp[q].get<double>();
    }
    // Two-stage runs: the wall enters at start_time (absent before), then moves.
    wall.start_time = number(wj, w, "start_time", 0.0);
    if (!(wall.start_time >= 0) || !std::isfinite(wall.start_time))
        throw ConfigError(w + ".start_time", "must be a finite time >= 0 (s)");
    // Walls placed by the state: enter above the grains, wherever they are at start_time.
    wall.enter = text(wj, w, "enter", "at_point", {"at_point", "above_grains"}) == "above_grains"
                     ? model::WallEnter::above_grains
                     : model::WallEnter::at_point;
    wall.gap = number(wj, w, "gap", 0.0);
    if (!(wall.gap >= 0) || !std::isfinite(wall.gap))
        throw ConfigError(w + ".gap", "must be a finite distance >= 0 (m)");
    if (wall.enter == model::WallEnter::above_grains && wall.shape != model::WallShape::plane)
        throw ConfigError(w + ".enter", "\"above_grains\" places plane walls only");
    wall.group = static_cast<std::int32_t>(std::clamp(number(wj, w, "group", -1), -1e9, 1e9));
    return wall;
}

} // namespace

void place_walls(SceneBuild& s) {
    model::Model& m = s.m;
    for (std::size_t k = 0; k < m.walls.size(); ++k) {
        auto& wall = m.walls[k];
        if (wall.enter != model::WallEnter::above_grains || wall.start_time > 0)
            continue;
        double level = HUGE_VAL;
        for (std::size_t i = 0; i < m.nodes.num(); ++i)
            level = std::min(
                level, model::entry_level(m, wall,
                                          m.bodies.group[static_cast<std::size_t>(m.nodes.body[i])],
                                          &m.nodes.x0[3 * i]));
        if (!std::isfinite(level))
            throw ConfigError(fmt::format("walls[{}].enter", k),
                              "\"above_grains\": the wall touches no grain (no contact law "
                              "between them)");
        model::place_wall(wall, level);
    }
}

void parse_walls(SceneBuild& s) {
    const json& root = s.root;
    model::Model& m = s.m;
    const auto& B = m.bodies;
    const auto& inst = s.inst;
    // Rigid analytic walls.
    std::int32_t max_group = *std::max_element(B.group.begin(), B.group.end());
    if (root.contains("walls")) {
        if (!root["walls"].is_array())
            throw ConfigError("walls", "expected a list of walls");
        for (std::size_t k = 0; k < root["walls"].size(); ++k) {
            const json& wj = root["walls"][k];
            m.walls.push_back(parse_wall(wj, k, m, s.base_dir));
        }
        // Walls without a group share one group after the particles'.
        for (auto& wall : m.walls)
            if (wall.group < 0)
                wall.group = max_group + 1;
        // Every node must start on the free side of every wall present at t = 0 (a wall with a
        // start_time enters later, where pd-solve's rigid-wall guard checks the grains).
        for (std::size_t k = 0; k < m.walls.size(); ++k) {
            const auto& wall = m.walls[k];
            if (wall.start_time > 0 || wall.enter == model::WallEnter::above_grains)
                continue; // enters later, or placed by place_walls
            for (std::size_t i = 0; i < m.nodes.num(); ++i) {
                const double d = model::wall_distance(wall, &m.nodes.x0[3 * i]);
                if (d < 0)
                    throw ConfigError(
                        fmt::format("{}, walls[{}]",
                                    inst[static_cast<std::size_t>(m.nodes.body[i])].where, k),
                        fmt::format("the grain crosses the wall (a node lies {:.4g} m behind it)",
                                    -d));
            }
        }
    }
}

void warn_close_to_walls(SceneBuild& s) {
    const model::Model& m = s.m;
    const Log& log = s.log;
    // Grains that start within the contact radius of a wall are pushed off at t = 0: each
    // node against the law between its grain's group and the wall's (none, or stiffness 0: the
    // wall does not act on that grain, as on a protrusion that turns with the drum).
    for (std::size_t k = 0; k < m.walls.size(); ++k) {
        const auto& wall = m.walls[k];
        if (wall.start_time > 0)
            continue; // enters later
        std::size_t close = 0;
        double rc = 0;
        for (std::size_t i = 0; i < m.nodes.num(); ++i) {
            const auto* p = m.contact_between(
                m.bodies.group[static_cast<std::size_t>(m.nodes.body[i])], wall.group);
            if (p == nullptr || !(p->stiffness > 0) || !(p->offset() > 0) ||
                !(model::wall_distance(wall, &m.nodes.x0[3 * i]) < p->offset()))
                continue;
            ++close;
            rc = std::max(rc, p->radius);
        }
        if (close > 0)
            log.warn("walls[{}]: {} nodes start within the contact radius {:.3g} m of the wall "
                     "(they are pushed off at t = 0)",
                     k, close, rc);
    }
}

} // namespace pd::pipeline::scene
