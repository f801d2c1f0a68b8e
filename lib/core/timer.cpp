// SPDX-License-Identifier: MIT
#include "core/timer.hpp"

#include <fmt/format.h>

namespace pd {

int Timers::id(const std::string& label) {
    for (std::size_t i = 0; i < label_.size(); ++i)
        if (label_[i] == label)
            return static_cast<int>(i);
    label_.push_back(label);
    total_.push_back(0.0);
    calls_.push_back(0);
    return static_cast<int>(label_.size() - 1);
}

std::string Timers::table(double wall) const {
    std::string s =
        fmt::format("{:<34} {:>10} {:>12} {:>7}\n", "timer", "calls", "seconds", "share");
    for (std::size_t i = 0; i < label_.size(); ++i)
        s += fmt::format("{:<34} {:>10} {:>12.4f} {:>6.1f}%\n", label_[i], calls_[i], total_[i],
                         wall > 0 ? 100.0 * total_[i] / wall : 0.0);
    s += fmt::format("{:<34} {:>10} {:>12.4f}\n", "wall", "", wall);
    return s;
}

} // namespace pd
