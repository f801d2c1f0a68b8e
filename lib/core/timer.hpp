// SPDX-License-Identifier: MIT
// Labelled wall-clock timers ("pd::solver::bond_forces"), printed as a table at the end of a run.
#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace pd {

class Timers {
  public:
    /// Index of the timer named `label`, created on first use. Call outside hot loops.
    int id(const std::string& label);
    void add(int id, double seconds) {
        total_[id] += seconds;
        ++calls_[id];
    }
    double total(int id) const { return total_[id]; }
    /// Table of label, calls, seconds and share of `wall`.
    std::string table(double wall) const;

  private:
    std::vector<std::string> label_;
    std::vector<double> total_;
    std::vector<long> calls_;
};

/// RAII scope timer: adds the elapsed time to one Timers entry.
class ScopedTimer {
  public:
    ScopedTimer(Timers& t, int id)
        : t_(t)
        , id_(id)
        , start_(std::chrono::steady_clock::now()) {}
    ~ScopedTimer() {
        t_.add(id_,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
    }
    ScopedTimer(const ScopedTimer&) = delete;
    ScopedTimer& operator=(const ScopedTimer&) = delete;

  private:
    Timers& t_;
    int id_;
    std::chrono::steady_clock::time_point start_;
};

/// Seconds since an arbitrary epoch (steady clock).
inline double wall_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

} // namespace pd
