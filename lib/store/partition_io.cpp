// SPDX-License-Identifier: MIT
#include "store/partition_io.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "store/schema.hpp"

namespace pd::store {

void write_partition(h5::File& f, const Partition& p) {
    const std::string g = path::partition;
    f.remove(g);
    f.create_group(g);
    f.write(g + "/owner", p.owner);
    f.set_attr(g + "/owner", "unit", "1");
    f.set_attr(g, "by", p.by);
    f.set_attr(g, "method", p.method);
    f.set_attr(g, "num_parts", p.num_parts);
    f.set_attr(g, "edge_cut", p.edge_cut);
    f.set_attr(g, "imbalance", p.imbalance);
    f.set_attr(g, "block_edge_cut", p.block_edge_cut);
    f.set_attr(g, "block_imbalance", p.block_imbalance);
}

Partition read_partition(const h5::File& f, std::size_t num_items) {
    const std::string g = path::partition;
    if (!f.exists(g + "/owner"))
        throw SchemaError(f.name(), g + "/owner", "missing (run pd-partition first)");
    Partition p;
    p.owner = f.read<std::int32_t>(g + "/owner");
    p.by = f.attr_string(g, "by");
    p.method = f.attr_string(g, "method");
    p.num_parts = f.attr<std::int32_t>(g, "num_parts");
    p.edge_cut = f.attr<std::int64_t>(g, "edge_cut");
    p.imbalance = f.attr<double>(g, "imbalance");
    if (f.has_attr(g, "block_edge_cut")) {
        p.block_edge_cut = f.attr<std::int64_t>(g, "block_edge_cut");
        p.block_imbalance = f.attr<double>(g, "block_imbalance");
    }
    if (p.owner.size() != num_items)
        throw SchemaError(f.name(), g + "/owner",
                          fmt::format("has {} entries, expected {}", p.owner.size(), num_items));
    for (auto o : p.owner)
        if (o < 0 || o >= p.num_parts)
            throw SchemaError(f.name(), g + "/owner",
                              fmt::format("part {} outside [0, {})", o, p.num_parts));
    return p;
}

} // namespace pd::store
