// SPDX-License-Identifier: MIT
// Nearest-point distances to a fixed set of points (a static k-d tree), exact: the distance it
// returns is the smallest of dist(q, p) over every point p, bit for bit what a loop over all of
// them gives, in O(log n) per query on average instead of O(n).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace pd::mesh {

class NearestPoints {
  public:
    /// The points `ids` of `xyz` (3 doubles per point, indexed by id); `dimension` 2 or 3 (the
    /// coordinates split on; a 2D point's z takes part in the distance all the same).
    NearestPoints(const std::vector<double>& xyz, std::vector<std::int32_t> ids, int dimension);

    /// The smallest Euclidean distance from q (3 doubles) to the points; +inf when there are none.
    double distance(const double* q) const;

  private:
    void build(std::size_t lo, std::size_t hi, int depth);
    void search(std::size_t lo, std::size_t hi, int depth, const double* q,
                std::array<double, 3> gap, double& best) const;
    const double* at(std::size_t k) const;

    const std::vector<double>& xyz_;
    std::vector<std::int32_t> ids_; ///< in tree order: the median of [lo, hi) at (lo + hi) / 2
    int dim_;
};

/// Euclidean distance of two points (3 doubles each), as every distance of this module.
double point_distance(const double* a, const double* b);

} // namespace pd::mesh
