// SPDX-License-Identifier: MIT
#include "pipeline/partition.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "partition/graph.hpp"
#include "store/model_io.hpp"
#include "store/partition_io.hpp"
#include "store/provenance.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <unistd.h>

namespace pd::pipeline {

store::Partition make_partition(const model::Model& m, int num_parts, const std::string& by_in,
                                const std::string& file, const std::vector<double>& centre) {
    if (num_parts < 1)
        throw InputError(fmt::format("-n {}: the number of parts must be at least 1", num_parts));
    if (by_in != "auto" && by_in != "body" && by_in != "grain" && by_in != "node")
        throw InputError(fmt::format("--by {}: expected grain, node or auto", by_in));
    // auto: whole grains per part when there are enough of them (at least 4 per part, or one
    // when grain-level damping needs whole grains), else nodes (a plate, a few large grains).
    bool damped = false;
    for (const auto& c : m.contact)
        damped = damped || ((c.restitution < 1 || c.approach > 0) && c.stiffness > 0);
    const std::size_t enough = (damped ? 1 : 4) * static_cast<std::size_t>(num_parts);
    const std::string by = by_in == "grain"           ? "body"
                           : by_in != "auto"          ? by_in
                           : m.bodies.num() >= enough ? "body"
                                                      : "node";
    const std::size_t work = by == "body" ? m.bodies.num() : m.nodes.num();
    if (static_cast<std::size_t>(num_parts) > work)
        throw InputError(fmt::format("-n {}: more parts than the {} {} of {}", num_parts, work,
                                     by == "body" ? "grains" : "nodes", file));
    partition::Graph g;
    if (by == "body") {
        double reach = 0;
        for (const auto& c : m.contact)
            reach = std::max(reach, c.radius);
        reach *= 2; // contact radius plus a skin of the same size
        g = partition::body_graph(m, reach, centre);
    } else {
        g = partition::node_graph(m);
    }
    store::Partition p;
    p.by = by;
    p.num_parts = num_parts;
    p.method = num_parts == 1 ? "trivial" : "metis_kway";
    p.owner = partition::metis_partition(g, num_parts);
    p.edge_cut = partition::edge_cut(g, p.owner);
    p.imbalance = partition::imbalance(g, p.owner, num_parts);
    // The naive alternative for comparison: consecutive blocks of equal item counts.
    std::vector<std::int32_t> block(work);
    for (std::size_t i = 0; i < work; ++i)
        block[i] = static_cast<std::int32_t>(i * static_cast<std::size_t>(num_parts) / work);
    p.block_edge_cut = partition::edge_cut(g, block);
    p.block_imbalance = partition::imbalance(g, block, num_parts);
    return p;
}

std::vector<std::int32_t> node_owner(const model::Model& m, const store::Partition& p) {
    if (p.by == "node")
        return p.owner;
    std::vector<std::int32_t> owner(m.nodes.num());
    for (std::size_t b = 0; b < m.bodies.num(); ++b)
        for (auto i = m.bodies.begin(b); i < m.bodies.end(b); ++i)
            owner[static_cast<std::size_t>(i)] = p.owner[b];
    return owner;
}

void partition(const PartitionOptions& opt, Context& ctx) {
    if (opt.num_parts < 1)
        throw InputError(
            fmt::format("-n {}: the number of parts must be at least 1", opt.num_parts));
    if (::access(opt.file.c_str(), W_OK) != 0)
        throw InputError(fmt::format("{}: cannot write to this file ({}): pd-partition stores "
                                     "/partition in it",
                                     opt.file, std::strerror(errno)));
    model::Model m;
    {
        // Read only: a refused run leaves the file as it was, byte for byte.
        const h5::File rf(opt.file, h5::Mode::read);
        m = store::read_model(rf); // refuses a file it cannot read
    }
    const auto p = make_partition(m, opt.num_parts, opt.by, opt.file);
    auto f = std::make_shared<h5::File>(opt.file, h5::Mode::read_write);
    // Recorded from here: a refused run leaves the file as it was.
    ctx.on_exit = [f, &ctx](int code) { store::append_provenance(*f, ctx.run, code); };
    store::write_partition(*f, p);
    const std::size_t work = p.owner.size();
    ctx.log.info("partitioned {} {} of {} into {} parts ({}, by {}): edge cut {}, imbalance "
                 "{:.3f} (naive block split: edge cut {}, imbalance {:.3f})",
                 work, p.by == "body" ? "grains" : "nodes", opt.file, p.num_parts, p.method, p.by,
                 p.edge_cut, p.imbalance, p.block_edge_cut, p.block_imbalance);
}

} // namespace pd::pipeline
