// SPDX-License-Identifier: MIT
// Requests the ranks agree on: a stop signal (SIGTERM, SIGUSR1) and the agreed wall-clock
// triggers (--checkpoint-every-wall, by rank 0's clock). Serial runs look at every step, MPI runs
// every stop_check_every steps (one Allreduce); never at the last step (it ends anyway).
#include "core/timer.hpp"
#include "pipeline/run/schedule.hpp"
#include "pipeline/run/signals.hpp"

namespace pd::pipeline::run {

namespace {

/// Steps between the ranks' agreement on a stop request under MPI (one Allreduce of ints).
constexpr std::int64_t stop_check_every = 10;

class Poll final : public Action {
  public:
    explicit Poll(const Run& r)
        : Action(Trigger().every(r.par ? stop_check_every : 1).before(r.steps.last)) {}
    void run(Run& r, std::int64_t n) override {
        auto& flags = flags_; // (kept: nothing allocated per step)
        auto& walls = walls_;
        flags.assign(1, stop_signal());
        walls.clear();
        for (auto& a : r.schedule->actions()) {
            if (!a->trigger().agreed_wall())
                continue;
            walls.push_back(&a->trigger());
            flags.push_back(r.ctx.rank == 0 && a->trigger().wall_due(wall_seconds()));
        }
        if (r.par)
            MPI_Allreduce(MPI_IN_PLACE, flags.data(), static_cast<int>(flags.size()), MPI_INT,
                          MPI_MAX, r.comm);
        for (std::size_t k = 0; k < walls.size(); ++k)
            if (flags[k + 1] != 0)
                walls[k]->request();
        if (flags[0] == 0)
            return;
        r.stopped_by = flags[0];
        r.stopped_at = n;
        for (auto& a : r.schedule->actions())
            if (a->trigger().stops())
                a->trigger().request();
    }

  private:
    std::vector<int> flags_;
    std::vector<Trigger*> walls_;
};

} // namespace

std::unique_ptr<Action> make_poll(Run& r) {
    return std::make_unique<Poll>(r);
}

} // namespace pd::pipeline::run
