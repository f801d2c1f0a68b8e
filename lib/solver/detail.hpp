// SPDX-License-Identifier: MIT
// The solver's own steps on the shared Forces (internal to lib/solver): the bond rows of this
// rank, the conditions, the pre-cracks, the external power.
#pragma once

#include "solver/forces.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace pd::solver::detail {

/// The rows `rows` of a whole bond-list array (CSR `whole`), concatenated: this rank's CSR.
template <class T>
std::vector<T> rows_of(const std::vector<T>& from, const std::vector<offset_t>& whole,
                       const std::vector<index_t>& rows) {
    std::size_t total = 0; // exactly: a per-bond array (no growth slack)
    for (auto row : rows)
        total += static_cast<std::size_t>(whole[static_cast<std::size_t>(row) + 1] -
                                          whole[static_cast<std::size_t>(row)]);
    std::vector<T> out;
    out.reserve(total);
    for (auto row : rows) {
        const auto i = static_cast<std::size_t>(row);
        out.insert(out.end(), from.begin() + whole[i], from.begin() + whole[i + 1]);
    }
    return out;
}

/// Writes this rank's CSR rows (`local`, over `rows`) into their places of a whole-list array.
template <class T>
void put_rows(const std::vector<T>& from, const std::vector<offset_t>& local,
              const std::vector<index_t>& rows, const std::vector<offset_t>& whole,
              std::vector<T>& to) {
    for (std::size_t a = 0; a < rows.size(); ++a)
        std::copy(from.begin() + local[a], from.begin() + local[a + 1],
                  to.begin() + whole[static_cast<std::size_t>(rows[a])]);
}

// bond_rows.cpp
/// |X_j - X_i| of nodes i and j in x0 (3 per node): a bond's reference length xi, the same bits
/// wherever it is computed (build_bonds; bond_spectrum restores xi with it).
/// Inline: bond_spectrum calls it twice per bond.
inline double bond_length(const std::vector<double>& x0, std::size_t i, std::size_t j) {
    double r2 = 0;
    for (std::size_t d = 0; d < 3; ++d)
        r2 += std::pow(x0[3 * j + d] - x0[3 * i + d], 2);
    return std::sqrt(r2);
}
/// Per-body constants of the bond laws (f.law), from the materials (constructor).
void law_constants(Forces& f);
/// This rank's rows of the bond list (reference lengths, factors, influence; alive = 1), the
/// neighbour lists from the model or from `row_neighbors` (then emptied).
void build_bonds(Forces& f, std::vector<index_t>& row_neighbors);
/// Ghosts for the bond neighbours owned elsewhere (collective).
void set_bond_ghosts(Forces& f);
/// Surface-correction factors and LPS weighted volumes of the rows and their ghosts
/// (collective; after set_bond_ghosts()).
void family_factors(Forces& f);
/// Every node's neighbour list (the model's, or gathered from the ranks; collective).
std::vector<index_t> global_neighbors(const Forces& f);
/// Broken bond ends in this rank's rows.
std::int64_t count_broken(const Forces& f);

// handover.cpp
/// Every ghost gets its owner's u and v, and x = x0 + u (collective, neighbour-only).
void exchange_motion(Forces& f);

// conditions.cpp
/// Per condition: the x and y range of its nodes (space functions); marks the prescribed
/// components and sizes fbc when some condition is a force.
void condition_boxes(Forces& f);
/// Sets u, v, x of prescribed components at time s.time (spec 5.6).
void apply_displacements(Forces& f);
/// Breaks the bonds that cross a pre-crack segment.
void break_precracks(Forces& f);
/// Power of gravity, force conditions, prescribed displacements and moving walls (W).
double external_power(const Forces& f);
/// Does external_power() sum over the nodes (gravity, force or displacement conditions)?
inline bool node_power_needed(const Forces& f) {
    return f.has_gravity() || !f.fbc.empty() || f.has_prescribed;
}
/// Node i's share of external_power() (0 unless it moves).
inline double node_power(const Forces& f, std::size_t i) {
    if (!f.s.moving[i])
        return 0.0;
    const bool bc = !f.fbc.empty();
    double p = 0;
    for (std::size_t d = 0; d < 3; ++d) {
        const double ext = f.s.rho[i] * f.g[d] + (bc ? f.fbc[3 * i + d] : 0.0);
        p += ext * f.s.v[3 * i + d];
        if (f.s.fixed_dof[i] & (1u << d))
            p -= f.s.f[3 * i + d] * f.s.v[3 * i + d];
    }
    return p * f.s.vol[i];
}
/// external_power() given the nodes' sum `nodes` (the moving walls' share added).
double external_power(const Forces& f, double nodes);

} // namespace pd::solver::detail
