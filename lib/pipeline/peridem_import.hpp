// SPDX-License-Identifier: MIT
// PeriDEM 0.2.x YAML deck (spec section 6; also the pre-2024 format with a `Wall:` block, spec
// 8.3) -> pdgrain scene JSON. The translation produces scene text only: the model is then built by
// the ordinary build_scene path, so there is one model builder. What the scene cannot express is a
// warning (harmless: output paths, search settings) or an InputError naming the deck key.
#pragma once

#include "core/log.hpp"

#include <string>

namespace pd::pipeline {

/// Reads the deck at `yaml_path` with its .msh and particle CSV files (paths as written in the
/// deck, relative to the deck's folder, falling back to the bare file name next to the deck) and
/// returns the equivalent scene as JSON text. Throws InputError / ConfigError naming the deck key.
/// With `parity` (pd-pack --parity peridem) the scene reproduces PeriDEM 0.2.1's numbers: the 2D
/// PDState material mapped to its 3D-formula equivalent (mu' = 15 G / 8, kappa' = 9 K / 4, Gc'
/// keeping s0); without it the deck's constants are pdgrain's consistent 2D LPS and the log says
/// how the two differ.
std::string peridem_to_scene(const std::string& yaml_path, const Log& log, bool parity = false);

} // namespace pd::pipeline
