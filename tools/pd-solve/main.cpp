// SPDX-License-Identifier: MIT
// pd-solve: explicit peridynamics + contact on a pd-file; frames and observables go into it.
// Usage: pd-solve FILE.h5 [--restart | --overwrite] [--steps N] [--final-time T] [--force-dt]
#include "core/tool.hpp"
#include "pipeline/solve.hpp"

#include <CLI/CLI.hpp>

int main(int argc, char** argv) {
    pd::pipeline::SolveOptions opt;
    CLI::App app{"pd-solve: run a pd-file to its final time (velocity Verlet, PMB, contact)",
                 "pd-solve"};
    app.add_option("file", opt.file, "pd-file, updated in place (frames, observables)")
        ->required()
        ->check(CLI::ExistingFile);
    auto* steps = app.add_option("--steps", opt.max_steps, "stop after N >= 1 steps (short runs)");
    app.add_flag("--force-dt", opt.force_dt, "accept a scene dt above the stability estimate");
    auto* restart =
        app.add_flag("--restart", opt.restart, "continue from the latest checkpoint in the file");
    app.add_flag("--overwrite", opt.overwrite,
                 "start afresh on a file that already holds frames or checkpoints (deletes them)")
        ->excludes(restart);
    app.add_option("--set", opt.sets,
                   "with --restart: change a wall or the loading of the checkpointed run, "
                   "KEY=VALUE (walls.<name>.point|center|normal|radius|velocity|angular_velocity|"
                   "rotation_center|start_time|enter|gap, loading.gravity, "
                   "loading.viscous_damping; VALUE as JSON); repeatable; recorded in /provenance")
        ->allow_extra_args(false)
        ->needs(restart);
    app.add_option("--compress", opt.compress, "gzip level 1-9 of the frames (0: none)")
        ->check(CLI::Range(0, 9));
    app.add_flag("--rebalance", opt.rebalance,
                 "under MPI: re-partition the grains where they are at each checkpoint");
    auto* final_time =
        app.add_option("--final-time", opt.final_time, "override the scene's final time (s)");
    app.add_option("--energy-tolerance", opt.energy_tolerance,
                   "stop (exit 3) when the energy balance drifts by more than this fraction of "
                   "the energy in play (default 0.05; 0: off)")
        ->check(CLI::Range(0.0, 1e6));
    bool no_penetration = false;
    app.add_flag("--no-penetration-check", no_penetration,
                 "run on when a node is more than R_c + h/2 inside another grain (default: stop, "
                 "exit 3)");
    app.add_option("--progress-every", opt.progress_seconds, "seconds between progress lines");
    app.add_option("--checkpoint-every-wall", opt.checkpoint_wall_seconds,
                   "also checkpoint when this much wall time (s) has passed since the last "
                   "checkpoint (default 600; 0 = only the scene's checkpoint_interval and the end)")
        ->check(CLI::NonNegativeNumber);
    app.footer("On SIGTERM or SIGUSR1 (Slurm: before the wall-time limit, on pre-emption), SIGINT "
               "(Ctrl-C) or SIGHUP (terminal closed) pd-solve "
               "finishes the current step, writes a checkpoint, records exit status 75 in "
               "/provenance and exits with 75; continue with --restart (bit for bit).\n"
               "Exit codes: 0 ok, 2 bad input, 3 numerical failure, 4 internal error, 75 stopped "
               "by a signal with a checkpoint.");
    pd::add_common_flags(app, opt.common);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return pd::usage_exit(app, e);
    }
    opt.penetration_check = !no_penetration;
    opt.max_steps_given = steps->count() > 0;
    opt.final_time_given = final_time->count() > 0;
    return pd::run_tool("pd-solve", argc, argv, opt.common,
                        [&](pd::Context& ctx) { pd::pipeline::solve(opt, ctx); });
}
