// SPDX-License-Identifier: MIT
// The surface law's depth history (surface_contact.cpp): a node's depth behind a boundary grows
// only with the motion of the node and the facet, and a node enters a body from its boundary.
// Checkpointed (/checkpoints/*/surface_depths), so a restart decides as the run would have.
#include "core/errors.hpp"
#include "solver/contact.hpp"

#include <algorithm>
#include <cmath>

namespace pd::solver {

// Between two evaluations a node's depth grows by at most its motion relative to the facet,
// and it comes into contact by crossing the boundary. A depth that grew by more than that (plus
// the onset) is not a node that came through this boundary: the closest facet changed under it
// (a facet torn, a corner of a breaking grain rearranged) or the inside test flipped. A force
// from that depth would create its energy at once (a 3D cuboid's corner: the contact energy x10
// in one step, nodes flung at 35 m/s). Such a pair is held until its node is found outside:
// let back in where the jump allowance (which grows with the speeds) next admitted it, it got
// U(d) V there from nothing (examples/oedometer_3d: re-entries at 7-11 um, 1e-7 J each, were
// the balance's drift once grains chipped, +3.2e-6 J of 3.8e-6 J at 13.3 ms).
bool ContactList::depth_continuous(std::size_t i, std::int32_t body, std::int32_t facet,
                                   const double* w, double onset, double d, const State& s) const {
    const Touched key{static_cast<index_t>(i), body, 0.0};
    const auto it = std::lower_bound(touched_.begin(), touched_.end(), key);
    const bool known = it != touched_.end() && it->i == key.i && it->body == body;
    if (known && it->depth < 0)
        return false; // held: no force until found outside
    const double since = std::max(s.time - touched_time_, 0.0);
    const auto nv = static_cast<std::size_t>(facets_.nv);
    const index_t* fv = &facets_.v[nv * static_cast<std::size_t>(facet)];
    const double* vi = &s.v[3 * i];
    if (!known) {
        // Entering: the node came through the boundary since the last evaluation, so its depth
        // is at most its motion relative to its foot point p (velocity sum w_a v_a) over that
        // time, twice that for the facet's turning and the step's change of velocity. Not the
        // fastest vertex: a chip flying off a facet's far corner swept nodes in at up to
        // 0.2 mm in the oedometer (4 v_max dt, 43 m/s), each with its U(d) V from nothing.
        double rel[3] = {vi[0], vi[1], vi[2]};
        for (std::size_t a = 0; a < nv; ++a)
            for (std::size_t c = 0; c < 3; ++c)
                rel[c] -= w[a] * s.v[3 * static_cast<std::size_t>(fv[a]) + c];
        const double vr = std::sqrt(rel[0] * rel[0] + rel[1] * rel[1] + rel[2] * rel[2]);
        return d <= 2 * vr * since + 2 * onset;
    }
    // Inside before: the fastest of the node and the facet's vertices, relative motion at most
    // twice that.
    auto speed = [&](std::size_t k) {
        const double* v = &s.v[3 * k];
        return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    };
    double vmax = speed(i);
    for (std::size_t a = 0; a < nv; ++a)
        vmax = std::max(vmax, speed(static_cast<std::size_t>(fv[a])));
    return d <= it->depth + 4 * vmax * since + 2 * onset;
}

void ContactList::count_held() const {
    held_count_ = static_cast<std::size_t>(std::count_if(
        touched_.begin(), touched_.end(), [](const Touched& t) { return t.depth < 0; }));
}

bool ContactList::held(std::size_t i, std::int32_t body) const {
    const Touched key{static_cast<index_t>(i), body, 0.0};
    const auto it = std::lower_bound(touched_.begin(), touched_.end(), key);
    return it != touched_.end() && it->i == key.i && it->body == body && it->depth < 0;
}

bool ContactList::in_contact(std::size_t i, std::int32_t body) const {
    const Touched key{static_cast<index_t>(i), body, 0.0};
    const auto it = std::lower_bound(touched_.begin(), touched_.end(), key);
    return it != touched_.end() && it->i == key.i && it->body == body && it->depth >= 0;
}

void ContactList::remember_depths(double time, std::vector<Touched>& marks) const {
    // The held pairs carry over unless this evaluation marked them (held again, or free): a
    // row not evaluated (its slack) or a body out of reach says nothing about inside.
    std::sort(marks.begin(), marks.end());
    std::vector<Touched> next;
    next.reserve(events_.size() + marks.size() + held_count_);
    for (const auto& t : touched_)
        if (t.depth < 0 && !std::binary_search(marks.begin(), marks.end(), t))
            next.push_back(t);
    for (const auto& ev : events_)
        next.push_back({ev.i, facets_.body[static_cast<std::size_t>(ev.facet)], ev.depth});
    for (const auto& m : marks)
        if (m.depth == held_mark)
            next.push_back(m);
    std::sort(next.begin(), next.end()); // one entry per (node, body): surface_row
    touched_.swap(next);
    count_held();
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
    count_held();
    touched_known_ = time >= 0;
    touched_time_ = time;
}

} // namespace pd::solver
