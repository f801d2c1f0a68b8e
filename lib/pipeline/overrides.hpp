// SPDX-License-Identifier: MIT
// pd-pack --set PATH=VALUE: scene overrides for parameter sweeps. PATH is a dotted path
// ("contact.restitution", "materials.m1.youngs_modulus", "particles.0.velocity" or
// "particles[0].velocity") or a JSON pointer ("/contact/restitution"); VALUE is parsed as JSON
// (0.5, [0, -1], true, "pmb") and taken as a string when it is not JSON (pmb).
#pragma once

#include <string>
#include <vector>

namespace pd::pipeline {

struct Resolved {
    std::string scene;     ///< the scene with the overrides applied, plain JSON (no comments)
    std::string overrides; ///< the overrides as a JSON object {"PATH": value}; "" if none
};

/// Parses `text` (JSON, comments allowed; `source` names it in messages) and applies `sets`
/// ("PATH=VALUE") in order. Every component of PATH but the last must exist; the last may be a
/// new key of an object unless it is a near miss of an existing one (edit distance <= 2). Throws
/// ConfigError (exit 2) naming the path and the closest existing key.
Resolved apply_overrides(const std::string& text, const std::string& source,
                         const std::vector<std::string>& sets);

/// pd-pack --print-scene --defaults: `scene` (plain JSON) with every default of `schema` (the
/// text of data-schema/scene.schema.json) filled in where the key is absent: the properties'
/// "default" values, through $ref, objects, arrays and maps. Not filled: a key another given key
/// replaces (radius_factor beside radius or radius_mesh_factor, fracture_energy beside
/// fracture_toughness, stiffness_factor beside a numeric stiffness) and contact.pairs (they
/// inherit the top-level contact). A oneOf (particles) takes the first branch the entry fits.
/// Returns plain JSON, indented.
std::string fill_defaults(const std::string& scene, const std::string& schema);

} // namespace pd::pipeline
