// SPDX-License-Identifier: MIT
#include "pipeline/overrides.hpp"

#include "core/errors.hpp"
#include "pipeline/scene.hpp"
#include "pipeline/scene/fields.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>

namespace pd::pipeline {

namespace {

using json = nlohmann::json;

/// "a.b[2].c" -> {a, b, 2, c}; "/a/b/2/c" -> the same (JSON pointer, ~0 ~1 unescaped).
std::vector<std::string> split_path(const std::string& path) {
    std::vector<std::string> parts;
    if (!path.empty() && path[0] == '/') {
        std::string cur;
        for (std::size_t i = 1; i <= path.size(); ++i) {
            if (i == path.size() || path[i] == '/') {
                std::string k;
                for (std::size_t j = 0; j < cur.size(); ++j) {
                    if (cur[j] == '~' && j + 1 < cur.size() &&
                        (cur[j + 1] == '0' || cur[j + 1] == '1')) {
                        k += cur[j + 1] == '0' ? '~' : '/';
                        ++j;
                    } else {
                        k += cur[j];
                    }
                }
                parts.push_back(k);
                cur.clear();
            } else {
                cur += path[i];
            }
        }
        return parts;
    }
    std::string cur;
    auto flush = [&] {
        if (!cur.empty())
            parts.push_back(cur);
        cur.clear();
    };
    for (char c : path) {
        if (c == '.' || c == '[' || c == ']')
            flush();
        else
            cur += c;
    }
    flush();
    return parts;
}

bool is_index(const std::string& s) {
    return !s.empty() &&
           std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
}

/// The key of object `o` closest to `key`, and its distance.
std::pair<std::string, std::size_t> closest(const json& o, const std::string& key) {
    std::string best;
    std::size_t bd = std::string::npos;
    for (auto it = o.begin(); it != o.end(); ++it) {
        const auto d = edit_distance(key, it.key());
        if (d < bd) {
            bd = d;
            best = it.key();
        }
    }
    return {best, bd};
}

std::string keys_of(const json& o) {
    std::string s;
    for (auto it = o.begin(); it != o.end(); ++it)
        s += (s.empty() ? "" : ", ") + it.key();
    return s;
}

} // namespace

Resolved apply_overrides(const std::string& text, const std::string& source,
                         const std::vector<std::string>& sets) {
    json root = scene::parse_json(text, source);
    json record = json::object();
    for (const auto& set : sets) {
        const auto eq = set.find('=');
        if (eq == std::string::npos || eq == 0)
            throw InputError(fmt::format("--set '{}': expected PATH=VALUE (e.g. "
                                         "contact.restitution=0.5)",
                                         set));
        const std::string path = set.substr(0, eq), raw = set.substr(eq + 1);
        json value;
        if (!scene::parse_json_value(raw, fmt::format("--set {}", path), value))
            value = raw; // a bare word: a string
        const auto parts = split_path(path);
        if (parts.empty())
            throw ConfigError(path, "--set: empty path");
        json* node = &root;
        std::string where;
        for (std::size_t k = 0; k < parts.size(); ++k) {
            const auto& p = parts[k];
            const bool leaf = k + 1 == parts.size();
            const std::string here = where.empty() ? p : where + "." + p;
            if (node->is_array()) {
                if (!is_index(p) || std::stoull(p) >= node->size())
                    throw ConfigError(here, fmt::format("--set: {} has {} entries (indices 0 to "
                                                        "{})",
                                                        where, node->size(),
                                                        static_cast<long long>(node->size()) - 1));
                node = &(*node)[std::stoull(p)];
            } else if (node->is_object()) {
                if (!node->contains(p)) {
                    const auto [best, d] = closest(*node, p);
                    // A new leaf key is allowed (pd-pack checks it against the scene keys);
                    // a near miss of an existing key is a typo.
                    if (!leaf || (d <= 2 && !best.empty()))
                        throw ConfigError(
                            here, best.empty()
                                      ? fmt::format("--set: no such key ({} is empty)",
                                                    where.empty() ? "the scene" : where)
                                      : fmt::format(
                                            "--set: no such key in the scene; did you mean "
                                            "'{}'?{}",
                                            where.empty() ? best : where + "." + best,
                                            d > 2 ? fmt::format(" (keys here: {})", keys_of(*node))
                                                  : std::string{}));
                }
                node = &(*node)[p];
            } else {
                throw ConfigError(here, fmt::format("--set: {} is a {}, not an object or array",
                                                    where, node->type_name()));
            }
            where = here;
        }
        *node = value;
        record[path] = value;
    }
    Resolved r;
    r.scene = root.dump(2);
    if (!sets.empty())
        r.overrides = record.dump();
    return r;
}

namespace {

/// Whether a contact table selects the node law as pd-pack reads it (contact.cpp choose_law): it
/// names it, or gives a radius or a numeric stiffness; else the default law, the surface law.
bool node_law(const json& obj) {
    auto has = [&](const char* k) { return obj.contains(k); };
    if (has("law"))
        return obj["law"] == "node";
    return has("radius") || has("radius_factor") || has("radius_mesh_factor") ||
           (has("stiffness") && obj["stiffness"].is_number());
}

/// A key not filled while one of these is present (it would replace or contradict them). The
/// node law's keys (radius_factor, approach_damping) are not filled in a contact table on the
/// surface law: they would select the node law, or be refused by it.
bool replaced(const json& obj, const std::string& key) {
    auto has = [&](const char* k) { return obj.contains(k); };
    if ((key == "radius_factor" || key == "approach_damping") && !node_law(obj))
        return true;
    if (key == "radius_factor")
        return has("radius") || has("radius_mesh_factor");
    if (key == "fracture_energy")
        return has("fracture_toughness");
    if (key == "stiffness_factor")
        return has("stiffness") && obj["stiffness"].is_number();
    return false;
}

const json& deref(const json& s, const json& root) {
    if (s.is_object() && s.contains("$ref") && s["$ref"].is_string()) {
        const std::string ref = s["$ref"];
        if (ref.rfind("#", 0) == 0)
            return deref(root.at(json::json_pointer(ref.substr(1))), root);
    }
    return s;
}

/// The branch of a oneOf that `v` takes: the first whose required keys `v` has and, when it
/// admits no other keys, whose properties hold every key of `v` (nullptr: none).
const json* branch(const json& v, const json& one_of, const json& root) {
    for (const auto& b0 : one_of) {
        const json& b = deref(b0, root);
        if (!b.is_object() || !v.is_object())
            continue;
        bool ok = true;
        if (b.contains("required"))
            for (const auto& k : b["required"])
                ok = ok && v.contains(k.get<std::string>());
        if (ok && b.contains("additionalProperties") && b["additionalProperties"] == false &&
            b.contains("properties"))
            for (const auto& [k, x] : v.items())
                ok = ok && b["properties"].contains(k);
        if (ok)
            return &b;
    }
    return nullptr;
}

void fill(json& v, const json& schema, const json& root, const std::string& where) {
    const json* sp = &deref(schema, root);
    if (sp->is_object() && sp->contains("oneOf") && v.is_object())
        if (const json* b = branch(v, (*sp)["oneOf"], root))
            sp = b;
    const json& s = *sp;
    if (!s.is_object() || where == "/contact/pairs")
        return;
    if (v.is_object()) {
        const json none = json::object();
        const json& props = s.contains("properties") ? s["properties"] : none;
        for (const auto& [k, ps] : props.items()) {
            const json& p = deref(ps, root);
            if (!v.contains(k) && p.is_object() && p.contains("default") && !replaced(v, k))
                v[k] = p["default"];
            if (v.contains(k))
                fill(v[k], p, root, where + "/" + k);
        }
        if (s.contains("additionalProperties") && s["additionalProperties"].is_object())
            for (auto& [k, x] : v.items())
                if (!props.contains(k))
                    fill(x, s["additionalProperties"], root, where + "/" + k);
    } else if (v.is_array() && s.contains("items") && s["items"].is_object()) {
        for (auto& x : v)
            fill(x, s["items"], root, where);
    }
}

} // namespace

std::string fill_defaults(const std::string& scene, const std::string& schema) {
    json v = json::parse(scene);
    const json root = json::parse(schema);
    fill(v, root, root, "");
    return v.dump(2);
}

} // namespace pd::pipeline
