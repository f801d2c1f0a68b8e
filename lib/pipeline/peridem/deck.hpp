// SPDX-License-Identifier: MIT
// Reading a PeriDEM YAML deck (internal to the importer, lib/pipeline/peridem/*.cpp): typed
// values with the deck key path in every message, and the files the deck names.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>
#include <yaml-cpp/yaml.h>

namespace pd::pipeline::peridem {

using json = nlohmann::ordered_json;
namespace fs = std::filesystem;

/// `a.b`, or `b` when `a` is empty.
std::string dot(const std::string& a, const std::string& b);

/// The deck, with the key path of every value for messages.
struct Deck {
    YAML::Node root;
    std::string path;
    fs::path dir;
};

/// n[key], or an undefined node (false in a test) if n is not a map or has no such non-null key.
YAML::Node child(const YAML::Node& n, const std::string& key);

/// The number `n`; ConfigError naming `key` if it is not a finite number.
double num(const YAML::Node& n, const std::string& key);

double num_or(const YAML::Node& parent, const std::string& where, const std::string& key,
              double fallback);
/// An integer in [lo, hi] (`key` in `where`, or `fallback` if absent), checked before any cast:
/// 1e12, 2.5 or -3 where a count or an index is expected is refused naming the key.
int int_or(const YAML::Node& parent, const std::string& where, const std::string& key, int fallback,
           int lo, int hi);
/// The same for a node that is there (`key` is its full name).
int int_of(const YAML::Node& n, const std::string& key, int lo, int hi);

bool flag_or(const YAML::Node& parent, const std::string& where, const std::string& key,
             bool fallback);

std::string str_or(const YAML::Node& parent, const std::string& where, const std::string& key,
                   const std::string& fallback);

std::vector<double> nums(const YAML::Node& parent, const std::string& where,
                         const std::string& key);

std::vector<long> ints(const YAML::Node& parent, const std::string& where, const std::string& key);

/// A file named in the deck: as written (relative to the deck's folder), else the bare file name
/// next to the deck (the shipped decks name the paths of their original run scripts).
std::string deck_file(const Deck& d, const std::string& key, std::string name);

/// Zone_<i><j> (1-based, concatenated) -> (i, j) with i <= j, both in [1, n].
std::pair<int, int> zone_pair(const std::string& key, const std::string& where, int n);

} // namespace pd::pipeline::peridem
