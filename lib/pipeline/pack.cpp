// SPDX-License-Identifier: MIT
#include "pipeline/pack.hpp"

#include "core/errors.hpp"
#include "core/file_lock.hpp"
#include "core/files.hpp"
#include "h5/file.hpp"
#include "pipeline/overrides.hpp"
#include "pipeline/peridem_import.hpp"
#include "pipeline/scene.hpp"
#include "store/model_io.hpp"
#include "store/provenance.hpp"
#include "store/schema.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace pd::pipeline {

namespace {

/// workflows/preview/preview.py: PD_SOURCE_DIR, else up from the executable (build*/bin/pd-pack).
/// A file of the source tree: under PD_SOURCE_DIR, else above this executable.
std::string source_file(const std::string& option, const std::string& rel) {
    namespace fs = std::filesystem;
    if (const char* s = std::getenv("PD_SOURCE_DIR"); s && fs::is_regular_file(fs::path(s) / rel))
        return (fs::path(s) / rel).string();
    std::error_code ec;
    auto exe = fs::read_symlink("/proc/self/exe", ec);
    for (auto p = exe.parent_path(); !ec && !p.empty() && p != p.root_path(); p = p.parent_path())
        if (fs::is_regular_file(p / rel))
            return (p / rel).string();
    throw InputError(option + ": cannot find " + rel + " (set PD_SOURCE_DIR to the source tree)");
}

std::string preview_script() {
    return source_file("--preview", "workflows/preview/preview.py");
}

std::string quote(const std::string& s) {
    std::string q = "'";
    for (char c : s)
        q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

/// Warns about bodies whose median bond family is too small for a peridynamic solid: h is the
/// smallest node spacing (spec 2.2), so a mesh with a few very close nodes (sharp corners of a
/// remeshed STL) gets a horizon far below its typical spacing, and state-based laws go unstable
/// (measured: an LPS STL grain with a median of 8 bonds per node blew up at any dt). The PeriDEM
/// example decks have medians of 6 (2D, delta = 2h) and 11 (3D spheres), and run.
void warn_sparse_families(const model::Model& m, const Log& log) {
    const double least = m.dimension == 3 ? 10 : 5;
    std::vector<std::size_t> sparse;
    double worst = 1e300;
    for (std::size_t b = 0; b < m.bodies.num(); ++b) {
        if (m.bodies.fixed[b])
            continue;
        std::vector<std::int64_t> count;
        for (auto i = m.bodies.begin(b); i < m.bodies.end(b); ++i)
            count.push_back(m.bonds.offsets[static_cast<std::size_t>(i) + 1] -
                            m.bonds.offsets[static_cast<std::size_t>(i)]);
        if (count.empty())
            continue;
        std::nth_element(count.begin(),
                         count.begin() + static_cast<std::ptrdiff_t>(count.size() / 2),
                         count.end());
        const double median = static_cast<double>(count[count.size() / 2]);
        if (median < least) {
            sparse.push_back(b);
            worst = std::min(worst, median);
        }
    }
    if (sparse.empty())
        return;
    std::string ids;
    for (std::size_t k = 0; k < std::min<std::size_t>(sparse.size(), 5); ++k)
        ids += (k ? ", " : "") + std::to_string(sparse[k]);
    log.warn("{} bodies (ids {}{}) have a median of {} bonds per node or fewer (a regular mesh has "
             "about {} at horizon = 3 h): their smallest node spacing h is far below the typical "
             "one, and the solid may go unstable. Give /discretization/horizon as a length "
             "(PeriDEM decks use 3 x the nominal mesh size) or mesh them more evenly",
             sparse.size(), ids, sparse.size() > 5 ? ", ..." : "", worst,
             m.dimension == 3 ? 113 : 28);
}

/// The file written, read back as pd-solve reads it (store::read_model: every range and
/// cross-reference of data-schema/pd-file.md section 7): pd-pack refuses what pd-solve would.
void verify_packed(const std::string& tmp, const std::string& output) {
    try {
        const h5::File f(tmp, h5::Mode::read);
        (void)store::read_model(f, true);
    } catch (const InputError& e) {
        std::string why = e.what();
        if (why.rfind(tmp, 0) == 0)
            why = output + why.substr(tmp.size());
        throw InputError(fmt::format("{} (the model built is one pd-solve would refuse: "
                                     "nothing written)",
                                     why));
    }
}

/// Writes the packed model under a temporary name and renames it into place: a failed write
/// (full disk) leaves any previous output as it was. The temporary file is created exclusively
/// (never through a link planted under its name).
/// Writes `m` (taken, and freed once written: the check reads the file back into a model of the
/// same size, so holding both would double pd-pack's peak) to a temporary file, checks it as
/// pd-solve will read it, and renames it to `output`.
void write_packed(model::Model m, const std::string& output, Context& ctx) {
    const std::string tmp = fmt::format("{}.tmp.{}", output, ::getpid());
    const int fd = create_side_file(tmp);
    if (fd < 0)
        throw InputError(fmt::format("-o {}: cannot create the temporary file {}: {}", output, tmp,
                                     std::strerror(errno)));
    ::close(fd);
    try {
        // 1 MB set aside, freed when a write fails (full disk) so that HDF5 can close the
        // temporary file instead of crashing (SIGSEGV at close before).
        SpaceReserve reserve = SpaceReserve::create(tmp, std::uint64_t{1} << 20);
        {
            h5::File f(tmp, h5::Mode::create_truncate);
            try {
                store::write_model(f, m);
                if (!ctx.run.overrides.empty())
                    f.write_string(store::path::parameters_overrides, ctx.run.overrides);
                store::append_provenance(f, ctx.run, 0);
            } catch (...) {
                reserve.release();
                throw;
            }
            reserve.release();
        }
        m = model::Model{};
        verify_packed(tmp, output);
        std::filesystem::rename(tmp, output);
    } catch (...) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        throw;
    }
}

/// -o onto a pd-file holding the results of a run (frames, observables, checkpoints) would
/// destroy them: only with --overwrite.
void refuse_results(const PackOptions& opt) {
    if (opt.overwrite || !h5::is_hdf5(opt.output))
        return;
    const h5::File f(opt.output, h5::Mode::read);
    std::string what;
    for (const char* p :
         {store::path::particles, store::path::observables, store::path::checkpoints})
        if (f.exists(p))
            what += (what.empty() ? "" : ", ") + std::string(p);
    if (!what.empty())
        throw InputError(fmt::format("-o {}: holds the results of a run ({}); pd-pack would "
                                     "replace them: give another name, or --overwrite",
                                     opt.output, what));
}

/// Every output against everything the run has read (scene, deck, its meshes, CSV and STL
/// files, by device + inode): checked after the build has read them, before any output is
/// written.
void check_outputs_against_inputs(const PackOptions& opt) {
    for (const auto& [option, path] : {std::pair<const char*, const std::string&>{"-o", opt.output},
                                       {"--write-scene", opt.write_scene},
                                       {"--preview", opt.preview}})
        if (!path.empty())
            check_output_target(option, path);
}

} // namespace

void pack(const PackOptions& opt, Context& ctx) {
    // Outputs never replace an input or each other, and are files, not directories.
    check_output_file("-o", opt.output,
                      {{"scene", opt.scene}, {"--from-peridem deck", opt.from_peridem}});
    if (!opt.write_scene.empty())
        check_output_file("--write-scene", opt.write_scene,
                          {{"scene", opt.scene},
                           {"--from-peridem deck", opt.from_peridem},
                           {"-o file", opt.output}});
    if (!opt.preview.empty())
        check_output_file("--preview", opt.preview,
                          {{"scene", opt.scene},
                           {"--from-peridem deck", opt.from_peridem},
                           {"-o file", opt.output},
                           {"--write-scene file", opt.write_scene}});
    if (opt.max_nodes_given && !(opt.max_nodes >= 1))
        throw InputError(fmt::format("--max-nodes {}: must be at least 1", opt.max_nodes));
    if (!opt.output.empty())
        refuse_results(opt);
    std::string text, source;
    if (!opt.from_peridem.empty()) {
        text = peridem_to_scene(opt.from_peridem, ctx.log, opt.parity == "peridem");
        source = opt.from_peridem;
    } else {
        note_input("scene", opt.scene);
        std::ifstream in(opt.scene);
        if (!in)
            throw InputError(fmt::format("{}: cannot read the scene file", opt.scene));
        std::stringstream ss;
        ss << in.rdbuf();
        text = ss.str();
        source = opt.scene;
    }
    if (!opt.sets.empty() || opt.print_scene) { // --set, --print-scene: plain resolved JSON
        auto r = apply_overrides(text, source, opt.sets);
        text = std::move(r.scene);
        ctx.run.overrides = std::move(r.overrides);
        if (opt.print_scene) {
            if (opt.defaults) {
                const auto path = source_file("--defaults", "data-schema/scene.schema.json");
                std::ifstream in(path);
                std::stringstream schema;
                schema << in.rdbuf();
                text = fill_defaults(text, schema.str());
            }
            std::fputs((text + "\n").c_str(), stdout);
            return;
        }
    }
    // The output may be a file another tool is running on (an MPI pd-solve): refused before the
    // work, and held until the new file is renamed into place (issue 13).
    const FileLock output_lock = FileLock::acquire(opt.output);
    model::Model m = build_scene(text, source, ctx.log, opt.max_nodes_given ? opt.max_nodes : 0,
                                 opt.allow_outside);
    warn_sparse_families(m, ctx.log);
    // The build has read every file the scene names: no output may be one of them (a deck's
    // .msh, a particle CSV, an STL), and none is written before this check.
    check_outputs_against_inputs(opt);
    if (!opt.write_scene.empty()) {
        std::ofstream out(opt.write_scene);
        if (!(out << text))
            throw InputError(fmt::format("{}: cannot write the scene", opt.write_scene));
        ctx.log.info("wrote the scene {}", opt.write_scene);
    }

    const auto summary =
        fmt::format("{} bodies, {} walls, {} nodes, {} bonds, {} materials", m.bodies.num(),
                    m.walls.size(), m.nodes.num(), m.bonds.num(), m.materials.size());
    write_packed(std::move(m), opt.output, ctx);
    ctx.log.info("wrote {}: {}", opt.output, summary);
    if (!opt.preview.empty()) {
        const auto cmd = fmt::format("/usr/bin/python3 {} {} -o {}", quote(preview_script()),
                                     quote(opt.output), quote(opt.preview));
        const int rc = std::system(cmd.c_str());
        if (rc != 0)
            throw InputError(fmt::format("--preview: '{}' failed (status {})", cmd,
                                         WIFEXITED(rc) ? WEXITSTATUS(rc) : rc));
        ctx.log.info("wrote the preview {}", opt.preview);
    }
}

} // namespace pd::pipeline
