// SPDX-License-Identifier: MIT
// The surface law's depth history (surface_contact.cpp): a node's depth behind a boundary grows
// only with the motion of the node and the facet, and a node enters a body from its boundary.
#include "solver/contact.hpp"

#include <algorithm>
#include <cmath>

namespace pd::solver {

bool ContactList::depth_continuous(std::size_t i, std::int32_t body, std::int32_t facet,
                                   double onset, double d, const State& s) const {
    const Touched key{static_cast<index_t>(i), body, 0.0};
    const auto it = std::lower_bound(touched_.begin(), touched_.end(), key);
    const bool known = it != touched_.end() && it->i == key.i && it->body == body;
    // The fastest of the node and the facet's vertices, relative motion at most twice that.
    auto speed = [&](std::size_t k) {
        const double* v = &s.v[3 * k];
        return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    };
    double vmax = speed(i);
    const auto nv = static_cast<std::size_t>(facets_.nv);
    const index_t* fv = &facets_.v[nv * static_cast<std::size_t>(facet)];
    for (std::size_t a = 0; a < nv; ++a)
        vmax = std::max(vmax, speed(static_cast<std::size_t>(fv[a])));
    const double jump = 4 * vmax * std::max(s.time - touched_time_, 0.0) + 2 * onset;
    return d <= (known ? it->depth : 0.0) + jump;
}

void ContactList::remember_depths(double time) const {
    touched_.clear();
    for (const auto& ev : events_)
        touched_.push_back({ev.i, facets_.body[static_cast<std::size_t>(ev.facet)], ev.depth});
    std::sort(touched_.begin(), touched_.end()); // one event per (node, body): surface_row
    touched_known_ = true;
    touched_time_ = time;
}

} // namespace pd::solver
