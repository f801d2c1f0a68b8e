// SPDX-License-Identifier: MIT
#include "mesh/nearest.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pd::mesh {

namespace {
/// Ranges this short are scanned point by point.
constexpr std::size_t leaf_size = 8;
/// A subtree is skipped only when q's distance to its box (the gaps to its slabs, a lower bound of
/// every point's distance in it) exceeds the best distance by this factor: each computed distance
/// (sums of squares and a square root, each rounded) is within a factor (1 +- 3 eps) of the exact
/// one, so every point of a skipped box has a computed distance > best, and skipping never
/// changes the minimum, to the last bit.
constexpr double skip_factor = 1 + 8 * std::numeric_limits<double>::epsilon();
} // namespace

double point_distance(const double* a, const double* b) {
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                     (a[2] - b[2]) * (a[2] - b[2]));
}

NearestPoints::NearestPoints(const std::vector<double>& xyz, std::vector<std::int32_t> ids,
                             int dimension)
    : xyz_(xyz)
    , ids_(std::move(ids))
    , dim_(dimension == 2 ? 2 : 3) {
    build(0, ids_.size(), 0);
}

const double* NearestPoints::at(std::size_t k) const {
    return &xyz_[3 * static_cast<std::size_t>(ids_[k])];
}

void NearestPoints::build(std::size_t lo, std::size_t hi, int depth) {
    if (hi - lo <= leaf_size)
        return;
    const std::size_t mid = lo + (hi - lo) / 2;
    const int axis = depth % dim_;
    const auto first = ids_.begin() + static_cast<std::ptrdiff_t>(lo);
    std::nth_element(first, ids_.begin() + static_cast<std::ptrdiff_t>(mid),
                     ids_.begin() + static_cast<std::ptrdiff_t>(hi),
                     [&](std::int32_t a, std::int32_t b) {
                         const double xa = xyz_[3 * static_cast<std::size_t>(a) + axis];
                         const double xb = xyz_[3 * static_cast<std::size_t>(b) + axis];
                         return xa != xb ? xa < xb : a < b;
                     });
    build(lo, mid, depth + 1);
    build(mid + 1, hi, depth + 1);
}

void NearestPoints::search(std::size_t lo, std::size_t hi, int depth, const double* q,
                           std::array<double, 3> gap, double& best) const {
    if (hi - lo <= leaf_size) {
        for (std::size_t k = lo; k < hi; ++k)
            best = std::min(best, point_distance(q, at(k)));
        return;
    }
    const std::size_t mid = lo + (hi - lo) / 2;
    const int axis = depth % dim_;
    const double* p = at(mid);
    best = std::min(best, point_distance(q, p));
    // Points before mid have coordinate <= p's on this axis, points after it >= p's.
    const double off = q[axis] - p[axis];
    const bool left_first = off < 0;
    if (left_first)
        search(lo, mid, depth + 1, q, gap, best);
    else
        search(mid + 1, hi, depth + 1, q, gap, best);
    // The far side lies beyond the plane: q's distance to its box is at least the gaps so far
    // with this axis's raised to |off| (each axis's gap only grows down the tree).
    gap[static_cast<std::size_t>(axis)] =
        std::max(gap[static_cast<std::size_t>(axis)], std::abs(off));
    const double box = std::sqrt(gap[0] * gap[0] + gap[1] * gap[1] + gap[2] * gap[2]);
    if (box <= best * skip_factor) {
        if (left_first)
            search(mid + 1, hi, depth + 1, q, gap, best);
        else
            search(lo, mid, depth + 1, q, gap, best);
    }
}

double NearestPoints::distance(const double* q) const {
    double best = std::numeric_limits<double>::infinity();
    if (!ids_.empty())
        search(0, ids_.size(), 0, q, {0.0, 0.0, 0.0}, best);
    return best;
}

} // namespace pd::mesh
