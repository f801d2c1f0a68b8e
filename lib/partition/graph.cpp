// SPDX-License-Identifier: MIT
#include "partition/graph.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <unordered_map>

namespace pd::partition {

namespace {

using Adjacency = std::vector<std::vector<std::int32_t>>;
using PairCounts = std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t>;

/// Bodies whose bounding spheres at `centre` come within `reach`: a sweep over the bodies sorted
/// by the low end of their x extent.
Adjacency near_bodies(const model::Bodies& B, double reach, const std::vector<double>& centre) {
    const std::size_t nb = B.num();
    Adjacency adj(nb);
    std::vector<std::size_t> order(nb);
    std::iota(order.begin(), order.end(), 0);
    auto lo = [&](std::size_t b) { return centre[3 * b] - B.bounding_radius[b]; };
    std::sort(order.begin(), order.end(), [&](auto a, auto b) { return lo(a) < lo(b); });
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
    return adj;
}

/// Surface-node pairs closer than `reach` between grains (body i < body j), on a cell grid of
/// spacing `reach`, over the grains that have a neighbour in `adj`. Grains displaced to `where`
/// are moved rigidly (rotation ignored).
PairCounts near_node_pairs(const model::Model& m, double reach, const std::vector<double>& where,
                           const Adjacency& adj) {
    const auto& B = m.bodies;
    const std::size_t nb = B.num();
    std::vector<double> shift(3 * nb, 0.0);
    if (!where.empty())
        for (std::size_t k = 0; k < 3 * nb; ++k)
            shift[k] = where[k] - B.center[k];
    auto pos = [&](std::size_t i, int d) {
        const auto b = static_cast<std::size_t>(m.nodes.body[i]);
        return m.nodes.x0[3 * i + static_cast<std::size_t>(d)] +
               shift[3 * b + static_cast<std::size_t>(d)];
    };
    auto key = [](std::int64_t cx, std::int64_t cy, std::int64_t cz) {
        return ((cx + (1 << 20)) << 42) | ((cy + (1 << 20)) << 21) | (cz + (1 << 20));
    };
    auto cell = [&](std::size_t i, int d) {
        return static_cast<std::int64_t>(std::floor(pos(i, d) / reach));
    };
    std::unordered_map<std::int64_t, std::vector<std::size_t>> cells;
    for (std::size_t i = 0; i < m.nodes.num(); ++i)
        if ((m.nodes.surface.empty() || m.nodes.surface[i]) &&
            !adj[static_cast<std::size_t>(m.nodes.body[i])].empty())
            cells[key(cell(i, 0), cell(i, 1), cell(i, 2))].push_back(i);
    PairCounts pairs;
    const int zr = m.dimension == 3 ? 1 : 0;
    for (const auto& [k, nodes] : cells) {
        const auto i0 = nodes.front();
        const auto cx = cell(i0, 0), cy = cell(i0, 1), cz = cell(i0, 2);
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -zr; dz <= zr; ++dz) {
                    auto it = cells.find(key(cx + dx, cy + dy, cz + dz));
                    if (it == cells.end())
                        continue;
                    for (auto i : nodes)
                        for (auto j : it->second) {
                            const auto bi = m.nodes.body[i], bj = m.nodes.body[j];
                            if (bi >= bj)
                                continue; // each pair once, no same-grain pairs
                            double d2 = 0;
                            for (int d = 0; d < 3; ++d)
                                d2 += std::pow(pos(j, d) - pos(i, d), 2);
                            if (d2 < reach * reach)
                                ++pairs[{bi, bj}];
                        }
                }
    }
    return pairs;
}

} // namespace

Graph body_graph(const model::Model& m, double reach, const std::vector<double>& where) {
    const auto& B = m.bodies;
    const std::size_t nb = B.num();
    auto adj = near_bodies(B, reach, where.empty() ? B.center : where);
    // Edge weights: the near node pairs of the two grains, at least 1: what their ranks would
    // exchange as contact ghosts.
    const PairCounts pairs = reach > 0 ? near_node_pairs(m, reach, where, adj) : PairCounts{};
    Graph g;
    for (std::size_t b = 0; b < nb; ++b) {
        std::sort(adj[b].begin(), adj[b].end());
        g.adjncy.insert(g.adjncy.end(), adj[b].begin(), adj[b].end());
        for (auto c : adj[b]) {
            const auto it = pairs.find({std::min(static_cast<std::int32_t>(b), c),
                                        std::max(static_cast<std::int32_t>(b), c)});
            g.adjwgt.push_back(it == pairs.end() ? 1 : std::max(1, it->second));
        }
        g.xadj.push_back(static_cast<std::int32_t>(g.adjncy.size()));
        const auto i0 = B.begin(b), i1 = B.end(b);
        const auto bonds = m.bonds.offsets[static_cast<std::size_t>(i1)] -
                           m.bonds.offsets[static_cast<std::size_t>(i0)];
        g.vwgt.push_back(static_cast<std::int32_t>(std::max<std::int64_t>(1, bonds + (i1 - i0))));
    }
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
