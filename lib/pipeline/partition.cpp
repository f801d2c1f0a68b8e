// SPDX-License-Identifier: MIT
#include "pipeline/partition.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "partition/graph.hpp"
#include "store/model_io.hpp"
#include "store/partition_io.hpp"
#include "store/provenance.hpp"

#include <algorithm>

namespace pd::pipeline {

void partition(const PartitionOptions& opt, Context& ctx) {
    auto f = std::make_shared<h5::File>(opt.file, h5::Mode::read_write);
    const model::Model m = store::read_model(*f); // refuses a file it cannot read, untouched
    ctx.on_exit = [f, &ctx](int code) { store::append_provenance(*f, ctx.run, code); };
    if (opt.num_parts < 1)
        throw InputError(
            fmt::format("-n {}: the number of parts must be at least 1", opt.num_parts));
    if (opt.by != "auto" && opt.by != "body" && opt.by != "node")
        throw InputError(fmt::format("--by {}: expected body, node or auto", opt.by));
    // auto: whole grains per part when there are enough of them (at least 4 per part), else
    // nodes (a plate, a few large grains).
    const std::string by = opt.by != "auto"                                                ? opt.by
                           : m.bodies.num() >= 4 * static_cast<std::size_t>(opt.num_parts) ? "body"
                                                                                           : "node";
    const std::size_t work = by == "body" ? m.bodies.num() : m.nodes.num();
    if (static_cast<std::size_t>(opt.num_parts) > work)
        throw InputError(fmt::format("-n {}: more parts than the {} {} of {}", opt.num_parts, work,
                                     by == "body" ? "grains" : "nodes", opt.file));
    partition::Graph g;
    if (by == "body") {
        double reach = 0;
        for (const auto& c : m.contact)
            reach = std::max(reach, c.radius);
        reach *= 2; // contact radius plus a skin of the same size
        g = partition::body_graph(m, reach);
    } else {
        g = partition::node_graph(m);
    }
    store::Partition p;
    p.by = by;
    p.num_parts = opt.num_parts;
    p.method = opt.num_parts == 1 ? "trivial" : "metis_kway";
    p.owner = partition::metis_partition(g, opt.num_parts);
    p.edge_cut = partition::edge_cut(g, p.owner);
    p.imbalance = partition::imbalance(g, p.owner, opt.num_parts);
    store::write_partition(*f, p);
    ctx.log.info("partitioned {} {} of {} into {} parts ({}, by {}): edge cut {}, imbalance "
                 "{:.3f}",
                 work, by == "body" ? "grains" : "nodes", opt.file, p.num_parts, p.method, by,
                 p.edge_cut, p.imbalance);
}

} // namespace pd::pipeline
