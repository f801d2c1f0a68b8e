// SPDX-License-Identifier: MIT
// pd-post as a library call: validate a pd-file (--check), or export its frames to VTU/PVD and
// its observables to CSV. Tests call post() in-process; tools/pd-post/main.cpp only parses.
#pragma once

#include "core/tool.hpp"

#include <string>

namespace pd::pipeline {

struct PostOptions {
    std::string file;    ///< pd HDF5 file (read; /provenance is appended unless `check`)
    std::string out_dir; ///< output directory; empty = "post" beside `file`
    bool check = false;  ///< only validate against the pd-file schema, write nothing
    bool vtu = true;     ///< write <stem>_<frame>.vtu + <stem>.pvd
    bool csv = true;     ///< write observables.csv
    pd::CommonOptions common;
};

/// Runs pd-post. With `check`, lists every schema violation on stderr and throws SchemaError
/// (exit 2) if there is any. Otherwise writes the outputs, prints one summary line and records
/// the run in the file's /provenance (through ctx.on_exit, once the file has opened).
void post(const PostOptions& opt, pd::Context& ctx);

} // namespace pd::pipeline
