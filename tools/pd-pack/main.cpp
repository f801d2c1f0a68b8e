// SPDX-License-Identifier: MIT
// pd-pack: scene (JSON, comments allowed) or PeriDEM deck -> pd-file (HDF5).
// Usage: pd-pack SCENE.json -o FILE.h5 | pd-pack --from-peridem input.yaml -o FILE.h5
#include "core/tool.hpp"
#include "pipeline/pack.hpp"

#include <CLI/CLI.hpp>

int main(int argc, char** argv) {
    pd::pipeline::PackOptions opt;
    CLI::App app{"pd-pack: build a pdgrain scene (meshes, nodes, bonds, contact) into a pd-file",
                 "pd-pack"};
    auto* scene = app.add_option("scene", opt.scene, "scene file (JSON; comments allowed)")
                      ->check(CLI::ExistingFile);
    auto* deck = app.add_option("--from-peridem", opt.from_peridem,
                                "import a PeriDEM 0.2.x YAML deck (with its .msh and CSV files)")
                     ->check(CLI::ExistingFile);
    scene->excludes(deck);
    app.add_option("--parity", opt.parity,
                   "with --from-peridem: 'peridem' maps the deck so that it matches PeriDEM "
                   "0.2.1's numbers (2D PDState material as its 3D formulas make it)")
        ->check(CLI::IsMember({"peridem"}))
        ->needs(deck);
    app.add_option("--write-scene", opt.write_scene, "also write the scene JSON that is built");
    auto* out = app.add_option("-o,--output", opt.output, "pd-file to write (HDF5)");
    app.add_option("--set", opt.sets,
                   "override a scene value: PATH=VALUE, PATH dotted (contact.restitution, "
                   "particles.0.velocity) or a JSON pointer (/contact/restitution), VALUE JSON "
                   "(0.5, [0,-1], \"pmb\"); repeatable; recorded in /parameters and /provenance")
        ->allow_extra_args(false);
    auto* print = app.add_flag("--print-scene", opt.print_scene,
                               "print the resolved scene (overrides applied, comments removed) "
                               "as plain JSON to stdout and exit");
    out->excludes(print);
    app.add_flag("--overwrite", opt.overwrite,
                 "let -o replace a pd-file that holds the results of a run (frames, "
                 "observables, checkpoints)");
    app.add_flag("--defaults", opt.defaults,
                 "with --print-scene: fill in every default the scene leaves out "
                 "(data-schema/scene.schema.json)")
        ->needs(print);
    app.add_flag("--allow-outside", opt.allow_outside,
                 "let the scene (or deck) name files outside its folder (.., absolute paths, "
                 "links pointing out); without it they are refused");
    app.add_option("--preview", opt.preview, "draw the packed scene to this PNG (matplotlib)");
    auto* max_nodes = app.add_option("--max-nodes", opt.max_nodes,
                                     "refuse a scene estimated (before meshing or packing) above "
                                     "this many nodes (default: what fits in the memory "
                                     "available, about 1.5 kB a node in 2D, 5 kB in 3D)");
    pd::add_common_flags(app, opt.common);
    try {
        app.parse(argc, argv);
        if (opt.scene.empty() && opt.from_peridem.empty())
            throw CLI::RequiredError("give a SCENE file or --from-peridem DECK");
        if (opt.output.empty() && !opt.print_scene)
            throw CLI::RequiredError("--output");
        opt.max_nodes_given = max_nodes->count() > 0;
        if (opt.print_scene)
            opt.common.quiet = true; // stdout carries the JSON alone
    } catch (const CLI::ParseError& e) {
        return pd::usage_exit(app, e);
    }
    return pd::run_tool("pd-pack", argc, argv, opt.common,
                        [&](pd::Context& ctx) { pd::pipeline::pack(opt, ctx); });
}
