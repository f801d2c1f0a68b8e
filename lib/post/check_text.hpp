// SPDX-License-Identifier: MIT
// Text of the pd-file checker's messages, worded as data-schema/check_pd_file.py prints them
// (internal to lib/post/check*.cpp).
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pd::post::detail {

using json = nlohmann::json;

std::string trim(const std::string& s);

std::vector<std::string> split(const std::string& s, char sep);

/// True if `s` is one of the '|'-separated alternatives of `alts` ("m|N m-3").
bool is_one_of(const std::string& s, const std::string& alts);

std::string num_text(double v);

/// "(10,)", "(T, n, 3)" as Python prints tuples.
std::string tuple_text(const std::vector<std::string>& items);

std::string json_item_text(const json& j);

/// JSON text as Python's json.dumps prints it (", " between array items, integers without ".0").
std::string json_text(const json& j);

/// Value text as the Python checker prints it: strings quoted with '', the rest as JSON.
std::string value_text(const json& j);

/// The dtype class name of an HDF5 type class letter (f, i, u, s).
std::string class_name(char c);

} // namespace pd::post::detail
