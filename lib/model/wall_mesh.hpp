// SPDX-License-Identifier: MIT
// The surface of a rigid triangulated wall (3D: triangles, e.g. from an STL file; 2D: segments of
// a polyline) in the wall's reference frame (its pose at t = 0), and the signed distance of a
// point from it. The distance is the distance to the closest point of the surface (on a face, an
// edge or a vertex); its sign is that of (x - closest) . N with N the face normal, or at an edge
// or a vertex the angle-weighted pseudo-normal of the cells that meet there (Baerentzen and
// Aanaes, IEEE TVCG 11 (2005) 243), so that it is exact for any closed or open oriented surface.
// Normals point into the free side (the grains' side): a triangle (a, b, c) faces (b-a) x (c-a)
// (STL's right-hand rule), a 2D segment (a, b) faces its left, z x (b - a) (a polygon listed
// counter-clockwise holds its grains inside). A closest point on an open rim (an edge of one
// triangle, the end of a polyline) counts as outside: the rim acts as a rounded edge.
// The closest-cell query is accelerated by a uniform grid of cells over the surface's bounding
// box; it answers exactly what the brute-force search over every cell answers (within `rmax`).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace pd::model {

/// Largest number of cells (triangles or segments) a wall mesh may have: bounded work per node.
inline constexpr std::size_t max_wall_mesh_cells = 200000;

class WallMesh {
  public:
    /// `points`: 3 per vertex (m; z = 0 in 2D); `cells`: 3 vertex indices per triangle (dim 3)
    /// or 2 per segment (dim 2). Call check_wall_mesh first: the constructor assumes a valid mesh.
    WallMesh(int dim, std::vector<double> points, std::vector<std::int32_t> cells);
    int dim() const { return dim_; }
    const std::vector<double>& points() const { return points_; }
    const std::vector<std::int32_t>& cells() const { return cells_; }
    std::size_t num_cells() const { return cells_.size() / static_cast<std::size_t>(dim_); }
    /// Signed distance of X (reference frame) and the unit normal n into the free side at the
    /// closest point, when the closest cell lies within rmax (rmax may be +infinity); false
    /// otherwise (d and n untouched). Grid-accelerated.
    bool closest(const double* X, double rmax, double& d, double n[3]) const;
    /// The same answer by testing every cell (tests; unbounded queries).
    bool closest_brute(const double* X, double rmax, double& d, double n[3]) const;

  private:
    struct Hit {
        double d2;
        std::int64_t cell;
        int feature; ///< 0: face/segment interior; 1-3: edge k-1 (triangles); 4-6: vertex k-4
        double q[3];
    };
    void test_cell(std::size_t c, const double* X, Hit& best) const;
    bool finish(const Hit& best, const double* X, double rmax, double& d, double n[3]) const;
    void build_normals();
    void build_grid();
    int dim_;
    std::vector<double> points_;
    std::vector<std::int32_t> cells_;
    std::vector<double> face_n_;   ///< 3 per cell: unit face normal
    std::vector<double> edge_n_;   ///< 9 per triangle: pseudo-normal of edge k (0: open rim)
    std::vector<double> vertex_n_; ///< 3 per vertex: pseudo-normal (0: on an open rim)
    // uniform grid: cell (i, j, k) -> CSR list of mesh cells whose bounding box overlaps it
    double lo_[3] = {0, 0, 0};
    double size_ = 1;
    std::int64_t n_[3] = {1, 1, 1};
    std::vector<std::int64_t> offsets_;
    std::vector<std::int32_t> items_;
};

/// What is wrong with a wall mesh ("" if nothing): a count of cells of 0 or above
/// max_wall_mesh_cells, an index out of range, a non-finite coordinate, a degenerate cell (area
/// or length below 1e-12 of the bounding box's), an edge shared by more than two cells or by two
/// cells of opposite orientation (their normals must all point into the free side).
std::string check_wall_mesh(int dim, const std::vector<double>& points,
                            const std::vector<std::int32_t>& cells);

/// Merges the vertices of a triangle soup (9 coordinates per triangle, as an STL file lists
/// them) that have equal coordinates: points and cells for WallMesh.
void weld_triangles(const std::vector<double>& soup, std::vector<double>& points,
                    std::vector<std::int32_t>& cells);

} // namespace pd::model
