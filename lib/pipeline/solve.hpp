// SPDX-License-Identifier: MIT
// pd-solve: run the explicit dynamics of a pd-file; frames and observables go into the file.
#pragma once

#include "core/tool.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace pd::pipeline {

struct SolveOptions {
    std::string file;
    bool force_dt = false;  ///< accept a scene dt above the stability estimate
    bool restart = false;   ///< continue from the latest checkpoint in the file
    bool overwrite = false; ///< start afresh on a file that holds frames or checkpoints
    double final_time = 0;  ///< overrides /solver/final_time (extend a run) if given
    bool final_time_given = false;
    std::int64_t max_steps = -1; ///< stop after this many steps (short runs, tests); -1: no limit
    bool max_steps_given = false;
    double progress_seconds = 10; ///< wall time between progress lines
    /// Default checkpoint policy (issue 13): also checkpoint when this much wall time (s) has
    /// passed since the last checkpoint, besides the scene's checkpoint_interval and the clean
    /// end or stop of the run. 0 = off (--checkpoint-every-wall).
    double checkpoint_wall_seconds = 600;
    bool rebalance = false; ///< re-partition the grains at checkpoints (MPI)
    int compress = 0;       ///< gzip level 1-9 of new frame datasets (0: none)
    /// Energy balance guard: the run stops (exit 3) when KE + elastic + contact + dissipated -
    /// external work drifts from its t = 0 value by more than this fraction of the energy in
    /// play (the largest KE + elastic + contact + dissipated + |external work| seen). 0: off.
    double energy_tolerance = 0.05;
    /// Stop (exit 3) when a node is more than R_c + h/2 inside another grain.
    bool penetration_check = true;
    /// --restart --set KEY=VALUE: changes of the walls and loading (restart_changes.hpp).
    std::vector<std::string> sets;
    CommonOptions common;
};

void solve(const SolveOptions& opt, Context& ctx);

} // namespace pd::pipeline
