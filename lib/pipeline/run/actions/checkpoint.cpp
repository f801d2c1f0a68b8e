// SPDX-License-Identifier: MIT
// /checkpoints: at the scene's checkpoint interval, at the last step, on a stop request and when
// --checkpoint-every-wall seconds passed since the last checkpoint (agreed by the poll).
#include "pipeline/run/schedule.hpp"
#include "store/checkpoint_io.hpp"
#include "store/frames.hpp"

#include <algorithm>

namespace pd::pipeline::run {

namespace {

/// The surface law's depth history: every rank's entries in rank order, this rank's rows its own
/// (collective).
void depth_history(Run& r, store::Checkpoint& c) {
    std::vector<std::int64_t> pairs;
    std::vector<double> depths;
    r.s.surface_depths(pairs, depths, c.depth_time);
    c.depth_time = r.s.domain().max(c.depth_time); // every rank evaluated at the same step
    const auto mine = static_cast<std::int64_t>(depths.size());
    std::int64_t before = 0, total = mine;
    if (r.par) {
        MPI_Exscan(&mine, &before, 1, MPI_INT64_T, MPI_SUM, r.comm);
        if (r.s.domain().rank() == 0)
            before = 0; // MPI_Exscan leaves rank 0's undefined
        total = r.s.domain().sum(mine);
    }
    const auto off = static_cast<std::size_t>(before);
    c.depth_pairs.assign(2 * static_cast<std::size_t>(total), 0);
    c.depths.assign(static_cast<std::size_t>(total), 0.0);
    std::copy(pairs.begin(), pairs.end(),
              c.depth_pairs.begin() + static_cast<std::ptrdiff_t>(2 * off));
    std::copy(depths.begin(), depths.end(), c.depths.begin() + static_cast<std::ptrdiff_t>(off));
    // Under MPI always this rank's run, empty or not: no run at all would mean every row (a rank
    // with no touching pair wrote its zeros over the others' entries: a restart at 1 and 4 ranks
    // of a 2-rank run differed by 0.99 in its frames).
    if (r.par)
        c.depth_runs = {
            {static_cast<std::uint64_t>(before), static_cast<std::uint64_t>(before + mine)}};
}

} // namespace

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
    depth_history(r, c);
    s.surface_build(c.build_x, c.build_whole);
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
