// SPDX-License-Identifier: MIT
// Notch slots (scene key "slots"): a rectangle of the xy plane from p0 to p1 with a width,
// extruded along z in 3D. pd-pack removes the nodes inside a slot and every bond whose segment
// runs through it, so those bonds never exist (they are not broken bonds: a node beside a notch
// starts with damage 0). Width 0 is a cut: the bonds crossing the segment p0-p1.
// Used for the Kalthoff-Winkler plate (spec 8.7; PeriDEM 0.3's break_bonds_in_slots).
#pragma once

#include "model/model.hpp"

#include <array>
#include <cstddef>
#include <vector>

namespace pd::model {

struct Slot {
    std::array<double, 3> p0{0, 0, 0}; ///< m, one end of the centre line (z ignored)
    std::array<double, 3> p1{0, 0, 0}; ///< m, the other end
    double width = 0;                  ///< m, full width across the centre line; 0 = a cut
};

/// Do the segments ab and cd cross in the xy plane? Touching counts. (Pre-cracks and width-0
/// slots.)
bool segments_cross(const double* a, const double* b, const double* c, const double* d);

/// True if x lies strictly inside the slot (|across| < width/2, 0 < along < length); never
/// for width 0.
bool slot_contains(const Slot& s, const double* x);

/// Distance (m, xy plane) from x to the slot's rectangle (0 inside); to the segment for width 0.
double slot_distance(const Slot& s, const double* x);

/// True if the segment a-b runs through the slot: for width > 0 a piece of positive length lies
/// inside the closed rectangle (a bond sliding along its edge or touching a corner is kept); for
/// width 0 the segments a-b and p0-p1 cross (as pre-cracks).
bool slot_cuts(const Slot& s, const double* a, const double* b);

struct SlotCut {
    std::size_t nodes_removed = 0;
    std::size_t bonds_removed = 0;           ///< bond pairs (i-j and j-i count once)
    std::vector<std::size_t> nodes_per_slot; ///< nodes inside each slot
    std::vector<std::size_t> bonds_per_slot; ///< bond pairs each slot cut (first slot counted)
};

/// Removes the nodes inside any slot (compacting nodes, surface flags and body offsets) and the
/// bonds that run through any slot (the bond list must be complete). Throws InputError naming
/// `slots[k]` if a slot has zero length, a negative width, or leaves a body without nodes.
SlotCut apply_slots(Model& m, const std::vector<Slot>& slots);

} // namespace pd::model
