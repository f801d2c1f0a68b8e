// SPDX-License-Identifier: MIT
#pragma once
/// pd-solve's figures per rank at the close (issue 29 item 6, `workflows/bench/scaling/`): ghost
/// counts (bond and contact halo), the ghost exchanges' messages and bytes per step, the
/// whole-array gathers, the step loop's compute and halo seconds, and the peak resident memory.
#include "core/tool.hpp"
#include "solver/domain.hpp"

#include <cstdint>

namespace pd::solver {
class Solver;
}

namespace pd::pipeline {

/// A rank's counters at one moment: the step loop's figures are the differences from its start.
struct RankMark {
    solver::Traffic traffic;
    double wall = 0; ///< steady clock, s
    double busy = 0; ///< run::busy_seconds: forces, contact, integration
    double halo = 0; ///< the ghost exchanges (waiting for the peers included)
};

/// This rank's counters now (local, no MPI call).
RankMark mark_rank(solver::Solver& s);

/// Collective: rank 0 logs the max/mean over ranks (info, MPI only) and one line per rank
/// (debug, `-v`, also at one rank), per step of the `steps` since `from`. The figures cost a
/// few integer adds per exchange and one read of /proc/self/status here.
void report_ranks(Context& ctx, solver::Solver& s, const RankMark& from, std::int64_t steps);

/// Peak resident set of this process (VmHWM of /proc/self/status), bytes; 0 when unknown.
double peak_rss_bytes();

} // namespace pd::pipeline
