// SPDX-License-Identifier: MIT
// Drawable outlines of the rigid analytic walls (/walls) at a given time, for ParaView: pd-post
// writes them as their own series next to the node frames (`<stem>_walls_<k>.vtu` + `.pvd`, and a
// second temporal collection "walls" in the .xmf). The pose follows pd-solve's (solver::wall_pose:
// displacement = velocity T(t), rotation by angular_velocity T(t) about the moving rotation
// centre, T the wall's motion function); tests/unit/post/test_wall_outline.cpp holds the two
// equal. An infinite plane is drawn as a patch centred on the projection of the centre of the
// nodes' reference bounding box: in 2D a segment, in 3D a square, of side 1.2 x the box diagonal.
// A circle wall is a closed polyline of 128 segments (2D), a sphere a 16 x 32 latitude-longitude
// quadrilateral mesh (3D); their points turn with the wall. A triangulated wall is drawn as its
// cells in their pose (3D: one quadrilateral with a repeated corner per triangle). Meshed walls
// (fixed or driven bodies, e.g. a drum's protrusion) are nodes and are in the node frames already.
#pragma once

#include "model/model.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace pd::post {

/// Where planes are drawn: centre and half side of their patch.
struct WallExtent {
    std::array<double, 3> centre{0, 0, 0};
    double half = 1;
};

/// The extent of the nodes' reference positions (1.2 x the bounding-box diagonal; 1 m without
/// nodes, 1e-3 m for a single point).
WallExtent wall_extent(const model::Nodes& nodes);

/// The walls' outline at one time: 2D cells are segments (2 points), 3D cells quadrilaterals (4).
struct WallOutline {
    int points_per_cell = 2;
    std::vector<double> points;      ///< 3 per point, m
    std::vector<double> velocity;    ///< 3 per point: velocity of the wall surface, m s-1
    std::vector<std::int64_t> cells; ///< points_per_cell point indices per cell
    std::vector<std::int32_t> wall;  ///< per cell: index into /walls
    std::size_t num_points() const { return points.size() / 3; }
    std::size_t num_cells() const { return wall.size(); }
};

WallOutline wall_outline(const std::vector<model::Wall>& walls, int dimension,
                         const WallExtent& extent, double t);

} // namespace pd::post
