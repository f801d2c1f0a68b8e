// SPDX-License-Identifier: MIT
// pd-partition: METIS partition of a pd-file's grain graph. Usage: pd-partition FILE.h5 -n K
#include "core/tool.hpp"
#include "pipeline/partition.hpp"

#include <CLI/CLI.hpp>

int main(int argc, char** argv) {
    pd::pipeline::PartitionOptions opt;
    CLI::App app{"pd-partition: split the grains of a pd-file into MPI parts (METIS)",
                 "pd-partition"};
    app.add_option("file", opt.file, "pd-file, updated in place (/partition)")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("-n,--parts", opt.num_parts, "number of parts")->required();
    app.add_option("--by", opt.by, "grain (alias body: whole grains), node (bond graph) or auto");
    pd::add_common_flags(app, opt.common);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return pd::usage_exit(app, e);
    }
    return pd::run_tool("pd-partition", argc, argv, opt.common,
                        [&](pd::Context& ctx) { pd::pipeline::partition(opt, ctx); });
}
