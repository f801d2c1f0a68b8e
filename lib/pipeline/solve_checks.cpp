// SPDX-License-Identifier: MIT
#include "pipeline/solve_checks.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "store/frames.hpp"
#include "store/schema.hpp"

#include <cmath>

namespace pd::pipeline {

void check_options(const SolveOptions& opt) {
    if (!opt.restart && !opt.sets.empty()) // the CLI's --set needs --restart; so does the library
        throw InputError(fmt::format("{}: changes of walls or loading ({}) apply at a restart "
                                     "only (restart = true)",
                                     opt.file, opt.sets.front()));
    if (opt.max_steps_given && opt.max_steps < 1)
        throw InputError(fmt::format("--steps {}: must be at least 1", opt.max_steps));
    if (opt.final_time_given && !(std::isfinite(opt.final_time) && opt.final_time > 0))
        throw InputError(
            fmt::format("--final-time {}: must be a finite time > 0 (s)", opt.final_time));
    if (!(std::isfinite(opt.energy_tolerance) && opt.energy_tolerance >= 0))
        throw InputError(fmt::format("--energy-tolerance {}: must be a finite fraction >= 0",
                                     opt.energy_tolerance));
    if (!(opt.checkpoint_wall_seconds >= 0))
        throw InputError(fmt::format("--checkpoint-every-wall {}: must be >= 0 (s)",
                                     opt.checkpoint_wall_seconds));
    if (!(opt.progress_seconds >= 0))
        throw InputError(
            fmt::format("--progress-every {}: must be >= 0 (s)", opt.progress_seconds));
    if (opt.compress < 0 || opt.compress > 9)
        throw InputError(fmt::format("--compress {}: must be 0-9", opt.compress));
}

void refuse_existing_results(const h5::File& rf, const std::string& file) {
    std::string what;
    if (rf.exists(std::string(store::path::particles) + "/position/value")) {
        const store::FrameReader fr(rf);
        what = fmt::format("{} frame{}", fr.num_frames(), fr.num_frames() == 1 ? "" : "s");
        if (fr.num_frames() > 0)
            what += fmt::format(" (up to step {}, t = {:.6g} s)", fr.step(fr.num_frames() - 1),
                                fr.time(fr.num_frames() - 1));
    }
    if (rf.exists(store::path::checkpoints) && !rf.list(store::path::checkpoints).empty())
        what += (what.empty() ? "" : " and ") + std::string("a checkpoint");
    else if (rf.exists(store::path::observables) && what.empty())
        what = "observables";
    if (what.empty())
        return;
    throw InputError(fmt::format("{}: already holds the results of a run: {}. Continue it with "
                                 "--restart (add --final-time T to go further), or pass "
                                 "--overwrite to delete them and start again from t = 0",
                                 file, what));
}

} // namespace pd::pipeline
