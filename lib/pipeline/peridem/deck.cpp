// SPDX-License-Identifier: MIT
#include "pipeline/peridem/deck.hpp"

#include "core/errors.hpp"

#include <cctype>
#include <cmath>

namespace pd::pipeline::peridem {

std::string dot(const std::string& a, const std::string& b) {
    return a.empty() ? b : a + "." + b;
}

YAML::Node child(const YAML::Node& n, const std::string& key) {
    if (!n || !n.IsMap())
        return YAML::Node(YAML::NodeType::Undefined);
    YAML::Node c = n[key];
    if (!c || c.IsNull())
        return YAML::Node(YAML::NodeType::Undefined);
    return c;
}

double num(const YAML::Node& n, const std::string& key) {
    try {
        const double d = n.as<double>();
        if (!std::isfinite(d))
            throw ConfigError(key, "must be finite");
        return d;
    } catch (const YAML::Exception&) {
        throw ConfigError(key, "expected a number, found '" + YAML::Dump(n) + "'");
    }
}

double num_or(const YAML::Node& parent, const std::string& where, const std::string& key,
              double fallback) {
    auto n = child(parent, key);
    return n ? num(n, dot(where, key)) : fallback;
}

int int_of(const YAML::Node& n, const std::string& key, int lo, int hi) {
    const double d = num(n, key);
    if (d != std::floor(d) || d < lo || d > hi)
        throw ConfigError(key, fmt::format("{}: expected an integer from {} to {}", d, lo, hi));
    return static_cast<int>(d);
}

int int_or(const YAML::Node& parent, const std::string& where, const std::string& key, int fallback,
           int lo, int hi) {
    auto n = child(parent, key);
    return n ? int_of(n, dot(where, key), lo, hi) : fallback;
}

bool flag_or(const YAML::Node& parent, const std::string& where, const std::string& key,
             bool fallback) {
    auto n = child(parent, key);
    if (!n)
        return fallback;
    try {
        return n.as<bool>();
    } catch (const YAML::Exception&) {
        throw ConfigError(dot(where, key), "expected true or false");
    }
}

std::string str_or(const YAML::Node& parent, const std::string& where, const std::string& key,
                   const std::string& fallback) {
    auto n = child(parent, key);
    if (!n)
        return fallback;
    if (!n.IsScalar())
        throw ConfigError(dot(where, key), "expected a name");
    auto s = n.as<std::string>();
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())))
        s.pop_back();
    return s;
}

std::vector<double> nums(const YAML::Node& parent, const std::string& where,
                         const std::string& key) {
    auto n = child(parent, key);
    std::vector<double> v;
    if (!n)
        return v;
    if (n.IsScalar())
        return {num(n, dot(where, key))};
    if (!n.IsSequence())
        throw ConfigError(dot(where, key), "expected a list of numbers");
    for (std::size_t k = 0; k < n.size(); ++k)
        v.push_back(num(n[k], fmt::format("{}[{}]", dot(where, key), k)));
    return v;
}

std::vector<long> ints(const YAML::Node& parent, const std::string& where, const std::string& key) {
    std::vector<long> v;
    for (double d : nums(parent, where, key)) {
        if (d != std::floor(d))
            throw ConfigError(dot(where, key), fmt::format("{} is not an integer", d));
        v.push_back(static_cast<long>(d));
    }
    return v;
}

std::string deck_file(const Deck& d, const std::string& key, std::string name) {
    while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back())))
        name.pop_back();
    fs::path p(name);
    std::vector<fs::path> tries = {p.is_absolute() ? p : d.dir / p, d.dir / p.filename()};
    for (const auto& t : tries)
        if (fs::is_regular_file(t))
            return fs::absolute(t).lexically_normal().string();
    throw ConfigError(key, fmt::format("cannot find the file '{}' (looked for {} and {})", name,
                                       tries[0].string(), tries[1].string()));
}

std::pair<int, int> zone_pair(const std::string& key, const std::string& where, int n) {
    const std::string d = key.substr(5);
    std::vector<std::pair<int, int>> found;
    for (std::size_t p = 1; p < d.size(); ++p) {
        const auto a = d.substr(0, p), b = d.substr(p);
        if (a[0] == '0' || b[0] == '0' || a.size() > 4 || b.size() > 4 ||
            !std::all_of(d.begin(), d.end(), [](char c) { return std::isdigit(c); }))
            continue;
        const int i = std::stoi(a), j = std::stoi(b);
        if (i >= 1 && j >= i && j <= n)
            found.emplace_back(i, j);
    }
    if (found.size() != 1)
        throw ConfigError(dot(where, key), found.empty()
                                               ? fmt::format("not a pair of zones in [1, {}]", n)
                                               : "ambiguous pair of zones");
    return found[0];
}

} // namespace pd::pipeline::peridem
