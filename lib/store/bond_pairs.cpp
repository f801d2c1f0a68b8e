// SPDX-License-Identifier: MIT
// The reader's check of the bond list: each bond once in each direction (model_io_detail.hpp).
#include "core/errors.hpp"
#include "model/model.hpp"
#include "store/model_io_detail.hpp"
#include "store/schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace pd::store {

namespace detail {

/// Each bond once in each direction: a row holds no node twice and not its own node, and j in
/// the row of i means i in the row of j. An asymmetric or duplicated bond breaks Newton's third
/// law (the momentum drifts) or counts one pair twice; pd-pack never writes either.
void check_bond_pairs(const h5::File& f, const std::vector<std::int64_t>& offsets,
                      const std::vector<std::int32_t>& neighbor) {
    const std::string p = std::string(path::bonds) + "/neighbor";
    const std::size_t n = offsets.size() - 1;
    // pd-pack writes every row in increasing order (no node twice): then the rows are searched
    // where they are, without a sorted copy (4 B per bond) and its sorts.
    bool increasing = true;
    for (std::size_t i = 0; i < n && increasing; ++i)
        for (auto k = offsets[i] + 1; k < offsets[i + 1]; ++k)
            if (neighbor[static_cast<std::size_t>(k - 1)] >=
                neighbor[static_cast<std::size_t>(k)]) {
                increasing = false;
                break;
            }
    std::vector<std::int32_t> copy;
    if (!increasing)
        copy.assign(neighbor.begin(), neighbor.end());
    const std::vector<std::int32_t>& sorted = increasing ? neighbor : copy;
    auto row = [&](std::size_t i) {
        return std::pair{sorted.begin() + offsets[i], sorted.begin() + offsets[i + 1]};
    };
    for (std::size_t i = 0; i < n; ++i) {
        auto [lo, hi] = row(i);
        if (!increasing)
            std::sort(copy.begin() + offsets[i], copy.begin() + offsets[i + 1]);
        if (const auto d = std::adjacent_find(lo, hi); d != hi)
            throw SchemaError(
                f.name(), p, fmt::format("node {} lists node {} twice (a duplicated bond)", i, *d));
        if (std::binary_search(lo, hi, static_cast<std::int32_t>(i)))
            throw SchemaError(f.name(), p, fmt::format("node {} is bonded to itself", i));
    }
    // Symmetric iff, visiting i in increasing order, each j listed by i finds i next in its
    // (sorted) row, and every row is used up: one cursor per row, no search. Only a failure
    // searches, to name the first pair in row order.
    std::vector<std::int64_t> next(offsets.begin(), offsets.end() - 1);
    bool symmetric = true;
    for (std::size_t i = 0; i < n && symmetric; ++i)
        for (auto k = offsets[i]; k < offsets[i + 1]; ++k) {
            const auto j = static_cast<std::size_t>(sorted[static_cast<std::size_t>(k)]);
            auto& c = next[j];
            if (c == offsets[j + 1] ||
                sorted[static_cast<std::size_t>(c)] != static_cast<std::int32_t>(i)) {
                symmetric = false;
                break;
            }
            ++c;
        }
    for (std::size_t i = 0; i < n && symmetric; ++i)
        symmetric = next[i] == offsets[i + 1];
    for (std::size_t i = 0; i < n && !symmetric; ++i) {
        const auto [lo, hi] = row(i);
        for (auto it = lo; it != hi; ++it) {
            const auto [jl, jh] = row(static_cast<std::size_t>(*it));
            if (!std::binary_search(jl, jh, static_cast<std::int32_t>(i)))
                throw SchemaError(f.name(), p,
                                  fmt::format("node {} is bonded to node {}, but node {} not to "
                                              "node {} (an asymmetric bond)",
                                              i, *it, *it, i));
        }
    }
}

} // namespace detail

} // namespace pd::store
