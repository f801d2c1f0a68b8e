// SPDX-License-Identifier: MIT
// pd-post: export a pd-file to VTU/PVD, an XDMF sidecar and CSV tables (observables, grains,
// walls, crack), or --check it against the schema. Usage: pd-post FILE [-o DIR] [options]
// Exit codes: 0 ok, 2 bad or invalid file or option, 4 internal error (see README).
#include "core/tool.hpp"
#include "pipeline/post.hpp"

#include <CLI/CLI.hpp>

int main(int argc, char** argv) {
    pd::pipeline::PostOptions opt;
    CLI::App app{"pd-post: export a pd file to ParaView (.vtu/.pvd/.xmf) and CSV, or check it",
                 "pd-post"};
    app.add_option("file", opt.file, "pd HDF5 file (its /provenance is appended)")->required();
    app.add_option("-o,--out", opt.out_dir, "output directory (default: 'post' beside FILE)");
    app.add_flag("--check", opt.check, "only validate FILE against the schema; write nothing");
    for (auto [flag, target] : {std::pair{"--no-vtu", &opt.vtu},
                                {"--no-csv", &opt.csv},
                                {"--no-xdmf", &opt.xdmf},
                                {"--no-grains", &opt.grains},
                                {"--no-walls", &opt.walls}})
        app.add_flag_callback(
            flag, [t = target] { *t = false; },
            std::string("do not write ") + (flag + 5) + " output");
    app.add_option("--wall-length", opt.wall_length, "walls.csv stress = force / L (m; 3D: m2)");
    app.add_option("--crack-origin", opt.crack_origin, "crack path point x,y[,z] (m); crack.csv")
        ->delimiter(',')
        ->expected(2, 3);
    app.add_option("--crack-direction", opt.crack_direction, "crack growth direction dx,dy[,dz]")
        ->delimiter(',')
        ->expected(2, 3);
    app.add_option("--crack-axis", opt.crack_axis, "reference axis of the crack angle dx,dy")
        ->delimiter(',')
        ->expected(2, 3);
    app.add_option("--crack-fit-radius", opt.crack_opt.fit_radius, "crack angle: nodes within (m)");
    app.add_option("--crack-link", opt.crack_opt.link, "crack path link distance (m; 0 = horizon)");
    app.add_option("--crack-start-radius", opt.crack_opt.start_radius,
                   "the path starts at cracked nodes within (m, at least the link) of the "
                   "origin; a notch's width when the origin is its nominal tip");
    app.add_option("--crack-threshold", opt.crack_opt.threshold, "phi of a cracked node (0.3)");
    app.add_option("--crack-band", opt.crack_opt.band, "max distance from the path (m)");
    app.add_option("--crack-window", opt.crack_opt.half_window, "speed fit half-width (frames)");
    app.add_flag("--fragments", opt.fragments, "write fragments.csv and psd.csv");
    app.add_option("--fines-nodes", opt.fragment_opt.fines_nodes,
                   "fragments of fewer nodes are fines (10)");
    app.add_option("--psd-cutoff", opt.fragment_opt.cutoff,
                   "Hardin's cut-off size (m; 0 = diameter of fines-nodes nodes)");
    app.add_option("--progress-seconds", opt.progress_seconds, "seconds between progress lines");
    pd::add_common_flags(app, opt.common);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return pd::usage_exit(app, e);
    }
    return pd::run_tool("pd-post", argc, argv, opt.common,
                        [&](pd::Context& ctx) { pd::pipeline::post(opt, ctx); });
}
