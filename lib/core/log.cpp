// SPDX-License-Identifier: MIT
#include "core/log.hpp"

#include <cstdio>

namespace pd {

void Log::write_out(const std::string& line) const {
    std::fputs(line.c_str(), stdout);
    std::fputc('\n', stdout);
    std::fflush(stdout);
}

void Log::write_err(const std::string& line) const {
    std::string s = tool_ + ": " + line + "\n";
    std::fputs(s.c_str(), stderr);
}

void Log::error(const std::string& msg) const {
    std::string s = rank_ > 0 ? fmt::format("[rank {}] ", rank_) : std::string{};
    write_err(s + "error: " + msg);
}

} // namespace pd
