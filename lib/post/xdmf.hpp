// SPDX-License-Identifier: MIT
// XDMF 2 sidecar of a pd-file: a temporal collection of Polyvertex grids whose Geometry and
// Attributes are HyperSlab DataItems slicing frame k out of /particles/nodes/<field>/value
// ([T][N][3] or [T][N]) in the HDF5 file itself, so ParaView's XDMFReader (legacy, XDMF 2) and
// VisIt open the time series with no copy. body and volume come from /nodes (time-independent).
// With a model that has rigid walls, a second temporal collection "walls" holds their outlines
// at each frame's time (vtk_export_walls.hpp), inline as XML (a few hundred points per wall).
#pragma once

#include "model/model.hpp"

#include <cstddef>
#include <string>

namespace pd::h5 {
class File;
}

namespace pd::post {

/// Writes `xmf_path` describing every frame of `f`. `h5_ref` is the HDF5 file name as written in
/// the XML (a path relative to the .xmf, so the pair can be moved together). Only the frame
/// metadata (steps, times, field names) is read. Returns the number of frames described. Throws
/// SchemaError if /particles/nodes/position is missing, InputError if `xmf_path` cannot be written.
/// `m`, if given, supplies the rigid walls.
std::size_t write_xdmf(const h5::File& f, const std::string& xmf_path, const std::string& h5_ref,
                       const model::Model* m = nullptr);

} // namespace pd::post
