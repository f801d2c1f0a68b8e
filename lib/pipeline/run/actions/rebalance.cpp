// SPDX-License-Identifier: MIT
// --rebalance (MPI): at the checkpoint steps before the last, re-partitions the grains where
// they are now: METIS on the current grain graph; adopted if it cuts fewer near-grain pairs than
// the partition in use. Collective.
#include "core/timer.hpp"
#include "partition/graph.hpp"
#include "pipeline/partition.hpp"
#include "pipeline/run/schedule.hpp"
#include "store/frames.hpp"

#include <algorithm>

namespace pd::pipeline::run {

namespace {

/// The new domain (already handed to the solver), or nullptr when the partition is kept.
std::unique_ptr<solver::Domain> repartition(const model::Model& m, solver::Solver& s,
                                            const std::vector<std::int32_t>& owner, Context& ctx,
                                            const std::string& file) {
    const double t0 = wall_seconds();
    MPI_Comm comm = s.domain().comm();
    const auto centre = s.body_centres();
    const std::size_t nb = m.bodies.num();
    std::vector<std::int32_t> next(m.nodes.num());
    std::int64_t cut[2] = {0, 0};
    if (ctx.rank == 0) {
        std::vector<std::int32_t> now(nb);
        bool whole = true;
        for (std::size_t b = 0; b < nb; ++b) {
            now[b] = owner[static_cast<std::size_t>(m.bodies.begin(b))];
            for (auto i = m.bodies.begin(b); i < m.bodies.end(b); ++i)
                whole = whole && owner[static_cast<std::size_t>(i)] == now[b];
        }
        if (whole && nb >= 4 * static_cast<std::size_t>(ctx.size)) {
            const auto p = make_partition(m, ctx.size, "body", file, centre);
            double reach = 0;
            for (const auto& c : m.contact)
                reach = std::max(reach, 2 * c.radius);
            cut[0] = partition::edge_cut(partition::body_graph(m, reach, centre), now);
            cut[1] = p.edge_cut;
            next = node_owner(m, p);
        }
    }
    MPI_Bcast(cut, 2, MPI_INT64_T, 0, comm);
    if (!(cut[1] < cut[0])) {
        ctx.log.info("rebalance at step {}: kept the partition (edge cut {}, a new one {}; "
                     "{:.3g} s)",
                     s.state().step, cut[0], cut[1], wall_seconds() - t0);
        return nullptr;
    }
    MPI_Bcast(next.data(), static_cast<int>(next.size()), MPI_INT32_T, 0, comm);
    auto dom = std::make_unique<solver::Domain>(comm, std::move(next));
    s.redistribute(dom.get());
    ctx.log.info("rebalance at step {}: re-partitioned the grains where they are (edge cut: "
                 "near node pairs across ranks {} -> {}) in {:.3g} s",
                 s.state().step, cut[0], cut[1], wall_seconds() - t0);
    return dom;
}

class Rebalance final : public Action {
  public:
    explicit Rebalance(const Run& r)
        : Action(Trigger().every(r.steps.ckpt_every).before(r.steps.last)) {}
    void run(Run& r, std::int64_t) override {
        if (auto next = repartition(r.m, r.s, r.dom->owner_map(), r.ctx, r.opt.file)) {
            r.frames.set_runs(next->runs());
            r.dom = std::move(next); // after s.redistribute(): the old one is done
        }
    }
};

} // namespace

std::unique_ptr<Action> make_rebalance(Run& r) {
    if (!r.opt.rebalance || !r.par)
        return nullptr;
    return std::make_unique<Rebalance>(r);
}

} // namespace pd::pipeline::run
