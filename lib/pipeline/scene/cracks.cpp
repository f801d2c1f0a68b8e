// SPDX-License-Identifier: MIT
#include "core/errors.hpp"
#include "model/slots.hpp"
#include "pipeline/scene/build.hpp"

namespace pd::pipeline::scene {

void parse_slots(SceneBuild& s) {
    const json& root = s.root;
    model::Model& m = s.m;
    const auto& B = m.bodies;
    const Log& log = s.log;
    // Notch slots: nodes inside are removed and bonds through them never exist (before the
    // loading, whose regions select nodes by index).
    if (root.contains("slots")) {
        if (!root["slots"].is_array())
            throw ConfigError("slots",
                              "expected a list of {\"from\": [..], \"to\": [..], \"width\": w}");
        std::vector<model::Slot> slots;
        for (std::size_t k = 0; k < root["slots"].size(); ++k) {
            const json& sj = root["slots"][k];
            const std::string w = fmt::format("slots[{}]", k);
            check_keys(sj, w, {"from", "to", "width"});
            slots.push_back({vec(sj, w, "from", m.dimension, {0, 0, 0}, true),
                             vec(sj, w, "to", m.dimension, {0, 0, 0}, true),
                             number(sj, w, "width", 0, true)});
        }
        const auto cut = model::apply_slots(m, slots);
        // The notch faces are boundary: nodes near a slot join the surface layer (as above).
        double rc_max = 0;
        for (const auto& p : m.contact)
            rc_max = std::max(rc_max, p.radius);
        for (std::size_t i = 0; i < m.nodes.num(); ++i) {
            const double layer =
                2 * rc_max + 0.5 * B.mesh_size[static_cast<std::size_t>(m.nodes.body[i])];
            for (const auto& sl : slots)
                if (model::slot_distance(sl, &m.nodes.x0[3 * i]) <= layer)
                    m.nodes.surface[i] = 1;
        }
        for (std::size_t k = 0; k < slots.size(); ++k)
            log.info("slots[{}]: {} nodes inside removed, {} bonds through it never exist", k,
                     cut.nodes_per_slot[k], cut.bonds_per_slot[k]);
    }
}

void parse_cracks(SceneBuild& s) {
    const json& root = s.root;
    model::Model& m = s.m;
    // Pre-cracks: bonds crossing a segment start broken.
    if (root.contains("cracks")) {
        if (!root["cracks"].is_array())
            throw ConfigError("cracks", "expected a list of {\"from\": [..], \"to\": [..]}");
        for (std::size_t k = 0; k < root["cracks"].size(); ++k) {
            const json& cj = root["cracks"][k];
            const std::string w = fmt::format("cracks[{}]", k);
            check_keys(cj, w, {"from", "to"});
            m.cracks.push_back({vec(cj, w, "from", m.dimension, {0, 0, 0}, true),
                                vec(cj, w, "to", m.dimension, {0, 0, 0}, true)});
        }
    }
}

} // namespace pd::pipeline::scene
