// SPDX-License-Identifier: MIT
// A frame of /particles at the output interval and at the final step; under MPI also the work
// imbalance since the last frame (collective, as frames are), for the progress line.
#include "store/frames.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
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
        ensure_room(r, true, false);
        r.obs.flush();
        write_frame(r);
        check_named(r);
        if (r.par) {
            const double now = busy_seconds(timers), mine = now - busy_at_frame_;
            busy_at_frame_ = now;
            const double mean = r.s.domain().sum(mine) / r.ctx.size;
            r.imbalance = mean > 0 ? r.s.domain().max(mine) / mean : 1.0;
        }
    }

  private:
    /// After each frame (complete and flushed): a file renamed, removed or replaced under its
    /// name ends the run (exit 2), the ranks agreeing on rank 0's look.
    static void check_named(Run& r) {
        double gone = r.ctx.rank == 0 && !r.file.still_named() ? 1.0 : 0.0;
        if (r.par)
            gone = r.s.domain().max(gone);
        if (gone > 0)
            throw InputError(fmt::format(
                "{}: renamed, removed or replaced during the run: stopped at step {} after a "
                "complete frame. A renamed file holds the run up to that frame (continue it "
                "under its new name with --restart from its last checkpoint); a removed one is "
                "gone when pd-solve exits",
                r.opt.file, r.s.state().step));
    }

    int t_out_;
    double busy_at_frame_ = 0;
};

} // namespace

std::unique_ptr<Action> make_frames(Run& r) {
    return std::make_unique<Frames>(r);
}

} // namespace pd::pipeline::run
