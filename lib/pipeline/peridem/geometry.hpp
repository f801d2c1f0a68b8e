// SPDX-License-Identifier: MIT
// PeriDEM zone geometry -> scene shapes (internal to the importer): the deck's geometry objects,
// the outline of a 2D mesh, and whether a shape describes a mesh.
#pragma once

#include "geometry/shapes.hpp"
#include "model/model.hpp"
#include "pipeline/peridem/deck.hpp"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace pd::pipeline::peridem {

/// One zone's reference geometry as a scene shape (JSON) and the same shape for checks.
struct ZoneShape {
    json spec;
    geometry::Shape shape = geometry::Shape::circle(1); // replaced before use
    double p0 = 0; ///< Parameters[0]: the length a CSV radius scales (spec 2.5)
};

/// Box [lo, hi] of a PeriDEM rectangle with 6 (corners), 5 (Lx, Ly, centre) or 2 (Lx, Ly)
/// parameters.
std::optional<std::array<double, 4>> rectangle_box(const std::vector<double>& p);

/// PeriDEM geometry (Type, Parameters) -> shape, with Parameters[0] replaced by `r` if r > 0.
std::optional<ZoneShape> deck_shape(const std::string& type, std::vector<double> p,
                                    const std::string& key, double r = 0);

/// The boundary of a 2D mesh as a polygon (holes subtracted), collinear vertices removed.
std::optional<ZoneShape> mesh_outline(const model::RefMesh& m);

/// Does the shape describe the mesh: every node inside (to 1e-6 R) and the mesh area within 3%?
bool fits(const geometry::Shape& s, const model::RefMesh& m, int dim);

} // namespace pd::pipeline::peridem
