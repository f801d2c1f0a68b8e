// SPDX-License-Identifier: MIT
#include "pipeline/run/trigger.hpp"

#include "core/timer.hpp"

#include <algorithm>

namespace pd::pipeline::run {

Trigger& Trigger::every(std::int64_t steps) {
    every_.push_back(steps);
    return *this;
}

Trigger& Trigger::at(std::int64_t step) {
    at_.push_back(step);
    return *this;
}

Trigger& Trigger::before(std::int64_t step) {
    before_ = step;
    return *this;
}

Trigger& Trigger::every_wall(double seconds, Clock clock) {
    wall_ = seconds;
    clock_ = clock;
    return *this;
}

Trigger& Trigger::on_stop() {
    on_stop_ = true;
    return *this;
}

bool Trigger::operator()(std::int64_t n) const {
    if (!(n < before_))
        return false;
    if (requested_)
        return true;
    if (std::any_of(every_.begin(), every_.end(), [n](auto k) { return n % k == 0; }) ||
        std::find(at_.begin(), at_.end(), n) != at_.end())
        return true;
    return clock_ == Clock::local && wall_due(wall_seconds());
}

bool Trigger::wall_due(double now) const {
    return wall_ >= 0 && now - last_wall_ >= wall_;
}

void Trigger::fired(double now) {
    requested_ = false;
    last_wall_ = now;
}

} // namespace pd::pipeline::run
