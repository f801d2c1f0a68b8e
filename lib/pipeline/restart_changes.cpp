// SPDX-License-Identifier: MIT
#include "pipeline/restart_changes.hpp"

#include "core/errors.hpp"
#include "model/functions.hpp"
#include "pipeline/scene.hpp"
#include "solver/walls.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace pd::pipeline {

namespace {

using json = nlohmann::json;
using V3 = std::array<double, 3>;

const std::vector<std::string> wall_fields{
    "point",           "center",     "normal", "radius", "velocity", "angular_velocity",
    "rotation_center", "start_time", "enter",  "gap"};

/// The closest of `names` to `key` (for "did you mean").
std::string closest(const std::vector<std::string>& names, const std::string& key) {
    std::string best;
    std::size_t bd = std::string::npos;
    for (const auto& n : names)
        if (const auto d = edit_distance(key, n); d < bd) {
            bd = d;
            best = n;
        }
    return best;
}

double finite(const json& v, const std::string& key, double lo) {
    if (!v.is_number() || !std::isfinite(v.get<double>()) || !(v.get<double>() >= lo))
        throw ConfigError(key,
                          fmt::format("expected a finite number >= {:g}, got {}", lo, v.dump()));
    return v.get<double>();
}

/// A vector of the model's dimension (z = 0 in 2D).
V3 vec(const json& v, const std::string& key, int dim) {
    if (!v.is_array() || static_cast<int>(v.size()) != dim)
        throw ConfigError(key, fmt::format("expected {} numbers, got {}", dim, v.dump()));
    V3 r{0, 0, 0};
    for (std::size_t d = 0; d < v.size(); ++d)
        r[d] = finite(v[d], key, -HUGE_VAL);
    return r;
}

/// walls.<wall>.<field> = v.
void set_wall(model::Model& m, model::Wall& w, const std::string& field, const json& v,
              const std::string& key) {
    const bool plane = w.shape == model::WallShape::plane;
    if (w.shape == model::WallShape::mesh &&
        (field == "point" || field == "center" || field == "normal" || field == "radius"))
        throw ConfigError(key, "a mesh wall's surface is its file or polyline: move it with "
                               "velocity, angular_velocity and rotation_center");
    if (field == "point" || field == "center") {
        if ((field == "point") != plane)
            throw ConfigError(key, plane ? "a plane has a point" : "a circle has a center");
        const V3 p = vec(v, key, m.dimension);
        if (w.centre == w.point)
            w.centre = p; // the rotation centre that defaulted to the point follows it
        w.point = p;
    } else if (field == "normal") {
        if (!plane)
            throw ConfigError(key, "only a plane has a normal");
        const V3 n = vec(v, key, m.dimension);
        const double nn = std::hypot(n[0], n[1], n[2]);
        if (!(nn > 0))
            throw ConfigError(key, "must be a non-zero vector");
        w.normal = {n[0] / nn, n[1] / nn, n[2] / nn};
    } else if (field == "radius") {
        if (plane)
            throw ConfigError(key, "only a circle has a radius");
        w.radius = finite(v, key, 0);
        if (!(w.radius > 0))
            throw ConfigError(key, "must be > 0");
    } else if (field == "velocity") {
        w.velocity = vec(v, key, m.dimension);
    } else if (field == "angular_velocity") {
        w.angular_velocity =
            m.dimension == 2 ? V3{0, 0, finite(v, key, -HUGE_VAL)} : vec(v, key, 3);
    } else if (field == "rotation_center") {
        w.centre = vec(v, key, m.dimension);
    } else if (field == "start_time") {
        w.start_time = finite(v, key, 0);
    } else if (field == "enter") {
        if (v != "at_point" && v != "above_grains")
            throw ConfigError(
                key, fmt::format("expected \"at_point\" or \"above_grains\", got {}", v.dump()));
        if (v == "above_grains" && !plane)
            throw ConfigError(key, "\"above_grains\" places plane walls only");
        w.enter = v == "above_grains" ? model::WallEnter::above_grains : model::WallEnter::at_point;
    } else {
        w.gap = finite(v, key, 0);
    }
}

/// The wall a key names: its name, or its index.
std::size_t wall_index(const model::Model& m, const std::string& id, const std::string& key) {
    std::vector<std::string> names;
    for (std::size_t k = 0; k < m.walls.size(); ++k) {
        if (m.walls[k].name == id || std::to_string(k) == id)
            return k;
        names.push_back(m.walls[k].name);
    }
    if (names.empty())
        throw ConfigError(key, "the file has no rigid walls");
    throw ConfigError(key,
                      fmt::format("no wall '{}' (did you mean '{}'?)", id, closest(names, id)));
}

/// The changes applied: the JSON record and the walls changed (ascending).
struct Changes {
    json record = json::object();
    std::vector<std::size_t> walls;
};

Changes apply(model::Model& m, const std::vector<std::string>& sets) {
    Changes out;
    json& record = out.record;
    for (const auto& set : sets) {
        const auto eq = set.find('=');
        if (eq == std::string::npos || eq == 0)
            throw ConfigError("--set", fmt::format("expected KEY=VALUE, got '{}'", set));
        const std::string key = set.substr(0, eq), text = set.substr(eq + 1);
        json v = json::parse(text, nullptr, false);
        if (v.is_discarded())
            v = text; // a bare word: a string
        const auto dot1 = key.find('.');
        const std::string top = key.substr(0, dot1);
        if (top == "walls") {
            const auto dot2 = key.rfind('.');
            if (dot1 == std::string::npos || dot2 == dot1)
                throw ConfigError(key, "expected walls.<name>.<field>");
            const std::string field = key.substr(dot2 + 1);
            const auto k = wall_index(m, key.substr(dot1 + 1, dot2 - dot1 - 1), key);
            if (std::find(wall_fields.begin(), wall_fields.end(), field) == wall_fields.end())
                throw ConfigError(key, fmt::format("a restart changes point, center, normal, "
                                                   "radius, velocity, angular_velocity, "
                                                   "rotation_center, start_time, enter or gap of "
                                                   "a wall, not '{}' (did you mean '{}'?)",
                                                   field, closest(wall_fields, field)));
            set_wall(m, m.walls[k], field, v, key);
            out.walls.push_back(k);
        } else if (key == "loading.gravity") {
            m.loading.gravity = vec(v, key, m.dimension);
        } else if (key == "loading.viscous_damping") {
            m.loading.viscous_damping = finite(v, key, 0);
        } else {
            throw ConfigError(key, "a restart changes walls.<name>.<field>, loading.gravity or "
                                   "loading.viscous_damping (other changes: pd-pack a new scene)");
        }
        record[key] = v;
    }
    std::sort(out.walls.begin(), out.walls.end());
    out.walls.erase(std::unique(out.walls.begin(), out.walls.end()), out.walls.end());
    return out;
}

/// Signed distance of x from wall w at pose p (positive on the free side).
double distance(const model::Wall& w, const solver::WallPose& p, const double* x) {
    if (w.shape == model::WallShape::mesh) {
        double n[3];
        return solver::wall_distance(w, p, x, n, HUGE_VAL);
    }
    if (w.shape == model::WallShape::plane)
        return (x[0] - p.point[0]) * p.normal[0] + (x[1] - p.point[1]) * p.normal[1] +
               (x[2] - p.point[2]) * p.normal[2];
    const double r = std::hypot(x[0] - p.point[0], x[1] - p.point[1], x[2] - p.point[2]);
    return w.shape == model::WallShape::circle_inside ? w.radius - r : r - w.radius;
}

void check_walls(const model::Model& m, const std::vector<std::size_t>& walls,
                 const std::vector<double>& u, double t, const std::string& file) {
    for (const auto k : walls) {
        const auto& w = m.walls[k];
        if (!model::wall_present(w, t))
            continue; // checked as it enters
        if (w.enter == model::WallEnter::above_grains)
            throw InputError(fmt::format(
                "{}: wall '{}' enters above the grains at start_time {:.6g} s, not after the "
                "checkpoint at t = {:.6g} s: give walls.{}.start_time > {:.6g}",
                file, w.name, w.start_time, t, w.name, t));
        const auto p = solver::wall_pose(w, t);
        std::size_t count = 0;
        double deepest = 0;
        for (std::size_t i = 0; i < m.nodes.num(); ++i) {
            const double x[3]{m.nodes.x0[3 * i] + u[3 * i], m.nodes.x0[3 * i + 1] + u[3 * i + 1],
                              m.nodes.x0[3 * i + 2] + u[3 * i + 2]};
            if (const double d = distance(w, p, x); d < 0) {
                ++count;
                deepest = std::max(deepest, -d);
            }
        }
        if (count > 0)
            throw InputError(fmt::format(
                "{}: wall '{}' as changed would have {} node(s) behind its surface at the "
                "checkpoint (t = {:.6g} s), the deepest {:.4g} m: move it to the free side of "
                "the grains (the file is unchanged)",
                file, w.name, count, t, deepest));
    }
}

} // namespace

std::string apply_restart_changes(model::Model& m, const std::vector<std::string>& sets,
                                  const std::vector<double>& u, double t, const std::string& file) {
    if (sets.empty())
        return "";
    const auto ch = apply(m, sets);
    check_walls(m, ch.walls, u, t, file);
    return ch.record.dump();
}

} // namespace pd::pipeline
