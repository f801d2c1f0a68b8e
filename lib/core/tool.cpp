// SPDX-License-Identifier: MIT
#include "core/tool.hpp"

#include "core/errors.hpp"
#include "core/files.hpp"
#include "core/mpi.hpp"
#include "core/threads.hpp"
#include "core/version.hpp"

#include <CLI/CLI.hpp>

#include <cstdlib>
#include <ctime>
#include <exception>
#include <filesystem>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace pd {

void add_common_flags(CLI::App& app, CommonOptions& opt) {
    app.add_flag("-q,--quiet", opt.quiet, "print errors and warnings only");
    app.add_flag("-v,--verbose", opt.verbose, "print debug messages");
    app.set_version_flag("--version", fmt::format("{} (pdgrain) {} git {}", app.get_name(),
                                                  pd::version, pd::git_commit));
}

int usage_exit(CLI::App& app, const CLI::ParseError& e) {
    // CLI11's own codes: 0 for --help/--version (CLI::Success, CallForHelp, CallForVersion),
    // 100-127 for errors; app.exit() prints either.
    return app.exit(e) == 0 ? exit_ok : exit_input;
}

std::string utc_now() {
    std::time_t t = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}

bool same_path(const std::string& a, const std::string& b) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::exists(a, ec) && fs::exists(b, ec)) {
        const bool eq = fs::equivalent(a, b, ec);
        if (!ec)
            return eq;
    }
    // Not both stat-able (a new output, or a directory this user cannot search): compare the
    // resolved paths, or the lexical absolute paths where resolving fails (never two empty
    // paths from two failures).
    auto resolved = [](const std::string& p) {
        std::error_code e;
        const auto abs = fs::absolute(p, e).lexically_normal();
        auto c = fs::weakly_canonical(abs, e);
        return e || c.empty() ? abs : c;
    };
    return resolved(a) == resolved(b);
}

void check_output_file(const std::string& option, const std::string& path,
                       const std::vector<std::pair<std::string, std::string>>& inputs) {
    check_output_target(option, path); // a directory, device, FIFO, socket; an input read
    for (const auto& [what, in] : inputs)
        if (!in.empty() && same_path(path, in))
            throw InputError(fmt::format("{} {}: is the same file as the {} {}; it would be "
                                         "overwritten; give another name",
                                         option, path, what, in));
}

namespace {
/// The ranks of this run on this rank's machine (1 without MPI).
int ranks_on_node(const mpi::Session& session) {
    int init = 0;
    MPI_Initialized(&init);
    if (session.size() <= 1 || !init)
        return 1;
    MPI_Comm node;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, session.rank(), MPI_INFO_NULL, &node);
    int n = 1;
    MPI_Comm_size(node, &n);
    MPI_Comm_free(&node);
    return n;
}

/// An error every rank raised alike is reported once, by rank 0.
void report(const Context& ctx, const std::exception& e) {
    if (ctx.rank == 0 || !ctx.errors_collective)
        ctx.log.error(e.what());
}
} // namespace

int run_tool(const std::string& tool, int argc, char** argv, const CommonOptions& opt,
             const std::function<void(Context&)>& body) {
    // Idle OpenMP threads sleep rather than spin (a re-exec when the environment must change).
    threads::passive_wait(argv);
    mpi::Session session(&argc, &argv);
    Verbosity v = opt.quiet ? Verbosity::quiet : opt.verbose ? Verbosity::debug : Verbosity::normal;
    Context ctx{Log(tool, session.rank(), v), {}, session.rank(), session.size(), {}};
    ctx.run.tool = tool;
    ctx.run.version = pd::version;
    ctx.run.git_commit = pd::git_commit;
    for (int i = 0; i < argc; ++i)
        ctx.run.command_line += (i ? " " : "") + std::string(argv[i]);
    ctx.run.start_time = utc_now();
    ctx.run.mpi_ranks = session.size();
#ifdef _OPENMP
    if (std::getenv("OMP_NUM_THREADS") == nullptr) {
        const auto choice = threads::default_threads(threads::machine(ranks_on_node(session)));
        omp_set_num_threads(choice.threads);
        ctx.run.threads_why = choice.why;
    } else {
        ctx.run.threads_why = fmt::format("OMP_NUM_THREADS={}", std::getenv("OMP_NUM_THREADS"));
    }
    ctx.run.threads = omp_get_max_threads();
    if (ctx.run.threads > 1 || std::getenv("OMP_WAIT_POLICY") != nullptr)
        ctx.run.threads_why += ", OpenMP wait " + threads::wait_policy();
#endif
    int code = exit_ok;
    try {
        body(ctx);
        code = ctx.exit_code;
    } catch (const InputError& e) {
        code = exit_input;
        report(ctx, e);
    } catch (const NumericalError& e) {
        code = exit_numerical;
        report(ctx, e);
    } catch (const std::exception& e) {
        code = exit_internal;
        report(ctx, e);
    }
    if (ctx.on_exit) {
        try {
            ctx.on_exit(code);
        } catch (const std::exception& e) {
            ctx.log.error(std::string("while recording provenance: ") + e.what());
            if (code == exit_ok)
                code = exit_internal;
        }
    }
    if (code != exit_ok && session.size() > 1 && !ctx.errors_collective)
        MPI_Abort(MPI_COMM_WORLD, code);
    return code;
}

} // namespace pd
