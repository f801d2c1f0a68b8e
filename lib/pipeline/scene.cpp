// SPDX-License-Identifier: MIT
#include "pipeline/scene.hpp"

#include "core/errors.hpp"
#include "pipeline/scene/build.hpp"
#include "pipeline/scene/fields.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>

namespace pd::pipeline {

using json = nlohmann::json;

std::size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j)
        prev[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        cur[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j)
            cur[j] = std::min(
                {prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
        std::swap(prev, cur);
    }
    return prev[b.size()];
}

namespace {
model::Model build_scene_impl(const std::string& source_text, const std::string& source,
                              const Log& log, double max_nodes, bool allow_outside);
} // namespace

model::Model build_scene(const std::string& source_text, const std::string& source, const Log& log,
                         double max_nodes, bool allow_outside) {
    try {
        return build_scene_impl(source_text, source, log, max_nodes, allow_outside);
    } catch (const json::exception& e) { // a value of the wrong JSON type read without a check
        throw InputError(fmt::format("{}: {}", source, e.what()));
    }
}

namespace {
model::Model build_scene_impl(const std::string& source_text, const std::string& source,
                              const Log& log, double max_nodes, bool allow_outside) {
    using scene::check_keys;
    using scene::number;
    using scene::text;
    const json root = scene::parse_json(source_text, source);
    check_keys(root, "",
               {"title", "dimension", "planar", "materials", "discretization", "shapes",
                "particles", "walls", "cracks", "slots", "contact", "loading", "solver"});
    model::Model m;
    m.scene_json = root.dump(2);
    m.title = text(root, "", "title", source);
    m.dimension = static_cast<int>(std::clamp(number(root, "", "dimension", 2), -1e9, 1e9));
    if (m.dimension != 2 && m.dimension != 3)
        throw ConfigError("dimension", fmt::format("{}: expected 2 or 3", m.dimension));
    const scene::Folder base_dir{std::filesystem::path(source).parent_path().string(),
                                 allow_outside};
    m.planar =
        text(root, "", "planar", "plane_stress", {"plane_stress", "plane_strain"}) == "plane_strain"
            ? model::Planar::plane_strain
            : model::Planar::plane_stress;

    // One step per section (lib/pipeline/scene/<section>.cpp), in this order: each reads what
    // the steps before it left (materials before particles, contact radii before the surface
    // layer, slots before the loading, whose regions select nodes by index).
    scene::SceneBuild s(root, log, max_nodes, base_dir, m);
    scene::parse_materials(s);
    scene::parse_discretization(s);
    scene::parse_shapes(s);
    scene::parse_particles(s);
    scene::mesh_reference_shapes(s);
    scene::place_particles(s);
    scene::parse_walls(s);
    scene::parse_contact(s);
    scene::place_walls(s);
    scene::warn_close_to_walls(s);
    scene::mark_surface_layer(s);
    scene::parse_slots(s);
    scene::parse_loading(s);
    scene::parse_cracks(s);
    scene::parse_solver(s);
    scene::raise_for_speed(s);
    m.check_consistency();
    return m;
}

} // namespace

} // namespace pd::pipeline
