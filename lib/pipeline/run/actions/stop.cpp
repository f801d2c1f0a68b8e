// SPDX-License-Identifier: MIT
// Ends the step loop after a stop request (the checkpoint action wrote its checkpoint before);
// solve() then exits with exit_preempted.
#include "pipeline/run/schedule.hpp"

namespace pd::pipeline::run {

namespace {

class Stop final : public Action {
  public:
    Stop()
        : Action(Trigger().on_stop()) {}
    void run(Run& r, std::int64_t) override { r.stop = true; }
};

} // namespace

std::unique_ptr<Action> make_stop(Run&) {
    return std::make_unique<Stop>();
}

} // namespace pd::pipeline::run
