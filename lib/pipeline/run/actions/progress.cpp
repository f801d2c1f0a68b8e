// SPDX-License-Identifier: MIT
// The progress line: on rank 0 every --progress-every wall seconds (its own clock, no
// collective), and on every rank at the last step.
#include "pipeline/run/schedule.hpp"

namespace pd::pipeline::run {

namespace {

Trigger progress_trigger(const Run& r) {
    Trigger t;
    t.at(r.steps.last);
    if (r.ctx.rank == 0)
        t.every_wall(r.opt.progress_seconds, Trigger::Clock::local);
    return t;
}

class Progress final : public Action {
  public:
    explicit Progress(const Run& r)
        : Action(progress_trigger(r)) {}
    void run(Run& r, std::int64_t n) override {
        const auto& o = r.last_obs; // no collective call here: ranks differ in wall time
        const auto& st = r.steps;
        const double el = wall_seconds() - r.wall0;
        const double done = static_cast<double>(n - st.first);
        r.ctx.log.info("step {}/{} t={:.4e} s dt={:.3e} s KE={:.4e} J broken={} contacts={} "
                       "wall={:.1f} s ETA={:.1f} s{}",
                       n, st.total, r.s.state().time, st.dt, o.kinetic_energy, o.broken_bonds,
                       o.contact_count, el, el / done * static_cast<double>(st.last - n),
                       r.par ? fmt::format(" imbalance={:.3f}", r.imbalance) : std::string{});
    }
};

} // namespace

std::unique_ptr<Action> make_progress(Run& r) {
    return std::make_unique<Progress>(r);
}

} // namespace pd::pipeline::run
