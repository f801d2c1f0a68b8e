// SPDX-License-Identifier: MIT
// Pre-emption: SIGTERM or SIGUSR1 (Slurm before the wall-time limit, or on pre-emption) asks the
// run to stop. The poll action sees the request, the ranks agree on the step, the checkpoint
// action writes a checkpoint and the stop action ends the loop: exit_preempted (75).
#pragma once

#include <csignal>

namespace pd::pipeline::run {

/// Installs the handlers for the life of a solve; the previous ones come back after it.
class StopSignals {
  public:
    StopSignals();
    ~StopSignals();
    StopSignals(const StopSignals&) = delete;
    StopSignals& operator=(const StopSignals&) = delete;

  private:
    struct sigaction old_term_ {};
    struct sigaction old_usr1_ {};
};

/// The signal received since the handlers were installed, or 0.
int stop_signal();

} // namespace pd::pipeline::run
