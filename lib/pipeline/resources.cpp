// SPDX-License-Identifier: MIT
#include "pipeline/resources.hpp"

#include "core/errors.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <unistd.h>

namespace pd::pipeline {

namespace {

/// Bytes per node and per bond of a packed model held in memory (pd-pack builds the bond lists,
/// pd-solve adds state): positions, velocities, forces, volumes and per-node state, about 40
/// doubles; a bond stores its neighbour, reference length, state and the CSR copy, about 40 B.
constexpr double bytes_per_node = 320;
constexpr double bytes_per_bond = 40;

std::string human_bytes(double b) {
    const char* unit[] = {"B", "KB", "MB", "GB", "TB", "PB"};
    int k = 0;
    while (b >= 1000 && k < 5) {
        b /= 1000;
        ++k;
    }
    return fmt::format("{:.3g} {}", b, unit[k]);
}

} // namespace

double bonds_per_node(double ratio, int dimension) {
    return dimension == 3 ? 4.0 / 3.0 * std::numbers::pi * ratio * ratio * ratio
                          : std::numbers::pi * ratio * ratio;
}

ResourceEstimate estimate_resources(double nodes, int dimension) {
    const double per_node = bonds_per_node(3, dimension); // horizon 3 h, the usual one
    ResourceEstimate e;
    e.nodes = nodes;
    e.bonds = nodes * per_node;
    e.bytes = nodes * bytes_per_node + e.bonds * bytes_per_bond;
    return e;
}

double available_memory() {
    std::ifstream in("/proc/meminfo");
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream ss(line);
        std::string key;
        double kb = 0;
        if (ss >> key >> kb && key == "MemAvailable:" && kb > 0)
            return kb * 1024;
    }
    const long pages = ::sysconf(_SC_PHYS_PAGES), size = ::sysconf(_SC_PAGE_SIZE);
    return pages > 0 && size > 0 ? static_cast<double>(pages) * static_cast<double>(size) : 0;
}

double default_max_nodes(int dimension) {
    const double avail = available_memory();
    if (!(avail > 0))
        return 2e7;
    const double per_node = estimate_resources(1, dimension).bytes;
    return std::max(1e5, std::floor(avail / per_node));
}

void check_node_budget(double nodes, double max_nodes, int dimension, const std::string& key,
                       const std::string& what) {
    const bool by_memory = !(max_nodes > 0);
    const double limit = by_memory ? default_max_nodes(dimension) : max_nodes;
    if (nodes <= limit)
        return;
    const auto e = estimate_resources(nodes, dimension);
    const std::string why =
        by_memory ? fmt::format("the default, what fits in the {} of memory available now",
                                human_bytes(available_memory()))
                  : std::string("pd-pack --max-nodes");
    throw ConfigError(key, fmt::format("{} is estimated at {:.3g} nodes, {:.3g} bonds and {} of "
                                       "memory, above the limit of {:.3g} nodes ({}): coarsen "
                                       "mesh_size or reduce the count, or raise --max-nodes if "
                                       "the machine can hold it",
                                       what, e.nodes, e.bonds, human_bytes(e.bytes), limit, why));
}

void check_bond_budget(double nodes, double bonds, double max_nodes, int dimension,
                       const std::string& key, const std::string& what) {
    const bool by_memory = !(max_nodes > 0);
    const double limit_nodes = by_memory ? default_max_nodes(dimension) : max_nodes;
    const double limit = limit_nodes * bonds_per_node(3, dimension);
    if (bonds <= limit)
        return;
    const double bytes = nodes * bytes_per_node + bonds * bytes_per_bond;
    throw ConfigError(key, fmt::format("{} is estimated at {:.3g} nodes and {:.3g} bonds ({} of "
                                       "memory), above the limit of {:.3g} bonds ({:.3g} nodes "
                                       "at horizon 3 h, {}): a smaller horizon or coarser "
                                       "mesh_size, or raise --max-nodes if the machine can hold "
                                       "it",
                                       what, nodes, bonds, human_bytes(bytes), limit, limit_nodes,
                                       by_memory ? "the default, from the memory available now"
                                                 : "pd-pack --max-nodes"));
}

} // namespace pd::pipeline
