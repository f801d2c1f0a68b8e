// SPDX-License-Identifier: MIT
// /partition: which MPI part owns each body (by = "body") or node (by = "node").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pd::h5 {
class File;
}

namespace pd::store {

struct Partition {
    std::string by = "body"; ///< "body" or "node"
    std::string method;      ///< "metis_kway", "trivial"
    std::int32_t num_parts = 1;
    std::vector<std::int32_t> owner; ///< part of each body (or node)
    std::int64_t edge_cut = 0;       ///< weighted edges between parts
    double imbalance = 1.0;          ///< max part weight / mean part weight
    std::int64_t block_edge_cut = 0; ///< the same for consecutive blocks (naive split)
    double block_imbalance = 1.0;
};

void write_partition(h5::File& f, const Partition& p);
/// Reads /partition; throws SchemaError if absent or inconsistent with `num_items`.
Partition read_partition(const h5::File& f, std::size_t num_items);

} // namespace pd::store
