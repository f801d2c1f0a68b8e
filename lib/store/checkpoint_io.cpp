// SPDX-License-Identifier: MIT
#include "store/checkpoint_io.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "store/schema.hpp"

#include <algorithm>
#include <cmath>

namespace pd::store {

const std::array<const char*, 7>& checkpoint_dissipation() {
    static const std::array<const char*, 7> names{
        "fracture_energy", "damping_dissipation", "friction_dissipation", "viscous_dissipation",
        "damping_rate",    "friction_rate",       "viscous_rate"};
    return names;
}

void write_checkpoint(h5::File& f, const Checkpoint& c) {
    const std::string root = path::checkpoints;
    f.create_group(root);
    const std::string name = fmt::format("step_{:012d}", c.step);
    const std::string g = root + "/" + name;
    f.remove(g);
    f.create_group(g);
    const std::uint64_t n = c.u.size() / 3;
    const h5::runs_t all_nodes{{0, n}}, all_bonds{{0, c.alive.size()}};
    const auto& nodes = c.node_runs.empty() ? all_nodes : c.node_runs;
    const auto& bonds = c.bond_runs.empty() ? all_bonds : c.bond_runs;
    auto put = [&](const std::string& p, const std::vector<double>& v, const char* unit) {
        f.write_runs<double>(g + "/" + p, v, {n, 3}, nodes);
        f.set_attr(g + "/" + p, "unit", unit);
    };
    put("displacement", c.u, "m");
    put("velocity", c.v, "m s-1");
    put("force_density", c.f, "N m-3");
    f.write_runs<std::uint8_t>(g + "/bond_alive", c.alive, {c.alive.size()}, bonds);
    f.set_attr(g + "/bond_alive", "unit", "1");
    f.set_attr(g, "step", c.step);
    f.set_attr(g, "time", c.time);
    f.set_attr(g, "dt", c.dt);
    f.set_attr(g, "broken_total", c.broken_total);
    f.set_attr(g, "external_work", c.external_work);
    f.set_attr(g, "external_power", c.external_power);
    for (std::size_t k = 0; k < c.dissipation.size(); ++k)
        f.set_attr(g, checkpoint_dissipation()[k], c.dissipation[k]);
    f.set_attr(g, "interval_steps", c.interval_steps);
    if (!c.interval_sum.empty())
        f.set_attr(g, "interval_sum", c.interval_sum);
    if (!c.build_x.empty() || c.depth_time >= 0)
        raise_version(f); // pd-file 1.9.0 objects (1.9.1: held pairs)
    if (!c.build_x.empty()) {
        f.write_runs<double>(g + "/surface_build_position", c.build_x, {n, 3}, nodes);
        f.set_attr(g + "/surface_build_position", "unit", "m");
        f.write_runs<std::uint8_t>(g + "/surface_build_whole", c.build_whole, {n}, nodes);
        f.set_attr(g + "/surface_build_whole", "unit", "1");
    }
    if (c.depth_time >= 0) {
        f.set_attr(g, "surface_depth_time", c.depth_time);
        const std::uint64_t k = c.depths.size();
        const h5::runs_t all{{0, k}};
        const auto& mine = c.depth_runs.empty() ? all : c.depth_runs;
        f.write_runs<std::int64_t>(g + "/surface_depth_pairs", c.depth_pairs, {k, 2}, mine);
        f.set_attr(g + "/surface_depth_pairs", "unit", "1");
        f.write_runs<double>(g + "/surface_depths", c.depths, {k}, mine);
        f.set_attr(g + "/surface_depths", "unit", "m");
    }
    f.set_attr(g, "complete", std::int32_t{1});
    f.flush();
    f.set_attr(root, "latest", name);
    f.flush();
    for (const auto& old : f.list(root))
        if (old != name)
            f.remove(root + "/" + old);
    f.flush();
}

namespace {

/// The surface law's last rebuild and depth history of checkpoint group g, if it has them
/// (checked).
void read_surface_state(const h5::File& f, const std::string& g, std::size_t num_nodes,
                        Checkpoint& c) {
    if (f.exists(g + "/surface_build_position")) {
        c.build_x = f.read<double>(g + "/surface_build_position");
        c.build_whole = f.read<std::uint8_t>(g + "/surface_build_whole");
        if (c.build_x.size() != 3 * num_nodes || c.build_whole.size() != num_nodes ||
            !std::all_of(c.build_x.begin(), c.build_x.end(),
                         [](double v) { return std::isfinite(v); }))
            throw SchemaError(
                f.name(), g + "/surface_build_position",
                fmt::format("must be finite, {} x 3, with surface_build_whole", num_nodes));
    }
    if (!f.has_attr(g, "surface_depth_time"))
        return;
    c.depth_time = f.attr<double>(g, "surface_depth_time");
    c.depth_pairs = f.read<std::int64_t>(g + "/surface_depth_pairs");
    c.depths = f.read<double>(g + "/surface_depths");
    if (!(c.depth_time >= 0 && c.depth_time <= c.time) ||
        c.depth_pairs.size() != 2 * c.depths.size())
        throw SchemaError(f.name(), g + "/surface_depths",
                          "the depth history does not match its pairs or its time");
    for (std::size_t k = 0; k < c.depths.size(); ++k)
        if (!std::isfinite(c.depths[k]) || (c.depths[k] < 0 && c.depths[k] != -1) ||
            c.depth_pairs[2 * k] < 0 ||
            static_cast<std::size_t>(c.depth_pairs[2 * k]) >= num_nodes ||
            c.depth_pairs[2 * k + 1] < 0)
            throw SchemaError(
                f.name(), g + "/surface_depths",
                fmt::format("entry {}: not a node, body and depth >= 0 (or -1: held)", k));
}

} // namespace

std::optional<Checkpoint> read_latest_checkpoint(const h5::File& f, std::size_t num_nodes,
                                                 std::size_t num_bonds) {
    const std::string root = path::checkpoints;
    if (!f.exists(root) || !f.has_attr(root, "latest"))
        return std::nullopt;
    const std::string g = root + "/" + f.attr_string(root, "latest");
    if (!f.exists(g) || !f.has_attr(g, "complete"))
        throw SchemaError(f.name(), g, "the latest checkpoint is missing or incomplete");
    Checkpoint c;
    c.step = f.attr<std::int64_t>(g, "step");
    c.time = f.attr<double>(g, "time");
    c.dt = f.attr<double>(g, "dt");
    c.broken_total = f.attr<std::int64_t>(g, "broken_total");
    c.external_work = f.attr<double>(g, "external_work");
    c.external_power = f.attr<double>(g, "external_power");
    for (std::size_t k = 0; k < c.dissipation.size(); ++k)
        if (f.has_attr(g, checkpoint_dissipation()[k]))
            c.dissipation[k] = f.attr<double>(g, checkpoint_dissipation()[k]);
    if (f.has_attr(g, "interval_steps"))
        c.interval_steps = f.attr<std::int64_t>(g, "interval_steps");
    if (f.has_attr(g, "interval_sum"))
        c.interval_sum = f.attr_vector<double>(g, "interval_sum");
    read_surface_state(f, g, num_nodes, c);
    if (c.interval_steps < 0 || c.interval_steps > c.step)
        throw SchemaError(f.name(), g + "@interval_steps",
                          fmt::format("{}: must be in [0, step = {}]", c.interval_steps, c.step));
    for (const double v : c.interval_sum)
        if (!std::isfinite(v))
            throw SchemaError(f.name(), g + "@interval_sum", "must be finite");
    // A restart truncates the frames after this step: the numbers must make sense first.
    if (c.step < 0 || c.step >= (std::int64_t{1} << 53))
        throw SchemaError(f.name(), g + "@step", fmt::format("{} is not a step number", c.step));
    if (f.attr_string(root, "latest") != fmt::format("step_{:012d}", c.step))
        throw SchemaError(f.name(), g + "@step",
                          fmt::format("{} does not match the checkpoint's name", c.step));
    if (!std::isfinite(c.dt) || !(c.dt > 0))
        throw SchemaError(f.name(), g + "@dt", fmt::format("{} is not a time step", c.dt));
    // time is the sum of the steps' dt; a run extended with --final-time may have changed dt
    // (by up to one step over the run), so only a gross mismatch is refused.
    if (!std::isfinite(c.time) || c.time < 0 ||
        std::abs(c.time - static_cast<double>(c.step) * c.dt) >
            0.5 * std::max(c.time, static_cast<double>(c.step) * c.dt) + 1e-300)
        throw SchemaError(f.name(), g + "@time",
                          fmt::format("{} s is not step x dt = {} x {} s", c.time, c.step, c.dt));
    if (c.broken_total < 0)
        throw SchemaError(f.name(), g + "@broken_total", "must be >= 0");
    if (!std::isfinite(c.external_work) || !std::isfinite(c.external_power))
        throw SchemaError(f.name(), g + "@external_work", "must be finite");
    for (std::size_t k = 0; k < c.dissipation.size(); ++k)
        if (!std::isfinite(c.dissipation[k]))
            throw SchemaError(f.name(), g + "@" + checkpoint_dissipation()[k], "must be finite");
    auto get3 = [&](const std::string& p) {
        h5::dims_t d;
        auto v = f.read<double>(g + "/" + p, &d);
        if (d.size() != 2 || d[0] != num_nodes || d[1] != 3)
            throw SchemaError(
                f.name(), g + "/" + p,
                fmt::format("expected shape ({}, 3) (the file's node count)", num_nodes));
        for (std::size_t i = 0; i < v.size(); ++i)
            if (!std::isfinite(v[i]))
                throw SchemaError(f.name(), g + "/" + p,
                                  fmt::format("node {}: value is not finite", i / 3));
        return v;
    };
    c.u = get3("displacement");
    c.v = get3("velocity");
    c.f = get3("force_density");
    c.alive = f.read<std::uint8_t>(g + "/bond_alive");
    if (c.alive.size() != num_bonds)
        throw SchemaError(
            f.name(), g + "/bond_alive",
            fmt::format("has {} entries, expected {} bonds", c.alive.size(), num_bonds));
    return c;
}

} // namespace pd::store
