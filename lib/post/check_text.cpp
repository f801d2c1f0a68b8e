// SPDX-License-Identifier: MIT
#include "post/check_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace pd::post::detail {

std::string trim(const std::string& s) {
    auto b = s.find_first_not_of(" \t");
    auto e = s.find_last_not_of(" \t");
    return b == std::string::npos ? std::string{} : s.substr(b, e - b + 1);
}

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::size_t start = 0;
    for (;;) {
        auto p = s.find(sep, start);
        out.push_back(s.substr(start, p == std::string::npos ? std::string::npos : p - start));
        if (p == std::string::npos)
            return out;
        start = p + 1;
    }
}

/// True if `s` is one of the '|'-separated alternatives of `alts` ("m|N m-3").
bool is_one_of(const std::string& s, const std::string& alts) {
    const auto parts = split(alts, '|');
    return std::find(parts.begin(), parts.end(), s) != parts.end();
}

std::string num_text(double v) {
    if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 1e18)
        return fmt::format("{}", static_cast<long long>(v));
    return fmt::format("{:.6g}", v);
}

/// "(10,)", "(T, n, 3)" as Python prints tuples.
std::string tuple_text(const std::vector<std::string>& items) {
    std::string s = "(";
    for (std::size_t i = 0; i < items.size(); ++i)
        s += (i ? ", " : "") + items[i];
    return s + (items.size() == 1 ? ",)" : ")");
}

std::string json_item_text(const json& j) {
    return j.is_string() ? j.get<std::string>() : j.dump();
}

/// JSON text as Python's json.dumps prints it (", " between array items, integers without ".0").
std::string json_text(const json& j) {
    if (j.is_array()) {
        std::string s = "[";
        for (std::size_t i = 0; i < j.size(); ++i) {
            if (i)
                s += ", ";
            s += json_text(j[i]);
        }
        return s + "]";
    }
    if (j.is_number_float())
        return num_text(j.get<double>());
    return j.dump();
}

/// Value text as the Python checker prints it: strings quoted with '', the rest as JSON.
std::string value_text(const json& j) {
    return j.is_string() ? "'" + j.get<std::string>() + "'" : json_text(j);
}

std::string class_name(char c) {
    switch (c) {
    case 'f':
        return "float";
    case 'i':
        return "int";
    case 'u':
        return "uint";
    case 's':
        return "string";
    default:
        return "other";
    }
}

} // namespace pd::post::detail
