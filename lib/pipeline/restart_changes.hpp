// SPDX-License-Identifier: MIT
// pd-solve --restart --set KEY=VALUE: a checkpointed run continued with changed walls or loading
// (a plate moved, started later or placed above the grains; gravity or damping changed). The
// changes go into the model before the solver is built, into the file's /walls and /loading
// (rank 0, before the run) and into /provenance (@overrides).
#pragma once

#include "model/model.hpp"

#include <string>
#include <vector>

namespace pd::pipeline {

/// Applies `sets` ("KEY=VALUE", VALUE as JSON; a bare word is a string) to `m` in order. KEY is
/// walls.<name or index>.<field> with field one of point, center, normal, radius, velocity,
/// angular_velocity, rotation_center, start_time, enter, gap; or loading.gravity,
/// loading.viscous_damping. A wall's rotation centre that sat on its point follows the point.
/// Then refuses (InputError naming the wall) a changed wall present at the checkpoint's time `t`
/// with a node (at X + u, `u` the checkpoint's displacements) behind it, or one that would enter
/// above the grains at or before `t` (too late to place it). Returns the changes as a JSON
/// object {"KEY": value} for /provenance. Throws ConfigError (exit 2) naming the key, with the
/// closest name for a misspelt one.
std::string apply_restart_changes(model::Model& m, const std::vector<std::string>& sets,
                                  const std::vector<double>& u, double t, const std::string& file);

} // namespace pd::pipeline
