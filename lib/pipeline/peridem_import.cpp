// SPDX-License-Identifier: MIT
#include "pipeline/peridem_import.hpp"

#include "core/errors.hpp"
#include "core/files.hpp"
#include "pipeline/peridem/import.hpp"

#include <set>
#include <yaml-cpp/yaml.h>

namespace pd::pipeline {

using namespace peridem;

std::string peridem_to_scene(const std::string& yaml_path, const Log& log, bool parity) {
    Deck d;
    d.path = yaml_path;
    d.dir = fs::absolute(fs::path(yaml_path)).parent_path();
    try {
        note_input("--from-peridem deck", yaml_path);
        d.root = YAML::LoadFile(yaml_path);
    } catch (const YAML::BadFile&) {
        throw InputError(fmt::format("{}: cannot read the PeriDEM deck", yaml_path));
    } catch (const YAML::Exception& e) {
        throw InputError(fmt::format("{}: not a valid YAML deck: {}", yaml_path, e.what()));
    }
    const YAML::Node& R = d.root;
    if (!R.IsMap())
        throw InputError(
            fmt::format("{}: not a PeriDEM deck (expected blocks Model, Zone, ...)", yaml_path));
    static const std::set<std::string> known = {
        "Model", "Container", "Zone",    "Particle", "Wall",     "Particle_Generation",
        "Mesh",  "Material",  "Contact", "Neighbor", "Force_BC", "Displacement_BC",
        "IC",    "Output",    "Restart", "Policy",   "HPX"};
    for (auto it = R.begin(); it != R.end(); ++it) {
        const auto k = it->first.as<std::string>();
        if (!known.count(k))
            log.warn("{}: deck block '{}' is not a PeriDEM 0.2 block: ignored", yaml_path, k);
    }
    for (const char* ignored : {"Policy", "HPX", "Neighbor"})
        if (R[ignored])
            log.info("deck block '{}' ignored (pdgrain chooses its own contact search and "
                     "threads)",
                     ignored);
    if (R["Restart"])
        throw ConfigError("Restart", "a PeriDEM restart (VTU state) cannot be imported; import "
                                     "the deck without it and use pd-solve --restart");

    // One step per block (lib/pipeline/peridem/<block>.cpp), in this order: each reads what the
    // steps before it left (zones before materials and meshes, particles before the conditions
    // that select them).
    Import im(d, log, parity);
    read_model(im);
    read_zones(im);
    read_materials(im);
    read_meshes(im);
    read_particles(im);
    read_loading(im);
    read_contact(im);
    read_output(im);
    return scene_text(im, yaml_path);
}

} // namespace pd::pipeline
