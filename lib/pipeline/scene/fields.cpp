// SPDX-License-Identifier: MIT
#include "pipeline/scene/fields.hpp"

#include "core/errors.hpp"
#include "pipeline/scene.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace pd::pipeline::scene {

void check_keys(const json& o, const std::string& where, const std::vector<std::string>& allowed) {
    if (!o.is_object())
        throw ConfigError(where.empty() ? "(top level)" : where, "expected an object");
    for (auto it = o.begin(); it != o.end(); ++it) {
        if (std::find(allowed.begin(), allowed.end(), it.key()) != allowed.end())
            continue;
        std::string best;
        std::size_t bd = 1000;
        for (const auto& k : allowed) {
            auto d = edit_distance(it.key(), k);
            if (d < bd) {
                bd = d;
                best = k;
            }
        }
        const std::string key = where.empty() ? it.key() : where + "." + it.key();
        throw ConfigError(
            key, bd <= std::max<std::size_t>(2, best.size() / 3)
                     ? "unknown key; did you mean '" + best + "'?"
                     : "unknown key; valid keys here: " + [&] {
                           std::string s;
                           for (const auto& k : allowed)
                               s += (s.empty() ? "" : ", ") + k;
                           return s;
                       }());
    }
}

std::string join(const std::string& where, const std::string& key) {
    return where.empty() ? key : where + "." + key;
}

double number(const json& o, const std::string& where, const std::string& key, double fallback,
              bool required) {
    if (!o.contains(key)) {
        if (required)
            throw ConfigError(join(where, key), "missing (required)");
        return fallback;
    }
    const auto& v = o.at(key);
    if (!v.is_number())
        throw ConfigError(join(where, key), "expected a number, found " + v.dump());
    const double d = v.get<double>();
    if (!std::isfinite(d))
        throw ConfigError(join(where, key), "must be finite");
    return d;
}

double positive(const json& o, const std::string& where, const std::string& key, double fallback,
                bool required) {
    double d = number(o, where, key, fallback, required);
    if (!(d > 0))
        throw ConfigError(join(where, key), fmt::format("must be positive, found {}", d));
    return d;
}

std::array<double, 3> vec(const json& o, const std::string& where, const std::string& key,
                          int dimension, std::array<double, 3> fallback, bool required) {
    if (!o.contains(key)) {
        if (required)
            throw ConfigError(join(where, key), "missing (required)");
        return fallback;
    }
    const auto& v = o.at(key);
    if (!v.is_array() || (v.size() != static_cast<std::size_t>(dimension) && v.size() != 3))
        throw ConfigError(join(where, key), fmt::format("expected an array of {} numbers, found {}",
                                                        dimension, v.dump()));
    std::array<double, 3> r{0, 0, 0};
    for (std::size_t k = 0; k < v.size(); ++k) {
        if (!v[k].is_number() || !std::isfinite(v[k].get<double>()))
            throw ConfigError(join(where, key), "entries must be finite numbers");
        r[k] = v[k].get<double>();
    }
    if (dimension == 2 && r[2] != 0)
        throw ConfigError(join(where, key), "z must be 0 in a 2D scene");
    return r;
}

bool boolean(const json& o, const std::string& where, const std::string& key, bool fallback) {
    if (!o.contains(key))
        return fallback;
    if (!o.at(key).is_boolean())
        throw ConfigError(join(where, key), "expected true or false");
    return o.at(key).get<bool>();
}

std::string text(const json& o, const std::string& where, const std::string& key,
                 const std::string& fallback, const std::vector<std::string>& choices) {
    if (!o.contains(key))
        return fallback;
    if (!o.at(key).is_string())
        throw ConfigError(join(where, key), "expected a string");
    auto s = o.at(key).get<std::string>();
    if (!choices.empty() && std::find(choices.begin(), choices.end(), s) == choices.end()) {
        std::string c;
        for (const auto& k : choices)
            c += (c.empty() ? "" : ", ") + k;
        throw ConfigError(join(where, key), "'" + s + "' is not one of: " + c);
    }
    return s;
}

std::string resolve(const std::string& base, const std::string& file) {
    std::filesystem::path p(file);
    return p.is_absolute() || base.empty() ? file : (std::filesystem::path(base) / p).string();
}

} // namespace pd::pipeline::scene
