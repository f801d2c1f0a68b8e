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

/// Bounds of a scene's JSON, enforced while it is parsed, before any traversal: the nesting
/// depth (a scene needs about 8 levels; each level adds its indentation to every line below it,
/// so a deep file dumps quadratically) and the size of the text.
constexpr int max_json_depth = 64;
constexpr std::size_t max_json_bytes = std::size_t{1} << 30;

/// Parses `text` (comments allowed) within those bounds. InputError naming `source` and the byte
/// (never the content) on invalid JSON, a number that overflows, too deep or too large a text.
json parse_json(const std::string& text, const std::string& source);

/// The same for a `--set` value: false (and `out` untouched) when `text` is not JSON (a bare
/// word); throws InputError naming `source` when it is beyond the bounds.
bool parse_json_value(const std::string& text, const std::string& source, json& out);

/// The folder a scene's relative files are read from (the scene file's, or the deck's), and
/// whether a file may lie outside it (pd-pack --allow-outside).
struct Folder {
    std::string dir;
    bool outside = false;
};

/// `file` relative to `base.dir`, unless absolute. A file that leaves the folder (by .., an
/// absolute path elsewhere, or a link pointing out) is refused (ConfigError naming `key`) unless
/// `base.outside`.
std::string resolve(const Folder& base, const std::string& file, const std::string& key);

} // namespace pd::pipeline::scene
