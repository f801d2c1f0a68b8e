// SPDX-License-Identifier: MIT
// pd-pack: scene (JSON) -> pd-file. The file is written under a temporary name and renamed when
// complete, so a failed run never leaves a half-written file (nor touches an existing one).
#pragma once

#include "core/tool.hpp"

#include <string>

namespace pd::pipeline {

struct PackOptions {
    std::string scene;  ///< JSON scene path
    std::string output; ///< pd-file to write
    CommonOptions common;
};

void pack(const PackOptions& opt, Context& ctx);

} // namespace pd::pipeline
