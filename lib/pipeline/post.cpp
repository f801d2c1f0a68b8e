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
#include "post/fragments.hpp"
#include "post/grains.hpp"
#include "post/vtk_export.hpp"
#include "post/walls.hpp"
#include "post/xdmf.hpp"
#include "store/frames.hpp"
#include "store/model_io.hpp"
#include "store/provenance.hpp"
#include "store/schema.hpp"

#include <fmt/format.h>

#include <algorithm>
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

namespace fs = std::filesystem;

/// The crack options with --crack-origin/direction/axis parsed in; checked before anything is
/// read or written.
post::CrackOptions crack_options(const PostOptions& opt) {
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
    return crack_opt;
}

/// Products are written under a temporary name and renamed into place, so a link under a
/// product's name is replaced, never followed; a FIFO, device, socket or directory there is
/// refused before anything is written (it would be replaced, or the rename fail half-way).
void refuse_special_products(const fs::path& out_dir, const std::string& stem) {
    std::error_code ec;
    if (!fs::is_directory(out_dir, ec))
        return;
    const std::array<std::string, 8> csv = {
        "observables.csv", "grains.csv",        "walls.csv",     "crack.csv",
        "crack_nodes.csv", "crack_summary.csv", "fragments.csv", "psd.csv"};
    for (const auto& e : fs::directory_iterator(out_dir, ec)) {
        const std::string name = e.path().filename().string();
        const auto ext = e.path().extension().string();
        const bool product =
            std::find(csv.begin(), csv.end(), name) != csv.end() ||
            (name.rfind(stem, 0) == 0 && (ext == ".vtu" || ext == ".pvd" || ext == ".xmf"));
        const auto st = e.symlink_status(ec);
        if (!product || ec || st.type() == fs::file_type::regular ||
            st.type() == fs::file_type::symlink)
            continue;
        throw InputError(fmt::format("-o {}: {} is not a regular file (a directory, FIFO, device "
                                     "or socket); pd-post would replace it: move it away first",
                                     out_dir.string(), e.path().string()));
    }
}

/// -o, or "post" beside the file; neither the input file nor an existing non-directory.
fs::path output_dir(const PostOptions& opt) {
    const fs::path out_dir =
        opt.out_dir.empty() ? fs::path(opt.file).parent_path() / "post" : fs::path(opt.out_dir);
    std::error_code ec;
    if (same_path(out_dir.string(), opt.file))
        throw InputError(fmt::format("-o {}: is the input file; give a directory for the "
                                     "outputs",
                                     out_dir.string()));
    if (fs::exists(out_dir, ec) && !fs::is_directory(out_dir, ec))
        throw InputError(fmt::format("-o {}: exists and is not a directory; give a directory "
                                     "for the outputs",
                                     out_dir.string()));
    refuse_special_products(out_dir, fs::path(opt.file).stem().string());
    return out_dir;
}

/// From here on the run is recorded in the file, unless refused (exit 2: the file stays byte for
/// byte as it was); ctx.on_exit runs after post() has returned or thrown, its read handle closed. A
/// read-only file still gets its outputs; only the record is missing (warned).
void record_on_exit(const PostOptions& opt, Context& ctx) {
    if (::access(opt.file.c_str(), W_OK) != 0)
        ctx.log.warn("{}: read-only ({}): the outputs are written, but this run cannot be "
                     "recorded in /provenance",
                     opt.file, std::strerror(errno));
    else
        ctx.on_exit = [&opt, &ctx](int code) {
            if (code == exit_input)
                return; // a refusal (bad option, damaged or unsuitable file): the file unchanged
            try {
                h5::File w(opt.file, h5::Mode::read_write);
                store::append_provenance(w, ctx.run, code);
            } catch (const std::exception& e) {
                ctx.log.warn("{}: this run could not be recorded in /provenance: {}", opt.file,
                             e.what());
            }
        };
}

/// One export run over an open file: its inputs and what was written so far.
struct Exporter {
    const PostOptions& opt;
    Context& ctx;
    const h5::File& f;
    const model::Model& m;
    fs::path out_dir;
    std::string stem;
    post::Progress progress;
    std::size_t frames = 0, rows = 0;
    std::string pvd{};
    std::vector<std::string> made{}; // "<what> -> <path>" of the other products

    void vtu() {
        const auto series = post::write_vtu_series(f, m.nodes, out_dir.string(), stem, progress,
                                                   post::grain_outline(m));
        frames = series.frames;
        pvd = series.pvd;
        const auto walls = post::write_wall_series(f, m, out_dir.string(), stem);
        if (!walls.pvd.empty())
            made.push_back(fmt::format("{} wall frame(s) -> {}", walls.frames, walls.pvd));
    }

    void xdmf() {
        const fs::path file(opt.file);
        const auto xmf = out_dir / (stem + ".xmf");
        // The HDF5 file is named relative to the .xmf, so the pair can move together.
        std::error_code ec;
        const auto ref = fs::relative(fs::absolute(file), fs::absolute(out_dir), ec);
        const auto n = post::write_xdmf(
            f, xmf.string(), ec || ref.empty() ? fs::absolute(file).string() : ref.string(), &m);
        made.push_back(fmt::format("{} frame(s) -> {}", n, xmf.string()));
    }

    void grains() {
        const auto csv = out_dir / "grains.csv";
        const auto n = post::write_grains_csv(f, m, csv.string(), progress);
        made.push_back(fmt::format("{} grain row(s) -> {}", n, csv.string()));
    }

    void fragments() {
        const auto csv = out_dir / "fragments.csv", psd = out_dir / "psd.csv";
        const auto c =
            post::write_fragments_csv(f, m, opt.fragment_opt, csv.string(), psd.string(), progress);
        made.push_back(fmt::format("{} fragment row(s) -> {}; {} frame(s) (d_cut {:.4g} m) -> {}",
                                   c.rows, csv.string(), c.frames, c.cutoff, psd.string()));
    }

    void walls(bool has_obs) {
        const bool meshed_walls = !store::read_reaction_bodies(f).empty();
        if (opt.walls && has_obs && (!m.walls.empty() || meshed_walls)) {
            const auto csv = out_dir / "walls.csv";
            const auto n = post::write_walls_csv(f, m, csv.string(), opt.wall_length);
            made.push_back(fmt::format("{} wall row(s) -> {}", n, csv.string()));
        } else if (opt.wall_length > 0 && m.walls.empty()) {
            ctx.log.warn("{}: --wall-length given but the file has no rigid walls ({}) and no "
                         "fixed or driven body reactions",
                         opt.file, store::path::walls);
        }
    }

    void crack(const post::CrackOptions& crack_opt) {
        const auto csv = out_dir / "crack.csv";
        const auto n = post::write_crack_csv(f, crack_opt, csv.string(), progress);
        made.push_back(fmt::format("{} crack row(s) -> {}", n, csv.string()));
        const auto fit =
            post::write_crack_arrivals(f, m, crack_opt, (out_dir / "crack_nodes.csv").string(),
                                       (out_dir / "crack_summary.csv").string(), progress);
        const std::string to_axis =
            std::isnan(fit.angle_to_axis_deg)
                ? std::string()
                : fmt::format(" ({:.2f} deg to the axis)", fit.angle_to_axis_deg);
        made.push_back(fmt::format("crack path: {} nodes, angle {:.2f} deg{}, mean speed "
                                   "{:.4g} m/s -> {}",
                                   fit.nodes, fit.angle_deg, to_axis, fit.mean_speed,
                                   (out_dir / "crack_summary.csv").string()));
        if (fit.nodes < 2 && !std::isnan(fit.nearest))
            ctx.log.warn(
                "{}: no crack path: the nearest cracked node ahead of the origin is "
                "{:.4g} m from it, beyond the start radius {:.4g} m (--crack-start-radius; "
                "a notch's corners are its half-width from its nominal tip)",
                opt.file, fit.nearest, fit.start_radius);
    }

    /// `pd-post: FILE: N frame(s) -> PVD; M observable row(s) -> CSV; <made>...`
    std::string summary() const {
        std::string s = fmt::format("pd-post: {}:", opt.file);
        if (opt.vtu)
            s += fmt::format(" {} frame(s) -> {}", frames, pvd.empty() ? "(none)" : pvd);
        if (opt.csv)
            s += fmt::format("{} {} observable row(s) -> {}", opt.vtu ? ";" : "", rows,
                             rows ? (out_dir / "observables.csv").string() : "(none)");
        bool first = !opt.vtu && !opt.csv;
        for (const auto& p : made) {
            s += (first ? " " : "; ") + p;
            first = false;
        }
        return s;
    }
};

} // namespace

void post(const PostOptions& opt, Context& ctx) {
    if (opt.check)
        return run_check(opt, ctx);
    const bool crack = !opt.crack_origin.empty() || !opt.crack_direction.empty();
    const post::CrackOptions crack_opt = crack_options(opt);
    if (opt.fragment_opt.fines_nodes < 1 || !(opt.fragment_opt.cutoff >= 0))
        throw ConfigError(opt.fragment_opt.fines_nodes < 1 ? "--fines-nodes" : "--psd-cutoff",
                          "expected --fines-nodes >= 1 and --psd-cutoff >= 0 (m)");
    const fs::path out_dir = output_dir(opt);
    std::string summary;
    {
        h5::File f(opt.file, h5::Mode::read);
        store::check_version(f);
        record_on_exit(opt, ctx);
        const auto model = store::read_model(f);
        Exporter run{opt,
                     ctx,
                     f,
                     model,
                     out_dir,
                     fs::path(opt.file).stem().string(),
                     make_progress(ctx, opt.progress_seconds)};
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
        if (opt.vtu && has_frames)
            run.vtu();
        if (opt.xdmf && has_frames)
            run.xdmf();
        if (opt.csv && has_obs)
            run.rows = post::write_observables_csv(f, (out_dir / "observables.csv").string());
        else if (opt.csv)
            ctx.log.warn("{}: no {} (run pd-solve first), no observables.csv written", opt.file,
                         store::path::observables);
        if (opt.grains && has_frames)
            run.grains();
        if (opt.fragments && has_frames)
            run.fragments();
        run.walls(has_obs);
        if (crack && has_frames)
            run.crack(crack_opt);
        summary = run.summary();
    }
    ctx.log.info("{}", summary);
}

} // namespace pd::pipeline
