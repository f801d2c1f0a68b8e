// SPDX-License-Identifier: MIT
// pd-pack: scene (JSON, comments allowed) -> pd-file (HDF5). Usage: pd-pack SCENE.json -o FILE.h5
#include "core/tool.hpp"
#include "pipeline/pack.hpp"

#include <CLI/CLI.hpp>

int main(int argc, char** argv) {
    pd::pipeline::PackOptions opt;
    CLI::App app{"pd-pack: build a pdgrain scene (meshes, nodes, bonds, contact) into a pd-file", "pd-pack"};
    app.add_option("scene", opt.scene, "scene file (JSON; comments allowed)")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("-o,--output", opt.output, "pd-file to write (HDF5)")->required();
    pd::add_common_flags(app, opt.common);
    CLI11_PARSE(app, argc, argv);
    return pd::run_tool("pd-pack", argc, argv, opt.common,
                        [&](pd::Context& ctx) { pd::pipeline::pack(opt, ctx); });
}
