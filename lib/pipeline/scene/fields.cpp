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

namespace {

struct TooDeep {};

/// nlohmann's parse with a callback that stops at max_json_depth (the parser is iterative; the
/// callback sees each value's depth as it starts).
json parse_limited(const std::string& text, const std::string& source, bool comments) {
    if (text.size() > max_json_bytes)
        throw InputError(fmt::format("{}: {} bytes, above the limit of {} bytes for a scene",
                                     source, text.size(), max_json_bytes));
    const json::parser_callback_t cb = [](int depth, json::parse_event_t event, json&) {
        if ((event == json::parse_event_t::object_start ||
             event == json::parse_event_t::array_start) &&
            depth >= max_json_depth)
            throw TooDeep{};
        return true;
    };
    try {
        return json::parse(text, cb, true, comments);
    } catch (const TooDeep&) {
        throw InputError(fmt::format("{}: nested more than {} levels deep (objects and arrays): "
                                     "refused before it is read further",
                                     source, max_json_depth));
    }
}

} // namespace

json parse_json(const std::string& text, const std::string& source) {
    try {
        return parse_limited(text, source, /*comments=*/true);
    } catch (const json::parse_error& e) {
        // The place, never the bytes read (nlohmann's "; last read: '...'"): a file that is
        // not a scene is not echoed.
        std::string why = e.what();
        why = why.substr(0, why.find("; last read"));
        throw InputError(fmt::format("{}: not valid JSON (byte {}): {}", source, e.byte, why));
    } catch (const json::exception& e) { // out_of_range 406: a number like 1e999
        throw InputError(fmt::format("{}: not valid JSON: {}", source, e.what()));
    }
}

bool parse_json_value(const std::string& text, const std::string& source, json& out) {
    try {
        out = parse_limited(text, source, /*comments=*/false);
        return true;
    } catch (const json::parse_error&) {
        return false;
    } catch (const json::exception& e) {
        throw InputError(fmt::format("{}: {}", source, e.what()));
    }
}

std::string resolve(const Folder& base, const std::string& file, const std::string& key) {
    namespace fs = std::filesystem;
    const fs::path p(file);
    const std::string path =
        p.is_absolute() || base.dir.empty() ? file : (fs::path(base.dir) / p).string();
    if (base.outside)
        return path;
    std::error_code ec;
    const fs::path dir = base.dir.empty() ? fs::path(".") : fs::path(base.dir);
    const fs::path root = fs::weakly_canonical(fs::absolute(dir, ec), ec);
    const fs::path target = fs::weakly_canonical(fs::absolute(fs::path(path), ec), ec);
    const fs::path rel = target.lexically_relative(root);
    if (ec || rel.empty() || *rel.begin() == "..")
        throw ConfigError(key, fmt::format("'{}' lies outside the folder of the scene ({}): a "
                                           "path that leaves it (by .., an absolute path or a "
                                           "link) needs pd-pack --allow-outside",
                                           file, dir.string()));
    return path;
}

} // namespace pd::pipeline::scene
