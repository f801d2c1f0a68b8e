// SPDX-License-Identifier: MIT
// Explicit dynamics of a model::Model: PMB bond forces, contact, gravity; velocity Verlet
// (default) or symplectic Euler; the stable time step estimate; observables. No I/O here.
#pragma once

#include "core/timer.hpp"
#include "model/model.hpp"
#include "solver/contact.hpp"
#include "solver/domain.hpp"
#include "solver/reactions.hpp"
#include "solver/state.hpp"
#include "solver/walls.hpp"

#include <map>
#include <memory>
#include <string>
#include <utility>

namespace pd::solver {

/// Stable time step estimate (s) and the limit that governs it (solver/stability.hpp).
struct StableDt {
    double pd = 0;         ///< bond limit 2 / sqrt(lambda_max) of the bonds' mass-scaled stiffness,
                           ///< 3 significant digits, rounded down
    double contact = 0;    ///< contact limit 2 / sqrt(lambda) of the densest contact that can form
    double limit = 0;      ///< min(pd, contact)
    int lanczos_steps = 0; ///< steps the bond eigenvalue took
    std::string governing; ///< "peridynamic bonds" or "contact stiffness"
};

/// Quantities observed after a step (2D: per unit thickness).
struct Observables {
    double kinetic_energy = 0; ///< J
    double elastic_energy = 0; ///< J, intact bonds
    double contact_energy = 0; ///< J, contact springs
    double external_work = 0;  ///< J, work of gravity, force and displacement conditions,
                               ///< moving walls since t = 0
    // Energy dissipated since t = 0 (J, cumulative): with them the balance
    // KE + elastic + contact + fracture + damping + friction + viscous - external_work
    // stays at its t = 0 value (to the integrator's error; pd-solve's guard checks it).
    double fracture_energy = 0;      ///< elastic energy bonds held when they broke
    double damping_dissipation = 0;  ///< removed by hysteretic contact damping
    double friction_dissipation = 0; ///< removed by Coulomb friction
    double viscous_dissipation = 0;  ///< removed by viscous relaxation
    double gravity_potential = 0;    ///< J, -sum m g . u of moving nodes (part of external_work)
    /// Node pairs with a node more than R_c + h/2 inside another grain (solver/contact.hpp
    /// Penetration), over all ranks, and one of them as this rank saw it (-1: none here). Not
    /// written to the file.
    std::int64_t inside_pairs = 0;
    std::int64_t inside_node = -1;
    std::int32_t inside_body = -1, inside_of = -1;
    /// Nodes more than h/2 beyond a rigid wall's surface (solver/walls.hpp), over all ranks, and
    /// one of them with its wall as this rank saw it. Not written to the file.
    std::int64_t beyond_wall = 0;
    std::int64_t beyond_node = -1;
    std::int32_t beyond_wall_index = -1;
    double momentum[3] = {0, 0, 0};  ///< kg m s-1
    std::int64_t contact_count = 0;  ///< node pairs (and node-wall pairs) closer than R_c
    std::int64_t broken_bonds = 0;   ///< broken bonds (pairs)
    std::vector<double> wall_force;  ///< 3 per wall, N, received by the wall
    std::vector<double> wall_moment; ///< 3 per wall, N m, about its rotation centre
    /// Contact reactions of the fixed or driven meshed bodies (Solver::reaction_bodies()):
    /// 3 per body, N, and moment about its centroid, N m.
    std::vector<double> body_force;
    std::vector<double> body_moment;
};

/// KE + elastic + contact + dissipated - external work: constant in an exact integration (J).
double energy_balance(const Observables& o);
/// The energy in play, the scale the balance drift is measured against: KE + elastic + contact
/// + dissipated + |external work| (J).
double energy_in_play(const Observables& o);

class Solver {
  public:
    /// `dom`: the nodes this rank owns and its ghost exchange (nullptr: one rank owns all).
    /// Collective over the domain's ranks, as are initialize(), advance(), observe(),
    /// fragments() and broken_total().
    /// `row_neighbors`: when `m` was read without its neighbour lists (store::read_model with
    /// neighbors = false), those of the domain's rows, concatenated in row order.
    explicit Solver(const model::Model& m, Domain* dom = nullptr,
                    std::vector<index_t> row_neighbors = {});

    StableDt stable_dt() const;
    void set_dt(double dt) {
        dt_ = dt;
        law_.dt = dt;
    }
    double dt() const { return dt_; }
    /// Whether the next force evaluations sum the elastic (bond) energy and the broken-bond
    /// repulsion energy (on by default). observe() reports them as of the last evaluation that
    /// did: pd-solve turns them on for the steps it observes only (issue 15). Dissipation,
    /// fracture energy and external work are integrated at every step either way.
    void set_energies(bool on) { law_.energy = on; }
    /// The bond kernels alone on the current positions (benchmarks: workflows/bench);
    /// `reference`: the naive PMB loop of before issue 15 instead. Overwrites the forces.
    void bond_forces_only(bool reference = false);

    /// Sets initial velocities and computes forces at t = 0. Call once before step().
    void initialize();
    /// Restores a state (restart) and recomputes forces without breaking bonds anew.
    void advance();
    Observables observe() const;

    State& state() { return s_; }
    const State& state() const { return s_; }
    /// This rank's rows of the bond list (CSR over state().rows; on one rank, all of it).
    const BondData& bonds() const { return b_; }
    BondData& bonds() { return b_; }
    /// Writes this rank's bond states into their places of a whole-list array (size of the
    /// model's bond list; other entries untouched).
    void alive_into(std::vector<std::uint8_t>& full) const;
    /// Every bond's state, on every rank (collective).
    std::vector<std::uint8_t> global_alive() const;
    /// LPS dilatation theta per node (0 for PMB nodes) at the last force evaluation.
    const std::vector<double>& dilatation() const { return law_.theta; }
    /// Damage_Z per node (spec 3): max over all bonds, broken or not, of |s| / s0 (RNP:
    /// |S| / S_c(r)); >= 1 where a bond has reached its critical stretch. 0 if unbreakable.
    void damage_z(std::vector<double>& z) const;
    /// Fragment id per node: the smallest node index of its connected component of intact
    /// bonds (a grain that broke in two has two ids). Exact for every frame.
    void fragments(std::vector<double>& id) const;
    /// Number of broken bonds of each node (each broken pair counts at both ends).
    void broken_per_node(std::vector<double>& count) const;
    /// phi per node.
    void damage(std::vector<double>& phi) const;
    /// Nodal force f V (N) per node, 3 per node.
    void nodal_force(std::vector<double>& out) const;
    /// Index of the first node with a non-finite position or velocity, or -1.
    std::int64_t first_nonfinite() const;
    Timers& timers() { return timers_; }
    const ContactList& contact() const { return *contact_; }
    const WallContact& walls() const { return *walls_; }
    std::size_t num_walls() const { return walls_->num_walls(); }
    /// The meshed bodies whose contact reaction observe() reports (fixed, or driven whole by
    /// displacement conditions), ascending.
    const std::vector<std::int32_t>& reaction_bodies() const { return reactions_.bodies(); }
    /// Broken bonds counted from both ends, over all ranks (collective).
    std::int64_t broken_total() const { return dom_->sum(broken_total_); }
    const Domain& domain() const { return *dom_; }

    /// Continues from a checkpoint instead of initialize(): state, bond state and forces as they
    /// were, so the run continues bit for bit.
    void restore(std::int64_t step, double time, const std::vector<double>& u,
                 const std::vector<double>& v, const std::vector<double>& f,
                 const std::vector<std::uint8_t>& alive, std::int64_t broken_total);
    /// Hands the nodes over to another decomposition of the same ranks (re-partitioning at a
    /// checkpoint): every rank first receives the whole state, then keeps computing its new
    /// rows. Collective; the run continues exactly as it would have. `dom` must outlive the
    /// solver or the next call.
    void redistribute(Domain* dom);
    /// Centre of mass of every body (3 per body), over all ranks. Collective.
    std::vector<double> body_centres() const;
    /// Sets u, v, x of prescribed components at time s.time (spec 5.6).
    void apply_displacements();
    /// Number of bond ends that cross a pre-crack (broken at initialize()), over all ranks.
    std::int64_t precracked() const { return dom_->sum(precracked_); }

    /// Work of external forces since t = 0 (J) and the external power at the last step (W):
    /// checkpointed, so the work continues across restarts.
    double external_work() const { return external_work_; }
    double external_power_last() const { return power_; }
    void set_external_work(double w, double power) {
        external_work_ = w;
        power_ = power;
    }
    /// Energy dissipated since t = 0 on this rank's nodes (J), and the dissipation rates of the
    /// last force evaluation (W) their trapezoidal integration continues from: checkpointed.
    struct Dissipation {
        double fracture = 0, damping = 0, friction = 0, viscous = 0;
        double damping_rate = 0, friction_rate = 0, viscous_rate = 0;
    };
    const Dissipation& dissipation() const { return diss_; }
    void set_dissipation(const Dissipation& d) { diss_ = d; }

  private:
    void compute_forces();
    double external_power() const;
    void break_precracks();
    void apply_damping(const std::vector<BodyPairForce>& pairs,
                       const std::vector<BodyWallForce>& walls);
    void apply_friction();

    void set_ghosts();
    void check_whole_grains() const;
    /// Takes the domain's rows (state loops, contact rows).
    void take_rows();
    /// This rank's rows of the bond list (reference lengths, factors, influence; alive = 1).
    void build_bonds();
    /// Ghosts for the bond neighbours owned elsewhere (collective).
    void set_bond_ghosts();
    /// Surface-correction factors and LPS weighted volumes of the rows and their ghosts
    /// (collective; after set_bond_ghosts()).
    void family_factors();
    /// Every node's neighbour list (the model's, or gathered from the ranks; collective).
    std::vector<index_t> global_neighbors() const;
    /// Broken bond ends in this rank's rows.
    std::int64_t count_broken() const;

    const model::Model& m_;
    std::unique_ptr<Domain> serial_; ///< the one-rank domain when none is given
    Domain* dom_ = nullptr;
    std::vector<index_t> bond_ghosts_;   ///< bond neighbours of owned nodes owned elsewhere
    std::vector<index_t> row_neighbors_; ///< neighbour lists for build_bonds() (then empty)
    bool bonds_cross_ranks_ = false;     ///< some bond joins nodes of two ranks
    State s_;
    BondData b_;
    BodyLaw law_;
    std::unique_ptr<ContactList> contact_;
    std::unique_ptr<WallContact> walls_;
    WallLoad wall_load_;
    BodyReactions reactions_;
    bool damping_ = false;  ///< some contact law has restitution < 1
    bool friction_ = false; ///< some contact law has mu > 0
    bool records_ = false;  ///< damping or friction need the touching-pair records
    std::vector<double> body_mass_;
    std::vector<BodyPairForce> pair_records_;
    std::vector<BodyWallForce> wall_records_;
    UnloadMap unload_; ///< unloading pairs of this evaluation (friction limits)
    double dt_ = 0;
    double g_[3] = {0, 0, 0};
    double elastic_energy_ = 0;
    double contact_energy_ = 0;
    std::int64_t contact_count_ = 0;
    std::int64_t broken_total_ = 0; ///< from both ends, this rank's rows
    std::int64_t precracked_ = 0;
    std::vector<double> fbc_; ///< force-condition density per component (if any)
    std::vector<std::array<double, 4>> cond_box_; ///< per condition: x and y range of its nodes
    bool has_prescribed_ = false;
    double external_work_ = 0;
    double power_ = 0; ///< external power at the last force evaluation
    Dissipation diss_;
    double repulsion_energy_ = 0; ///< broken-bond repulsion of the last evaluation (J)
    bool initialized_ = false;
    Timers timers_;
    int t_bonds_, t_contact_, t_search_, t_integrate_, t_walls_, t_damping_, t_halo_ = 0;
};

} // namespace pd::solver
