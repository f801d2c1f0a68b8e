// SPDX-License-Identifier: MIT
// run_tool(): the one startup of every pd-* executable. It opens the MPI session, builds the
// Context (log, ranks, threads, provenance) and maps exceptions to exit codes:
// 0 ok, 2 bad input, 3 numerical failure, 4 internal error, 75 stopped by a signal with a
// checkpoint to restart from. A command-line usage error is bad input too: exit 2 with CLI11's
// message (usage_exit()).
#pragma once

#include "core/log.hpp"

#include <functional>
#include <string>
#include <vector>

namespace CLI {
class App;
class ParseError;
} // namespace CLI

namespace pd {

enum ExitCode : int {
    exit_ok = 0,
    exit_input = 2,
    exit_numerical = 3,
    exit_internal = 4,
    /// Stopped early on request (SIGTERM/SIGUSR1) after writing a checkpoint: continue with
    /// --restart. 75 is EX_TEMPFAIL of sysexits.h ("try again later").
    exit_preempted = 75
};

/// Options every tool shares.
struct CommonOptions {
    bool quiet = false;
    bool verbose = false;
};

/// What one tool run records about itself in /provenance.
struct RunInfo {
    std::string tool;
    std::string version;
    std::string git_commit;
    std::string command_line;
    std::string start_time; ///< ISO 8601, UTC
    int mpi_ranks = 1;
    int threads = 1;
    /// How the thread count was chosen and the OpenMP wait policy (printed by pd-solve).
    std::string threads_why;
    /// pd-pack --set: the scene overrides as a JSON object (path -> value); empty if none.
    std::string overrides;
};

/// Per-run context handed to the pipeline function.
struct Context {
    Log log;
    RunInfo run;
    int rank = 0;
    int size = 1;
    /// Set by a pipeline step that owns a file: called once with the exit code before exit,
    /// so the file records the run's status in /provenance even when the run failed.
    std::function<void(int exit_code)> on_exit;
    /// Set by a step whose error every rank raised alike: the ranks then exit together with
    /// the error's code; otherwise a failing rank aborts them all (MPI_Abort).
    bool errors_collective = false;
    /// The exit code of a body that returns normally (exit_ok, or exit_preempted); every rank
    /// sets the same.
    int exit_code = exit_ok;
};

/// Adds --quiet, -v/--verbose and --version to a CLI11 app.
void add_common_flags(CLI::App& app, CommonOptions& opt);

/// The answer to a CLI11 parse error: --help and --version print and return exit_ok; a usage
/// error (missing argument, unconvertible value, unknown option, failed check) prints CLI11's
/// message to stderr and returns exit_input (2), like any other bad input. Every tool's main:
/// `try { app.parse(argc, argv); } catch (const CLI::ParseError& e) { return usage_exit(app, e); }`
int usage_exit(CLI::App& app, const CLI::ParseError& e);

/// ISO 8601 UTC time of now ("2026-11-23T13:38:05Z").
std::string utc_now();

/// True if `a` and `b` name the same file (an existing one, or the same path once resolved).
bool same_path(const std::string& a, const std::string& b);

/// Refuses (InputError, exit 2) an output file `path` given as `option` that is a directory or
/// names one of `inputs` ({option or role, path}): checked before anything is written.
void check_output_file(const std::string& option, const std::string& path,
                       const std::vector<std::pair<std::string, std::string>>& inputs);

/// Runs `body` inside the MPI session; returns the exit code.
int run_tool(const std::string& tool, int argc, char** argv, const CommonOptions& opt,
             const std::function<void(Context&)>& body);

} // namespace pd
