// SPDX-License-Identifier: MIT
// Each grain's boundary for ParaView: the facets of its reference mesh (/reference_meshes, cells
// over the body's nodes) that belong to one cell only. 2D: segments of the triangles' and
// quadrilaterals' edges; 3D: triangles of the tetrahedra's faces and of the hexahedra's faces
// (split in two). The node frames' VTUs carry them as cells after the vertex cells, so ParaView
// draws outlines of the deformed grains (a broken grain keeps its reference outline: facets are
// not cut by damage). Bodies without a mesh (point clouds) have none.
#pragma once

#include "model/model.hpp"

#include <cstdint>
#include <vector>

namespace pd::post {

struct GrainOutline {
    int points_per_cell = 2;         ///< 2: segments (2D), 3: triangles (3D)
    std::vector<std::int64_t> cells; ///< points_per_cell global node indices per facet
    std::size_t num_cells() const {
        return cells.size() / static_cast<std::size_t>(points_per_cell);
    }
};

/// The boundary facets of every body's reference mesh, in global node indices (body by body, in
/// the order of its cells). A mesh whose cells index past its body's nodes is skipped.
GrainOutline grain_outline(const model::Model& m);

} // namespace pd::post
