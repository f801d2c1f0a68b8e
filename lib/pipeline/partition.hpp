// SPDX-License-Identifier: MIT
// pd-partition: METIS partition of the grain graph of a pd-file; writes /partition.
#pragma once

#include "core/tool.hpp"
#include "model/model.hpp"
#include "store/partition_io.hpp"

#include <string>

namespace pd::pipeline {

struct PartitionOptions {
    std::string file;
    int num_parts = 1;
    std::string by = "auto"; ///< "body" or "grain" (grain graph), "node" (bond graph) or "auto"
    CommonOptions common;
};

void partition(const PartitionOptions& opt, Context& ctx);

/// The partition pd-partition writes, in memory (pd-solve re-partitions with it when the file's
/// /partition was made for another rank count). `by`: "body" (alias "grain"), "node", "auto".
/// Throws InputError for more parts than work.
/// `centre` (3 per body, optional): current grain centres for a grain partition.
store::Partition make_partition(const model::Model& m, int num_parts, const std::string& by,
                                const std::string& file, const std::vector<double>& centre = {});

/// Owner rank of every node under `p` (by body or by node).
std::vector<std::int32_t> node_owner(const model::Model& m, const store::Partition& p);

} // namespace pd::pipeline
