// SPDX-License-Identifier: MIT
// Pre-emption: SIGTERM or SIGUSR1 (Slurm before the wall-time limit, or on pre-emption), SIGINT
// (Ctrl-C) or SIGHUP (the terminal closed) asks the run to stop. The poll action sees the request,
// the ranks agree on the step, the checkpoint action writes a checkpoint and the stop action ends
// the loop: exit_preempted (75).
#pragma once

#include <csignal>

namespace pd::pipeline::run {

/// Installs the handlers at the start of a solve and keeps them to the end of the process: a
/// signal after the step loop (the run complete, its last checkpoint written) is recorded and
/// ignored, so it cannot cut off the provenance record or the file's close; the run exits 0.
/// (The default action killed pd-solve there: exit -15 on a complete run, seen by a sweep.)
class StopSignals {
  public:
    StopSignals();
    StopSignals(const StopSignals&) = delete;
    StopSignals& operator=(const StopSignals&) = delete;
};

/// The signal received since the handlers were installed, or 0.
int stop_signal();

/// "SIGTERM", "SIGUSR1", "SIGINT" or "SIGHUP".
const char* stop_signal_name(int sig);

} // namespace pd::pipeline::run
