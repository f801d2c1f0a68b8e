// SPDX-License-Identifier: MIT
// The row of /observables at the observed steps (after the guards passed it).
#include "pipeline/run/schedule.hpp"
#include "store/frames.hpp"

namespace pd::pipeline::run {

namespace {

class ObservablesRow final : public Action {
  public:
    explicit ObservablesRow(const Steps& st)
        : Action(observation_trigger(st)) {}
    void run(Run& r, std::int64_t n) override {
        r.obs.add(n, r.s.state().time, observable_row(r.last_obs));
        r.agreed = false;
    }
};

} // namespace

std::unique_ptr<Action> make_observables(Run& r) {
    return std::make_unique<ObservablesRow>(r.steps);
}

} // namespace pd::pipeline::run
