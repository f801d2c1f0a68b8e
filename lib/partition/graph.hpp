// SPDX-License-Identifier: MIT
// Graphs to partition (CSR, METIS' xadj/adjncy form) and partition quality measures.
#pragma once

#include "model/model.hpp"

#include <cstdint>
#include <vector>

namespace pd::partition {

/// Undirected graph in CSR form; every edge stored in both directions.
struct Graph {
    std::vector<std::int32_t> xadj{0};
    std::vector<std::int32_t> adjncy;
    std::vector<std::int32_t> vwgt;   ///< vertex weights (work)
    std::vector<std::int32_t> adjwgt; ///< edge weights (communication)
    std::size_t num_vertices() const { return xadj.size() - 1; }
};

/// Grain graph: one vertex per body, weight = its bond count + node count; an edge between two
/// bodies whose bounding spheres come within `reach` (contact radius plus skin) of each other,
/// weighted by their surface-node pairs closer than `reach` (at least 1).
/// Sweep over bodies sorted by x: O(nb log nb + candidate pairs).
/// `centre` (3 per body): where the grains are now (default: their reference centres).
Graph body_graph(const model::Model& m, double reach, const std::vector<double>& centre = {});

/// Node graph: one vertex per node (weight = its bond count + 1), edges = bonds (weight 1).
/// For few large bodies (a plate, a single grain).
Graph node_graph(const model::Model& m);

/// Sum of weights of edges whose ends lie in different parts.
std::int64_t edge_cut(const Graph& g, const std::vector<std::int32_t>& part);

/// Max part weight over mean part weight (1 = perfect balance).
double imbalance(const Graph& g, const std::vector<std::int32_t>& part, int num_parts);

/// METIS k-way partition (fixed seed: reproducible); parts in [0, num_parts).
std::vector<std::int32_t> metis_partition(const Graph& g, int num_parts);

} // namespace pd::partition
