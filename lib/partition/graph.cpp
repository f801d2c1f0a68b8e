// SPDX-License-Identifier: MIT
#include "partition/graph.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace pd::partition {

Graph body_graph(const model::Model& m, double reach, const std::vector<double>& where) {
    const auto& B = m.bodies;
    const std::size_t nb = B.num();
    const auto& centre = where.empty() ? B.center : where;
    std::vector<std::vector<std::int32_t>> adj(nb);
    std::vector<std::size_t> order(nb);
    std::iota(order.begin(), order.end(), 0);
    auto lo = [&](std::size_t b) { return centre[3 * b] - B.bounding_radius[b]; };
    std::sort(order.begin(), order.end(), [&](auto a, auto b) { return lo(a) < lo(b); });
    double rmax = 0;
    for (double r : B.bounding_radius)
        rmax = std::max(rmax, r);
    for (std::size_t ia = 0; ia < nb; ++ia) {
        const std::size_t a = order[ia];
        const double hi = centre[3 * a] + B.bounding_radius[a] + reach;
        for (std::size_t ib = ia + 1; ib < nb && lo(order[ib]) <= hi; ++ib) {
            const std::size_t b = order[ib];
            double d2 = 0;
            for (int k = 0; k < 3; ++k)
                d2 += std::pow(centre[3 * a + k] - centre[3 * b + k], 2);
            const double lim = B.bounding_radius[a] + B.bounding_radius[b] + reach;
            if (d2 < lim * lim) {
                adj[a].push_back(static_cast<std::int32_t>(b));
                adj[b].push_back(static_cast<std::int32_t>(a));
            }
        }
    }
    Graph g;
    for (std::size_t b = 0; b < nb; ++b) {
        std::sort(adj[b].begin(), adj[b].end());
        g.adjncy.insert(g.adjncy.end(), adj[b].begin(), adj[b].end());
        g.adjwgt.insert(g.adjwgt.end(), adj[b].size(), 1);
        g.xadj.push_back(static_cast<std::int32_t>(g.adjncy.size()));
        const auto i0 = B.begin(b), i1 = B.end(b);
        const auto bonds = m.bonds.offsets[static_cast<std::size_t>(i1)] -
                           m.bonds.offsets[static_cast<std::size_t>(i0)];
        g.vwgt.push_back(static_cast<std::int32_t>(std::max<std::int64_t>(1, bonds + (i1 - i0))));
    }
    (void)rmax;
    return g;
}

Graph node_graph(const model::Model& m) {
    Graph g;
    const auto n = m.nodes.num();
    g.xadj.assign(1, 0);
    g.adjncy.reserve(m.bonds.num());
    for (std::size_t i = 0; i < n; ++i) {
        const auto a = m.bonds.offsets[i], b = m.bonds.offsets[i + 1];
        for (auto k = a; k < b; ++k)
            g.adjncy.push_back(m.bonds.neighbor[static_cast<std::size_t>(k)]);
        g.xadj.push_back(static_cast<std::int32_t>(g.adjncy.size()));
        g.vwgt.push_back(static_cast<std::int32_t>(b - a + 1));
    }
    g.adjwgt.assign(g.adjncy.size(), 1);
    return g;
}

std::int64_t edge_cut(const Graph& g, const std::vector<std::int32_t>& part) {
    std::int64_t cut = 0;
    for (std::size_t v = 0; v < g.num_vertices(); ++v)
        for (auto e = g.xadj[v]; e < g.xadj[v + 1]; ++e)
            if (part[v] != part[static_cast<std::size_t>(g.adjncy[static_cast<std::size_t>(e)])])
                cut += g.adjwgt[static_cast<std::size_t>(e)];
    return cut / 2;
}

double imbalance(const Graph& g, const std::vector<std::int32_t>& part, int num_parts) {
    std::vector<double> w(static_cast<std::size_t>(num_parts), 0.0);
    double total = 0;
    for (std::size_t v = 0; v < g.num_vertices(); ++v) {
        w[static_cast<std::size_t>(part[v])] += g.vwgt[v];
        total += g.vwgt[v];
    }
    const double mean = total / num_parts;
    return mean > 0 ? *std::max_element(w.begin(), w.end()) / mean : 1.0;
}

} // namespace pd::partition
