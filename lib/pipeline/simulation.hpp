// SPDX-License-Identifier: MIT
// A pd-solve run held open between steps: what solve() does, cut at the step loop so another
// driver (the Python module, a coupling code) advances it a few steps at a time and reads or
// changes the state in between. solve() is Simulation(opt, ctx), advance() to the last step,
// close(): the same calls in the same order, so its files are bitwise those of a driven run
// that advances to the same last step.
#pragma once

#include "core/tool.hpp"
#include "pipeline/solve.hpp"

#include <cstdint>
#include <memory>
#include <utility>

namespace pd::model {
struct Model;
}
namespace pd::solver {
class Solver;
}

namespace pd::pipeline {

/// The steps of a run: [first, last] for this invocation, total to the final time.
struct SimulationSteps {
    double dt = 0;
    std::int64_t first = 0, last = 0, total = 0;
    std::int64_t out_every = 1, ckpt_every = 1, obs_every = 1;
};

class Simulation {
  public:
    /// Open and set up (pd-solve's phases 1 and 2) and the start of the run: the file prepared,
    /// the checkpoint restored or t = 0 written (a frame and an observable row). Throws as
    /// solve() does (InputError, ...). `opt` is copied; `ctx` must outlive the simulation.
    Simulation(const SolveOptions& opt, Context& ctx);
    ~Simulation();
    Simulation(const Simulation&) = delete;
    Simulation& operator=(const Simulation&) = delete;

    /// Advances at most `n` steps, never past the last step, each followed by the scheduled
    /// actions (frames, observables, checkpoints, guards); returns the steps done (fewer when the
    /// run reached its last step or a stop signal ended it). Collective under MPI.
    std::int64_t advance(std::int64_t n);
    /// The last step is done, a stop ended the run, or a restart found it complete.
    bool finished() const;
    /// The step the state is at.
    std::int64_t step() const;
    /// Writes a checkpoint of the current state (replacing one of the same step). Collective.
    void checkpoint();
    /// Ends the run: observables flushed, a checkpoint of the current step when the run stopped
    /// before its last step (so `pd-solve --restart` continues it), the file closed, the report
    /// logged and the provenance hook left in the Context. Returns the exit code (0, or 75 when
    /// a stop signal ended the run). Called by the destructor if not before (errors swallowed).
    int close();
    /// After an error from advance(), checkpoint() or close(): closes the file without writing
    /// more (for the provenance hook), keeping the state readable.
    void abandon();

    solver::Solver& solver();
    const model::Model& model() const;
    /// The model the solver runs, writable between advance() calls where the solver reads it
    /// afresh at every step: a condition's amplitude, time function and parameters (its nodes
    /// and components are fixed at set-up). Not written back to the file.
    model::Model& model() { return const_cast<model::Model&>(std::as_const(*this).model()); }
    const SimulationSteps& steps() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace pd::pipeline
