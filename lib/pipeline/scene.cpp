// SPDX-License-Identifier: MIT
#include "pipeline/scene.hpp"

#include "core/errors.hpp"
#include "geometry/packing.hpp"
#include "geometry/shapes.hpp"
#include "mesh/discretize.hpp"
#include "mesh/gmsh_mesher.hpp"
#include "mesh/shape_mesher.hpp"
#include "model/pmb.hpp"
#include "model/slots.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>
#include <set>

namespace pd::pipeline {

using json = nlohmann::json;

std::size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j)
        prev[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        cur[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j)
            cur[j] = std::min(
                {prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
        std::swap(prev, cur);
    }
    return prev[b.size()];
}

namespace {

/// Checks that object `o` at `where` has only keys from `allowed`.
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
              bool required = false) {
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
                bool required = false) {
    double d = number(o, where, key, fallback, required);
    if (!(d > 0))
        throw ConfigError(join(where, key), fmt::format("must be positive, found {}", d));
    return d;
}

std::array<double, 3> vec(const json& o, const std::string& where, const std::string& key,
                          int dimension, std::array<double, 3> fallback, bool required = false) {
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
                 const std::string& fallback, const std::vector<std::string>& choices = {}) {
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

/// A named reference shape and how to mesh it.
struct ShapeSpec {
    geometry::Shape shape;
    std::string method = "gmsh"; ///< gmsh | grid | file
    std::string file;            ///< .msh path (method file)
    bool quads = false;
    double mesh_size = 0; ///< 0: the scene's discretization.mesh_size
};

/// One particle to place.
struct Instance {
    std::string shape;
    std::array<double, 3> center{0, 0, 0};
    double radius = 0; ///< bounding radius; 0 = the shape as given (scale 1)
    double orientation = 0;
    std::int32_t material = 0;
    std::int32_t group = 0;
    std::array<double, 3> velocity{0, 0, 0};
    bool fixed = false;
    std::string where; ///< scene key, for messages
};

std::string resolve(const std::string& base, const std::string& file) {
    std::filesystem::path p(file);
    return p.is_absolute() || base.empty() ? file : (std::filesystem::path(base) / p).string();
}

const std::vector<std::string> shape_keys = {
    "type",    "radius",     "semi_axes", "sides",    "phase", "size",
    "corners", "neck_width", "vertices",  "parts",    "base",  "minus",
    "length",  "offset",     "rotation",  "centered", "file"};

/// A shape; relative surface_mesh files are resolved against `base` (the scene file's folder).
geometry::Shape parse_shape(const json& o, const std::string& w, int dim, const std::string& base) {
    check_keys(o, w, shape_keys);
    const auto type = text(o, w, "type", "",
                           {"circle", "ellipse", "triangle", "square", "hexagon", "regular_polygon",
                            "rectangle", "drum2d", "polygon", "union", "difference", "sphere",
                            "box", "cylinder", "surface_mesh"});
    if (type.empty())
        throw ConfigError(w + ".type", "missing: the kind of shape");
    if (type != "surface_mesh" && o.contains("file"))
        throw ConfigError(w + ".file", "only a surface_mesh shape reads a file (a named shape "
                                       "meshed with \"mesh\": \"file\" gives its .msh here)");
    auto pair = [&](const char* key) {
        if (!o.contains(key) || !o[key].is_array() || o[key].size() < 2)
            throw ConfigError(join(w, key), "expected a list of numbers");
        return std::array<double, 3>{o[key][0].get<double>(), o[key][1].get<double>(),
                                     o[key].size() > 2 ? o[key][2].get<double>() : 0.0};
    };
    auto list = [&](const json& arr, const std::string& ww) {
        if (!arr.is_array() || arr.empty())
            throw ConfigError(ww, "expected a list of shapes");
        std::vector<geometry::Shape> v;
        for (std::size_t k = 0; k < arr.size(); ++k)
            v.push_back(parse_shape(arr[k], fmt::format("{}[{}]", ww, k), dim, base));
        return v;
    };
    geometry::Shape sh = [&]() {
        if (type == "circle")
            return geometry::Shape::circle(positive(o, w, "radius", 0, true));
        if (type == "ellipse") {
            auto a = pair("semi_axes");
            return geometry::Shape::ellipse(a[0], a[1]);
        }
        if (type == "triangle")
            return geometry::Shape::triangle(positive(o, w, "radius", 0, true));
        if (type == "square")
            return geometry::Shape::square(positive(o, w, "radius", 0, true));
        if (type == "hexagon")
            return geometry::Shape::hexagon(positive(o, w, "radius", 0, true));
        if (type == "regular_polygon") {
            const double sides = positive(o, w, "sides", 0, true);
            if (sides != std::floor(sides) || sides < 3 || sides > 10000)
                throw ConfigError(join(w, "sides"),
                                  fmt::format("{:g}: must be a whole number from 3 to 10000 (more "
                                              "sides than that: use a circle)",
                                              sides));
            return geometry::Shape::regular_polygon(static_cast<int>(sides),
                                                    positive(o, w, "radius", 0, true),
                                                    number(o, w, "phase", 0));
        }
        if (type == "rectangle") {
            if (o.contains("corners")) {
                const auto& c = o["corners"];
                if (!c.is_array() || c.size() != 2)
                    throw ConfigError(w + ".corners", "expected [[x0, y0], [x1, y1]]");
                return geometry::Shape::rectangle_corners(
                    c[0][0].get<double>(), c[0][1].get<double>(), c[1][0].get<double>(),
                    c[1][1].get<double>());
            }
            auto a = pair("size");
            return geometry::Shape::rectangle(a[0], a[1]);
        }
        if (type == "drum2d")
            return geometry::Shape::drum2d(positive(o, w, "radius", 0, true),
                                           positive(o, w, "neck_width", 0, true));
        if (type == "polygon") {
            if (!o.contains("vertices") || !o["vertices"].is_array())
                throw ConfigError(w + ".vertices", "expected [[x, y], ...]");
            std::vector<geometry::Vec2> v;
            for (const auto& p : o["vertices"])
                v.push_back({p[0].get<double>(), p[1].get<double>()});
            return geometry::Shape::polygon(v);
        }
        if (type == "union") {
            if (!o.contains("parts"))
                throw ConfigError(w + ".parts", "missing");
            return geometry::Shape::unite(list(o["parts"], w + ".parts"));
        }
        if (type == "difference") {
            if (!o.contains("base") || !o.contains("minus"))
                throw ConfigError(w, "a difference needs base and minus");
            return geometry::Shape::difference(parse_shape(o["base"], w + ".base", dim, base),
                                               list(o["minus"], w + ".minus"));
        }
        if (type == "sphere")
            return geometry::Shape::sphere(positive(o, w, "radius", 0, true));
        if (type == "box") {
            auto a = pair("size");
            return geometry::Shape::box(a[0], a[1], a[2]);
        }
        if (type == "surface_mesh") {
            const auto file = text(o, w, "file", "");
            if (file.empty())
                throw ConfigError(w + ".file", "missing: the STL file (ASCII or binary) of this "
                                               "surface_mesh, relative to the scene file");
            try {
                return geometry::Shape::surface_mesh(resolve(base, file));
            } catch (const ConfigError&) {
                throw;
            } catch (const InputError& e) {
                throw ConfigError(w + ".file", e.what());
            }
        }
        return geometry::Shape::cylinder(positive(o, w, "radius", 0, true),
                                         positive(o, w, "length", 0, true));
    }();
    if (o.contains("rotation"))
        sh = sh.rotated(number(o, w, "rotation", 0));
    if (o.contains("offset")) {
        auto t = pair("offset");
        sh = sh.translated(t[0], t[1], t[2]);
    }
    if (boolean(o, w, "centered", false))
        sh = sh.centered();
    if (sh.dimension() != dim)
        throw ConfigError(w + ".type",
                          fmt::format("a {}D shape in a {}D scene", sh.dimension(), dim));
    return sh;
}

ShapeSpec parse_shape_spec(const json& o, const std::string& w, int dim, const std::string& base) {
    // "file" (in shape_keys): a surface_mesh's STL, or the .msh of mesh "file".
    auto keys = shape_keys;
    keys.insert(keys.end(), {"mesh", "quads", "mesh_size"});
    check_keys(o, w, keys);
    const bool surface = o.contains("type") && o["type"] == "surface_mesh";
    json geo = json::object();
    for (auto it = o.begin(); it != o.end(); ++it)
        if (std::find(shape_keys.begin(), shape_keys.end(), it.key()) != shape_keys.end() &&
            (it.key() != "file" || surface))
            geo[it.key()] = *it;
    ShapeSpec sp{parse_shape(geo, w, dim, base), "gmsh", "", false, 0};
    sp.method = text(o, w, "mesh", "gmsh", {"gmsh", "grid", "file"});
    if (surface && sp.method == "file")
        throw ConfigError(w + ".mesh", "a surface_mesh is meshed from its STL: use gmsh "
                                       "(tetrahedra) or grid");
    if (sp.method == "file") {
        sp.file = resolve(base, text(o, w, "file", ""));
        if (sp.file.empty())
            throw ConfigError(w + ".file", "missing: the .msh file of this shape");
    }
    sp.quads = boolean(o, w, "quads", false);
    sp.mesh_size = o.contains("mesh_size") ? positive(o, w, "mesh_size", 0) : 0.0;
    return sp;
}

/// Signed distance of x from a wall at t = 0 (positive on the free side).
double wall_distance(const model::Wall& w, const double* x) {
    if (w.shape == model::WallShape::plane) {
        double d = 0;
        for (std::size_t q = 0; q < 3; ++q)
            d += (x[q] - w.point[q]) * w.normal[q];
        return d;
    }
    const double r = std::hypot(x[0] - w.point[0], x[1] - w.point[1], x[2] - w.point[2]);
    return w.shape == model::WallShape::circle_inside ? w.radius - r : r - w.radius;
}

/// Grains must not overlap: for every pair whose bounding spheres intersect, no node of one may
/// lie inside the other's shape (exact shape tests in the reference frame).
void check_overlaps(const model::Model& m, const std::vector<Instance>& inst,
                    const std::map<std::string, ShapeSpec>& shapes) {
    const auto& B = m.bodies;
    const std::size_t nb = B.num();
    std::vector<std::size_t> order(nb);
    for (std::size_t k = 0; k < nb; ++k)
        order[k] = k;
    auto lo = [&](std::size_t b) { return B.center[3 * b] - B.bounding_radius[b]; };
    std::sort(order.begin(), order.end(), [&](auto a, auto b) { return lo(a) < lo(b); });
    auto inside = [&](std::size_t a, std::size_t b) -> std::int64_t {
        // First node of body a strictly inside body b's shape, or -1.
        const auto& sh = shapes.at(inst[b].shape).shape;
        const double c = std::cos(B.orientation[b]), sn = std::sin(B.orientation[b]);
        const double tol = 1e-9 * sh.bounding_radius();
        for (auto i = B.begin(a); i < B.end(a); ++i) {
            const double* x = &m.nodes.x0[3 * static_cast<std::size_t>(i)];
            const double dx = x[0] - B.center[3 * b], dy = x[1] - B.center[3 * b + 1],
                         dz = x[2] - B.center[3 * b + 2];
            const double s = B.scale[b];
            const double X = (c * dx + sn * dy) / s, Y = (-sn * dx + c * dy) / s, Z = dz / s;
            if (sh.clearance(X, Y, Z) > tol)
                return i - B.begin(a);
        }
        return -1;
    };
    for (std::size_t ia = 0; ia < nb; ++ia) {
        const auto a = order[ia];
        for (std::size_t ib = ia + 1; ib < nb; ++ib) {
            const auto b = order[ib];
            if (lo(b) > B.center[3 * a] + B.bounding_radius[a])
                break;
            const double d = std::hypot(B.center[3 * a] - B.center[3 * b],
                                        B.center[3 * a + 1] - B.center[3 * b + 1],
                                        B.center[3 * a + 2] - B.center[3 * b + 2]);
            if (d >= B.bounding_radius[a] + B.bounding_radius[b])
                continue;
            std::size_t p = a, q = b;
            auto node = inside(a, b);
            if (node < 0) {
                node = inside(b, a);
                std::swap(p, q);
            }
            if (node >= 0)
                throw ConfigError(
                    fmt::format("{}, {}", inst[std::min(p, q)].where, inst[std::max(p, q)].where),
                    fmt::format("grains overlap: node {} of the {} lies inside the {}", node,
                                p < q ? "first" : "second", p < q ? "second" : "first"));
        }
    }
}

/// Prints each group's horizon and smallest node spacing (min-max over its grains) and each
/// contact law's stiffness and radius; warns when the horizons of groups that can touch (a law
/// with Kn > 0 between them, or a group with itself) differ by more than 20 %: the contact
/// stiffness (~ delta^-(d+2)) and the bond response then differ between them.
void report_horizons(const model::Model& m, const Log& log) {
    const auto& B = m.bodies;
    struct Range {
        std::size_t n = 0;
        double dmin = 1e300, dmax = 0, hmin = 1e300, hmax = 0;
    };
    std::map<std::int32_t, Range> by_group;
    for (std::size_t b = 0; b < B.num(); ++b) {
        auto& r = by_group[B.group[b]];
        ++r.n;
        r.dmin = std::min(r.dmin, B.horizon[b]);
        r.dmax = std::max(r.dmax, B.horizon[b]);
        r.hmin = std::min(r.hmin, B.mesh_size[b]);
        r.hmax = std::max(r.hmax, B.mesh_size[b]);
    }
    for (const auto& [g, r] : by_group)
        log.info("group {}: {} grains, horizon {:.4g}-{:.4g} m, smallest node spacing "
                 "{:.4g}-{:.4g} m",
                 g, r.n, r.dmin, r.dmax, r.hmin, r.hmax);
    for (const auto& p : m.contact) {
        const auto a = by_group.find(p.group_a), b = by_group.find(p.group_b);
        log.info("contact groups {}-{}: stiffness Kn {:.4g}, radius R_c {:.4g} m", p.group_a,
                 p.group_b, p.stiffness, p.radius);
        if (!(p.stiffness > 0) || a == by_group.end() || b == by_group.end())
            continue; // no contact, or a rigid wall (no horizon)
        const double lo = std::min(a->second.dmin, b->second.dmin);
        const double hi = std::max(a->second.dmax, b->second.dmax);
        if (hi > 1.2 * lo)
            log.warn(
                "contact groups {}-{}: horizons range over {:.4g}-{:.4g} m ({:+.0f} %): "
                "grains that touch have different contact stiffness (~ delta^-{}) and bond "
                "response (use horizon, or horizon_factor with one mesh_size for their shapes)",
                p.group_a, p.group_b, lo, hi, 100.0 * (hi - lo) / lo, m.dimension + 2);
    }
}

} // namespace

namespace {
model::Model build_scene_impl(const std::string& source_text, const std::string& source,
                              const Log& log, double max_nodes);
} // namespace

model::Model build_scene(const std::string& source_text, const std::string& source, const Log& log,
                         double max_nodes) {
    try {
        return build_scene_impl(source_text, source, log, max_nodes);
    } catch (const json::exception& e) { // a value of the wrong JSON type read without a check
        throw InputError(fmt::format("{}: {}", source, e.what()));
    }
}

namespace {
model::Model build_scene_impl(const std::string& source_text, const std::string& source,
                              const Log& log, double max_nodes) {
    json root;
    try {
        root = json::parse(source_text, nullptr, true, /*ignore_comments=*/true);
    } catch (const json::parse_error& e) {
        throw InputError(fmt::format("{}: not valid JSON: {}", source, e.what()));
    } catch (const json::exception& e) { // out_of_range 406: a number like 1e999
        throw InputError(fmt::format("{}: not valid JSON: {}", source, e.what()));
    }
    check_keys(root, "",
               {"title", "dimension", "planar", "materials", "discretization", "shapes",
                "particles", "walls", "cracks", "slots", "contact", "loading", "solver"});
    model::Model m;
    m.scene_json = root.dump(2);
    m.title = text(root, "", "title", source);
    m.dimension = static_cast<int>(number(root, "", "dimension", 2));
    if (m.dimension != 2 && m.dimension != 3)
        throw ConfigError("dimension", fmt::format("{}: expected 2 or 3", m.dimension));
    const std::string base_dir = std::filesystem::path(source).parent_path().string();
    m.planar =
        text(root, "", "planar", "plane_stress", {"plane_stress", "plane_strain"}) == "plane_strain"
            ? model::Planar::plane_strain
            : model::Planar::plane_stress;

    // Materials.
    if (!root.contains("materials") || !root["materials"].is_object() || root["materials"].empty())
        throw ConfigError("materials", "missing: give at least one material by name");
    std::map<std::string, std::int32_t> material_index;
    for (auto it = root["materials"].begin(); it != root["materials"].end(); ++it) {
        const std::string w = "materials." + it.key();
        check_keys(*it, w,
                   {"law", "density", "youngs_modulus", "bulk_modulus", "shear_modulus",
                    "poisson_ratio", "fracture_energy", "fracture_toughness", "influence"});
        model::Material mat;
        mat.name = it.key();
        for (char ch : mat.name)
            if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'))
                throw ConfigError(w, "material names may hold letters, digits and '_' only");
        const auto law = text(*it, w, "law", "pmb", {"pmb", "lps", "rnp"});
        mat.law = law == "lps" ? model::Law::lps : law == "rnp" ? model::Law::rnp : model::Law::pmb;
        const auto inf =
            text(*it, w, "influence", mat.law == model::Law::pmb ? "constant" : "linear",
                 {"constant", "linear", "gaussian"});
        mat.influence = inf == "linear"     ? model::Influence::linear
                        : inf == "gaussian" ? model::Influence::gaussian
                                            : model::Influence::constant;
        if (mat.law == model::Law::pmb && mat.influence != model::Influence::constant)
            throw ConfigError(w + ".influence", "the PMB law uses J = 1 (constant); influence "
                                                "functions apply to laws \"lps\" and \"rnp\"");
        mat.density = positive(*it, w, "density", 0, true);
        // Elastic constants: two of E, K, G, nu (spec 1.2-1.3); a bond-based law (pmb, rnp)
        // fixes nu, so E alone is enough there and a pair must agree with the law's nu.
        const double nu_law = mat.law == model::Law::rnp ? 0.25
                              : mat.law == model::Law::pmb
                                  ? model::pmb_poisson_ratio(m.dimension, m.planar)
                                  : -2.0;
        const bool hE = it->contains("youngs_modulus"), hK = it->contains("bulk_modulus"),
                   hG = it->contains("shear_modulus"), hn = it->contains("poisson_ratio");
        const int given = hE + hK + hG + hn;
        double E = hE ? positive(*it, w, "youngs_modulus", 0) : 0;
        const double K = hK ? positive(*it, w, "bulk_modulus", 0) : 0;
        const double G = hG ? positive(*it, w, "shear_modulus", 0) : 0;
        double nu = hn ? number(*it, w, "poisson_ratio", 0) : nu_law;
        if (hn && !(nu > -1 && nu < 0.5))
            throw ConfigError(w + ".poisson_ratio", "must be in (-1, 0.5)");
        if (given == 1 && hE && nu_law > -2) {
            // E with the law's nu
        } else if (given != 2) {
            throw ConfigError(w, nu_law > -2 ? "give youngs_modulus, or two of youngs_modulus, "
                                               "bulk_modulus, shear_modulus, poisson_ratio"
                                             : "give two of youngs_modulus, bulk_modulus, "
                                               "shear_modulus, poisson_ratio");
        } else if (hE && hG) {
            nu = E / (2 * G) - 1;
        } else if (hE && hK) {
            nu = (3 * K - E) / (6 * K);
        } else if (hK && hG) {
            nu = (3 * K - 2 * G) / (2 * (3 * K + G));
            E = 9 * K * G / (3 * K + G);
        } else if (hK && hn) {
            E = 3 * K * (1 - 2 * nu);
        } else if (hG && hn) {
            E = 2 * G * (1 + nu);
        }
        if (!(E > 0) || !(nu > -1 && nu < 0.5))
            throw ConfigError(w, fmt::format("the elastic constants give E = {:.4g} Pa, nu = "
                                             "{:.4g}: not a stable isotropic solid",
                                             E, nu));
        if (nu_law > -2 && std::abs(nu - nu_law) > 1e-6)
            throw ConfigError(
                w, fmt::format("the {} law fixes nu = {:.4g} ({}), the constants "
                               "given imply nu = {:.4g}",
                               mat.law == model::Law::rnp ? "RNP" : "bond-based PMB", nu_law,
                               mat.law == model::Law::rnp                ? "spec 1.4"
                               : m.planar == model::Planar::plane_stress ? "2D plane stress"
                                                                         : "plane strain / 3D",
                               nu));
        mat.youngs_modulus = E;
        // Beyond any solid (diamond: E ~ 1.2e12 Pa, osmium 2.2e4 kg/m3): such values overflow
        // the contact stiffness, the stable time step and the energies.
        if (!(E <= 1e15))
            throw ConfigError(w + (hE ? ".youngs_modulus" : ".bulk_modulus"),
                              fmt::format("E = {:g} Pa is above 1e15 Pa", E));
        if (mat.density > 1e6)
            throw ConfigError(w + ".density",
                              fmt::format("{:g} kg/m3 is above 1e6 kg/m3", mat.density));
        mat.poisson_ratio = nu_law > -2 ? nu_law : nu;
        // Fracture: Gc, or KIc with Gc = KIc^2 / E (spec 1.2).
        if (it->contains("fracture_energy") && it->contains("fracture_toughness"))
            throw ConfigError(w, "give fracture_energy or fracture_toughness, not both");
        mat.fracture_energy = it->contains("fracture_toughness")
                                  ? std::pow(positive(*it, w, "fracture_toughness", 0), 2) / E
                                  : number(*it, w, "fracture_energy", 0);
        if (mat.fracture_energy < 0)
            throw ConfigError(w + ".fracture_energy", "must be >= 0 (0 = unbreakable)");
        if (mat.law == model::Law::rnp && !(mat.fracture_energy > 0))
            throw ConfigError(w + ".fracture_energy", "the RNP law needs Gc > 0");
        material_index[mat.name] = static_cast<std::int32_t>(m.materials.size());
        m.materials.push_back(mat);
    }

    // Discretisation.
    if (!root.contains("discretization"))
        throw ConfigError("discretization", "missing: give mesh_size and horizon");
    const json& dz = root["discretization"];
    check_keys(dz, "discretization",
               {"mesh_size", "horizon", "horizon_factor", "horizon_mesh_ratio", "bond_cutoff",
                "small_horizon"});
    // A horizon below 2 h (a family of one ring of neighbours) is refused by default; PeriDEM
    // runs such decks, so --from-peridem writes "warn".
    const bool small_horizon_warns =
        text(dz, "discretization", "small_horizon", "refuse", {"refuse", "warn"}) == "warn";
    std::size_t small_horizons = 0;
    double small_ratio = std::numeric_limits<double>::infinity();
    const bool partial_cutoff =
        text(dz, "discretization", "bond_cutoff", "partial", {"partial", "strict"}) == "partial";
    const double h_ref = positive(dz, "discretization", "mesh_size", 0, true);
    // Horizon (spec 2.3): absolute; horizon_factor x the nominal mesh size (the shape's
    // mesh_size, else the scene's: the same for every grain of a shape, whatever its scale and
    // its mesh's smallest spacing); or horizon_mesh_ratio x each grain's smallest node spacing
    // (PeriDEM's Horizon_Mesh_Ratio, for --from-peridem parity).
    const bool has_h = dz.contains("horizon"), has_m = dz.contains("horizon_factor"),
               has_r = dz.contains("horizon_mesh_ratio");
    if (int(has_h) + int(has_m) + int(has_r) != 1)
        throw ConfigError("discretization",
                          "give exactly one of horizon (m), horizon_factor (multiple of "
                          "mesh_size) or horizon_mesh_ratio (multiple of each grain's smallest "
                          "node spacing)");
    const std::string horizon_key = has_h   ? "discretization.horizon"
                                    : has_m ? "discretization.horizon_factor"
                                            : "discretization.horizon_mesh_ratio";
    const double horizon_abs = has_h ? positive(dz, "discretization", "horizon", 0) : 0;
    const double horizon_factor = has_m   ? positive(dz, "discretization", "horizon_factor", 0)
                                  : has_r ? positive(dz, "discretization", "horizon_mesh_ratio", 0)
                                          : 0;

    // Reference shapes: named in "shapes", or the implicit "disc" (a circle whose radius is the
    // first disc particle's).
    std::map<std::string, ShapeSpec> shapes;
    std::vector<std::string> shape_order; // in order of first use
    if (root.contains("shapes")) {
        if (!root["shapes"].is_object())
            throw ConfigError("shapes", "expected an object of named shapes");
        for (auto it = root["shapes"].begin(); it != root["shapes"].end(); ++it)
            shapes.emplace(it.key(),
                           parse_shape_spec(*it, "shapes." + it.key(), m.dimension, base_dir));
    }

    // Particles: explicit entries and generators (random_pack, lattice, csv).
    if (!root.contains("particles") || !root["particles"].is_array() || root["particles"].empty())
        throw ConfigError("particles", "missing: give a list of particles or generators");
    std::vector<Instance> inst;
    // Node estimate before anything is meshed or packed (a mesh_size far too small, a huge
    // radius or count would run for minutes or exhaust memory): a reference shape gets about
    // area / h^2 (volume / h^3) nodes, and each grain is an instance of its shape's mesh.
    const bool user_disc = shapes.count("disc") > 0; // else a disc is made per particle radius
    auto shape_nodes = [&](const std::string& name, double radius) {
        const bool disc = name == "disc" && !user_disc;
        if (!disc && !shapes.count(name))
            return 0.0;
        const ShapeSpec* sp = disc ? nullptr : &shapes.at(name);
        if (sp && sp->method == "file")
            return 0.0; // the file's own size
        const double h = sp && sp->mesh_size > 0 ? sp->mesh_size : h_ref;
        const double size = disc ? std::numbers::pi * std::pow(radius, m.dimension) *
                                       (m.dimension == 3 ? 4.0 / 3.0 : 1.0)
                                 : sp->shape.area_or_volume();
        return std::max(1.0, size / std::pow(h, m.dimension));
    };
    auto too_many = [&](double estimate, const std::string& key, const std::string& what) {
        if (!(estimate <= max_nodes))
            throw ConfigError(key, fmt::format("{} is estimated at {:.3g} nodes, above the limit "
                                               "{:.3g} (pd-pack --max-nodes): coarsen mesh_size, "
                                               "or raise --max-nodes if the machine can hold it",
                                               what, estimate, max_nodes));
    };
    auto common = [&](const json& p, const std::string& w, Instance& d) {
        d.velocity = vec(p, w, "velocity", m.dimension, {0, 0, 0});
        d.fixed = boolean(p, w, "fixed", false);
        d.group = static_cast<std::int32_t>(number(p, w, "group", 0));
        if (d.group < 0 || d.group > 1000)
            throw ConfigError(w + ".group", "must be in [0, 1000]");
        const std::string mat = text(p, w, "material", "");
        if (mat.empty())
            throw ConfigError(w + ".material", "missing (required)");
        auto it = material_index.find(mat);
        if (it == material_index.end())
            throw ConfigError(w + ".material", "no material named '" + mat + "' in materials");
        d.material = it->second;
        d.where = w;
    };
    auto shape_named = [&](const std::string& name, const std::string& w, double radius) {
        if (name == "disc" && !shapes.count("disc")) {
            if (!(radius > 0))
                throw ConfigError(w + ".radius", "a disc needs a positive radius");
            shapes.emplace("disc",
                           ShapeSpec{geometry::Shape::circle(radius), "gmsh", "", false, 0});
        }
        if (!shapes.count(name))
            throw ConfigError(w + ".shape", "no shape named '" + name + "' in shapes");
        if (std::find(shape_order.begin(), shape_order.end(), name) == shape_order.end())
            shape_order.push_back(name);
        const auto& sp = shapes.at(name);
        if (sp.shape.dimension() != m.dimension)
            throw ConfigError(w + ".shape", fmt::format("'{}' is a {}D shape in a {}D scene", name,
                                                        sp.shape.dimension(), m.dimension));
    };
    auto fractions_of = [&](const json& g, const std::string& w, std::vector<std::string>& names) {
        std::vector<double> fr;
        if (!g.contains("shapes")) {
            names = {"disc"};
            return std::vector<double>{1.0};
        }
        if (!g["shapes"].is_object() || g["shapes"].empty())
            throw ConfigError(w + ".shapes", "expected {\"shape name\": fraction, ...}");
        for (auto it = g["shapes"].begin(); it != g["shapes"].end(); ++it) {
            if (!it->is_number() || it->get<double>() < 0)
                throw ConfigError(w + ".shapes." + it.key(), "fraction must be a number >= 0");
            names.push_back(it.key());
            fr.push_back(it->get<double>());
        }
        return fr;
    };
    for (std::size_t k = 0; k < root["particles"].size(); ++k) {
        const json& p = root["particles"][k];
        const std::string w = fmt::format("particles[{}]", k);
        if (!p.is_object())
            throw ConfigError(w, "expected an object");
        if (!p.contains("generate")) {
            check_keys(p, w,
                       {"shape", "radius", "center", "material", "velocity", "fixed", "group",
                        "orientation"});
            Instance d;
            d.shape = text(p, w, "shape", "disc");
            d.radius = p.contains("radius") ? positive(p, w, "radius", 0) : 0.0;
            d.center = vec(p, w, "center", m.dimension, {0, 0, 0}, true);
            for (double c : d.center)
                if (std::abs(c) > 1e10 * h_ref)
                    throw ConfigError(w + ".center",
                                      fmt::format("{:g} m is more than 1e10 mesh sizes from the "
                                                  "origin: node positions would lose their "
                                                  "precision",
                                                  c));
            d.orientation = number(p, w, "orientation", 0);
            common(p, w, d);
            shape_named(d.shape, w, d.radius);
            inst.push_back(d);
            continue;
        }
        const auto type = text(p, w, "generate", "", {"random_pack", "lattice", "csv"});
        Instance tmpl;
        std::vector<geometry::Grain> grains;
        std::vector<std::string> names;
        if (type == "random_pack") {
            check_keys(p, w,
                       {"generate", "container", "count", "radius", "shapes", "gap", "seed",
                        "orientation", "material", "velocity", "fixed", "group"});
            if (!p.contains("container"))
                throw ConfigError(w + ".container", "missing: the region to fill (a shape)");
            const auto container =
                parse_shape(p["container"], w + ".container", m.dimension, base_dir);
            geometry::PackOptions o;
            const double count = positive(p, w, "count", 0, true);
            if (count != std::floor(count))
                throw ConfigError(w + ".count", fmt::format("{:g}: must be a whole number", count));
            too_many(count, w + ".count", fmt::format("{:g} grains", count));
            o.count = static_cast<std::size_t>(count);
            if (!p.contains("radius") || !p["radius"].is_array() || p["radius"].size() != 2)
                throw ConfigError(w + ".radius", "expected [rmin, rmax] (m)");
            o.rmin = p["radius"][0].get<double>();
            o.rmax = p["radius"][1].get<double>();
            if (!(o.rmin > 0 && o.rmax >= o.rmin))
                throw ConfigError(w + ".radius", "need 0 < rmin <= rmax");
            o.fractions = fractions_of(p, w, names);
            {
                double least = 1e300;
                for (std::size_t q = 0; q < names.size(); ++q)
                    if (o.fractions[q] > 0)
                        least = std::min(least, shape_nodes(names[q], o.rmin));
                too_many(static_cast<double>(o.count) * (least < 1e300 ? least : 1.0), w + ".count",
                         fmt::format("{} grains of {:.3g} nodes or more each", o.count, least));
            }
            o.gap = number(p, w, "gap", 0);
            o.seed = static_cast<std::uint64_t>(number(p, w, "seed", 1));
            o.random_orientation =
                text(p, w, "orientation", "random", {"random", "zero"}) == "random";
            geometry::PackStats st;
            grains = geometry::random_pack(container, o, &st);
            log.info("{}: packed {} grains (packing fraction {:.3f}, {} by relaxation)", w,
                     grains.size(), st.packing_fraction, st.relaxed);
        } else if (type == "lattice") {
            check_keys(p, w,
                       {"generate", "origin", "counts", "spacing", "stagger", "jitter", "radius",
                        "shapes", "gap", "seed", "orientation", "material", "velocity", "fixed",
                        "group"});
            geometry::LatticeOptions o;
            o.dimension = m.dimension;
            o.origin = vec(p, w, "origin", m.dimension, {0, 0, 0}, true);
            o.spacing = vec(p, w, "spacing", m.dimension, {0, 0, 0}, true);
            if (!p.contains("counts") || !p["counts"].is_array() ||
                p["counts"].size() != static_cast<std::size_t>(m.dimension))
                throw ConfigError(w + ".counts", "expected grain counts per axis");
            for (int d = 0; d < m.dimension; ++d)
                o.counts[static_cast<std::size_t>(d)] =
                    p["counts"][static_cast<std::size_t>(d)].get<std::size_t>();
            if (!p.contains("radius") || !p["radius"].is_array() || p["radius"].size() != 2)
                throw ConfigError(w + ".radius", "expected [rmin, rmax] (m)");
            o.rmin = p["radius"][0].get<double>();
            o.rmax = p["radius"][1].get<double>();
            o.stagger = boolean(p, w, "stagger", false);
            o.jitter = number(p, w, "jitter", 0);
            o.gap = number(p, w, "gap", 0);
            o.seed = static_cast<std::uint64_t>(number(p, w, "seed", 1));
            o.random_orientation =
                text(p, w, "orientation", "random", {"random", "zero"}) == "random";
            o.fractions = fractions_of(p, w, names);
            {
                double count = 1, least = 1e300;
                for (int d = 0; d < m.dimension; ++d)
                    count *= static_cast<double>(o.counts[static_cast<std::size_t>(d)]);
                for (std::size_t q = 0; q < names.size(); ++q)
                    if (o.fractions[q] > 0)
                        least = std::min(least, shape_nodes(names[q], o.rmin));
                too_many(count * (least < 1e300 ? least : 1.0), w + ".counts",
                         fmt::format("{:.3g} grains", count));
            }
            grains = geometry::lattice(o);
        } else {
            check_keys(p, w,
                       {"generate", "file", "shapes", "material", "velocity", "fixed", "group"});
            const auto file = text(p, w, "file", "");
            if (file.empty())
                throw ConfigError(w + ".file", "missing: a CSV of x, y, z, r, orientation, shape");
            if (!p.contains("shapes") || !p["shapes"].is_array())
                throw ConfigError(w + ".shapes", "expected the list of shape names, by CSV index");
            for (const auto& n : p["shapes"])
                names.push_back(n.get<std::string>());
            grains = geometry::read_particle_csv(resolve(base_dir, file));
        }
        common(p, w, tmpl);
        for (std::size_t g = 0; g < grains.size(); ++g) {
            const auto& gr = grains[g];
            if (gr.shape < 0 || static_cast<std::size_t>(gr.shape) >= names.size())
                throw ConfigError(w + ".shapes", fmt::format("grain {} uses shape index {}, "
                                                             "only {} shapes are named",
                                                             g, gr.shape, names.size()));
            Instance d = tmpl;
            d.shape = names[static_cast<std::size_t>(gr.shape)];
            d.center = gr.center;
            d.radius = gr.radius;
            d.orientation = gr.orientation;
            d.where = fmt::format("{} grain {}", w, g);
            shape_named(d.shape, w, d.radius);
            inst.push_back(d);
        }
    }
    if (inst.empty())
        throw ConfigError("particles", "no particle was placed");
    {
        // Each shape's mesh once, then every grain: refused before any meshing.
        std::map<std::string, double> per_shape;
        double total = 0;
        for (const auto& d : inst) {
            auto [it, fresh] = per_shape.try_emplace(d.shape, 0.0);
            if (fresh) {
                it->second = shape_nodes(d.shape, d.radius);
                const bool disc = d.shape == "disc" && !user_disc;
                too_many(it->second, disc ? d.where + ".radius" : "shapes." + d.shape,
                         disc ? fmt::format("a disc of radius {:g} m at mesh_size {:g} m", d.radius,
                                            h_ref)
                              : fmt::format("shape '{}'", d.shape));
            }
            total += it->second;
        }
        too_many(total, "particles",
                 fmt::format("the scene ({} grains; discretization.mesh_size {:g} m)", inst.size(),
                             h_ref));
    }

    // Mesh each reference shape once (spec 2.5).
    struct Ref {
        std::int32_t index;
        std::vector<double> volume, bdist;
        double h, bound;
    };
    std::map<std::string, Ref> refs;
    for (const auto& name : shape_order) {
        const auto& sp = shapes.at(name);
        const double h = sp.mesh_size > 0 ? sp.mesh_size : h_ref;
        model::RefMesh mesh;
        if (sp.method == "gmsh") {
            mesh::MeshOptions mo;
            mo.quads = sp.quads;
            mesh = mesh::mesh_shape(sp.shape, h, mo);
        } else if (sp.method == "grid") {
            mesh = mesh::uniform_grid(sp.shape, h);
        } else {
            mesh = mesh::read_msh(sp.file, m.dimension);
        }
        mesh.name = name;
        Ref r;
        r.index = static_cast<std::int32_t>(m.ref_meshes.size());
        r.volume = mesh::nodal_volumes(mesh, m.dimension);
        r.h = mesh::min_edge_length(mesh);
        r.bound = std::max(mesh::bounding_radius(mesh), sp.shape.bounding_radius());
        r.bdist = mesh::boundary_distance(mesh, m.dimension);
        double vsum = 0;
        for (std::size_t i = 0; i < r.volume.size(); ++i) {
            if (!(r.volume[i] > 0))
                throw ConfigError(
                    "shapes." + name,
                    fmt::format("mesh node {} has non-positive volume {}", i, r.volume[i]));
            vsum += r.volume[i];
        }
        const double exact = sp.shape.area_or_volume();
        log.info("shape '{}' ({}): {} nodes, {} cells, min spacing {:.4g} m, sum of nodal "
                 "volumes / exact = {:.5f}",
                 name, sp.shape.name(), mesh.nodes.size() / 3,
                 mesh.cells.size() / static_cast<std::size_t>(mesh.nodes_per_cell), r.h,
                 vsum / exact);
        refs.emplace(name, std::move(r));
        m.ref_meshes.push_back(std::move(mesh));
    }

    // Place instances: x = t + s R(theta) X, volumes x s^d, h x s (spec 2.5).
    auto& B = m.bodies;
    std::vector<double> h_nominal_of; // per body: its shape's nominal mesh size (contact radius)
    for (std::size_t k = 0; k < inst.size(); ++k) {
        const auto& d = inst[k];
        const auto& r = refs.at(d.shape);
        const auto& ref = m.ref_meshes[static_cast<std::size_t>(r.index)];
        const double s = d.radius > 0 ? d.radius / shapes.at(d.shape).shape.bounding_radius() : 1.0;
        const std::size_t nref = ref.nodes.size() / 3;
        mesh::place_instance(ref, d.orientation, s, d.center, m.nodes.x0);
        const double sd = std::pow(s, m.dimension);
        for (std::size_t i = 0; i < nref; ++i) {
            m.nodes.volume.push_back(r.volume[i] * sd);
            m.nodes.body.push_back(static_cast<std::int32_t>(k));
        }
        B.node_offsets.push_back(B.node_offsets.back() + static_cast<model::offset_t>(nref));
        B.material.push_back(d.material);
        B.group.push_back(d.group);
        B.ref_mesh.push_back(r.index);
        B.kind.push_back(model::BodyKind::particle);
        B.fixed.push_back(d.fixed ? 1 : 0);
        B.center.insert(B.center.end(), d.center.begin(), d.center.end());
        B.bounding_radius.push_back(r.bound * s);
        B.orientation.push_back(d.orientation);
        B.scale.push_back(s);
        B.initial_velocity.insert(B.initial_velocity.end(), d.velocity.begin(), d.velocity.end());
        const double h = r.h * s;
        const auto& spec = shapes.at(d.shape);
        const double h_nominal = spec.mesh_size > 0 ? spec.mesh_size : h_ref;
        const double delta = has_h   ? horizon_abs
                             : has_m ? horizon_factor * h_nominal
                                     : horizon_factor * h;
        if (delta < 2.0 * h && small_horizon_warns) {
            ++small_horizons;
            small_ratio = std::min(small_ratio, delta / h);
        } else if (delta < 2.0 * h)
            throw ConfigError(horizon_key,
                              fmt::format("{}: horizon {:.4g} m is less than 2 x its mesh "
                                          "spacing h = {:.4g} m (too coarse: refine mesh_size "
                                          "or enlarge the horizon)",
                                          d.where, delta, h));
        B.mesh_size.push_back(h);
        B.horizon.push_back(delta);
        h_nominal_of.push_back(h_nominal);
    }
    if (small_horizons > 0)
        log.warn("{}: {} grain(s) have a horizon below 2 x their smallest node spacing (down to "
                 "{:.3g} h): few bonds per node, a stiffer and more mesh-dependent response "
                 "(discretization.small_horizon = \"warn\")",
                 horizon_key, small_horizons, small_ratio);
    check_overlaps(m, inst, shapes);
    {
        double vol = 0, exact = 0;
        for (double v : m.nodes.volume)
            vol += v;
        for (std::size_t b = 0; b < B.num(); ++b)
            exact +=
                shapes.at(inst[b].shape).shape.area_or_volume() * std::pow(B.scale[b], m.dimension);
        log.info("{} particles: sum of nodal volumes {:.6e} m{} against {:.6e} m{} of the exact "
                 "shapes ({:+.3f}%)",
                 B.num(), vol, m.dimension, exact, m.dimension, 100.0 * (vol - exact) / exact);
    }
    m.bonds = model::build_bonds(m.nodes, B, partial_cutoff);

    // Rigid analytic walls.
    std::int32_t max_group = *std::max_element(B.group.begin(), B.group.end());
    if (root.contains("walls")) {
        if (!root["walls"].is_array())
            throw ConfigError("walls", "expected a list of walls");
        for (std::size_t k = 0; k < root["walls"].size(); ++k) {
            const json& wj = root["walls"][k];
            const std::string w = fmt::format("walls[{}]", k);
            check_keys(wj, w,
                       {"name", "type", "point", "normal", "center", "radius", "velocity",
                        "angular_velocity", "rotation_center", "group", "time_function",
                        "time_parameters", "start_time"});
            model::Wall wall;
            wall.name = text(wj, w, "name", fmt::format("wall_{}", k));
            const auto type =
                text(wj, w, "type", "plane", {"plane", "circle_inside", "circle_outside"});
            wall.shape = type == "plane"           ? model::WallShape::plane
                         : type == "circle_inside" ? model::WallShape::circle_inside
                                                   : model::WallShape::circle_outside;
            if (wall.shape == model::WallShape::plane) {
                wall.point = vec(wj, w, "point", m.dimension, {0, 0, 0}, true);
                wall.normal = vec(wj, w, "normal", m.dimension, {0, 0, 0}, true);
                const double nn = std::hypot(wall.normal[0], wall.normal[1], wall.normal[2]);
                if (!(nn > 0))
                    throw ConfigError(w + ".normal", "must be a non-zero vector");
                for (double& c : wall.normal)
                    c /= nn;
            } else {
                wall.point = vec(wj, w, "center", m.dimension, {0, 0, 0}, true);
                wall.radius = positive(wj, w, "radius", 0, true);
            }
            wall.velocity = vec(wj, w, "velocity", m.dimension, {0, 0, 0});
            if (wj.contains("angular_velocity")) {
                if (m.dimension == 2)
                    wall.angular_velocity = {0, 0, number(wj, w, "angular_velocity", 0)};
                else
                    wall.angular_velocity = vec(wj, w, "angular_velocity", 3, {0, 0, 0});
            }
            wall.centre = vec(wj, w, "rotation_center", m.dimension, wall.point);
            // Motion in time: displacement velocity T(t), angle angular_velocity T(t).
            const auto tf =
                text(wj, w, "time_function", "linear",
                     {"linear", "quadratic", "sine", "linear_step", "linear_slow_fast"});
            wall.motion = tf == "linear"        ? model::TimeFn::linear
                          : tf == "quadratic"   ? model::TimeFn::quadratic
                          : tf == "sine"        ? model::TimeFn::sine
                          : tf == "linear_step" ? model::TimeFn::linear_step
                                                : model::TimeFn::linear_slow_fast;
            if (wj.contains("time_parameters")) {
                const auto& tp = wj["time_parameters"];
                if (!tp.is_array() || tp.empty() || tp.size() > 3)
                    throw ConfigError(w + ".time_parameters", "expected [p1, p2, p3]");
                for (std::size_t q = 0; q < tp.size(); ++q)
                    wall.motion_params[q + 1] = tp[q].get<double>();
            }
            // Two-stage runs: the wall enters at start_time (absent before), then moves.
            wall.start_time = number(wj, w, "start_time", 0.0);
            if (!(wall.start_time >= 0) || !std::isfinite(wall.start_time))
                throw ConfigError(w + ".start_time", "must be a finite time >= 0 (s)");
            wall.group = static_cast<std::int32_t>(number(wj, w, "group", -1));
            m.walls.push_back(wall);
        }
        // Walls without a group share one group after the particles'.
        for (auto& wall : m.walls)
            if (wall.group < 0)
                wall.group = max_group + 1;
        // Every node must start on the free side of every wall present at t = 0 (a wall with a
        // start_time enters later, where pd-solve's rigid-wall guard checks the grains).
        for (std::size_t k = 0; k < m.walls.size(); ++k) {
            const auto& wall = m.walls[k];
            if (wall.start_time > 0)
                continue;
            for (std::size_t i = 0; i < m.nodes.num(); ++i) {
                const double d = wall_distance(wall, &m.nodes.x0[3 * i]);
                if (d < 0)
                    throw ConfigError(
                        fmt::format("{}, walls[{}]",
                                    inst[static_cast<std::size_t>(m.nodes.body[i])].where, k),
                        fmt::format("the grain crosses the wall (a node lies {:.4g} m behind it)",
                                    -d));
            }
        }
    }

    // Contact table: a default law for every pair of groups (particles and walls), overridden
    // per pair of groups under "pairs".
    const json empty = json::object();
    const json& c = root.contains("contact") ? root["contact"] : empty;
    const std::vector<std::string> law_keys = {
        "radius_factor", "radius",  "radius_mesh_factor", "stiffness", "stiffness_factor",
        "restitution",   "friction"};
    auto with = [](std::vector<std::string> v, std::initializer_list<std::string> more) {
        v.insert(v.end(), more);
        return v;
    };
    check_keys(c, "contact", with(law_keys, {"pairs"}));
    double hmin = *std::min_element(B.mesh_size.begin(), B.mesh_size.end());
    std::set<std::int32_t> groups(B.group.begin(), B.group.end());
    for (const auto& wall : m.walls)
        groups.insert(wall.group);
    auto group_modulus = [&](std::int32_t g) {
        double k = 0;
        for (std::size_t b = 0; b < B.num(); ++b)
            if (B.group[b] == g)
                k = std::max(k,
                             m.materials[static_cast<std::size_t>(B.material[b])].bulk_modulus());
        return k; // 0 for a group of rigid walls only
    };
    double delta_max = *std::max_element(B.horizon.begin(), B.horizon.end());
    auto make_law = [&](const json& o, const std::string& w, std::int32_t ga, std::int32_t gb,
                        const model::ContactPair* base) {
        model::ContactPair p = base ? *base : model::ContactPair{};
        p.group_a = ga;
        p.group_b = gb;
        const int radius_keys = int(o.contains("radius")) + int(o.contains("radius_factor")) +
                                int(o.contains("radius_mesh_factor"));
        if (radius_keys > 1)
            throw ConfigError(w, "give at most one of radius (m), radius_factor (multiple of the "
                                 "smallest node spacing) or radius_mesh_factor (multiple of "
                                 "mesh_size)");
        // The node spacing of the stiffness rule below: the smallest node spacing of the scene
        // (PeriDEM), or with radius_mesh_factor (here or inherited from the default law) the
        // pair's nominal mesh size, so that Kn R_c^(d+1) keeps the contact layer's pressure per
        // overlap tied to the same h as R_c.
        const bool mesh_radius = o.contains("radius_mesh_factor") ||
                                 (base && c.contains("radius_mesh_factor") &&
                                  !o.contains("radius") && !o.contains("radius_factor"));
        double h_pair = 0;
        for (std::size_t b = 0; b < B.num(); ++b)
            if (B.group[b] == ga || B.group[b] == gb)
                h_pair = std::max(h_pair, h_nominal_of[b]);
        if (!(h_pair > 0))
            h_pair = h_ref;
        const double h_law = mesh_radius ? h_pair : hmin;
        if (o.contains("radius"))
            p.radius = positive(o, w, "radius", 0);
        else if (o.contains("radius_mesh_factor")) {
            // R_c = factor x the coarser nominal mesh size of the two groups (the shapes'
            // mesh_size, else the scene's; a rigid wall's group takes the grains'): at R_c >= 3
            // h a node always has several partner nodes in reach, so it cannot slip through the
            // gap between two nodes of the other grain (R_c = 0.95 h_min lets a sharp tip or a
            // hard press push a node through; README "Contact"), and R_c -> 0 with h.
            p.radius = positive(o, w, "radius_mesh_factor", 0) * h_pair;
        } else if (o.contains("radius_factor") || !base)
            p.radius = positive(o, w, "radius_factor", 0.95) * hmin;
        if (o.contains("restitution") || !base) {
            p.restitution = number(o, w, "restitution", 1.0);
            if (!(p.restitution > 0 && p.restitution <= 1))
                throw ConfigError(w + ".restitution", "must be in (0, 1]");
        }
        if (o.contains("friction") || !base) {
            p.friction = number(o, w, "friction", 0.0);
            if (p.friction < 0)
                throw ConfigError(w + ".friction", "must be >= 0");
        }
        if (o.contains("stiffness") && !o["stiffness"].is_string()) {
            p.stiffness = number(o, w, "stiffness", 0); // 0: this pair does not interact
            if (p.stiffness < 0)
                throw ConfigError(w + ".stiffness", "must be >= 0 (0 = no contact), or \"auto\"");
        } else if (o.contains("stiffness") || o.contains("stiffness_factor") || !base) {
            text(o, w, "stiffness", "auto", {"auto"});
            // Kn = 18 kappa / (pi delta^(d+2)) (0.95 h_min / R_c)^(d+1): kappa the harmonic
            // mean of the two groups' bulk moduli (a rigid wall counts as the grain's own
            // modulus), delta the largest horizon. Dimensionally consistent in 2D and 3D (spec
            // decision 7). The last factor (1 at PeriDEM's R_c = 0.95 h) keeps the contact
            // layer's pressure per overlap, Kn times the integral of (R_c - r) over the partner's
            // nodes within R_c ~ Kn R_c^(d+1), when R_c grows: with R_c = 3 h the node-scale
            // roughness is gone and restitution and head-on impacts converge (measured in
            // tests/unit/solver/test_restitution.cpp).
            double ka = group_modulus(ga), kb = group_modulus(gb);
            if (ka == 0)
                ka = kb;
            if (kb == 0)
                kb = ka;
            const double kappa = ka > 0 ? 2 * ka * kb / (ka + kb) : 0;
            p.stiffness = 18.0 * kappa / (std::numbers::pi * std::pow(delta_max, m.dimension + 2)) *
                          std::pow(0.95 * h_law / p.radius, m.dimension + 1) *
                          number(o, w, "stiffness_factor", 1.0);
        }
        return p;
    };
    for (auto ga : groups)
        for (auto gb : groups)
            if (gb >= ga)
                m.contact.push_back(make_law(c, "contact", ga, gb, nullptr));
    if (c.contains("pairs")) {
        if (!c["pairs"].is_array())
            throw ConfigError("contact.pairs", "expected a list");
        for (std::size_t k = 0; k < c["pairs"].size(); ++k) {
            const json& pj = c["pairs"][k];
            const std::string w = fmt::format("contact.pairs[{}]", k);
            check_keys(pj, w, with(law_keys, {"groups"}));
            if (!pj.contains("groups") || !pj["groups"].is_array() || pj["groups"].size() != 2)
                throw ConfigError(w + ".groups", "expected two group numbers");
            const auto ga = pj["groups"][0].get<std::int32_t>(),
                       gb = pj["groups"][1].get<std::int32_t>();
            bool found = false;
            for (auto& p : m.contact)
                if ((p.group_a == ga && p.group_b == gb) || (p.group_a == gb && p.group_b == ga)) {
                    p = make_law(pj, w, p.group_a, p.group_b, &p);
                    found = true;
                }
            if (!found)
                throw ConfigError(w + ".groups",
                                  fmt::format("no particle or wall is in group {} or {}", ga, gb));
        }
    }

    report_horizons(m, log);

    // Grains that start within the contact radius of a wall are pushed off at t = 0.
    for (std::size_t k = 0; k < m.walls.size(); ++k) {
        const auto& wall = m.walls[k];
        if (wall.start_time > 0)
            continue; // enters later
        std::size_t close = 0;
        double rc = 0;
        for (const auto& p : m.contact)
            if (p.group_a == wall.group || p.group_b == wall.group)
                rc = std::max(rc, p.radius);
        for (std::size_t i = 0; i < m.nodes.num(); ++i)
            close += wall_distance(wall, &m.nodes.x0[3 * i]) < rc;
        if (close > 0)
            log.warn("walls[{}]: {} nodes start within the contact radius {:.3g} m of the wall "
                     "(they are pushed off at t = 0)",
                     k, close, rc);
    }

    // Surface-layer nodes: within R_c + h/2 + min(R_c, h) of their grain's boundary (R_c the
    // largest contact radius; 2 R_c + h/2 when R_c <= h). A node of another grain within
    // min(R_c, h) of a node below the layer is more than R_c + h/2 inside: pd-solve's
    // interpenetration guard (solver/contact.hpp Penetration). The layer is no thicker than
    // R_c + 1.5 h, so grains of a few R_c (R_c = 3 mesh_size) still have nodes below it.
    // Also the partitioner's weight. The contact search takes every node of grains near each
    // other, whatever its depth.
    {
        double rc_max = 0;
        for (const auto& p : m.contact)
            rc_max = std::max(rc_max, p.radius);
        m.nodes.surface.resize(m.nodes.num());
        for (std::size_t b = 0; b < B.num(); ++b) {
            const auto& bd = refs.at(inst[b].shape).bdist;
            for (auto i = B.begin(b); i < B.end(b); ++i) {
                const auto k = static_cast<std::size_t>(i - B.begin(b));
                const double h = B.mesh_size[b];
                m.nodes.surface[static_cast<std::size_t>(i)] =
                    bd[k] * B.scale[b] <= rc_max + 0.5 * h + std::min(rc_max, h) ? 1 : 0;
            }
        }
    }

    // Notch slots: nodes inside are removed and bonds through them never exist (before the
    // loading, whose regions select nodes by index).
    if (root.contains("slots")) {
        if (!root["slots"].is_array())
            throw ConfigError("slots",
                              "expected a list of {\"from\": [..], \"to\": [..], \"width\": w}");
        std::vector<model::Slot> slots;
        for (std::size_t k = 0; k < root["slots"].size(); ++k) {
            const json& sj = root["slots"][k];
            const std::string w = fmt::format("slots[{}]", k);
            check_keys(sj, w, {"from", "to", "width"});
            slots.push_back({vec(sj, w, "from", m.dimension, {0, 0, 0}, true),
                             vec(sj, w, "to", m.dimension, {0, 0, 0}, true),
                             number(sj, w, "width", 0, true)});
        }
        const auto cut = model::apply_slots(m, slots);
        // The notch faces are boundary: nodes near a slot join the surface layer (as above).
        double rc_max = 0;
        for (const auto& p : m.contact)
            rc_max = std::max(rc_max, p.radius);
        for (std::size_t i = 0; i < m.nodes.num(); ++i) {
            const double layer =
                2 * rc_max + 0.5 * B.mesh_size[static_cast<std::size_t>(m.nodes.body[i])];
            for (const auto& sl : slots)
                if (model::slot_distance(sl, &m.nodes.x0[3 * i]) <= layer)
                    m.nodes.surface[i] = 1;
        }
        for (std::size_t k = 0; k < slots.size(); ++k)
            log.info("slots[{}]: {} nodes inside removed, {} bonds through it never exist", k,
                     cut.nodes_per_slot[k], cut.bonds_per_slot[k]);
    }

    // Loading.
    const json& ld = root.contains("loading") ? root["loading"] : empty;
    check_keys(ld, "loading", {"gravity", "viscous_damping", "conditions"});
    m.loading.gravity = vec(ld, "loading", "gravity", m.dimension, {0, 0, 0});
    m.loading.viscous_damping = number(ld, "loading", "viscous_damping", 0);
    if (m.loading.viscous_damping < 0)
        throw ConfigError("loading.viscous_damping", "must be >= 0");
    if (ld.contains("conditions")) {
        if (!ld["conditions"].is_array())
            throw ConfigError("loading.conditions", "expected a list");
        for (std::size_t k = 0; k < ld["conditions"].size(); ++k) {
            const json& cj = ld["conditions"][k];
            const std::string w = fmt::format("loading.conditions[{}]", k);
            check_keys(cj, w,
                       {"name", "kind", "particles", "region", "components", "value",
                        "time_function", "time_parameter", "space_function", "space_parameter",
                        "rotation_center", "time_parameters"});
            model::NodeCondition c;
            c.name = text(cj, w, "name", fmt::format("condition_{}", k));
            c.is_force =
                text(cj, w, "kind", "", {"displacement", "force_density"}) == "force_density";
            if (!cj.contains("kind"))
                throw ConfigError(w + ".kind", "missing: displacement or force_density");
            c.amplitude = number(cj, w, "value", 0, true);
            const auto tf = text(cj, w, "time_function", "constant",
                                 {"constant", "linear", "quadratic", "sine", "rotation",
                                  "linear_step", "linear_slow_fast"});
            c.time_fn = tf == "constant"      ? model::TimeFn::constant
                        : tf == "linear"      ? model::TimeFn::linear
                        : tf == "quadratic"   ? model::TimeFn::quadratic
                        : tf == "sine"        ? model::TimeFn::sine
                        : tf == "rotation"    ? model::TimeFn::rotation
                        : tf == "linear_step" ? model::TimeFn::linear_step
                                              : model::TimeFn::linear_slow_fast;
            if ((c.time_fn == model::TimeFn::linear_step ||
                 c.time_fn == model::TimeFn::linear_slow_fast) &&
                !c.is_force)
                throw ConfigError(w + ".time_function",
                                  tf + " applies to force_density (spec 5.7)");
            if (c.time_fn == model::TimeFn::rotation) {
                // value = angular velocity (rad/s) about rotation_center, in the xy plane.
                if (c.is_force)
                    throw ConfigError(w + ".time_function", "rotation applies to displacements");
                c.centre = vec(cj, w, "rotation_center", m.dimension, {0, 0, 0}, true);
            } else if (cj.contains("rotation_center")) {
                throw ConfigError(w + ".rotation_center", "only with time_function rotation");
            }
            const auto sf = text(cj, w, "space_function", "constant",
                                 {"constant", "linear_x", "linear_y", "sine_x", "hat_x", "hat_y"});
            c.space_fn = sf == "constant"   ? model::SpaceFn::constant
                         : sf == "linear_x" ? model::SpaceFn::linear_x
                         : sf == "linear_y" ? model::SpaceFn::linear_y
                         : sf == "sine_x"   ? model::SpaceFn::sine_x
                         : sf == "hat_x"    ? model::SpaceFn::hat_x
                                            : model::SpaceFn::hat_y;
            c.params = {number(cj, w, "space_parameter", 1.0), number(cj, w, "time_parameter", 0.0),
                        0.0, 0.0};
            if (cj.contains("time_parameters")) {
                const auto& tp = cj["time_parameters"];
                if (!tp.is_array() || tp.empty() || tp.size() > 3 || cj.contains("time_parameter"))
                    throw ConfigError(w + ".time_parameters",
                                      "expected [p1, p2, p3] (instead of time_parameter)");
                for (std::size_t q = 0; q < tp.size(); ++q)
                    c.params[q + 1] = tp[q].get<double>();
            }
            if (!cj.contains("components") || !cj["components"].is_array() ||
                cj["components"].empty())
                throw ConfigError(w + ".components", "missing: a list of \"x\", \"y\", \"z\"");
            for (const auto& comp : cj["components"]) {
                const std::string cs = comp.is_string() ? comp.get<std::string>() : "";
                if (cs == "x")
                    c.dofs |= 1;
                else if (cs == "y")
                    c.dofs |= 2;
                else if (cs == "z" && m.dimension == 3)
                    c.dofs |= 4;
                else
                    throw ConfigError(w + ".components",
                                      "entries must be \"x\", \"y\"" +
                                          std::string(m.dimension == 3 ? " or \"z\"" : ""));
            }
            std::vector<std::uint8_t> take_body(B.num(), 1);
            if (cj.contains("particles")) {
                if (!cj["particles"].is_array())
                    throw ConfigError(w + ".particles", "expected a list of particle indices");
                std::fill(take_body.begin(), take_body.end(), 0);
                for (const auto& id : cj["particles"]) {
                    if (!id.is_number_integer() || id.get<long>() < 0 ||
                        static_cast<std::size_t>(id.get<long>()) >= B.num())
                        throw ConfigError(w + ".particles",
                                          fmt::format("{} is not a particle index in [0, {})",
                                                      id.dump(), B.num()));
                    take_body[id.get<std::size_t>()] = 1;
                }
            }
            std::array<double, 3> lo{-1e300, -1e300, -1e300}, hi{1e300, 1e300, 1e300};
            if (cj.contains("region")) {
                const json& r = cj["region"];
                check_keys(r, w + ".region", {"min", "max"});
                lo = vec(r, w + ".region", "min", m.dimension, {0, 0, 0}, true);
                hi = vec(r, w + ".region", "max", m.dimension, {0, 0, 0}, true);
                if (m.dimension == 2) {
                    lo[2] = -1e300;
                    hi[2] = 1e300;
                }
            }
            if (!cj.contains("particles") && !cj.contains("region"))
                throw ConfigError(w, "select nodes with \"particles\" and/or \"region\"");
            for (std::size_t i = 0; i < m.nodes.num(); ++i) {
                if (!take_body[static_cast<std::size_t>(m.nodes.body[i])])
                    continue;
                bool in = true;
                for (std::size_t d = 0; d < 3; ++d)
                    in = in && m.nodes.x0[3 * i + d] >= lo[d] && m.nodes.x0[3 * i + d] <= hi[d];
                if (in)
                    c.nodes.push_back(static_cast<model::index_t>(i));
            }
            if (c.nodes.empty())
                throw ConfigError(w, "selects no node (check region and particles)");
            m.loading.conditions.push_back(std::move(c));
        }
    }

    // Pre-cracks: bonds crossing a segment start broken.
    if (root.contains("cracks")) {
        if (!root["cracks"].is_array())
            throw ConfigError("cracks", "expected a list of {\"from\": [..], \"to\": [..]}");
        for (std::size_t k = 0; k < root["cracks"].size(); ++k) {
            const json& cj = root["cracks"][k];
            const std::string w = fmt::format("cracks[{}]", k);
            check_keys(cj, w, {"from", "to"});
            m.cracks.push_back({vec(cj, w, "from", m.dimension, {0, 0, 0}, true),
                                vec(cj, w, "to", m.dimension, {0, 0, 0}, true)});
        }
    }

    // Solver settings.
    if (!root.contains("solver"))
        throw ConfigError("solver", "missing: give at least final_time");
    const json& sv = root["solver"];
    check_keys(sv, "solver",
               {"final_time", "dt", "dt_safety", "output_interval", "observe_every", "integrator",
                "contact_skin", "checkpoint_interval", "surface_correction",
                "quadrature_calibration", "fields"});
    auto& S = m.solver;
    S.final_time = positive(sv, "solver", "final_time", 0, true);
    if (sv.contains("dt") && sv["dt"].is_string())
        text(sv, "solver", "dt", "auto", {"auto"});
    else
        S.dt = sv.contains("dt") ? positive(sv, "solver", "dt", 0) : 0.0;
    S.dt_safety = positive(sv, "solver", "dt_safety", 0.7);
    if (S.dt_safety > 1)
        throw ConfigError("solver.dt_safety", "must be in (0, 1]");
    S.output_interval = number(sv, "solver", "output_interval", 0);
    if (S.output_interval < 0)
        throw ConfigError("solver.output_interval", "must be >= 0");
    // Observables every 10 steps unless asked (1 = every step): a row costs a pass over the
    // nodes, reductions and an HDF5 append, as much as the bond loop of a small grain.
    S.observe_every = static_cast<std::int64_t>(positive(sv, "solver", "observe_every", 10));
    S.checkpoint_interval = number(sv, "solver", "checkpoint_interval", 0);
    S.surface_correction = boolean(sv, "solver", "surface_correction", false);
    S.quadrature_calibration = boolean(sv, "solver", "quadrature_calibration", true);
    if (sv.contains("fields")) {
        if (!sv["fields"].is_array())
            throw ConfigError("solver.fields", "expected a list of frame fields");
        S.fields.clear();
        for (const auto& x : sv["fields"]) {
            const std::string n = x.is_string() ? x.get<std::string>() : "";
            if (n != "velocity" && n != "displacement" && n != "force" && n != "damage" &&
                n != "damage_z" && n != "fragment" && n != "broken_bonds")
                throw ConfigError(
                    "solver.fields",
                    "'" + x.dump() +
                        "' is not one of velocity, "
                        "displacement, force, damage, damage_z, fragment, broken_bonds "
                        "(position is always written)");
            S.fields.push_back(n);
        }
    }
    if (S.checkpoint_interval < 0)
        throw ConfigError("solver.checkpoint_interval", "must be >= 0 (0 = at the end only)");
    S.integrator = text(sv, "solver", "integrator", "velocity_verlet",
                        {"velocity_verlet", "symplectic_euler"}) == "velocity_verlet"
                       ? model::Integrator::velocity_verlet
                       : model::Integrator::symplectic_euler;
    S.contact_skin = number(sv, "solver", "contact_skin", 0);
    if (S.contact_skin < 0)
        throw ConfigError("solver.contact_skin", "must be >= 0 (0 = automatic)");
    m.check_consistency();
    return m;
}

} // namespace

} // namespace pd::pipeline
