// SPDX-License-Identifier: MIT
// One Log per process, owned by run_tool and reached through Context (no singleton).
// error: stderr on every rank; warn: stderr, rank 0; info: stdout, rank 0; debug: with -v.
#pragma once

#include <fmt/format.h>

#include <string>

namespace pd {

enum class Verbosity { quiet = 0, normal = 1, debug = 2 };

class Log {
  public:
    Log(std::string tool, int rank = 0, Verbosity v = Verbosity::normal)
        : tool_(std::move(tool))
        , rank_(rank)
        , verbosity_(v) {}

    template <class... A>
    void info(fmt::format_string<A...> f, A&&... a) const {
        if (rank_ == 0 && verbosity_ >= Verbosity::normal)
            write_out(fmt::format(f, std::forward<A>(a)...));
    }
    template <class... A>
    void debug(fmt::format_string<A...> f, A&&... a) const {
        if (rank_ == 0 && verbosity_ >= Verbosity::debug)
            write_out(fmt::format(f, std::forward<A>(a)...));
    }
    template <class... A>
    void warn(fmt::format_string<A...> f, A&&... a) const {
        if (rank_ == 0)
            write_err("warning: " + fmt::format(f, std::forward<A>(a)...));
    }
    void error(const std::string& msg) const;

    Verbosity verbosity() const { return verbosity_; }
    void set_verbosity(Verbosity v) { verbosity_ = v; }
    const std::string& tool() const { return tool_; }

  private:
    void write_out(const std::string& line) const;
    void write_err(const std::string& line) const;
    std::string tool_;
    int rank_;
    Verbosity verbosity_;
};

} // namespace pd
