// SPDX-License-Identifier: MIT
// pd-post as a library call: validate a pd-file (--check), or export its frames to VTU/PVD and an
// XDMF sidecar, and its observables, grains, wall reactions and (on request) crack to CSV. Tests
// call post() in-process; tools/pd-post/main.cpp only parses.
#pragma once

#include "core/tool.hpp"
#include "post/crack.hpp"
#include "post/fragments.hpp"

#include <string>
#include <vector>

namespace pd::pipeline {

struct PostOptions {
    std::string file;    ///< pd HDF5 file (read; /provenance is appended unless `check`)
    std::string out_dir; ///< output directory; empty = "post" beside `file`
    bool check = false;  ///< only validate against the pd-file schema, write nothing
    bool vtu = true;     ///< write <stem>_<frame>.vtu + <stem>.pvd
    bool csv = true;     ///< write observables.csv
    bool xdmf = true;    ///< write <stem>.xmf (XDMF 2 pointing into FILE) in the output directory
    bool grains = true;  ///< write grains.csv (per body and frame)
    bool walls = true;   ///< write walls.csv (when the file has rigid walls)
    double wall_length = 0; ///< m (2D) or m2 (3D): walls.csv adds stress = force / this; 0 = none
    /// crack.csv is written when either is given: a point of the crack path and the direction
    /// of growth, 2 (z = 0) or 3 values each (default origin 0, direction +x).
    std::vector<double> crack_origin, crack_direction;
    /// Reference axis of the crack angle in crack_summary.csv (e.g. the notch axis); optional.
    std::vector<double> crack_axis;
    post::CrackOptions crack_opt; ///< threshold, band, window (origin/direction set from above)
    /// fragments.csv + psd.csv (on request: one pass over the frames' fragment ids)
    bool fragments = false;
    post::FragmentOptions fragment_opt; ///< fines threshold and Hardin cut-off
    double progress_seconds = 10;       ///< wall-clock seconds between progress lines
    pd::CommonOptions common;
};

/// Runs pd-post. With `check`, lists every schema violation on stderr and throws SchemaError
/// (exit 2) if there is any. Otherwise writes the outputs, prints one summary line and records
/// the run in the file's /provenance (through ctx.on_exit, once the file has opened).
void post(const PostOptions& opt, pd::Context& ctx);

} // namespace pd::pipeline
