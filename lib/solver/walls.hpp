// SPDX-License-Identifier: MIT
// Contact of nodes with rigid walls (planes, circles/spheres inside or outside, triangulated
// surfaces and polylines: model/wall_mesh.hpp; fixed, translating or rotating). A mesh wall's
// distance is found in its reference frame (the node moved by the inverse pose) and only within
// the candidate reach R_c + skin: a node deeper than that behind a mesh face is not pushed. A wall
// acts on a node like a mirror node of the same volume behind its surface: f_i = Kn (R_c - d) V_i n
// for signed distance d < R_c (n into the free side), with the (grain group, wall group) law of the
// contact table. Coulomb friction opposes slip relative to the moving wall surface. Every wall
// receives the reaction force and its moment about the wall's rotation centre. Candidate nodes
// (every moving node within R_c + skin of a wall; none is skipped by its depth in its grain) are
// kept in a list with a skin, rebuilt when a node moved more than half the skin minus a bound on
// how far any wall point near a node moved (translation plus rotation times the farthest node's
// distance from the rotation centre plus the reach).
#pragma once

#include "model/model.hpp"
#include "solver/state.hpp"

#include <array>
#include <vector>

namespace pd::solver {

/// Position of a wall at time t.
struct WallPose {
    std::array<double, 3> point;  ///< m
    std::array<double, 3> normal; ///< unit (plane)
    std::array<double, 3> centre; ///< m, rotation centre
    std::array<double, 3> velocity;
    std::array<double, 3> omega;
    std::array<double, 3> theta; ///< rad, rotation vector since t = 0
};
WallPose wall_pose(const model::Wall& w, double t);
/// Signed distance of x from wall w at pose p (positive on the free side) and the unit normal n
/// into the free side at the closest point; a mesh wall's closest cell is searched within rmax
/// (+infinity, n = 0, if none lies within it).
double wall_distance(const model::Wall& w, const WallPose& p, const double* x, double n[3],
                     double rmax);

/// Per-wall contact result of one force evaluation.
struct WallLoad {
    std::vector<double> force;  ///< 3 per wall, N (2D: per unit thickness), received by the wall
    std::vector<double> moment; ///< 3 per wall, N m, about the wall's current rotation centre
    std::int64_t touching = 0;  ///< node-wall pairs in contact
    double energy = 0;          ///< J, wall springs (node law 1/2 Kn (R_c - d)^2 V_i^2)
    /// J: the correction of the trapezoidal wall work of the last step for the node-wall pairs
    /// that came into contact during it, or that were within the surface law's onset (the first
    /// 0.01 h, where the force is quadratic in the depth) at its start: the change of their
    /// spring energy as the wall moved (the work of the wall that moved into them, exactly, the
    /// nodes' motion within the step aside) less the trapezoid's share dt/2 (F + F_before) .
    /// v_wall. The trapezoid alone over-counts first contacts by v_wall dt / overlap (a plate
    /// onto a grain at rest: 1.8-4 x at the first contact step).
    double work = 0;
    /// Nodes more than h/2 (their body's mesh size) beyond a wall's surface: contact failed
    /// (pd-solve stops, exit 3); one of them and its wall (-1: none).
    std::int64_t beyond = 0;
    std::int64_t beyond_node = -1;
    std::int32_t beyond_wall = -1;
};

/// Normal contact force on a body from one wall in one evaluation (for damping).
struct BodyWallForce {
    std::int32_t body;
    std::int32_t wall;
    index_t node;
    double force[3]; ///< normal force on the body, N
    double friction; ///< Coulomb coefficient of the law
    bool damped;     ///< the law has restitution < 1
};

class WallContact {
  public:
    WallContact(const model::Model& m, double skin);
    bool active() const { return active_; }
    /// Rebuilds candidate lists if a node or a wall moved more than half the skin.
    bool update(const State& s);
    /// Adds normal wall contact force densities to s.f at time s.time; with `normal`, lists the
    /// touching node-wall pairs whose law damps or has friction (sorted by node).
    /// `dt` > 0: also the walls' work over the step ending now (WallLoad::work).
    void add_forces(State& s, WallLoad& load, std::vector<BodyWallForce>* normal,
                    double dt = 0) const;
    std::size_t num_walls() const { return walls_.size(); }
    /// The next update() rebuilds (after a change of ownership).
    void invalidate() { built_ = false; }
    /// Wall k is now `w` (placed at its entry, changed at a restart); the next update() rebuilds.
    void set_wall(std::size_t k, const model::Wall& w) {
        walls_[k] = w;
        built_ = false;
    }
    std::int64_t rebuilds() const { return rebuilds_; }
    double max_radius() const { return rc_max_; }

  private:
    /// What add_nodes reads and the records it fills (shared by the threads).
    struct Step {
        const std::vector<WallPose>& pose;
        const std::vector<std::uint8_t>& present;
        WallLoad& load;
        std::vector<BodyWallForce>* normal;
        std::vector<BodyWallForce>& records;
    };
    void rebuild(const State& s);
    /// WallLoad::work of the step that ends with the walls at `pose` (before: `prev`).
    double first_contact(const State& s, const std::vector<WallPose>& pose,
                         const std::vector<WallPose>& prev,
                         const std::vector<std::uint8_t>& present,
                         const std::vector<std::uint8_t>& present_prev, double dt) const;
    void add_nodes(State& s, const Step& st, std::int64_t& touching, double& energy,
                   std::int64_t& beyond, double* fmp) const;
    // add_forces' work arrays, kept between calls (their sizes do not change).
    mutable std::vector<WallPose> pose_, pose_prev_;
    mutable std::vector<std::uint8_t> present_prev_;
    bool moving_ = false; ///< some wall moves (translation or rotation) or enters later
    mutable std::vector<std::uint8_t> present_;
    mutable std::vector<double> fm_;
    const model::Model& m_;
    std::vector<model::Wall> walls_;
    std::vector<std::int32_t> law_; ///< per (body group, wall): index into m_.contact or -1
    int ngroups_ = 0;
    bool active_ = false;
    double skin_ = 0;
    double rc_max_ = 0;
    double reach_ = 0; ///< rc_max_ + skin_: how far a mesh wall's closest cell is searched
    // candidates: node-major CSR of walls
    std::vector<index_t> nodes_;
    std::vector<std::int64_t> offsets_;
    std::vector<std::int32_t> wall_of_;
    std::vector<double> x_build_;
    double t_build_ = 0;
    double extent_ = 0; ///< max node distance from a rotation centre at build, plus the reach
    bool built_ = false;
    std::int64_t rebuilds_ = 0;
};

} // namespace pd::solver
