// SPDX-License-Identifier: MIT
// -v: one line per frame written (its index, step and time, with the broken bonds, contacts
// and contact-list rebuilds of the last observation), to follow a long run's output.
#include "pipeline/run/schedule.hpp"
#include "store/frames.hpp"

namespace pd::pipeline::run {

namespace {

class FrameLog final : public Action {
  public:
    explicit FrameLog(const Run& r)
        : Action(Trigger().every(r.steps.out_every).at(r.steps.total)) {}
    void run(Run& r, std::int64_t n) override {
        r.ctx.log.debug("frame {} at step {} (t = {:.6g} s): {} broken bonds, {} contacts, {} "
                        "contact-list rebuilds",
                        r.frames.frames() - 1, n, r.s.state().time, r.last_obs.broken_bonds,
                        r.last_obs.contact_count, r.s.contact().rebuilds());
    }
};

} // namespace

std::unique_ptr<Action> make_frame_log(Run& r) {
    return std::make_unique<FrameLog>(r);
}

} // namespace pd::pipeline::run
