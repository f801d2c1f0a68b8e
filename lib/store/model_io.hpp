// SPDX-License-Identifier: MIT
// The static part of a pd-file (written by pd-pack): H5MD header, scene, materials, reference
// meshes, bodies, nodes, bonds, contact table, loading, solver settings.
#pragma once

#include "model/model.hpp"

namespace pd::h5 {
class File;
}

namespace pd::store {

/// Writes the root attributes, /h5md, /parameters and every static group of `m`.
void write_model(h5::File& f, const model::Model& m);

/// Reads and validates the static part. Each dataset is checked for presence, shape and range;
/// a violation throws SchemaError naming the file and dataset path.
model::Model read_model(const h5::File& f);

} // namespace pd::store
