// SPDX-License-Identifier: MIT
// The surface law's torn facets (solver/contact.hpp): a facet with a vertex that lost half its
// bonds has no material under it any more and pushes nothing (ContactList::torn). The flags are
// counted at the contact list's rebuilds (when bonds broke since the last count). The contact
// energy a torn facet held goes with the tear, as a breaking bond's does: booked as fracture
// energy (released_), the contact energy at this step's positions with the old flags less that
// with the new (two shattering discs: 3.5 % of the energy in play lost from the balance before,
// 1.4 % after; tests/solve/test_guards.py).
// Tried and not kept: counting at every step where bonds broke, so that the skin (a cost
// device) would not decide when a facet tears: frames became independent of the skin bit for
// bit, but facets tearing sooner left the grains' last pairs 11 % of the energy deep in one
// step and the balance rose 2-3 % (SurfaceContact.ShatteringDiscsKeepTheirEnergy, the 3D
// oedometer's quick run 5 %).
#include "solver/contact.hpp"

#include <algorithm>

namespace pd::solver {

bool ContactList::count_whole(const State& s, const BondData& b, bool& cells_fell) {
    if (facet_rows_stale_) {
        // The flags of facet vertices (torn) and of interior cells' vertices (the guard's
        // material test, surface_inside.cpp); other nodes keep 1.
        facet_rows_.clear();
        for (std::size_t a = 0; a < s.rows.size(); ++a) {
            const auto i = static_cast<std::size_t>(s.rows[a]);
            if (facets_.offsets[i + 1] > facets_.offsets[i] ||
                (!icells_.empty() && icell_off_[i + 1] > icell_off_[i]))
                facet_rows_.push_back(a);
        }
        facet_rows_stale_ = false;
    }
    bool fell = false;
    cells_fell = false;
    for (const auto a : facet_rows_) {
        const auto n = b.offsets[a + 1] - b.offsets[a];
        offset_t alive = 0;
        for (auto k = b.offsets[a]; k < b.offsets[a + 1]; ++k)
            alive += b.alive[static_cast<std::size_t>(k)];
        const std::uint8_t w = 2 * alive >= n ? 1 : 0;
        const auto i = static_cast<std::size_t>(s.rows[a]);
        auto& flag = whole_[i];
        if (flag && !w) { // bonds only break: a flag only falls
            if (facets_.offsets[i + 1] > facets_.offsets[i])
                fell = true; // a facet tears: its contact energy is booked (update_surface)
            else
                cells_fell = true; // an interior node: only the guard reads it
        }
        flag = w;
    }
    return fell;
}

bool ContactList::update_surface(State& s, const Domain& dom, const BondData* b,
                                 std::int64_t broken) {
    const bool breakable = b && !b->alive.empty();
    if (!built_) {
        whole_.assign(s.n, 1);
        bool cells_fell = false;
        if (breakable)
            count_whole(s, *b, cells_fell);
        broken_seen_ = broken;
        if (dom.distributed()) {
            dom.allgather(whole_, 1);
            dom.allgather(s.x, 3);
        }
        moved_ = 0;
        rebuild(s);
        return true;
    }
    // Collective: every rank rebuilds when any rank needs it. How far the farthest node moved
    // since the rebuild is also surface_row's skip.
    moved_ = dom.max(max_moved(s, x_build_));
    if (!(moved_ > 0.5 * skin_))
        return false;
    std::vector<std::uint8_t> was; // the flags until now
    bool fell = false, cells_fell = false;
    if (breakable && broken != broken_seen_) {
        was = whole_;
        fell = count_whole(s, *b, cells_fell);
        broken_seen_ = broken;
    }
    const bool tear = dom.any(fell);
    double before = 0;
    if (tear) {
        if (was.empty())
            was = whole_; // this rank's flags did not change
        if (dom.distributed())
            dom.allgather(whole_, 1);
    } else if (dom.distributed() && dom.any(cells_fell)) {
        dom.allgather(whole_, 1); // interior flags only: every rank's guard reads them alike
    }
    if (dom.distributed())
        dom.allgather(s.x, 3); // every node where its owner has it
    if (tear) {
        was.swap(whole_);
        before = surface_energy(s);
        was.swap(whole_);
    }
    moved_ = 0;
    rebuild(s);
    if (tear)
        released_ += before - surface_energy(s);
    return true;
}

} // namespace pd::solver
