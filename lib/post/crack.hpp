// SPDX-License-Identifier: MIT
// crack.csv: crack tip and crack speed over time for a plate. Per frame, the damaged nodes
// (phi > threshold) within `band` of the crack path (a ray from `origin` along `direction`,
// current positions) are projected on the path; the tip is the farthest one (its arc length
// `length` and position). The speed is the slope of a least-squares line through length(t) over
// the 2w+1 frames centred on each frame (w = `half_window`, truncated at the ends; a first-order
// Savitzky-Golay derivative); the angle is that of the principal axis of the damaged nodes'
// positions (a total-least-squares line fit). Frames are streamed; the method is restated in the
// CSV.
#pragma once

#include "post/progress.hpp"

#include <array>
#include <cstddef>
#include <limits>
#include <string>

namespace pd::h5 {
class File;
}

namespace pd::post {

struct CrackOptions {
    std::array<double, 3> origin{0, 0, 0};    ///< m, a point of the crack path
    std::array<double, 3> direction{1, 0, 0}; ///< direction of growth (normalised here)
    double threshold = 0.3;                   ///< phi above which a node counts as cracked
    double band = std::numeric_limits<double>::infinity(); ///< m, max distance from the path
    int half_window = 2; ///< w: frames each side for the speed fit
    /// Reference axis of crack_summary.csv's angle_to_axis_deg (e.g. the notch axis); 0 = none.
    std::array<double, 3> axis{0, 0, 0};
    /// m: crack_summary.csv keeps the cracked nodes linked to the origin through cracked nodes
    /// at most this far apart (isolated damage, e.g. at a corner, is left out); 0 = pd-post
    /// uses the largest horizon of the model; infinity = no link test.
    double link = 0;
    /// m: the path starts at the cracked nodes within max(this, `link`) of the origin.
    /// A notch's nominal tip is a physical point, the first cracked nodes sit at its corners (a
    /// half-width away whatever the mesh): give that distance (issue 31: Kalthoff-Winkler at
    /// h = 0.25 mm, a horizon of 0.75 mm, left the path empty).
    double start_radius = 0;
    /// m: crack_summary.csv's angle_deg uses the path nodes within this distance of the origin
    /// (the initiation direction); path_angle_deg uses them all.
    double fit_radius = std::numeric_limits<double>::infinity();
};

/// Writes `csv_path` from the damage frames of `f`; returns the number of data rows (= frames).
/// Frames without a damaged node have empty tip columns (and no speed). Throws SchemaError if
/// the frames lack position or damage, ConfigError-like InputError for a zero direction or a
/// negative window, InputError if the CSV cannot be written.
std::size_t write_crack_csv(const h5::File& f, const CrackOptions& opt, const std::string& csv_path,
                            const Progress& progress = {});

} // namespace pd::post
