// SPDX-License-Identifier: MIT
// The step loop of pd-solve as a list of scheduled actions (HOOMD-blue's Analyzers, Updaters and
// Writers with their Triggers; LAMMPS' Output): frames, observables, checkpoints, rebalance,
// progress, guards and stop requests each run when their trigger fires, in the order of
// actions.def. Adding one: a file in run/actions/ that defines make_<name>, and one line there.
#pragma once

#include "core/tool.hpp"
#include "pipeline/run/trigger.hpp"
#include "pipeline/solve.hpp"
#include "solver/solver.hpp"

#include <mpi.h>

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace pd::h5 {
class File;
}
namespace pd::store {
class FrameWriter;
class ObservableWriter;
} // namespace pd::store

namespace pd::pipeline::run {

class Schedule;

/// Steps of the run: [first, last] done by this invocation, total to the final time.
struct Steps {
    double dt = 0;
    solver::StableDt est;
    std::int64_t first = 0, last = 0, total = 0;
    std::int64_t out_every = 1;  ///< a frame every this many steps (and at total)
    std::int64_t ckpt_every = 1; ///< a checkpoint every this many steps (and at last)
    std::int64_t obs_every = 1;  ///< an observable row every this many steps
};

/// What the actions share: the run's objects and the state that passes between actions.
struct Run {
    const SolveOptions& opt;
    Context& ctx;
    model::Model& m; ///< the solver reads it; only a wall's entry above the grains changes it
    solver::Solver& s;
    std::unique_ptr<solver::Domain>& dom; ///< replaced by a rebalance
    h5::File& file;
    store::FrameWriter& frames;
    store::ObservableWriter& obs;
    const Steps& steps;
    double wall0;     ///< wall time at the start of solve()
    bool& agreed;     ///< every rank holds the same reduced values (errors unwind collectively)
    bool par = false; ///< more than one rank
    MPI_Comm comm = MPI_COMM_WORLD;
    Schedule* schedule = nullptr;

    solver::Observables last_obs{}; ///< the latest observation (the observe action)
    double imbalance = 1.0;         ///< compute time max/mean over ranks since the last frame
    int stopped_by = 0;             ///< the signal that stopped the run early
    std::int64_t stopped_at = -1;   ///< the step it stopped after (checkpointed)
    bool stop = false;              ///< the loop ends after the current action
    std::vector<double> damage{}, force{}; ///< frame buffers
};

/// One scheduled action: runs after a step when its trigger fires.
class Action {
  public:
    explicit Action(Trigger trigger)
        : trigger_(std::move(trigger)) {}
    virtual ~Action() = default;
    Action(const Action&) = delete;
    Action& operator=(const Action&) = delete;

    virtual void run(Run& r, std::int64_t n) = 0;
    /// The step before a firing must compute the bond energies (observations).
    virtual bool needs_energies() const { return false; }

    Trigger& trigger() { return trigger_; }
    const Trigger& trigger() const { return trigger_; }

  private:
    Trigger trigger_;
};

/// The actions in their order; one call per step.
class Schedule {
  public:
    /// Every action of actions.def that the run needs (a factory may return nullptr).
    explicit Schedule(Run& r);
    /// Does step n compute the bond energies (asked before the step).
    bool needs_energies(std::int64_t n) const;
    /// Runs the actions whose trigger fires after step n; false when the run stops there.
    bool after_step(Run& r, std::int64_t n);
    std::vector<std::unique_ptr<Action>>& actions() { return actions_; }

  private:
    std::vector<std::unique_ptr<Action>> actions_;
};

// Shared by several actions and solve().
/// The steps that observe (observe, guards, observables): at the observables interval, at every
/// frame and at the last step.
Trigger observation_trigger(const Steps& st);
/// The observable row of one observation, in the order of store::ObservableWriter's columns.
std::vector<double> observable_row(const solver::Observables& o);
/// Seconds a rank spent computing (forces, contact, integration; not the ghost exchange).
double busy_seconds(Timers& timers);
/// Writes the requested fields of the current state as one frame.
void write_frame(Run& r);
/// Writes a checkpoint of the current state to /checkpoints (collective; actions/checkpoint.cpp).
void checkpoint_now(Run& r);
/// Under MPI, before the buffered observable rows and a frame (`frame`) or a checkpoint are
/// written (collective): throws DiskFullError on every rank when the disk cannot hold them
/// (pipeline/full_disk.hpp); nothing at one rank (a refused write is recovered after it).
void ensure_room(const Run& r, bool frame, bool checkpoint);

} // namespace pd::pipeline::run
