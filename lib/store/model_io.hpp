// SPDX-License-Identifier: MIT
// The static part of a pd-file (written by pd-pack): H5MD header, scene, materials, reference
// meshes, bodies, nodes, bonds, contact table, loading, solver settings.
#pragma once

#include "model/model.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace pd::h5 {
class File;
}

namespace pd::store {

/// Writes the root attributes, /h5md, /parameters and every static group of `m`.
void write_model(h5::File& f, const model::Model& m);

/// pd-solve --restart --set: rewrites /walls and /loading from `m` (serial file; raises
/// /@schema_version to this build's).
void write_walls_and_loading(h5::File& f, const model::Model& m);

/// pd-solve, when wall k entered above the grains: its rows of /walls/point and /walls/centre
/// (every rank calls it under MPI-IO; rank 0 writes).
void write_wall_position(h5::File& f, std::size_t k, const model::Wall& w);

/// Reads and validates the static part. Each dataset is checked for presence, shape and range;
/// a violation throws SchemaError naming the file and dataset path.
/// With `neighbors` false, /bonds/neighbor is left unread (m.bonds.complete() is false).
model::Model read_model(const h5::File& f, bool neighbors = true);

/// The neighbour lists of the nodes in `runs` ([begin, end) node ranges, ascending), concatenated
/// in node order: hyperslab reads of /bonds/neighbor, checked against the node count; the whole
/// list (one run over every node: pd-solve at one rank) also as read_model checks it (each bond
/// once in each direction).
std::vector<model::index_t> read_bond_rows(const h5::File& f, const model::Model& m,
                                           const std::vector<std::array<std::uint64_t, 2>>& runs);

} // namespace pd::store
