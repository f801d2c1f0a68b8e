// SPDX-License-Identifier: MIT
// A frame of /particles at the output interval and at the final step; under MPI also the work
// imbalance since the last frame (collective, as frames are), for the progress line.
#include "store/frames.hpp"

#include "pipeline/run/schedule.hpp"

namespace pd::pipeline::run {

namespace {

class Frames final : public Action {
  public:
    explicit Frames(Run& r)
        : Action(Trigger().every(r.steps.out_every).at(r.steps.total))
        , t_out_(r.s.timers().id("pd::store::output")) {}
    void run(Run& r, std::int64_t) override {
        Timers& timers = r.s.timers();
        ScopedTimer t(timers, t_out_);
        r.obs.flush();
        write_frame(r);
        if (r.par) {
            const double now = busy_seconds(timers), mine = now - busy_at_frame_;
            busy_at_frame_ = now;
            const double mean = r.s.domain().sum(mine) / r.ctx.size;
            r.imbalance = mean > 0 ? r.s.domain().max(mine) / mean : 1.0;
        }
    }

  private:
    int t_out_;
    double busy_at_frame_ = 0;
};

} // namespace

std::unique_ptr<Action> make_frames(Run& r) {
    return std::make_unique<Frames>(r);
}

} // namespace pd::pipeline::run
