// SPDX-License-Identifier: MIT
// Explicit dynamics of a model::Model: the integrator (velocity Verlet, default, or symplectic
// Euler) over the force terms of solver/forces.hpp (terms/terms.def); the stable time step
// estimate; observables; damage and fragments. No I/O here.
#pragma once

#include "core/timer.hpp"
#include "model/model.hpp"
#include "solver/contact.hpp"
#include "solver/domain.hpp"
#include "solver/forces.hpp"
#include "solver/observables.hpp"
#include "solver/reactions.hpp"
#include "solver/state.hpp"
#include "solver/walls.hpp"

#include <map>
#include <memory>
#include <string>
#include <utility>

namespace pd::solver {

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
        f_.dt = dt;
        f_.law.dt = dt;
    }
    double dt() const { return dt_; }
    /// Whether the next force evaluations sum the elastic (bond) energy and the broken-bond
    /// repulsion energy (on by default). observe() reports them as of the last evaluation that
    /// did: pd-solve turns them on for the steps it observes only (issue 15). Dissipation,
    /// fracture energy and external work are integrated at every step either way.
    void set_energies(bool on) { f_.law.energy = on; }
    /// The bond kernels alone on the current positions (benchmarks: workflows/bench);
    /// `reference`: the naive PMB loop of before issue 15 instead. Overwrites the forces.
    void bond_forces_only(bool reference = false);

    /// Sets initial velocities and computes forces at t = 0. Call once before step().
    void initialize();
    /// Restores a state (restart) and recomputes forces without breaking bonds anew.
    void advance();
    Observables observe() const;

    State& state() { return f_.s; }
    const State& state() const { return f_.s; }
    /// This rank's rows of the bond list (CSR over state().rows; on one rank, all of it).
    const BondData& bonds() const { return f_.b; }
    BondData& bonds() { return f_.b; }
    /// The per-body constants of the bond laws (s0, c, horizon; bond_beta()).
    const BodyLaw& bond_law() const { return f_.law; }
    /// Writes this rank's bond states into their places of a whole-list array (size of the
    /// model's bond list; other entries untouched).
    void alive_into(std::vector<std::uint8_t>& full) const;
    /// Every bond's state, on every rank (collective).
    std::vector<std::uint8_t> global_alive() const;
    /// LPS dilatation theta per node (0 for PMB nodes) at the last force evaluation.
    const std::vector<double>& dilatation() const { return f_.law.theta; }
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
    /// The force terms this scene needs, in the order they are summed (terms/terms.def).
    const std::vector<std::string>& terms() const { return term_names_; }
    Timers& timers() { return f_.timers; }
    const ContactList& contact() const { return *f_.contact; }
    const WallContact& walls() const { return *f_.walls; }
    std::size_t num_walls() const { return f_.walls->num_walls(); }
    /// Wall k of the model (which the solver reads) moved: placed above the grains as it
    /// enters. The wall contact search takes its new pose at the next step.
    void wall_moved(std::size_t k) { f_.walls->set_wall(k, f_.m.walls[k]); }
    /// The meshed bodies whose contact reaction observe() reports (fixed, or driven whole by
    /// displacement conditions), ascending.
    const std::vector<std::int32_t>& reaction_bodies() const { return f_.reactions.bodies(); }
    /// Broken bonds counted from both ends, over all ranks (collective).
    std::int64_t broken_total() const { return f_.dom->sum(f_.broken_total); }
    const Domain& domain() const { return *f_.dom; }
    /// This rank's bond halo (bond neighbours owned elsewhere) and contact halo (non-owned
    /// nodes the contact list reads, bond ghosts among them included): the ghost counts of
    /// issue 29 item 6 (MPI; 0 on one rank).
    std::size_t bond_ghosts() const { return f_.bond_ghosts.size(); }
    std::size_t contact_ghosts() const { return f_.contact_ghosts; }

    /// Continues from a checkpoint instead of initialize(): state, bond state and forces as they
    /// were, so the run continues bit for bit.
    void restore(std::int64_t step, double time, const std::vector<double>& u,
                 const std::vector<double>& v, const std::vector<double>& f,
                 const std::vector<std::uint8_t>& alive, std::int64_t broken_total);
    /// The surface law's depth history (ContactList::depth_history): this rank's entries for a
    /// checkpoint, and a restart's continuation from every rank's.
    void surface_depths(std::vector<std::int64_t>& pairs, std::vector<double>& depths,
                        double& time) const;
    void set_surface_depths(const std::vector<std::int64_t>& pairs,
                            const std::vector<double>& depths, double time);
    /// The surface law's last contact-list rebuild (ContactList::last_build / restore_build):
    /// a checkpoint's, and a restart's continuation from it.
    bool surface_build(std::vector<double>& x, std::vector<std::uint8_t>& whole) const;
    void restore_surface_build(std::vector<double> x, std::vector<std::uint8_t> whole);
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
    std::int64_t precracked() const { return f_.dom->sum(f_.precracked); }

    /// Work of external forces since t = 0 (J) and the external power at the last step (W):
    /// checkpointed, so the work continues across restarts.
    double external_work() const { return external_work_; }
    double external_power_last() const { return power_; }
    void set_external_work(double w, double power) {
        external_work_ = w;
        power_ = power;
    }
    /// Energy dissipated since t = 0 on this rank's nodes (solver/forces.hpp): checkpointed.
    using Dissipation = solver::Dissipation;
    const Dissipation& dissipation() const { return f_.diss; }
    void set_dissipation(const Dissipation& d) { f_.diss = d; }

    /// Wall and body reactions are averaged over an observation interval: each step adds its
    /// reactions to a sum, observe() reports sum / steps (the last evaluation's values when no
    /// step was summed, as at t = 0) and end_interval() starts the next interval. The sums
    /// (this rank's: wall force, wall moment, BodyReactions::load()) and their step count are
    /// checkpointed, so a restart continues the interval bit for bit.
    void end_interval();
    const std::vector<double>& interval_sum() const { return interval_sum_; }
    std::int64_t interval_steps() const { return interval_steps_; }
    void set_interval(std::vector<double> sum, std::int64_t steps);

  private:
    /// Sums the force terms at the current state (the integrator's force evaluation).
    void compute_forces();
    /// Takes the domain's rows (state loops, contact rows).
    void take_rows();
    /// Sizes of the state, densities, fixed components and condition boxes (constructor).
    void init_state();
    /// Contact, walls, damping and friction flags, body masses, timers (constructor).
    void init_contact();
    /// kick / rho_i of every node (the half or whole step's velocity change per unit force
    /// density), computed again only when kick changes: the same quotients as in the loop.
    const double* kick_per_rho(double kick);
    /// Velocity Verlet's second half kick (kr: kick_per_rho()); returns the external power at
    /// the new state (detail::external_power()).
    double second_kick(bool verlet, const double* kr);
    /// Adds this evaluation's reactions to the interval's sums.
    void add_interval();

    Forces f_;
    TermList terms_;
    std::vector<std::string> term_names_;
    std::unique_ptr<Domain> serial_;     ///< the one-rank domain when none is given
    std::vector<index_t> row_neighbors_; ///< neighbour lists for build_bonds() (then empty)
    double dt_ = 0;
    double elastic_energy_ = 0;   ///< of the last evaluation that summed the energies (J)
    double repulsion_energy_ = 0; ///< broken-bond repulsion of that evaluation (J)
    double contact_energy_ = 0;   ///< contact, walls and repulsion of the last evaluation (J)
    std::int64_t contact_count_ = 0;
    double external_work_ = 0;
    double power_ = 0;                 ///< external power at the last force evaluation
    std::vector<double> interval_sum_; ///< reactions summed since end_interval() (this rank)
    std::int64_t interval_steps_ = 0;  ///< steps in interval_sum_
    bool initialized_ = false;
    std::vector<double> kick_rho_; ///< kick_per_rho()
    double kick_ = 0;              ///< the kick of kick_rho_
};

} // namespace pd::solver
