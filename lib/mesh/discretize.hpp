// SPDX-License-Identifier: MIT
// From a mesh to peridynamic nodes: lumped nodal volumes (spec 2.1), mesh size h (spec 2.2) and
// the instance transform x = t + s R(theta) X (spec 2.5).
#pragma once

#include "model/model.hpp"

#include <array>

namespace pd::mesh {

/// Lumped nodal volumes: each triangle gives A/3 to its vertices, each tetrahedron V/4
/// (2D volumes are areas times a unit thickness).
std::vector<double> lumped_volumes(const model::RefMesh& m, int dimension);

/// Mesh size h = shortest mesh edge. For a Delaunay mesh this equals the minimum pairwise node
/// distance of spec 2.2 (the nearest-neighbour graph is a subgraph of the Delaunay graph), in
/// O(cells) instead of O(n^2).
double min_edge_length(const model::RefMesh& m);

/// Distance of every node to the nearest boundary node (m, reference coordinates), boundary
/// nodes being the vertices of facets used by one cell only (edges in 2D, faces in 3D); 0 for
/// every node of a mesh without cells. Nodes within the contact radius of the boundary are the
/// ones that take part in contact.
std::vector<double> boundary_distance(const model::RefMesh& m, int dimension);

/// Maximum distance of a node from the origin.
double bounding_radius(const model::RefMesh& m);

/// Appends the nodes of `m` transformed by rotation `theta` about z (through the origin), then
/// scale `s`, then translation `t`, to `x` (3 per node).
void place_instance(const model::RefMesh& m, double theta, double s, const std::array<double, 3>& t,
                    std::vector<double>& x);

} // namespace pd::mesh
