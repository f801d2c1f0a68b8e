// SPDX-License-Identifier: MIT
// pd-post pipeline step (see post.hpp): check, or VTU/PVD + observables.csv export.
#include "pipeline/post.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "post/check.hpp"
#include "post/csv.hpp"
#include "post/vtk_export.hpp"
#include "store/model_io.hpp"
#include "store/provenance.hpp"
#include "store/schema.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <system_error>

namespace pd::pipeline {

namespace {

void run_check(const PostOptions& opt, Context& ctx) {
    h5::File f(opt.file, h5::Mode::read);
    const auto problems = post::check(f);
    if (problems.empty()) {
        ctx.log.info("{}: valid pd-file (schema {})", opt.file, store::schema_version);
        return;
    }
    for (const auto& p : problems)
        ctx.log.error(opt.file + ": " + p);
    throw SchemaError(opt.file, "/",
                      fmt::format("{} violation(s) of the pd-file {} schema (listed above)",
                                  problems.size(), store::schema_version));
}

} // namespace

void post(const PostOptions& opt, Context& ctx) {
    if (opt.check)
        return run_check(opt, ctx);

    namespace fs = std::filesystem;
    const fs::path file(opt.file);
    const fs::path out_dir =
        opt.out_dir.empty() ? file.parent_path() / "post" : fs::path(opt.out_dir);
    const std::string stem = file.stem().string();
    std::size_t frames = 0, rows = 0;
    std::string pvd;
    {
        h5::File f(opt.file, h5::Mode::read);
        store::check_version(f);
        // From here on the run is recorded in the file, failed or not. The read handle above is
        // closed before run_tool calls this (post() has returned or thrown by then).
        ctx.on_exit = [&opt, &ctx](int code) {
            h5::File w(opt.file, h5::Mode::read_write);
            store::append_provenance(w, ctx.run, code);
        };
        const auto model = store::read_model(f);

        std::error_code ec;
        fs::create_directories(out_dir, ec);
        if (ec)
            throw InputError(fmt::format("{}: cannot create the output directory: {}",
                                         out_dir.string(), ec.message()));
        if (opt.vtu) {
            if (f.exists(store::path::particles)) {
                const auto series = post::write_vtu_series(f, model.nodes, out_dir.string(), stem);
                frames = series.frames;
                pvd = series.pvd;
            } else {
                ctx.log.warn("{}: no frames ({} missing; run pd-solve first), no .vtu written",
                             opt.file, store::path::particles);
            }
        }
        if (opt.csv) {
            if (f.exists(store::path::observables)) {
                rows = post::write_observables_csv(f, (out_dir / "observables.csv").string());
            } else {
                ctx.log.warn("{}: no {} (run pd-solve first), no observables.csv written", opt.file,
                             store::path::observables);
            }
        }
    }
    std::string summary = fmt::format("pd-post: {}:", opt.file);
    if (opt.vtu)
        summary += fmt::format(" {} frame(s) -> {}", frames, pvd.empty() ? "(none)" : pvd);
    if (opt.csv)
        summary += fmt::format("{} {} observable row(s) -> {}", opt.vtu ? ";" : "", rows,
                               rows ? (out_dir / "observables.csv").string() : "(none)");
    ctx.log.info("{}", summary);
}

} // namespace pd::pipeline
