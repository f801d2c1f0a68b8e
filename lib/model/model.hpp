// SPDX-License-Identifier: MIT
// The in-memory model: one flat node set (structure of arrays, 3-vectors interleaved), bodies as
// contiguous node ranges (CSR body -> nodes), materials, contact table, loading and solver
// settings. What pd-pack builds, the file stores and pd-solve runs. No I/O library here.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pd::model {

using index_t = std::int32_t; ///< node index (local)
using offset_t = std::int64_t;

enum class BodyKind : std::uint8_t { particle = 0, wall = 1 };

/// Peridynamic constitutive law. PMB: bond-based prototype microelastic brittle (spec 1.5);
/// LPS: ordinary state-based linear peridynamic solid (PeriDEM's PDState, spec 1.3), with
/// consistent 2D constants; RNP: regularised nonlinear bond-based potential (Lipton, spec 1.4).
enum class Law : std::uint8_t { pmb = 0, lps = 1, rnp = 2 };

/// Influence function J(r / delta) of the state-based law (spec 1.1; only its shape matters).
enum class Influence : std::uint8_t { constant = 0, linear = 1, gaussian = 2 };

/// Planar assumption of a 2D run. pdgrain's 2D PMB uses plane stress (nu = 1/3), stated in files.
enum class Planar : std::uint8_t { plane_stress = 0, plane_strain = 1 };

/// A material as given (classical constants), plus the law. Derived PD constants depend on the
/// horizon and live per body (see BodyConstants).
struct Material {
    std::string name;
    Law law = Law::pmb;
    double density = 0;         ///< kg m-3
    double youngs_modulus = 0;  ///< Pa
    double poisson_ratio = 0;   ///< 1 (bond-based: fixed by the law, 1/3 plane stress, 1/4 3D)
    double fracture_energy = 0; ///< Gc, J m-2; 0 = unbreakable
    Influence influence = Influence::constant; ///< LPS only (PMB uses J = 1)
    /// Bonds also break when compressed beyond the critical stretch (length < xi (1 - s0); RNP:
    /// S < -S_c), as PeriDEM does (|s| > s0, spec 1.3); off = tension only (pdgrain decision 4).
    bool break_in_compression = false;
    /// Random flaws (issue 31): each bond's critical stretch is s0 times a Weibull factor of
    /// modulus `flaw_modulus` and median 1 (model/flaws.hpp), drawn from `flaw_seed`, the body
    /// and the bond's two node indices in the body; 0 = none (every bond breaks at s0).
    double flaw_modulus = 0;
    std::int64_t flaw_seed = 0;
    /// m: 0 = one factor per bond; > 0 = one per patch of this size (model::flaw_cell_factor).
    double flaw_length = 0;
    bool has_flaws() const { return flaw_modulus > 0; }
    double bulk_modulus() const; ///< K, Pa, from E and nu
    bool breakable() const { return fracture_energy > 0; }
};

/// A mesh shared by instances (meshed once per shape, spec 2.5), centred at the origin.
struct RefMesh {
    std::string name;
    std::vector<double> nodes;       ///< 3 per node, m
    std::vector<std::int32_t> cells; ///< nodes_per_cell per cell, 0-based
    int nodes_per_cell = 3;
};

/// Bodies: node ranges and per-body data (all arrays have num() entries, vectors 3 per body).
struct Bodies {
    std::vector<offset_t> node_offsets{0}; ///< CSR: nodes of body b are [off[b], off[b+1])
    std::vector<std::int32_t> material;
    std::vector<std::int32_t> group;    ///< contact group (row/column of the contact table)
    std::vector<std::int32_t> ref_mesh; ///< index into Model::ref_meshes
    std::vector<BodyKind> kind;
    std::vector<std::uint8_t> fixed;      ///< 1 = not integrated (obstacle)
    std::vector<double> center;           ///< 3 per body, m (placement centre)
    std::vector<double> bounding_radius;  ///< m
    std::vector<double> orientation;      ///< rad about z
    std::vector<double> scale;            ///< 1
    std::vector<double> initial_velocity; ///< 3 per body, m s-1
    std::vector<double> mesh_size;        ///< h: min node spacing, m (spec 2.2)
    std::vector<double> horizon;          ///< delta, m
    std::size_t num() const { return node_offsets.size() - 1; }
    offset_t begin(std::size_t b) const { return node_offsets[b]; }
    offset_t end(std::size_t b) const { return node_offsets[b + 1]; }
};

/// Nodes: structure of arrays; 3-vectors interleaved (x, y, z per node).
struct Nodes {
    std::vector<double> x0;            ///< reference position, 3 per node, m
    std::vector<double> volume;        ///< m3 (2D: area x unit thickness)
    std::vector<std::int32_t> body;    ///< owning body
    std::vector<std::uint8_t> surface; ///< 1 = may touch another body (near the boundary)
    std::size_t num() const { return volume.size(); }
};

/// Bond list: CSR, full (i->j and j->i), same-body neighbours with |xi| < delta (spec 2.4).
struct Bonds {
    std::vector<offset_t> offsets{0};
    /// Every node's row (empty when only the offsets were read: pd-solve under MPI reads its
    /// own rows separately, store::read_bond_rows).
    std::vector<index_t> neighbor;
    std::size_t num() const { return static_cast<std::size_t>(offsets.back()); }
    bool complete() const { return neighbor.size() == num(); }
};

/// The normal force law of a contact pair.
/// - node: PeriDEM's node-to-node penalty (spec 4.3): f_i = Kn (R_c - r) V_j along the pair, for
///   node pairs closer than R_c; `stiffness` Kn in N m-7, `radius` R_c.
/// - surface: node-to-boundary penalty (solver/contact.hpp): a node inside the other body's
///   deformed boundary (its mesh's boundary facets: segments in 2D, triangles in 3D) or inside a
///   rigid wall gets the force density f_i = c (p - y_i), p the closest boundary point, and the
///   facet's nodes the reaction by the closest point's barycentric weights; `stiffness` c in
///   N m-5 (Pa m-2), `radius` the pair's mesh size h (a length scale: no force acts at a gap).
enum class ContactLaw : std::uint8_t { node = 0, surface = 1 };

/// One row of the contact table: the law between contact groups a and b (symmetric).
struct ContactPair {
    std::int32_t group_a = 0;
    std::int32_t group_b = 0;
    double radius = 0;      ///< node law: R_c, m; surface law: the pair's mesh size h, m
    double stiffness = 0;   ///< node law: K_n, N m-7; surface law: c, N m-5
    double restitution = 1; ///< eps in (0, 1]; 1 = no damping
    double friction = 0;    ///< Coulomb mu
    ContactLaw law = ContactLaw::node;
    /// PeriDEM 0.2's particle damping (`--parity peridem` imports, solver/terms/
    /// approach_damping.cpp), 2D node law only: A = beta_n sqrt(kappa), kappa the harmonic mean of
    /// the deck's bulk moduli; grains approaching within R_i + R_j + 1.01 R_c get the damping
    /// coefficient A sqrt(R_c m_eq). 0 = off, kg1/2 m-1/2 s-1 (2D, per unit thickness).
    double approach = 0;
    /// The force acts from this distance on: R_c (node law), 0 (surface law: at contact).
    double offset() const { return law == ContactLaw::surface ? 0.0 : radius; }
};

/// Time function T(t) of a boundary condition (spec 5.6-5.7; pdgrain takes the consistent
/// derivative for `quadratic`). value = amplitude * T(t) * S(X).
enum class TimeFn : std::uint8_t {
    constant = 0,    ///< T = 1 (displacement: u = a, v = 0)
    linear = 1,      ///< T = t
    quadratic = 2,   ///< T = t + p1 t^2
    sine = 3,        ///< T = sin(pi p1 t)
    rotation = 4,    ///< rigid in-plane rotation by amplitude * t (rad) about `centre` (spec 5.6)
    linear_step = 5, ///< force only: staircase L(t; p1, p2) of spec 5.7
    linear_slow_fast = 6, ///< force only: p2 t for t <= p1, p3 t after (spec 5.7)
};

/// Rigid analytic wall (spec decision 3): costs no nodes. Motion is rigid: translation at a
/// constant velocity and rotation at a constant angular velocity about `centre` (which itself
/// translates with the wall). Every wall records the contact force and moment it receives.
enum class WallShape : std::uint8_t {
    plane = 0,          ///< half-space boundary: `point` on it, unit `normal` into the free side
    circle_inside = 1,  ///< grains inside a circle (2D) / sphere (3D) of `radius` about `point`
    circle_outside = 2, ///< grains outside a circle/sphere (an obstacle)
    mesh = 3,           ///< triangulated surface (3D, e.g. STL) or polyline (2D): `Wall::mesh`
};

class WallMesh; // model/wall_mesh.hpp

/// Where a wall enters (at its start_time, or at t = 0).
enum class WallEnter : std::uint8_t {
    at_point = 0,     ///< through `point`, as given
    above_grains = 1, ///< plane only: moved along its normal to `gap` beyond the grains it touches
};

struct Wall {
    std::string name;
    WallShape shape = WallShape::plane;
    std::int32_t group = 0;                          ///< contact group (row of the contact table)
    std::array<double, 3> point{0, 0, 0};            ///< m, at t = 0
    std::array<double, 3> normal{0, 1, 0};           ///< unit, plane only
    double radius = 0;                               ///< m, circles only
    std::array<double, 3> velocity{0, 0, 0};         ///< m s-1, translation
    std::array<double, 3> angular_velocity{0, 0, 0}; ///< rad s-1 (2D: z only)
    std::array<double, 3> centre{0, 0, 0};           ///< m, rotation centre at t = 0
    /// Motion in time: displacement = velocity T(t), rotation angle = angular_velocity T(t)
    /// (linear: constant velocities; also quadratic, sine, linear_step, linear_slow_fast).
    TimeFn motion = TimeFn::linear;
    std::array<double, 4> motion_params{0, 0, 0, 0};
    /// s: the wall takes part from this time on (two-stage runs: a plate that enters a settled
    /// pack). Before it the wall touches nothing and stays at its t = 0 pose; from it on it moves
    /// by velocity T(t - start_time).
    double start_time = 0;
    /// above_grains: at start_time (pack time if 0) the plane and its rotation centre move along
    /// the normal so that the nearest node it touches lies `gap` beyond that node's contact reach
    /// (R_c of the pair's node law, 0 for the surface law); `point` then holds where it entered.
    WallEnter enter = WallEnter::at_point;
    double gap = 0; ///< m, above_grains only
    /// mesh only: the surface at the wall's t = 0 pose (shared, immutable; its normals point
    /// into the free side). `point` is the centre of its bounding box.
    std::shared_ptr<const WallMesh> mesh;
};

/// Space function S(X) of a boundary condition, of the reference position.
enum class SpaceFn : std::uint8_t {
    constant = 0, ///< S = 1
    linear_x = 1, ///< S = p0 x
    linear_y = 2, ///< S = p0 y
    sine_x = 3,   ///< S = sin(pi p0 x)
    hat_x = 4,    ///< S = p0 max(0, 1 - |2 (x - x_c) / L_x|) over the selected nodes' box
    hat_y = 5,    ///< same along y
};

/// A displacement or force condition on a node set resolved at pack time from bodies and/or a
/// box region of the reference configuration.
struct NodeCondition {
    std::string name;
    bool is_force = false;      ///< false: prescribed displacement; true: body force density
    std::uint8_t dofs = 0;      ///< bit d set = component d (x=1, y=2, z=4)
    std::vector<index_t> nodes; ///< selected nodes (sorted)
    double amplitude = 0;       ///< m (displacement) or N m-3 (force density)
    TimeFn time_fn = TimeFn::constant;
    SpaceFn space_fn = SpaceFn::constant;
    std::array<double, 4> params{0, 0, 0, 0}; ///< p0 (space), p1, p2, p3 (time)
    std::array<double, 3> centre{0, 0, 0};    ///< rotation centre, m (time_fn rotation)
};

struct Loading {
    std::array<double, 3> gravity{0, 0, 0}; ///< m s-2
    std::vector<NodeCondition> conditions;
    /// Mass-proportional viscous damping c (s-1): f -= c rho v on every moving node. For
    /// quasi-static problems by dynamic relaxation; 0 (default) for true dynamics.
    double viscous_damping = 0;
};

/// A straight pre-crack: bonds crossing the segment (2D) start broken. In 3D a planar
/// rectangle through p0, p1 extruded along z is used.
struct PreCrack {
    std::array<double, 3> p0{0, 0, 0};
    std::array<double, 3> p1{0, 0, 0};
};

enum class Integrator : std::uint8_t { velocity_verlet = 0, symplectic_euler = 1 };

struct SolverSettings {
    double final_time = 0;          ///< s
    double dt = 0;                  ///< s; 0 = automatic (stable estimate times safety)
    double dt_safety = 0.5;         ///< factor on the stability estimate
    double output_interval = 0;     ///< s between frames; 0 = first and last only
    double checkpoint_interval = 0; ///< s between checkpoints; 0 = at the end only
    std::int64_t observe_every = 1; ///< steps between observable rows
    Integrator integrator = Integrator::velocity_verlet;
    double contact_skin = 0;        ///< m; 0 = automatic (the largest contact radius)
    bool surface_correction = true; ///< surface correction (model/surface_correction.hpp)
    /// Scale each body's bond-law constants so that its interior families reproduce the
    /// classical modulus on the actual quadrature (model/quadrature.hpp); off = continuum constants
    /// (PeriDEM parity, and files written before pd-file 1.3).
    bool quadrature_calibration = true;
    /// A scene dt above the stability estimate runs with a warning (PeriDEM decks: the dt
    /// PeriDEM runs them at; a blow-up still stops the run, exit 3); false: refused unless
    /// pd-solve --force-dt.
    bool dt_above_estimate_warns = false;
    /// A node found inside another grain (or beyond a wall) is a warning, once, and the run goes
    /// on (PeriDEM decks: PeriDEM has no such guard and runs through the tunnelling its contact
    /// radius allows); false: the run stops, exit 3.
    bool penetration_warns = false;
    /// Nodal fields written in frames besides position (only these are computed at frames).
    std::vector<std::string> fields{"velocity", "displacement", "force",       "damage",
                                    "damage_z", "fragment",     "broken_bonds"};
};

/// Everything pd-pack writes and pd-solve reads.
struct Model {
    int dimension = 2;
    Planar planar = Planar::plane_stress;
    std::vector<Material> materials;
    std::vector<RefMesh> ref_meshes;
    Bodies bodies;
    Nodes nodes;
    Bonds bonds;
    std::vector<ContactPair> contact;
    std::vector<Wall> walls;
    std::vector<PreCrack> cracks;
    Loading loading;
    SolverSettings solver;
    std::string scene_json; ///< the scene as given (comments stripped)
    std::string title;

    /// Contact pair for groups a, b, or nullptr if they do not interact.
    const ContactPair* contact_between(std::int32_t a, std::int32_t b) const;
    /// Throws pd::InternalError if array sizes disagree (CSR monotone, indices in range).
    void check_consistency() const;
};

/// Builds the full CSR bond list: j in the same body as i, j != i, |X_j - X_i| < delta + h/2
/// (`partial_cutoff`, default: neighbours whose cell the horizon cuts, weighted by the linear
/// partial volume of spec 1.3, which then integrates the horizon to within a few per mille) or
/// < delta (PeriDEM's strict rule, spec 2.4: the family then misses about a quarter of the bond
/// energy at delta = 3 h). Cell-list search, O(n). Rows sorted by neighbour index.
Bonds build_bonds(const Nodes& nodes, const Bodies& bodies, bool partial_cutoff = true);

} // namespace pd::model
