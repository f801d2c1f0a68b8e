// SPDX-License-Identifier: MIT
// Typed reads of scene JSON values with the key path in every message (internal to the scene
// parser, lib/pipeline/scene/*.cpp): unknown keys are refused with the closest valid key.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <string>
#include <vector>

namespace pd::pipeline::scene {

using json = nlohmann::json;

/// Checks that object `o` at `where` has only keys from `allowed`.
void check_keys(const json& o, const std::string& where, const std::vector<std::string>& allowed);

/// `where.key`, or `key` at the top level.
std::string join(const std::string& where, const std::string& key);

double number(const json& o, const std::string& where, const std::string& key, double fallback,
              bool required = false);

double positive(const json& o, const std::string& where, const std::string& key, double fallback,
                bool required = false);

std::array<double, 3> vec(const json& o, const std::string& where, const std::string& key,
                          int dimension, std::array<double, 3> fallback, bool required = false);

bool boolean(const json& o, const std::string& where, const std::string& key, bool fallback);

std::string text(const json& o, const std::string& where, const std::string& key,
                 const std::string& fallback, const std::vector<std::string>& choices = {});

/// `file` relative to the folder `base` (the scene file's), unless absolute.
std::string resolve(const std::string& base, const std::string& file);

} // namespace pd::pipeline::scene
