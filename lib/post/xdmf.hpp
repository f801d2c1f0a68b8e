// SPDX-License-Identifier: MIT
// XDMF 2 sidecar of a pd-file: a temporal collection of Polyvertex grids whose Geometry and
// Attributes are HyperSlab DataItems slicing frame k out of /particles/nodes/<field>/value
// ([T][N][3] or [T][N]) in the HDF5 file itself, so ParaView's XDMFReader (legacy, XDMF 2) and
// VisIt open the time series with no copy. body and volume come from /nodes (time-independent).
#pragma once

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
std::size_t write_xdmf(const h5::File& f, const std::string& xmf_path, const std::string& h5_ref);

} // namespace pd::post
