// SPDX-License-Identifier: MIT
// pd-post: export a pd-file's frames to VTU/PVD and its observables to CSV, or --check it
// against the pd-file schema. Usage: pd-post FILE [-o DIR] [--check] [--no-vtu] [--no-csv]
// Exit codes: 0 ok, 2 bad or invalid file, 4 internal error (see README).
#include "core/tool.hpp"
#include "pipeline/post.hpp"

#include <CLI/CLI.hpp>

int main(int argc, char** argv) {
    pd::pipeline::PostOptions opt;
    CLI::App app{"pd-post: export a pd file to ParaView (.vtu/.pvd) and CSV, or check its schema",
                 "pd-post"};
    app.add_option("file", opt.file, "pd HDF5 file (its /provenance is appended)")->required();
    app.add_option("-o,--out", opt.out_dir, "output directory (default: 'post' beside FILE)");
    app.add_flag("--check", opt.check,
                 "only validate FILE against the pd-file schema; write nothing");
    app.add_flag_callback(
        "--no-vtu", [&] { opt.vtu = false; }, "do not write .vtu/.pvd");
    app.add_flag_callback(
        "--no-csv", [&] { opt.csv = false; }, "do not write observables.csv");
    pd::add_common_flags(app, opt.common);
    CLI11_PARSE(app, argc, argv);
    return pd::run_tool("pd-post", argc, argv, opt.common,
                        [&](pd::Context& ctx) { pd::pipeline::post(opt, ctx); });
}
