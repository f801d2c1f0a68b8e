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

/// pd-solve's peak memory at one rank (the most a run of the scene needs; pd-pack needs less),
/// fitted to /usr/bin/time's maximum RSS of `pd-solve --steps 1` on PMB grid blocks (3D) and
/// plates (2D) of 0.13-2.0 M nodes and 22-84 M bonds (workflows/bench/RESULTS.md, issue 29
/// item 3): base_bytes + bytes_per_node per node + bytes_per_bond per bond entry (i-j and j-i
/// both), within 1 % of each. A bond of an LPS or RNP body costs more (its influence, the LPS
/// weighted volume factor and the LPS kernel's two work arrays per bond; an RNP bond its partial
/// volume instead of the last three), measured on 3D LPS blocks the same way (h = 1.25 and 1.0
/// mm: 45.3 B per bond with the PMB fit's base and per-node terms, from 63.7 before the LPS
/// bonds dropped kb and beta; RESULTS.md "Issue 29 item 3: LPS bytes per bond").
constexpr double base_bytes = 60e6;
constexpr double bytes_per_node = 385;
constexpr double bytes_per_bond = 22;
constexpr double bytes_per_state_bond = 46;

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

double family_reach(double ratio) {
    return ratio + 0.5;
}

double solve_peak_bytes(double nodes, double bonds, bool state_based) {
    return base_bytes + nodes * bytes_per_node +
           bonds * (state_based ? bytes_per_state_bond : bytes_per_bond);
}

ResourceEstimate estimate_resources(double nodes, int dimension, bool state_based) {
    // horizon 3 h, the usual one; families to delta + h/2
    const double per_node = bonds_per_node(family_reach(3), dimension);
    ResourceEstimate e;
    e.nodes = nodes;
    e.bonds = nodes * per_node;
    e.bytes = solve_peak_bytes(nodes, e.bonds, state_based);
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

double default_max_nodes(int dimension, bool state_based) {
    const double avail = available_memory();
    if (!(avail > 0))
        return 2e7;
    const double per_node = estimate_resources(1, dimension, state_based).bytes - base_bytes;
    return std::max(1e5, std::floor((avail - base_bytes) / per_node));
}

void check_node_budget(double nodes, double max_nodes, int dimension, bool state_based,
                       const std::string& key, const std::string& what) {
    const bool by_memory = !(max_nodes > 0);
    const double limit = by_memory ? default_max_nodes(dimension, state_based) : max_nodes;
    if (nodes <= limit)
        return;
    const auto e = estimate_resources(nodes, dimension, state_based);
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
                       bool state_based, const std::string& key, const std::string& what) {
    const bool by_memory = !(max_nodes > 0);
    const double limit_nodes = by_memory ? default_max_nodes(dimension, state_based) : max_nodes;
    const double limit = limit_nodes * bonds_per_node(family_reach(3), dimension);
    if (bonds <= limit)
        return;
    const double bytes = solve_peak_bytes(nodes, bonds, state_based);
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
