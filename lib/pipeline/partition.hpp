// SPDX-License-Identifier: MIT
// pd-partition: METIS partition of the grain graph of a pd-file; writes /partition.
#pragma once

#include "core/tool.hpp"

#include <string>

namespace pd::pipeline {

struct PartitionOptions {
    std::string file;
    int num_parts = 1;
    std::string by = "auto"; ///< "body" (grain graph), "node" (bond graph) or "auto"
    CommonOptions common;
};

void partition(const PartitionOptions& opt, Context& ctx);

} // namespace pd::pipeline
