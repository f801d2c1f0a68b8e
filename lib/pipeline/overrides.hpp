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

} // namespace pd::pipeline
