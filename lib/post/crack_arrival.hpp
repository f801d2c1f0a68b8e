// SPDX-License-Identifier: MIT
// Crack arrival times and the crack path fit behind crack_nodes.csv and crack_summary.csv
// (Kalthoff-Winkler, spec 8.7). Arrival: per node, the first time its damage exceeds the
// threshold, interpolated linearly between the two frames that bracket the crossing. Path: the
// cracked nodes ahead of the origin (notch tip) along the growth direction and within the band,
// in the xy plane of the reference configuration; the angle is that of a total-least-squares
// line through the origin; the tip L(t) is the farthest projection on that line among nodes
// arrived by t; the mean speed is the path length over the time it took, the peak speed the
// largest least-squares slope of L over 2w+1 frames.
#pragma once

#include "post/crack.hpp"
#include "post/progress.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace pd::model {
struct Model;
}

namespace pd::post {

/// Per-node arrival times from a damage history fed frame by frame (times increasing).
class ArrivalTracker {
  public:
    ArrivalTracker(std::size_t num_nodes, double threshold);
    /// Feeds the damage of every node at time t.
    void add(double t, std::span<const double> damage);
    /// s per node; NaN = never above the threshold.
    const std::vector<double>& times() const { return arrival_; }

  private:
    double threshold_;
    bool first_ = true;
    double t_prev_ = 0;
    std::vector<double> prev_, arrival_;
};

struct CrackFit {
    static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    std::size_t nodes = 0;          ///< cracked nodes on the path (ahead of origin, in the band)
    double angle_deg = nan;         ///< from +x, in (-180, 180]: path nodes within fit_radius
    double angle_to_axis_deg = nan; ///< between that line and `axis`, [0, 180]; NaN if no axis
    double path_angle_deg = nan;    ///< the same over the whole path
    double path_angle_to_axis_deg = nan;
    double length = nan;              ///< m, farthest projection on the path (from the origin)
    double start_length = nan;        ///< m, projection of the first node to crack
    double t_start = nan;             ///< s, first arrival on the path
    double t_end = nan;               ///< s, arrival at the farthest node
    double mean_speed = nan;          ///< m/s, (length - start_length) / (t_end - t_start)
    double peak_speed = nan;          ///< m/s, max windowed slope of the tip L(t)
    double direction[2] = {nan, nan}; ///< unit path direction (x, y)
    double nearest = nan;      ///< m, from the origin to the nearest cracked node ahead of it
    double start_radius = nan; ///< m, the start radius used: max(CrackOptions start_radius, link)
    std::vector<std::uint8_t> on_path; ///< per node: 1 = used in the fit
    std::vector<double> along;         ///< per node: projection on the path (m), NaN off path
};

/// Fits the path from reference positions x0 (3 per node), arrival times (NaN = never) and the
/// frame times (for the tip history). `axis` (3 values, may be zero) is the reference direction
/// of angle_to_axis_deg, e.g. the notch axis. Throws InputError for a zero direction.
CrackFit fit_crack(std::span<const double> x0, std::span<const double> arrival,
                   const CrackOptions& opt, std::span<const double> frame_times);

/// Reads the damage frames of `f` and writes `nodes_csv` (every node that cracked: reference
/// position, arrival time, on-path flag, projection) and `summary_csv` (one row: CrackFit).
/// Returns the fit.
CrackFit write_crack_arrivals(const h5::File& f, const model::Model& m, const CrackOptions& opt,
                              const std::string& nodes_csv, const std::string& summary_csv,
                              const Progress& progress = {});

} // namespace pd::post
