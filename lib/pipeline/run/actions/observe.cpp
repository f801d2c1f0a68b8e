// SPDX-License-Identifier: MIT
// The observation of the observed steps: the reduced observables (collective, every rank at the
// same steps), for the guards and the observables row after it.
#include "pipeline/run/schedule.hpp"

namespace pd::pipeline::run {

Trigger observation_trigger(const Steps& st) {
    // At the observables interval and at every frame (the run's final step is one). Not at the
    // step a --steps run stops: a continued run has the rows of an uncut one.
    return Trigger().every(st.obs_every).every(st.out_every).at(st.total);
}

namespace {

class Observe final : public Action {
  public:
    explicit Observe(const Steps& st)
        : Action(observation_trigger(st)) {}
    bool needs_energies() const override { return true; } // bond energies only where observed
    void run(Run& r, std::int64_t) override {
        r.last_obs = r.s.observe(); // collective: every rank at the same steps
        r.s.end_interval();         // reactions: the next row averages the steps after this
        r.agreed = true;            // the checks after it see the same reduced values on every rank
    }
};

} // namespace

std::unique_ptr<Action> make_observe(Run& r) {
    return std::make_unique<Observe>(r.steps);
}

} // namespace pd::pipeline::run
