// SPDX-License-Identifier: MIT
// pd-pack: scene (JSON) or PeriDEM deck (YAML) -> pd-file. The file is written under a temporary
// name and renamed when complete, so a failed run never leaves a half-written file (nor touches an
// existing one).
#pragma once

#include "core/tool.hpp"

#include <string>
#include <vector>

namespace pd::pipeline {

struct PackOptions {
    std::string scene;             ///< JSON scene path (or empty with from_peridem)
    std::string from_peridem;      ///< PeriDEM 0.2.x YAML deck to import instead of a scene
    std::string parity;            ///< "peridem": import the deck to match PeriDEM 0.2.1's numbers
    std::string write_scene;       ///< if set, the scene JSON actually built is written here
    std::string output;            ///< pd-file to write
    std::string preview;           ///< if set, a PNG of the scene (workflows/preview/preview.py)
    std::vector<std::string> sets; ///< --set PATH=VALUE scene overrides (pipeline/overrides.hpp)
    bool print_scene = false;      ///< print the resolved scene (plain JSON) to stdout, no file
    bool defaults = false;         ///< with print_scene: every default filled in (the schema's)
    double max_nodes = 0; ///< refuse scenes estimated above this many nodes (before meshing);
                          ///< 0: what fits in the available memory (pipeline/resources.hpp)
    bool max_nodes_given = false; ///< --max-nodes was given (then it must be >= 1)
    bool overwrite = false;       ///< -o may replace a pd-file holding results
    bool allow_outside = false;   ///< the scene may name files outside its folder
    CommonOptions common;
};

void pack(const PackOptions& opt, Context& ctx);

} // namespace pd::pipeline
