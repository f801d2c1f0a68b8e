// SPDX-License-Identifier: MIT
// grains.csv: one row per (frame, body): centre of mass and its velocity, rigid rotation of the
// best fit of the current to the reference node positions (2D Procrustes angle, unwrapped in
// time; 3D angle of the Kabsch rotation), volume-weighted damage, and the bond state of the body
// (broken bonds, fragments = connected components of intact bonds) where the file holds it.
// Frames are streamed (memory does not grow with the number of frames).
#pragma once

#include "model/model.hpp"
#include "post/progress.hpp"

#include <cstddef>
#include <string>

namespace pd::h5 {
class File;
}

namespace pd::post {

/// Writes the per-grain table of `m` and the frames of `f` to `csv_path`; returns the number of
/// data rows. The per-bond state is not stored per frame: `broken_bonds` and `fragments` are
/// exact at the frame whose step equals the latest checkpoint's (its bond_alive) and empty
/// elsewhere; `broken_bonds_est` = sum_i phi_i * deg_i / 2 over the body's nodes is an estimate
/// from damage on every frame (exact when the partial volumes of a node's bonds are equal).
/// Throws SchemaError if positions are missing, InputError if the CSV cannot be written.
std::size_t write_grains_csv(const h5::File& f, const model::Model& m, const std::string& csv_path,
                             const Progress& progress = {});

} // namespace pd::post
