// SPDX-License-Identifier: MIT
// pd-post's rigid-wall outlines sit where pd-solve's walls are: for translating, rotating and
// non-linearly moving walls (quadratic, sine motion; rotation about an off-centre point), every
// plane point lies on solver::wall_pose's plane and every circle/sphere point at the radius from
// its centre, at several times.
#include "post/vtk_export_walls.hpp"
#include "solver/walls.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using pd::model::TimeFn;
using pd::model::Wall;
using pd::model::WallShape;

std::vector<Wall> walls() {
    Wall plane;
    plane.shape = WallShape::plane;
    plane.point = {0.001, 0.002, 0};
    plane.normal = {0.6, 0.8, 0};
    plane.velocity = {0.3, -0.2, 0};
    plane.angular_velocity = {0, 0, 50};
    plane.centre = {-0.002, 0.001, 0};
    plane.motion = TimeFn::quadratic;
    plane.motion_params = {40, 0, 0, 0};
    Wall drum;
    drum.shape = WallShape::circle_inside;
    drum.point = {0.001, 0, 0};
    drum.radius = 0.004;
    drum.angular_velocity = {0, 0, -30};
    drum.centre = {-0.001, 0.0005, 0}; // turns about an off-centre point: the centre moves
    drum.motion = TimeFn::sine;
    drum.motion_params = {100, 0, 0, 0};
    Wall ball;
    ball.shape = WallShape::circle_outside;
    ball.point = {0, 0, 0.003};
    ball.radius = 0.002;
    ball.velocity = {0, 0.5, 0};
    ball.centre = ball.point;
    return {plane, drum, ball};
}

double dist(const double* x, const std::array<double, 3>& c) {
    return std::sqrt((x[0] - c[0]) * (x[0] - c[0]) + (x[1] - c[1]) * (x[1] - c[1]) +
                     (x[2] - c[2]) * (x[2] - c[2]));
}

void check(int dimension) {
    const auto ws = walls();
    pd::post::WallExtent extent;
    extent.centre = {0, 0, 0};
    extent.half = 0.01;
    for (double t : {0.0, 1e-3, 7.3e-3, 2e-2}) {
        const auto o = pd::post::wall_outline(ws, dimension, extent, t);
        ASSERT_EQ(o.points_per_cell, dimension == 3 ? 4 : 2);
        ASSERT_EQ(o.cells.size(), o.num_cells() * static_cast<std::size_t>(o.points_per_cell));
        std::vector<int> seen(ws.size(), 0);
        for (std::size_t c = 0; c < o.num_cells(); ++c) {
            const auto k = static_cast<std::size_t>(o.wall[c]);
            ++seen[k];
            const auto p = pd::solver::wall_pose(ws[k], t);
            for (int j = 0; j < o.points_per_cell; ++j) {
                const double* x =
                    o.points.data() + 3 * o.cells[c * static_cast<std::size_t>(o.points_per_cell) +
                                                  static_cast<std::size_t>(j)];
                if (ws[k].shape == WallShape::plane) {
                    double d = 0;
                    for (int a = 0; a < 3; ++a)
                        d += (x[a] - p.point[a]) * p.normal[a];
                    EXPECT_NEAR(d, 0, 1e-17) << "t " << t;
                } else {
                    EXPECT_NEAR(dist(x, p.point), ws[k].radius, 1e-17) << "t " << t;
                }
                if (dimension == 2) {
                    EXPECT_EQ(x[2], ws[k].shape == WallShape::plane ? 0.0 : p.point[2]);
                }
            }
        }
        for (std::size_t k = 0; k < ws.size(); ++k)
            EXPECT_GT(seen[k], 0) << "wall " << k << " not drawn";
    }
}

TEST(WallOutline, FollowsTheSolversPoseIn2D) {
    check(2);
}
TEST(WallOutline, FollowsTheSolversPoseIn3D) {
    check(3);
}

TEST(WallOutline, DrumPointsTurnWithTheDrum) {
    Wall drum;
    drum.shape = WallShape::circle_inside;
    drum.radius = 0.01;
    drum.angular_velocity = {0, 0, 2.0};
    const auto o = pd::post::wall_outline({drum}, 2, {}, 0.25); // turned by 0.5 rad
    EXPECT_NEAR(o.points[0], 0.01 * std::cos(0.5), 1e-17);
    EXPECT_NEAR(o.points[1], 0.01 * std::sin(0.5), 1e-17);
    // surface velocity omega x r
    EXPECT_NEAR(o.velocity[0], -2.0 * o.points[1], 1e-15);
    EXPECT_NEAR(o.velocity[1], 2.0 * o.points[0], 1e-15);
}

TEST(WallOutline, PlanePatchIsCentredOnTheNodes) {
    pd::model::Nodes nodes;
    nodes.x0 = {0, 0, 0, 0.004, 0.003, 0};
    nodes.volume = {1, 1};
    const auto e = pd::post::wall_extent(nodes);
    EXPECT_DOUBLE_EQ(e.centre[0], 0.002);
    EXPECT_DOUBLE_EQ(e.centre[1], 0.0015);
    EXPECT_DOUBLE_EQ(e.half, 0.6 * 0.005);
    Wall floor; // y = -0.001, normal +y
    floor.point = {5, -0.001, 0};
    const auto o = pd::post::wall_outline({floor}, 2, e, 0);
    ASSERT_EQ(o.num_points(), 2u);
    EXPECT_DOUBLE_EQ(o.points[0] + o.points[3], 0.004); // centred at x = 0.002
    EXPECT_DOUBLE_EQ(o.points[1], -0.001);
    EXPECT_DOUBLE_EQ(o.points[4], -0.001);
}

TEST(WallOutline, BoxOfPlanesIsDrawnAsABox) {
    // Issue 28: six planes around the grains in 3D drew six crossing squares 1.2 x the nodes'
    // diagonal; each is now clipped by the others to the box face it bounds.
    pd::model::Nodes nodes;
    nodes.x0 = {0, 0, 0, 0.004, 0.003, 0.002};
    nodes.volume = {1, 1};
    const auto e = pd::post::wall_extent(nodes);
    const double lo[3] = {-0.001, -0.001, -0.001}, hi[3] = {0.005, 0.004, 0.003};
    std::vector<Wall> box;
    for (int d = 0; d < 3; ++d)
        for (int sgn : {1, -1}) {
            Wall w;
            w.point = {0, 0, 0};
            w.point[static_cast<std::size_t>(d)] = sgn > 0 ? lo[d] : hi[d];
            w.normal = {0, 0, 0};
            w.normal[static_cast<std::size_t>(d)] = sgn;
            w.centre = w.point;
            box.push_back(w);
        }
    const auto o = pd::post::wall_outline(box, 3, e, 0);
    ASSERT_EQ(o.num_cells(), 6u); // one quadrilateral per face
    for (std::size_t i = 0; i < o.num_points(); ++i)
        for (int d = 0; d < 3; ++d) {
            const double x = o.points[3 * i + static_cast<std::size_t>(d)];
            EXPECT_TRUE(std::abs(x - lo[d]) < 1e-15 || std::abs(x - hi[d]) < 1e-15)
                << "point " << i << " axis " << d << ": " << x;
        }
}

TEST(WallOutline, WallAtRestBeforeItsStartTime) {
    Wall plate;
    plate.point = {0, 0.01, 0};
    plate.normal = {0, -1, 0};
    plate.velocity = {0, -1, 0};
    plate.centre = plate.point;
    plate.start_time = 0.5;
    pd::post::WallExtent e;
    e.half = 0.01;
    EXPECT_DOUBLE_EQ(pd::post::wall_outline({plate}, 2, e, 0.4).points[1], 0.01);
    EXPECT_DOUBLE_EQ(pd::post::wall_outline({plate}, 2, e, 0.75).points[1], 0.01 - 0.25);
}

} // namespace
