// SPDX-License-Identifier: MIT
// ParaView/meshio output of the frames in a pd-file: one .vtu per frame (points at the current
// positions, one VTK_VERTEX cell per point, point data = every stored nodal field + body +
// volume) and a .pvd collection listing the files with their times. Frames are streamed one at
// a time through store::FrameReader, so memory does not grow with the number of frames. The
// rigid walls, which have no nodes, get their own series (write_wall_series).
#pragma once

#include "model/model.hpp"
#include "post/outline.hpp"
#include "post/progress.hpp"

#include <cstddef>
#include <string>

namespace pd::h5 {
class File;
}

namespace pd::post {

/// What write_vtu_series produced.
struct VtuSeries {
    std::size_t frames = 0; ///< .vtu files written
    std::string pvd;        ///< path of the .pvd collection
};

/// Writes `<out_dir>/<stem>_<frame:06>.vtu` for every frame of `f` and `<out_dir>/<stem>.pvd`,
/// and removes `<stem>_<k:06>.vtu` files numbered after the last frame (an older, longer export).
/// `nodes` supplies body and volume (from store::read_model). `out_dir` must exist. Throws
/// SchemaError if the frames lack /particles/nodes/position or disagree with `nodes`, InputError
/// if a file cannot be written. `outline` (grain_outline): the grains' boundary facets, written
/// as line (2D) or triangle (3D) cells after the vertex cells.
VtuSeries write_vtu_series(const h5::File& f, const model::Nodes& nodes, const std::string& out_dir,
                           const std::string& stem, const Progress& progress = {},
                           const GrainOutline& outline = {});

/// Writes the rigid walls of `m` (model::Model::walls) at every frame's time:
/// `<out_dir>/<stem>_walls_<frame:06>.vtu` (segments in 2D, quadrilaterals in 3D; cell data
/// `wall` = index into /walls, point data `velocity` = the wall surface's velocity; see
/// vtk_export_walls.hpp) and `<out_dir>/<stem>_walls.pvd`, removing an older, longer export's
/// tail like write_vtu_series. Nothing is written when `m` has no rigid wall (pvd empty).
VtuSeries write_wall_series(const h5::File& f, const model::Model& m, const std::string& out_dir,
                            const std::string& stem);

} // namespace pd::post
