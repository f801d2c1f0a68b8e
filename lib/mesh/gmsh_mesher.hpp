// SPDX-License-Identifier: MIT
// Reference meshes made in-process with the gmsh API (gmsh only here). Each reference shape is
// meshed once, centred at the origin, and instanced by rotation, scale and translation (spec 2.5).
#pragma once

#include "model/model.hpp"

namespace pd::mesh {

/// Triangle mesh of a disc of radius `radius` with target size `h`; the centre is a mesh node.
model::RefMesh mesh_disc(double radius, double h);

} // namespace pd::mesh
