// SPDX-License-Identifier: MIT
// The surface law's depth history (surface_contact.cpp): a node's depth behind a boundary grows
// only with the motion of the node and the facet, and a node enters a body from its boundary.
// Checkpointed (/checkpoints/*/surface_depths), so a restart decides as the run would have.
#include "core/errors.hpp"
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

void ContactList::depth_history(std::vector<std::int64_t>& pairs, std::vector<double>& depths,
                                double& time) const {
    pairs.clear();
    depths.clear();
    time = touched_known_ ? touched_time_ : -1.0;
    if (!touched_known_)
        return;
    for (const auto& t : touched_)
        if (owned_.empty() || owned_[static_cast<std::size_t>(t.i)]) {
            pairs.push_back(t.i);
            pairs.push_back(t.body);
            depths.push_back(t.depth);
        }
}

void ContactList::set_depth_history(const std::vector<std::int64_t>& pairs,
                                    const std::vector<double>& depths, double time) {
    PD_CHECK(pairs.size() == 2 * depths.size(), "depth history sizes");
    touched_.clear();
    for (std::size_t k = 0; k < depths.size(); ++k)
        touched_.push_back({static_cast<index_t>(pairs[2 * k]),
                            static_cast<std::int32_t>(pairs[2 * k + 1]), depths[k]});
    std::sort(touched_.begin(), touched_.end());
    touched_known_ = time >= 0;
    touched_time_ = time;
}

} // namespace pd::solver
