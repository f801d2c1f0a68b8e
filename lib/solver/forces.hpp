// SPDX-License-Identifier: MIT
// The force terms the integrator (Solver) sums, and what they share. After HOOMD-blue (a list of
// ForceComputes summed by an Integrator), LAMMPS (fixes that add to the atoms' forces at their
// place in Verlet::run) and CabanaPD (force models apart from the solver loop).
//
// A force evaluation runs the terms of the list in their order (terms/terms.def): each adds its
// force density to s.f of this rank's rows, and its share of the evaluation's sums (energies,
// contact count, dissipation rates). The order is the order of the sum at every node: changing
// it changes the last bits of every frame. A term the scene does not need is not in the list.
#pragma once

#include "core/timer.hpp"
#include "model/model.hpp"
#include "solver/contact.hpp"
#include "solver/domain.hpp"
#include "solver/observables.hpp"
#include "solver/reactions.hpp"
#include "solver/state.hpp"
#include "solver/walls.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pd::solver {

/// Energy dissipated since t = 0 on this rank's nodes (J), and the dissipation rates of the last
/// force evaluation (W) their trapezoidal integration continues from: checkpointed.
struct Dissipation {
    double fracture = 0, damping = 0, friction = 0, viscous = 0;
    double damping_rate = 0, friction_rate = 0, viscous_rate = 0;
};

/// What the force terms share: the model, this rank's state and bond rows, the contact
/// machinery, the records one term leaves for the next, and the sums of the evaluation.
struct Forces {
    explicit Forces(const model::Model& model)
        : m(model)
        , reactions(model) {}

    const model::Model& m;
    Domain* dom = nullptr;
    State s;
    BondData b;
    BodyLaw law;
    std::vector<index_t> bond_ghosts; ///< bond neighbours of owned nodes owned elsewhere
    bool bonds_cross_ranks = false;   ///< some bond joins nodes of two ranks
    /// Contact halo: the distinct non-owned nodes the contact list reads (candidates, facet
    /// vertices), bond ghosts among them included; set at each set_ghosts (MPI).
    std::size_t contact_ghosts = 0;
    std::unique_ptr<ContactList> contact;
    std::unique_ptr<WallContact> walls;
    WallLoad wall_load; ///< rigid walls' reactions of the evaluation (walls, damping, friction)
    BodyReactions reactions;
    std::vector<double> body_mass;
    double dt = 0;
    double g[3] = {0, 0, 0};
    // Conditions (spec 5.6).
    std::vector<double> fbc;                     ///< force-condition density per component (if any)
    std::vector<std::array<double, 4>> cond_box; ///< per condition: x and y range of its nodes
    bool has_prescribed = false;                 ///< some displacement condition
    // Contact damping and friction, and the touching-pair records they read.
    bool damping = false;  ///< some contact law has restitution < 1
    bool approach = false; ///< some contact law has PeriDEM's particle damping (approach > 0)
    bool friction = false; ///< some contact law has mu > 0
    bool records = false;  ///< damping or friction need the touching-pair records
    std::vector<BodyPairForce> pair_records;
    std::vector<BodyWallForce> wall_records;
    UnloadMap unload; ///< unloading pairs of this evaluation (friction limits)
    // Sums of the evaluation (this rank's rows), zeroed by begin_evaluation().
    double elastic = 0;   ///< bond energy, when law.energy
    double repulsion = 0; ///< broken-bond repulsion energy, when law.energy
    double contact_energy = 0;
    std::int64_t contact_count = 0;
    // Running totals.
    std::int64_t broken_total = 0; ///< from both ends, this rank's rows
    std::int64_t precracked = 0;
    Dissipation diss;
    Timers timers;
    int t_bonds = 0, t_contact = 0, t_search = 0, t_integrate = 0, t_walls = 0, t_damping = 0,
        t_halo = 0;

    bool has_gravity() const { return g[0] != 0 || g[1] != 0 || g[2] != 0; }
    void begin_evaluation() {
        elastic = repulsion = contact_energy = 0;
        contact_count = 0;
        diss.damping_rate = diss.friction_rate = diss.viscous_rate = 0;
    }
};

/// One force term.
class ForceTerm {
  public:
    virtual ~ForceTerm() = default;
    /// Adds the term's force density (N m-3) to s.f of this rank's rows and its share of the
    /// evaluation's sums (energy when law.energy asks for it, dissipation rate, counts).
    virtual void add(Forces& f) = 0;
    /// Tightens the stable time step where the term has a limit (collective: every rank has the
    /// same list).
    virtual void limit_dt(const Forces& /*f*/, StableDt& /*dt*/) const {}
    /// This rank's observables of the term beyond the evaluation's sums (before the reduction).
    virtual void observe(const Forces& /*f*/, Observables& /*o*/) const {}
    /// What the term must checkpoint beyond u, v, f (so that a restart continues bit for bit):
    /// the names of its quantities in store/checkpoint_io (alive, broken_total, dissipation
    /// fields, external work); empty when nothing.
    virtual std::vector<const char*> checkpointed() const { return {}; }
};

using TermList = std::vector<std::unique_ptr<ForceTerm>>;

/// The terms of terms/terms.def that the scene needs, in that order; their names into `names`.
TermList make_terms(Forces& f, std::vector<std::string>* names = nullptr);

/// Re-sets the ghosts (bond ghosts and the contact list's) and exchanges x, u, v (MPI: after a
/// contact-list rebuild).
void set_ghosts(Forces& f);

} // namespace pd::solver
