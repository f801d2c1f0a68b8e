// SPDX-License-Identifier: MIT
#pragma once
/// Resource guard of pd-pack (issue 13): before anything is meshed or packed, a scene's node
/// estimate is turned into bonds and memory and refused above a limit the user can raise.
#include <string>

namespace pd::pipeline {

/// What a scene of `nodes` nodes needs: bonds at horizon = 3 h, whose families reach 3.5 h
/// (family_reach; pi 3.5^2 per node in 2D, 4/3 pi 3.5^3 in 3D), and pd-solve's peak memory at
/// one rank holding it (solve_peak_bytes). `state_based`: some material is LPS or RNP.
struct ResourceEstimate {
    double nodes = 0, bonds = 0, bytes = 0;
};
ResourceEstimate estimate_resources(double nodes, int dimension, bool state_based = false);

/// pd-solve's peak memory at one rank, bytes, for a scene of `nodes` nodes and `bonds` bond
/// entries (i-j and j-i both), PMB or (`state_based`) LPS/RNP: the measured fit of
/// resources.cpp.
double solve_peak_bytes(double nodes, double bonds, bool state_based = false);

/// The radius, in node spacings, of the families of a horizon of `ratio` node spacings: the
/// default quadrature's partial volumes reach delta + h/2.
double family_reach(double ratio);

/// Bytes of memory the system can give now (/proc/meminfo MemAvailable, else physical memory);
/// 0 when unknown.
double available_memory();

/// The default --max-nodes: the nodes whose estimate fits in the available memory (at least
/// 1e5, so that a busy machine still packs small scenes; 2e7 when the memory is unknown).
double default_max_nodes(int dimension, bool state_based = false);

/// Throws ConfigError(`key`) naming `what`, the estimate (nodes, bonds, memory) and the limit
/// when `nodes` exceeds `max_nodes` (<= 0: default_max_nodes(dimension)) or is not finite.
void check_node_budget(double nodes, double max_nodes, int dimension, bool state_based,
                       const std::string& key, const std::string& what);

/// Bonds per node of a regular grid at horizon = `ratio` x the node spacing (pi r^2 in 2D,
/// 4/3 pi r^3 in 3D).
double bonds_per_node(double ratio, int dimension);

/// Throws ConfigError(`key`) when `bonds` (an estimate at the scene's own horizon) exceeds what
/// the node limit allows at horizon 3 h (the limit x bonds_per_node(3.5)), or is not finite: a
/// large horizon_factor multiplies the bonds, not the nodes.
void check_bond_budget(double nodes, double bonds, double max_nodes, int dimension,
                       bool state_based, const std::string& key, const std::string& what);

} // namespace pd::pipeline
