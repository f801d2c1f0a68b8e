// SPDX-License-Identifier: MIT
// The JSON scene (comments allowed) -> model::Model. Every key is checked: an unknown key is
// refused with the closest valid key; values are range-checked with the key path in the message.
#pragma once

#include "core/log.hpp"
#include "model/model.hpp"

#include <string>

namespace pd::pipeline {

/// Parses `text` (the content of `source`, used in messages) and builds the model: meshes each
/// reference shape once (gmsh), places instances, nodal volumes, bonds, contact table.
/// Throws ConfigError naming the key on bad input.
/// `max_nodes`: the scene is refused (ConfigError) when its node estimate, made before meshing
/// or packing, exceeds it (pd-pack --max-nodes; 0: what fits in the available memory,
/// pipeline/resources.hpp). `allow_outside`: files the scene names may lie outside its folder
/// (pd-pack --allow-outside; else refused, ConfigError naming the key).
model::Model build_scene(const std::string& text, const std::string& source, const Log& log,
                         double max_nodes = 0, bool allow_outside = false);

/// Levenshtein distance (for "did you mean" suggestions).
std::size_t edit_distance(const std::string& a, const std::string& b);

} // namespace pd::pipeline
