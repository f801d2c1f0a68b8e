// SPDX-License-Identifier: MIT
// pd-post pipeline step (see post.hpp): check, or VTU/PVD + XDMF + CSV export (observables,
// grains, walls, crack). Every product is computed from the file alone, frames streamed.
#include "pipeline/post.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "post/check.hpp"
#include "post/crack.hpp"
#include "post/crack_arrival.hpp"
#include "post/csv.hpp"
#include "post/grains.hpp"
#include "post/vtk_export.hpp"
#include "post/walls.hpp"
#include "post/xdmf.hpp"
#include "store/frames.hpp"
#include "store/model_io.hpp"
#include "store/provenance.hpp"
#include "store/schema.hpp"

#include <fmt/format.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <system_error>
#include <unistd.h>
#include <vector>

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

/// A progress sink printing one line every `seconds` of wall clock (and none for short runs):
/// `pd-post: grains frame 1200/5000 (24%) wall=31 s`.
post::Progress make_progress(const Context& ctx, double seconds) {
    using clock = std::chrono::steady_clock;
    const auto start = clock::now();
    auto last = std::make_shared<clock::time_point>(start);
    return [&ctx, seconds, start, last](const char* what, std::size_t done, std::size_t total) {
        const auto now = clock::now();
        if (std::chrono::duration<double>(now - *last).count() < seconds)
            return;
        *last = now;
        ctx.log.info("pd-post: {} frame {}/{} ({:.0f}%) wall={:.0f} s", what, done, total,
                     total ? 100.0 * static_cast<double>(done) / static_cast<double>(total) : 100.0,
                     std::chrono::duration<double>(now - start).count());
    };
}

} // namespace

void post(const PostOptions& opt, Context& ctx) {
    if (opt.check)
        return run_check(opt, ctx);

    // The crack options are checked before anything is read or written.
    const bool crack = !opt.crack_origin.empty() || !opt.crack_direction.empty();
    post::CrackOptions crack_opt = opt.crack_opt;
    const auto point = [](const std::vector<double>& v, const char* key, std::array<double, 3>& p) {
        if (v.empty())
            return;
        if (v.size() != 2 && v.size() != 3)
            throw ConfigError(
                key, fmt::format("expected 2 or 3 comma-separated values, got {}", v.size()));
        p = {v[0], v[1], v.size() == 3 ? v[2] : 0.0};
    };
    point(opt.crack_origin, "--crack-origin", crack_opt.origin);
    point(opt.crack_direction, "--crack-direction", crack_opt.direction);
    point(opt.crack_axis, "--crack-axis", crack_opt.axis);

    namespace fs = std::filesystem;
    const fs::path file(opt.file);
    const fs::path out_dir =
        opt.out_dir.empty() ? file.parent_path() / "post" : fs::path(opt.out_dir);
    const std::string stem = file.stem().string();
    {
        std::error_code ec;
        if (same_path(out_dir.string(), opt.file))
            throw InputError(fmt::format("-o {}: is the input file; give a directory for the "
                                         "outputs",
                                         out_dir.string()));
        if (fs::exists(out_dir, ec) && !fs::is_directory(out_dir, ec))
            throw InputError(fmt::format("-o {}: exists and is not a directory; give a directory "
                                         "for the outputs",
                                         out_dir.string()));
    }
    std::size_t frames = 0, rows = 0;
    std::string pvd;
    std::vector<std::string> made; // "<what> -> <path>" of the other products
    {
        h5::File f(opt.file, h5::Mode::read);
        store::check_version(f);
        // From here on the run is recorded in the file, failed or not. The read handle above is
        // closed before run_tool calls this (post() has returned or thrown by then).
        // A read-only file still gets its outputs; only the record is missing (warned).
        if (::access(opt.file.c_str(), W_OK) != 0)
            ctx.log.warn("{}: read-only ({}): the outputs are written, but this run cannot be "
                         "recorded in /provenance",
                         opt.file, std::strerror(errno));
        else
            ctx.on_exit = [&opt, &ctx](int code) {
                try {
                    h5::File w(opt.file, h5::Mode::read_write);
                    store::append_provenance(w, ctx.run, code);
                } catch (const std::exception& e) {
                    ctx.log.warn("{}: this run could not be recorded in /provenance: {}", opt.file,
                                 e.what());
                }
            };
        const auto model = store::read_model(f);
        const auto progress = make_progress(ctx, opt.progress_seconds);

        std::error_code ec;
        fs::create_directories(out_dir, ec);
        if (ec)
            throw InputError(fmt::format("{}: cannot create the output directory: {}",
                                         out_dir.string(), ec.message()));
        const bool has_frames = f.exists(store::path::particles);
        const bool has_obs = f.exists(store::path::observables);
        if (!has_frames && (opt.vtu || opt.xdmf || opt.grains || crack))
            ctx.log.warn("{}: no frames ({} missing; run pd-solve first), no .vtu written",
                         opt.file, store::path::particles);
        if (opt.vtu && has_frames) {
            const auto series =
                post::write_vtu_series(f, model.nodes, out_dir.string(), stem, progress);
            frames = series.frames;
            pvd = series.pvd;
            const auto walls = post::write_wall_series(f, model, out_dir.string(), stem);
            if (!walls.pvd.empty())
                made.push_back(fmt::format("{} wall frame(s) -> {}", walls.frames, walls.pvd));
        }
        if (opt.xdmf && has_frames) {
            const auto xmf = out_dir / (stem + ".xmf");
            // The HDF5 file is named relative to the .xmf, so the pair can move together.
            const auto ref = fs::relative(fs::absolute(file), fs::absolute(out_dir), ec);
            const auto n = post::write_xdmf(
                f, xmf.string(), ec || ref.empty() ? fs::absolute(file).string() : ref.string(),
                &model);
            made.push_back(fmt::format("{} frame(s) -> {}", n, xmf.string()));
        }
        if (opt.csv) {
            if (has_obs) {
                rows = post::write_observables_csv(f, (out_dir / "observables.csv").string());
            } else {
                ctx.log.warn("{}: no {} (run pd-solve first), no observables.csv written", opt.file,
                             store::path::observables);
            }
        }
        if (opt.grains && has_frames) {
            const auto csv = out_dir / "grains.csv";
            const auto n = post::write_grains_csv(f, model, csv.string(), progress);
            made.push_back(fmt::format("{} grain row(s) -> {}", n, csv.string()));
        }
        const bool meshed_walls = !store::read_reaction_bodies(f).empty();
        if (opt.walls && has_obs && (!model.walls.empty() || meshed_walls)) {
            const auto csv = out_dir / "walls.csv";
            const auto n = post::write_walls_csv(f, model, csv.string(), opt.wall_length);
            made.push_back(fmt::format("{} wall row(s) -> {}", n, csv.string()));
        } else if (opt.wall_length > 0 && model.walls.empty()) {
            ctx.log.warn("{}: --wall-length given but the file has no rigid walls ({}) and no "
                         "fixed or driven body reactions",
                         opt.file, store::path::walls);
        }
        if (crack && has_frames) {
            const auto csv = out_dir / "crack.csv";
            const auto n = post::write_crack_csv(f, crack_opt, csv.string(), progress);
            made.push_back(fmt::format("{} crack row(s) -> {}", n, csv.string()));
            const auto fit = post::write_crack_arrivals(
                f, model, crack_opt, (out_dir / "crack_nodes.csv").string(),
                (out_dir / "crack_summary.csv").string(), progress);
            const std::string to_axis =
                std::isnan(fit.angle_to_axis_deg)
                    ? std::string()
                    : fmt::format(" ({:.2f} deg to the axis)", fit.angle_to_axis_deg);
            made.push_back(fmt::format("crack path: {} nodes, angle {:.2f} deg{}, mean speed "
                                       "{:.4g} m/s -> {}",
                                       fit.nodes, fit.angle_deg, to_axis, fit.mean_speed,
                                       (out_dir / "crack_summary.csv").string()));
        }
    }
    std::string summary = fmt::format("pd-post: {}:", opt.file);
    if (opt.vtu)
        summary += fmt::format(" {} frame(s) -> {}", frames, pvd.empty() ? "(none)" : pvd);
    if (opt.csv)
        summary += fmt::format("{} {} observable row(s) -> {}", opt.vtu ? ";" : "", rows,
                               rows ? (out_dir / "observables.csv").string() : "(none)");
    bool first = !opt.vtu && !opt.csv;
    for (const auto& m : made) {
        summary += (first ? " " : "; ") + m;
        first = false;
    }
    ctx.log.info("{}", summary);
}

} // namespace pd::pipeline
