// SPDX-License-Identifier: MIT
// When a scheduled action of the step loop runs (HOOMD-blue's Trigger, LAMMPS' next_dump):
// a union of conditions, each optional.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

namespace pd::pipeline::run {

/// When an action runs, asked once per step after the step (and by the loop before the step, for
/// actions that need the energies). A trigger fires at step n if any of its conditions holds:
///   every(k)        n is a multiple of k
///   at(s)           n == s
///   every_wall(t)   t wall seconds have passed since it last fired: this rank's own clock
///                   (Clock::local), or rank 0's clock agreed by the poll action (Clock::agreed,
///                   collective, only at the poll's steps)
///   request()       once, at the next query (set by another action: the poll)
///   on_stop()       when a stop is requested (the poll requests every such trigger)
/// and, with before(s), only while n < s.
class Trigger {
  public:
    enum class Clock { local, agreed };

    Trigger& every(std::int64_t steps);
    Trigger& at(std::int64_t step);
    Trigger& before(std::int64_t step);
    /// seconds >= 0 (0: at every query).
    Trigger& every_wall(double seconds, Clock clock);
    Trigger& on_stop();

    /// Fires at step n (a step-count condition, a pending request, or a local wall time due).
    bool operator()(std::int64_t n) const;
    /// The agreed wall-time condition is due on this rank's clock (the poll reduces it).
    bool wall_due(double now) const;
    bool agreed_wall() const { return wall_ >= 0 && clock_ == Clock::agreed; }
    bool stops() const { return on_stop_; }

    void request() { requested_ = true; }
    /// Starts the wall clock (at the start of the loop).
    void start(double now) { last_wall_ = now; }
    /// Called after the action ran: clears the request, restarts the wall clock.
    void fired(double now);

  private:
    std::vector<std::int64_t> every_, at_;
    std::int64_t before_ = std::numeric_limits<std::int64_t>::max();
    double wall_ = -1; ///< < 0: no wall-time condition
    Clock clock_ = Clock::local;
    double last_wall_ = 0;
    bool on_stop_ = false;
    bool requested_ = false;
};

} // namespace pd::pipeline::run
