// SPDX-License-Identifier: MIT
// A wall with a start_time (a plate that enters a settled pack) must appear on the free side of
// every grain: a node behind its surface at that moment gets the full wall force at once, and
// the run blows up a step later with a message that blames dt. Checked just before the step in
// which the wall enters (after the step before it, or at set-up when the run's first step is
// that step), on every rank alike (reduced), and refused as a scene error (exit 2) naming the
// wall, with the frames before in the file. pd-pack checks the walls present at t = 0.
#include "core/errors.hpp"
#include "model/functions.hpp"
#include "pipeline/run/schedule.hpp"
#include "store/frames.hpp"

#include <cmath>
#include <string>

namespace pd::pipeline::run {

namespace {

/// The walls that enter between time t and t + dt.
std::vector<std::size_t> entering(const model::Model& m, double t, double dt) {
    std::vector<std::size_t> w;
    for (std::size_t k = 0; k < m.walls.size(); ++k)
        if (!model::wall_present(m.walls[k], t) && model::wall_present(m.walls[k], t + dt))
            w.push_back(k);
    return w;
}

/// Throws when a node of this run lies behind a wall that enters at the next step (collective).
void check_entry(Run& r) {
    const auto& st = r.s.state();
    for (const auto k : entering(r.m, st.time, r.steps.dt)) {
        const auto& wall = r.m.walls[k];
        struct {
            double d;
            int i;
        } mine{0.0, -1}, all{};
        double count = 0;
        for (auto row : st.rows) {
            const auto i = static_cast<std::size_t>(row);
            const double d = model::wall_distance(wall, &st.x[3 * i]);
            if (d < 0) {
                count += 1;
                if (d < mine.d) {
                    mine.d = d;
                    mine.i = static_cast<int>(i);
                }
            }
        }
        all = mine;
        if (r.par) {
            MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_DOUBLE, MPI_SUM, r.comm);
            MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE_INT, MPI_MINLOC, r.comm);
        }
        if (count == 0)
            continue;
        r.agreed = true; // every rank throws at this step (reduced values)
        r.obs.flush();
        const auto i = static_cast<std::size_t>(all.i);
        throw InputError(fmt::format(
            "{}: wall '{}' (walls[{}]) enters at t = {:.6g} s with {:.0f} node(s) behind its "
            "surface, the deepest {:.4g} m (node {} of body {}): it would appear inside the "
            "grains. Move its point to the free side of the grains or change its start_time "
            "(the frames before stay in the file)",
            r.opt.file, wall.name, k, wall.start_time, count, -all.d, i, st.body[i]));
    }
}

class WallEntry final : public Action {
  public:
    explicit WallEntry(Trigger t)
        : Action(std::move(t)) {}
    void run(Run& r, std::int64_t) override { check_entry(r); }
};

} // namespace

std::unique_ptr<Action> make_wall_entry(Run& r) {
    // The steps just before an entry: time is a running sum of dt, so a window of steps around
    // start_time / dt, each checked exactly.
    Trigger t;
    bool any = false;
    for (const auto& wall : r.m.walls) {
        if (!(wall.start_time > 0))
            continue;
        const auto n = static_cast<std::int64_t>(std::floor(wall.start_time / r.steps.dt));
        for (auto k = n - 2; k <= n + 1; ++k)
            if (k > r.steps.first && k <= r.steps.last) {
                t.at(k);
                any = true;
            }
    }
    check_entry(r); // the run's first step
    return any ? std::make_unique<WallEntry>(std::move(t)) : nullptr;
}

} // namespace pd::pipeline::run
