// SPDX-License-Identifier: MIT
// fragments.csv and psd.csv (issue 31): the fragments of every grain at every frame, from the
// per-node fragment ids pd-solve writes (/particles/nodes/fragment: the smallest node index of
// the connected component of intact bonds, solver/damage.cpp), and per frame the size
// distribution and Hardin's relative breakage. Only moving particle bodies count (not rigid
// walls, fixed obstacles or bodies driven by displacement: the file's reaction bodies). Frames are
// streamed; cost O(nodes) per frame.
#pragma once

#include "model/model.hpp"
#include "post/progress.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

namespace pd::h5 {
class File;
}

namespace pd::post {

struct FragmentOptions {
    /// A fragment of fewer nodes is a fine: not a row of its own but summed into one row
    /// (fragment -1) per grain and frame, and counted as fines in psd.csv.
    std::int64_t fines_nodes = 10;
    /// m: Hardin's cut-off size (no breakage potential below it); 0 = the equivalent diameter of
    /// `fines_nodes` nodes of the mean node volume of the counted bodies.
    double cutoff = 0;
};

struct FragmentCounts {
    std::size_t frames = 0, rows = 0;
    double cutoff = 0; ///< m, the cut-off used
};

/// Writes fragments.csv (one row per fragment and frame: step, time, fragment = its smallest
/// node index, parent body, nodes, volume, mass, equivalent diameter d = sqrt(4A/pi) in 2D (A
/// the area: volume per unit thickness) or (6V/pi)^(1/3) in 3D, mass centre, mass-weighted
/// velocity) and psd.csv (per frame: counts, mass-weighted d10/d50/d90 over every piece fines
/// included, largest fragment / parent mass, B_t, B_p, B_r; definitions in README.md).
/// The per-grain masses of fragments.csv sum to the grain masses. Throws SchemaError if the file
/// has no fragment frame field, InputError if a CSV cannot be written.
FragmentCounts write_fragments_csv(const h5::File& f, const model::Model& m,
                                   const FragmentOptions& opt, const std::string& fragments_csv,
                                   const std::string& psd_csv, const Progress& progress = {});

} // namespace pd::post
