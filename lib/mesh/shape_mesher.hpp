// SPDX-License-Identifier: MIT
// Reference meshes of any geometry::Shape, made once per shape (spec 2.5): gmsh/OpenCASCADE in
// process (triangles or quads in 2D, tetrahedra in 3D), a uniform lattice discretisation, and
// gmsh .msh files (ASCII 2.2 and 4.x) read through the gmsh API.
#pragma once

#include "geometry/shapes.hpp"
#include "model/model.hpp"

#include <array>
#include <string>
#include <vector>

namespace pd::mesh {

struct MeshOptions {
    bool quads = false;           ///< 2D: recombine into quadrangles (all cells 4-node)
    bool embed_centroid = true;   ///< a node exactly at the centroid if it lies inside the shape
                                  ///< with clearance >= h/2 (PeriDEM's centre node, spec 2.5)
    double min_size_factor = 0.5; ///< gmsh Mesh.MeshSizeMin = factor * h
};

/// Meshes `shape` once with gmsh's OpenCASCADE kernel, target element size `h` (m), in the
/// shape's frame (placements included; grain shapes are centred at the origin). Circles and
/// ellipses are exact OCC curves; CSG uses OCC fuse/cut. 2D: linear triangles (nodes_per_cell 3)
/// or, with opt.quads, quadrangles (4); 3D: linear tetrahedra (4). Cells are positively
/// oriented (CCW in 2D). Not thread-safe (gmsh is global). Throws InputError for h <= 0 or
/// h > bounding radius, and for gmsh failures (message names the shape).
model::RefMesh mesh_shape(const geometry::Shape& shape, double h, const MeshOptions& opt = {});

/// Uniform lattice discretisation: the shape's bounding box is split into n_k = floor(L_k / h)
/// cells per axis (spacing h_k = L_k / n_k >= h, so a rectangle is tiled exactly, as PeriDEM's
/// built-in grid, spec 2.1). A cell is kept if its centre lies in the shape (so the boundary is a
/// staircase within half a cell of the true one); nodes are the vertices of kept cells, cells are
/// quadrangles (2D, CCW) or hexahedra (3D, VTK order). With nodal_volumes() every interior node
/// gets h_x h_y (h_x h_y h_z), nodes on a straight boundary half, convex corners a quarter (an
/// eighth in 3D), exactly PeriDEM's createUniformMesh weights for rectangles.
model::RefMesh uniform_grid(const geometry::Shape& shape, double h);

/// Reads a gmsh .msh file (any format gmsh::open reads: ASCII 2.2, 4.x, binary). dimension = 3:
/// tetrahedra; 2: triangles or quadrangles (a mix is an error, as in PeriDEM); 0: 3 if the file
/// has tetrahedra, else 2. Nodes not used by a kept cell are dropped. Throws InputError naming
/// the file if it cannot be read, has second-order cells or no cells of the dimension.
model::RefMesh read_msh(const std::string& path, int dimension = 0);

/// Area (2D) or volume (3D) and centroid of `shape` from its OpenCASCADE boundary representation
/// (gmsh occ::getMass / getCenterOfMass: curved faces and CSG booleans exact up to OCC's
/// integration tolerance, no meshing). An independent check of Shape::area_or_volume() and
/// centroid(), whose 3D CSG values come from an octree quadrature. Throws InputError for shapes
/// holding a surface_mesh (no OCC solid).
struct MassProperties {
    double measure = 0;
    std::array<double, 3> centroid{0, 0, 0};
};
MassProperties occ_mass_properties(const geometry::Shape& shape);

/// Lumped nodal volumes for every cell type made here: triangles A/3, quadrangles A/4,
/// tetrahedra V/4, hexahedra V/8 (2D: areas times unit thickness). A 4-node cell is a quadrangle
/// if dimension = 2 and a tetrahedron if 3. Equals discretize.hpp lumped_volumes() where that
/// applies.
std::vector<double> nodal_volumes(const model::RefMesh& m, int dimension);

} // namespace pd::mesh
