// SPDX-License-Identifier: MIT
#include "pipeline/pack.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "pipeline/scene.hpp"
#include "store/model_io.hpp"
#include "store/provenance.hpp"

#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <unistd.h>

namespace pd::pipeline {

void pack(const PackOptions& opt, Context& ctx) {
    std::ifstream in(opt.scene);
    if (!in)
        throw InputError(fmt::format("{}: cannot read the scene file", opt.scene));
    std::stringstream ss;
    ss << in.rdbuf();
    model::Model m = build_scene(ss.str(), opt.scene, ctx.log);

    const std::string tmp = fmt::format("{}.tmp.{}", opt.output, ::getpid());
    try {
        {
            h5::File f(tmp, h5::Mode::create_truncate);
            store::write_model(f, m);
            store::append_provenance(f, ctx.run, 0);
        }
        std::filesystem::rename(tmp, opt.output);
    } catch (...) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        throw;
    }
    ctx.log.info("wrote {}: {} bodies, {} walls, {} nodes, {} bonds, {} materials", opt.output,
                 m.bodies.num(), m.walls.size(), m.nodes.num(), m.bonds.num(),
                 m.materials.size());
}

} // namespace pd::pipeline
