// SPDX-License-Identifier: MIT
// Typed errors of pdgrain. Library code throws; only run_tool() turns them into exit codes:
// InputError -> 2, NumericalError -> 3, anything else -> 4 (see README "Exit codes").
#pragma once

#include <fmt/format.h>

#include <source_location>
#include <stdexcept>
#include <string>

namespace pd {

/// Base of every pdgrain error. what() is one line, ready for stderr.
class Error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// Bad input: scene keys, files, datasets, command-line values. Exit code 2.
class InputError : public Error {
  public:
    using Error::Error;
};

/// A scene key is missing, unknown or has a bad value. `key` is the JSON path ("discs[1].radius").
class ConfigError : public InputError {
  public:
    ConfigError(std::string key, const std::string& why)
        : InputError(fmt::format("{}: {}", key, why))
        , key_(std::move(key)) {}
    const std::string& key() const { return key_; }

  private:
    std::string key_;
};

/// A file breaks the pd-file schema: names the file and dataset path.
class SchemaError : public InputError {
  public:
    SchemaError(const std::string& file, const std::string& path, const std::string& why)
        : InputError(fmt::format("{}: {}: {}", file, path, why)) {}
};

/// Numerical failure: NaN, blow-up, unstable time step. Exit code 3.
class NumericalError : public Error {
  public:
    using Error::Error;
};

/// A bug in pdgrain. Exit code 4.
class InternalError : public Error {
  public:
    using Error::Error;
};

[[noreturn]] inline void check_failed(const char* expr, const std::string& msg,
                                      std::source_location loc) {
    throw InternalError(fmt::format("internal check '{}' failed at {}:{}: {} (please report)", expr,
                                    loc.file_name(), loc.line(), msg));
}

} // namespace pd

/// Always-on invariant check; throws pd::InternalError with the source location.
#define PD_CHECK(expr, msg)                                                                        \
    do {                                                                                           \
        if (!(expr))                                                                               \
            ::pd::check_failed(#expr, (msg), std::source_location::current());                     \
    } while (0)

#if defined(PD_ENABLE_ASSERTS) || !defined(NDEBUG)
#define PD_ASSERT(expr) PD_CHECK(expr, "assertion")
#else
#define PD_ASSERT(expr) ((void)0)
#endif
