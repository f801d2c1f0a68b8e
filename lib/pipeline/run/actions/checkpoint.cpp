// SPDX-License-Identifier: MIT
// /checkpoints: at the scene's checkpoint interval, at the last step, on a stop request and when
// --checkpoint-every-wall seconds passed since the last checkpoint (agreed by the poll).
#include "pipeline/run/schedule.hpp"
#include "store/checkpoint_io.hpp"
#include "store/frames.hpp"

#include <algorithm>

namespace pd::pipeline::run {

void checkpoint_now(Run& r) {
    const auto& s = r.s;
    store::Checkpoint c;
    const auto& st = s.state();
    c.step = st.step;
    c.time = st.time;
    c.dt = r.steps.dt;
    c.u = st.u;
    c.v = st.v;
    c.f = st.f;
    s.alive_into(c.alive); // this rank's entries; write_runs reads only those
    c.broken_total = s.broken_total();
    c.external_work = s.domain().sum(s.external_work());
    c.external_power = s.domain().sum(s.external_power_last());
    const auto& d = s.dissipation();
    std::vector<double> diss{d.fracture,     d.damping,       d.friction,    d.viscous,
                             d.damping_rate, d.friction_rate, d.viscous_rate};
    s.domain().sum(diss);
    std::copy(diss.begin(), diss.end(), c.dissipation.begin());
    c.interval_sum = s.interval_sum();
    s.domain().sum(c.interval_sum);
    c.interval_steps = s.interval_steps();
    if (r.par) {
        c.node_runs = s.domain().runs();
        for (const auto& run : c.node_runs)
            c.bond_runs.push_back({static_cast<std::uint64_t>(r.m.bonds.offsets[run[0]]),
                                   static_cast<std::uint64_t>(r.m.bonds.offsets[run[1]])});
    }
    store::write_checkpoint(r.file, c);
}

namespace {

Trigger checkpoint_trigger(const Run& r) {
    Trigger t;
    t.every(r.steps.ckpt_every).at(r.steps.last).on_stop();
    if (r.opt.checkpoint_wall_seconds > 0)
        t.every_wall(r.opt.checkpoint_wall_seconds, Trigger::Clock::agreed);
    return t;
}

class Checkpoint final : public Action {
  public:
    explicit Checkpoint(Run& r)
        : Action(checkpoint_trigger(r))
        , t_ck_(r.s.timers().id("pd::store::checkpoint")) {}
    void run(Run& r, std::int64_t) override {
        ScopedTimer t(r.s.timers(), t_ck_);
        ensure_room(r, false, true);
        r.obs.flush();
        checkpoint_now(r);
    }

  private:
    int t_ck_;
};

} // namespace

std::unique_ptr<Action> make_checkpoint(Run& r) {
    return std::make_unique<Checkpoint>(r);
}

} // namespace pd::pipeline::run
