// SPDX-License-Identifier: MIT
// Node-to-node normal contact between different bodies (spec 4.3, pdgrain decisions):
//   f_i += Kn (R - R_c) V_j (y_j - y_i)/R   for R = |y_j - y_i| < R_c,
// a force density; the nodal force Kn (R_c - R) V_i V_j is symmetric, so momentum is conserved.
// Candidate pairs come from a broad phase over body bounding boxes (only bodies whose boxes come
// within reach R_c + skin are searched), then a cell list (cells of size reach) over EVERY node
// of those bodies, with a skin: the list is rebuilt only when some node moved more than half the
// skin since the last build (so no pair closer than R_c now was farther than reach then). Each
// skip is conservative: a body skipped by the broad phase has no node within reach of another
// body's node; a node whose cell and neighbour cells hold only nodes of its own body has no
// candidate (so the inside of a grain costs one lookup per cell, not a scan). No node is left
// out by its depth inside its grain (the old "surface layer" rule let grains pressed deeper than
// that layer tunnel through each other).
#pragma once

#include "model/model.hpp"
#include "solver/domain.hpp"
#include "solver/state.hpp"

namespace pd::solver {

/// Normal contact force between two bodies through one node pair (for damping): the force on
/// body `b` from body `a` (a < b), N.
struct BodyPairForce {
    std::int32_t a, b;
    index_t i, j;
    double force[3];
    double friction; ///< Coulomb coefficient of the pair's law
    bool damped;     ///< the law has restitution < 1
};

/// Interpenetration found by ContactList::add_forces(): a node within min(R_c, h) of a node of
/// another grain that lies below that grain's surface layer (reference depth > R_c + h/2 +
/// min(R_c, h), pd-pack's /nodes/surface; h that grain's smallest node spacing, R_c the largest
/// contact radius), so the node is more than R_c + h/2 inside the other grain (the bound of the
/// stress suite's check). In a grain whose nodes leave no hole wider than 0.7 h, a node deeper
/// than R_c + 1.2 h + min(R_c, h) always has such a node within reach when R_c >= 0.7 h. Contact
/// has failed there (too soft for the load or the impact) and no later step pushes the node back
/// out: pd-solve stops with exit 3.
struct Penetration {
    std::int64_t count = 0;   ///< such node pairs (this rank's rows, last evaluation)
    std::int64_t node = -1;   ///< the smallest node of them
    std::int32_t body = -1;   ///< its grain
    std::int32_t inside = -1; ///< the grain it is inside
};

/// Boundary facets of the bodies that touch under the surface law (model::ContactLaw): the
/// facets used by one cell of each body's mesh (segments in 2D; triangles in 3D, a quad face of a
/// hexahedral grid cell as two), with global node ids, ordered so that the normal of the current
/// positions, (b - a) rotated by -90 deg in 2D or (b - a) x (c - a) in 3D, points out of the body.
struct Facets {
    int nv = 2;                        ///< vertices per facet
    std::vector<index_t> v;            ///< nv per facet
    std::vector<std::int32_t> body;    ///< per facet
    std::vector<double> edge2;         ///< per facet: its longest edge squared (reference), m2
    std::vector<offset_t> offsets{0};  ///< CSR node -> incident facets (every node of the model)
    std::vector<std::int32_t> of_node; ///< facet ids
    double max_edge = 0;               ///< longest facet edge (reference), m
    /// 2D only (empty in 3D): per facet end e (index 2 f + e), the facet of the same body across
    /// that vertex (-1: none) and c (m): the depth behind a convex vertex is smoothed within
    /// |g_f - g_g| < c sin(theta / 2) (theta the angle between the facets' current normals;
    /// surface_blend.cpp, vertex_blend), a band of half-width c / 2 about the vertex's
    /// bisector; 0: not smoothed (no vertex of two facets, or a corner of the shape).
    std::vector<std::int32_t> across;
    std::vector<double> blend;
    std::size_t num() const { return body.size(); }
};
/// kappa: c = kappa x the shorter facet at the vertex (reference), so the band reaches kappa / 2
/// of that facet from the vertex and the bands of a facet's two ends never meet.
inline constexpr double vertex_blend_share = 0.5;
/// A cell none of whose edges is longer than this times its reference length is intact
/// material (surface_inside.cpp): a crack wide enough to let a node of another body in opens
/// the edges across it by about a mesh size, doubling them.
inline constexpr double intact_cell_stretch = 1.5;
/// Largest angle (rad) between the normals of a vertex's facets that is smoothed: a vertex of a
/// polygonised curve (a 32-gon: 11 deg), not a corner of the shape (a hexagon's 60 deg, a
/// rectangle's or a turned grid disc's staircase's 90 deg, where the bisector is no better a
/// normal than either facet's: a grid disc turned by 17 deg on a meshed floor slid at 17 % of
/// its impact speed with its 90 deg corners smoothed, 7 % without).
inline constexpr double vertex_blend_max_angle = 0.5235987755982988; // 30 deg
/// The closest point p of the facet with vertices v (nv of them; positions x) to xi, its
/// barycentric weights w, and the facet's outward normal n (not normalised;
/// surface_contact.cpp).
void facet_point(std::size_t nv, const index_t* v, const double* x, const double* xi, double* p,
                 double* w, double* n);
/// The facets of the bodies `want` (1 per body) from their reference meshes; a wanted body whose
/// mesh has no cells (or not its node count) is an InputError naming it.
Facets boundary_facets(const model::Model& m, const std::vector<std::uint8_t>& want);

/// Largest normal stiffness the law `p` reaches, N m-7: the derivative of the pair's force
/// density with respect to the overlap, per unit volume of the partner node, over every overlap
/// the law allows. The stability estimate (solver/stability.hpp) bounds contact with it, so a
/// law whose stiffness grows with penetration must return its largest value here.
double contact_max_stiffness(const model::ContactPair& p);

class ContactList {
  public:
    /// `skin` > 0. Bodies in groups with no contact law never interact.
    ContactList(const model::Model& m, double skin);

    /// True if the scene can have any contact at all (two or more bodies with a law).
    bool active() const { return active_; }
    double max_radius() const { return rc_max_; }

    /// Nodes whose rows this rank builds (all by default).
    void set_owned(const Domain& dom);
    /// Rebuilds the candidate list if any rank needs it (collective; gathers every position
    /// first under MPI); returns true if it did.
    /// `b`: this rank's bond rows (the surface law's facets act only between nodes that keep
    /// half their bonds); may be null (every node counts as whole). `broken`: this rank's count
    /// of broken bonds; at a rebuild the facets' flags are counted again if it changed.
    bool update(State& s, const Domain& dom, const BondData* b = nullptr, std::int64_t broken = 0);
    /// The next update() rebuilds (after a change of ownership).
    void invalidate() {
        built_ = false;
        touched_known_ = false; // rows may have changed ranks: no history (surface_row)
        touched_.clear();       // nor held pairs (remember_depths would carry them)
        held_count_ = 0;
    }
    /// The surface law's depth history (surface_history.cpp) for a checkpoint: the owned nodes'
    /// (node, body) pairs and depths of the last evaluation and its time; time < 0 when none is
    /// known (before the first evaluation, after a change of ownership).
    void depth_history(std::vector<std::int64_t>& pairs, std::vector<double>& depths,
                       double& time) const;
    /// Continues from a checkpoint's history (every rank's entries: a superset of its rows').
    void set_depth_history(const std::vector<std::int64_t>& pairs,
                           const std::vector<double>& depths, double time);
    /// The surface law's last rebuild for a checkpoint: every node's position then, and the
    /// torn flags counted then (whole_); false (outputs empty) when there is none. A restart
    /// rebuilds at those positions (restore_build), so its rebuilds, and with them the torn
    /// facets, fall on the uninterrupted run's steps.
    bool last_build(std::vector<double>& x, std::vector<std::uint8_t>& whole) const;
    /// The next update() rebuilds at `x` with `whole` (every node's), then continues as the
    /// run would have (collective).
    void restore_build(std::vector<double> x, std::vector<std::uint8_t> whole) {
        restore_x_ = std::move(x);
        restore_whole_ = std::move(whole);
    }
    /// The surface law's contact energy (J, owned nodes) released since the last call by facets
    /// that tore at a rebuild (a vertex lost half its bonds): the solver books it as fracture.
    double take_released() {
        const double e = released_;
        released_ = 0;
        return e;
    }
    /// Appends the candidates owned by other ranks (ghosts the contact forces read).
    void ghosts(std::vector<index_t>& out) const;
    /// Adds normal contact force densities to s.f; returns the number of node pairs in contact
    /// and their spring energy sum 1/2 Kn (R_c - R)^2 V_i V_j (J). With `normal`, also lists the
    /// normal force of every touching pair whose law damps or has friction (sorted by node, so
    /// damping and friction, applied from this list, do not depend on the thread schedule).
    std::int64_t add_forces(State& s, double& energy, std::vector<BodyPairForce>* normal) const;
    const std::vector<model::ContactPair>& laws() const { return laws_; }
    /// Nodes found inside another grain at the last add_forces() (see Penetration).
    const Penetration& penetration() const { return inside_; }
    /// Owned nodes inside an intact cell a layer below another body's boundary, at s (surface
    /// law; surface_inside.cpp): the guard's test that needs no facet.
    Penetration inside_material(const State& s) const;
    bool any_friction() const { return any_friction_; }
    std::int64_t rebuilds() const { return rebuilds_; }
    std::size_t num_candidates() const { return neighbor_.size(); }
    /// The candidates of owned node i (every node within R_c of it is among them after update()).
    std::pair<const index_t*, const index_t*> candidates(index_t i) const {
        const auto ii = static_cast<std::size_t>(i);
        if (ii + 1 >= offsets_.size())
            return {nullptr, nullptr};
        const index_t* p = neighbor_.data();
        return {p + offsets_[ii], p + offsets_[ii + 1]};
    }

  private:
    void rebuild(const State& s);
    /// Broad phase: which bodies are near another body they have a contact law with.
    std::vector<std::uint8_t> near_bodies(const State& s, double reach) const;
    /// The candidate rows (node -> neighbours, laws) as sorted CSR.
    void store_rows(std::size_t n, const std::vector<std::vector<index_t>>& rows,
                    const std::vector<std::vector<std::int32_t>>& laws);
    std::int64_t add_forces_impl(State& s, double& energy,
                                 std::vector<BodyPairForce>* normal) const;
    void add_rows(State& s, std::vector<BodyPairForce>* normal, std::vector<BodyPairForce>& records,
                  std::int64_t& touching, double& e, std::int64_t& inside) const;
    /// Surface law (surface_contact.cpp): the facets, which rows a rank computes, the forces.
    void init_surface(const model::Model& m);
    void surface_rows(const State& s);
    std::int64_t add_surface(State& s, double& energy, std::vector<BodyPairForce>* normal) const;
    bool torn(std::int32_t facet, const State& s) const;
    /// The contact energy of the owned nodes at s with the current list and flags (no force).
    double surface_energy(const State& s) const;
    /// update() for the surface law (surface_tear.cpp): the rebuild test, the torn flags.
    bool update_surface(State& s, const Domain& dom, const BondData* b, std::int64_t broken);
    /// The flags of the owned facet vertices and interior cells' vertices from their bond rows;
    /// true if a facet vertex's fell to 0 (cells_fell: an interior vertex's did).
    bool count_whole(const State& s, const BondData& b, bool& cells_fell);
    /// sphere_ per facet at s (with torn_flag: reach -1 for a torn facet).
    void facet_spheres(const State& s, bool torn_flag) const;
    struct Event;
    struct Best;
    /// A node's depth smoothed across a convex vertex (vertex_blend).
    struct Blend {
        double depth;    ///< m
        double share[2]; ///< d depth / d g of the closest facet f and of the facet g across
        double n[2][2];  ///< their outward unit normals
        double t[2];     ///< the node's foot parameters on their lines (weights 1 - t, t)
        std::int32_t g;  ///< the facet across the vertex
    };
    struct Touched;
    /// 2D: node xi behind facet f (closest point weights w) near a convex vertex of f: the
    /// smoothed depth and its two facets' shares (surface_blend.cpp); false: no smoothing.
    bool vertex_blend(std::int32_t f, const double* w, const double* xi, const State& s,
                      Blend& out) const;
    /// Node i at depth d behind `facet` of `body` (foot point weights w): the pair not held,
    /// and d within the motion since the last evaluation, plus twice the law's onset, of its
    /// depth then: four times the fastest of i and the facet's vertices times the time since;
    /// entering, twice i's speed relative to its foot point (surface_history.cpp).
    bool depth_continuous(std::size_t i, std::int32_t body, std::int32_t facet, const double* w,
                          double onset, double d, const State& s) const;
    /// touched_ from this evaluation's events and marks, at `time` (surface_history.cpp).
    void remember_depths(double time, std::vector<Touched>& marks) const;
    /// Is (i, body) held (touched_ with depth held_mark)?
    bool held(std::size_t i, std::int32_t body) const;
    /// Was (i, body) in contact at the last evaluation (touched_ with a depth >= 0)?
    bool in_contact(std::size_t i, std::int32_t body) const;
    void count_held() const; ///< held_count_ from touched_
    void closest_facets(std::size_t a, std::size_t i, const State& s,
                        std::vector<Best>& best) const;
    struct Sums {
        std::int64_t touching = 0, inside = 0, first_node = -1;
        std::int32_t first_body = -1;
        double energy = 0;
    };
    /// Row a's events into `out`; into `marks` (if given) the pairs held this evaluation
    /// (depth held_mark) and the held pairs found outside (depth free_mark).
    void surface_row(std::size_t a, const State& s, std::vector<Event>& out,
                     std::vector<Best>& best, std::vector<Touched>* marks) const;
    /// icells_ and its CSR from the reference meshes of the bodies `want` (after facets_).
    void interior_cells(const model::Model& m, const std::vector<std::uint8_t>& want);
    /// Is owned node i inside interior cell c, every vertex a candidate of i, no edge stretched
    /// past intact_cell_stretch?
    bool in_intact_cell(std::size_t i, std::size_t c, const State& s) const;
    /// Is node i (row a) within h/2 of a standing facet of `body` (this evaluation's spheres)?
    bool near_boundary(std::size_t a, std::size_t i, std::int32_t body, const State& s) const;
    /// Row i's event with facet b's body at depth d (bl: smoothed across a vertex, or nullptr).
    void push_pair(std::size_t i, const Best& b, const Blend* bl, double d, double d0,
                   const State& s, std::vector<Event>& out) const;
    void apply_events(State& s, Sums& sums, std::vector<BodyPairForce>* normal) const;
    template <class Keyed, class RowOf>
    void ghost_rows(const Keyed& keyed, const std::vector<std::vector<index_t>>& rows,
                    const std::vector<std::vector<std::int32_t>>& laws, const RowOf& row_of) const;

    bool active_ = false;
    double skin_ = 0;
    double rc_max_ = 0;
    int ngroups_ = 0;
    std::vector<std::int32_t> body_group_;
    std::vector<model::offset_t> body_offsets_;
    std::vector<std::int32_t> law_of_; ///< ngroups x ngroups -> index into laws_ or -1
    std::vector<model::ContactPair> laws_;
    // CSR candidate list (full: i->j and j->i) and the law of each candidate.
    std::vector<model::offset_t> offsets_;
    std::vector<index_t> neighbor_;
    std::vector<std::int32_t> law_;
    std::vector<double> x_build_;
    std::vector<double> restore_x_;           ///< restore_build's positions (empty: none)
    std::vector<std::uint8_t> restore_whole_; ///< restore_build's whole_
    std::vector<std::uint8_t> owned_;         ///< 1 = this rank builds the node's row
    bool built_ = false;
    bool any_friction_ = false;
    std::vector<std::uint8_t> deep_; ///< 1 = below its grain's surface layer (empty: no check)
    std::vector<double> rho_;        ///< per body: the guard distance min(R_c, h), m
    mutable Penetration inside_;
    std::int64_t rebuilds_ = 0;
    // rebuild()'s candidate rows before store_rows, kept for their capacity.
    std::vector<std::vector<index_t>> cand_rows_;
    std::vector<std::vector<std::int32_t>> cand_laws_;
    // Surface law.
    bool any_surface_ = false, any_node_ = false;
    Facets facets_;
    std::vector<double> h_body_; ///< per body: mesh size h (the penetration guard's h / 2)
    /// per node: 0 a facet vertex (or a vertex of icells_) that lost half its bonds
    std::vector<std::uint8_t> whole_;
    /// The cells of the surface-law bodies' meshes with no facet vertex (global node ids,
    /// icell_npc_ per cell) and node -> those cells (CSR): inside_material.
    std::vector<index_t> icells_;
    int icell_npc_ = 0, icell_dim_ = 2;
    std::vector<model::offset_t> icell_off_;
    std::vector<std::int32_t> icell_of_;
    /// Rows the surface law computes: owned rows, and under MPI the rows of ghost candidates of
    /// owned rows (their events put reactions on owned facet nodes).
    std::vector<index_t> srows_;
    std::vector<model::offset_t> sfac_off_{0}; ///< CSR srows_ -> the facets the row tests
    std::vector<std::int32_t> sfac_;
    /// Per row at the rebuild: min over its facets of |x_i - c| - r - h (centroid c, radius r
    /// of the facet's vertices, h its body's mesh size): the row has no force while every node
    /// moved less than a quarter of it (surface_row).
    std::vector<double> slack_;
    double moved_ = 0; ///< m, farthest any node moved since the rebuild (all ranks)
    struct Event {
        index_t i;           ///< the node inside
        std::int32_t facet;  ///< the facet it is pushed out of
        double w[3];         ///< barycentric weights of the closest point
        double force[3];     ///< on i through `facet`, N
        std::int32_t facet2; ///< the facet across a convex vertex sharing the force, or -1
        double w2[2];        ///< weights on facet2's vertices (its foot point)
        double force2[3];    ///< on i through facet2, N (the node gets force + force2)
        double energy;       ///< J
        double depth;        ///< m, |p - y_i|
        bool deep;           ///< more than h / 2 inside (the guard's failure)
        bool beyond;         ///< deep past the law's reach h, no force (surface_row)
    };
    struct Touched {
        index_t i;
        std::int32_t body;
        double depth; ///< m, >= 0; held_mark: held; free_mark (marks only): seen outside
        bool operator<(const Touched& o) const { return i != o.i ? i < o.i : body < o.body; }
    };
    static constexpr double held_mark = -1, free_mark = -2;
    mutable std::vector<Event> events_;
    double released_ = 0;                 ///< J, take_released()
    std::vector<std::size_t> facet_rows_; ///< the rows of owned facet vertices (count_whole)
    bool facet_rows_stale_ = true;
    std::int64_t broken_seen_ = -1;      ///< `broken` at the last count_whole
    mutable std::vector<double> sphere_; ///< per facet, this evaluation: centroid, reach
    /// (node, body it is inside, depth) of the last evaluation's events, sorted: a pair's depth
    /// grows by at most what its nodes moved since (depth_continuous), and a pair not among
    /// them enters from the boundary. With them the held pairs (depth held_mark): a node found
    /// inside by a jump gets no force from that body until an evaluation finds it outside.
    /// Known from the second evaluation on after a start, restart or change of ownership.
    mutable std::vector<Touched> touched_;
    mutable std::size_t held_count_ = 0; ///< held entries in touched_
    mutable bool touched_known_ = false;
    mutable double touched_time_ = 0; ///< s, the time of touched_
};

} // namespace pd::solver
