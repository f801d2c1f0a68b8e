// SPDX-License-Identifier: MIT
// A wall with a start_time (a plate that enters a settled pack) must appear on the free side of
// every grain: a node behind its surface at that moment gets the full wall force at once, and
// the run blows up a step later with a message that blames dt. Checked just before the step in
// which the wall enters (after the step before it, or at set-up when the run's first step is
// that step), on every rank alike (reduced), and refused as a scene error (exit 2) naming the
// wall, with the frames before in the file. pd-pack checks the walls present at t = 0.
// A wall that enters above the grains ("enter": "above_grains") is first placed there, from
// the state at that step: the scene needs no settled height.
#include "core/errors.hpp"
#include "model/functions.hpp"
#include "pipeline/run/schedule.hpp"
#include "store/frames.hpp"
#include "store/model_io.hpp"

#include <algorithm>
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

/// A wall that enters above the grains: placed where the grains are now (collective), its
/// position written to the file and handed to the solver.
void place(Run& r, std::size_t k) {
    const auto& st = r.s.state();
    auto& wall = r.m.walls[k];
    double level = HUGE_VAL;
    for (auto row : st.rows) {
        const auto i = static_cast<std::size_t>(row);
        const auto g = r.m.bodies.group[static_cast<std::size_t>(st.body[i])];
        level = std::min(level, model::entry_level(r.m, wall, g, &st.x[3 * i]));
    }
    if (r.par)
        MPI_Allreduce(MPI_IN_PLACE, &level, 1, MPI_DOUBLE, MPI_MIN, r.comm);
    if (!std::isfinite(level)) {
        r.agreed = true;
        r.obs.flush();
        throw InputError(fmt::format("{}: wall '{}' (walls[{}]) enters above the grains at t = "
                                     "{:.6g} s but touches no grain (no contact law between them)",
                                     r.opt.file, wall.name, k, wall.start_time));
    }
    const auto before = wall.point;
    model::place_wall(wall, level);
    r.s.wall_moved(k);
    store::write_wall_position(r.file, k, wall);
    const double moved = (wall.point[0] - before[0]) * wall.normal[0] +
                         (wall.point[1] - before[1]) * wall.normal[1] +
                         (wall.point[2] - before[2]) * wall.normal[2];
    r.ctx.log.info("wall '{}' enters above the grains at t = {:.6g} s: point ({:.6g}, {:.6g}, "
                   "{:.6g}) m, {:.4g} m along its normal from the scene's, gap {:.4g} m",
                   wall.name, st.time + r.steps.dt, wall.point[0], wall.point[1], wall.point[2],
                   moved, wall.gap);
}

/// Places the walls that enter above the grains at the next step, then throws when a node of
/// this run lies behind a wall that enters then (collective).
void check_entry(Run& r) {
    const auto& st = r.s.state();
    for (const auto k : entering(r.m, st.time, r.steps.dt)) {
        if (r.m.walls[k].enter == model::WallEnter::above_grains)
            place(r, k);
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
