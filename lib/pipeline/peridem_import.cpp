// SPDX-License-Identifier: MIT
#include "pipeline/peridem_import.hpp"

#include "core/errors.hpp"
#include "geometry/shapes.hpp"
#include "mesh/discretize.hpp"
#include "mesh/shape_mesher.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <yaml-cpp/yaml.h>

namespace pd::pipeline {

namespace {

using json = nlohmann::ordered_json;
namespace fs = std::filesystem;
constexpr double pi = std::numbers::pi;

std::string dot(const std::string& a, const std::string& b) {
    return a.empty() ? b : a + "." + b;
}

/// The deck, with the key path of every value for messages.
struct Deck {
    YAML::Node root;
    std::string path;
    fs::path dir;
};

/// n[key], or an undefined node (false in a test) if n is not a map or has no such non-null key.
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

/// A file named in the deck: as written (relative to the deck's folder), else the bare file name
/// next to the deck (the shipped decks name the paths of their original run scripts).
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

/// One zone's reference geometry as a scene shape (JSON) and the same shape for checks.
struct ZoneShape {
    json spec;
    geometry::Shape shape = geometry::Shape::circle(1); // replaced before use
    double p0 = 0; ///< Parameters[0]: the length a CSV radius scales (spec 2.5)
};

/// Box [lo, hi] of a PeriDEM rectangle with 6 (corners), 5 (Lx, Ly, centre) or 2 (Lx, Ly)
/// parameters.
std::optional<std::array<double, 4>> rectangle_box(const std::vector<double>& p) {
    if (p.size() == 6)
        return std::array<double, 4>{std::min(p[0], p[3]), std::min(p[1], p[4]),
                                     std::max(p[0], p[3]), std::max(p[1], p[4])};
    if (p.size() == 5)
        return std::array<double, 4>{p[2] - p[0] / 2, p[3] - p[1] / 2, p[2] + p[0] / 2,
                                     p[3] + p[1] / 2};
    if (p.size() == 2)
        return std::array<double, 4>{-p[0] / 2, -p[1] / 2, p[0] / 2, p[1] / 2};
    return std::nullopt;
}

json corners(const std::array<double, 4>& b) {
    return json{{"type", "rectangle"}, {"corners", {{b[0], b[1]}, {b[2], b[3]}}}};
}

/// PeriDEM geometry (Type, Parameters) -> shape, with Parameters[0] replaced by `r` if r > 0.
std::optional<ZoneShape> deck_shape(const std::string& type, std::vector<double> p,
                                    const std::string& key, double r = 0) {
    if (p.empty())
        return std::nullopt;
    if (r > 0) {
        const double f = r / p[0];
        p[0] = r;
        if (type == "drum2d" || type == "ellipse")
            p[1] *= f;
    }
    const double R = p[0];
    auto offset = [&](ZoneShape z, std::size_t at) {
        if (p.size() > at + 1 && (p[at] != 0 || p[at + 1] != 0)) {
            z.spec["offset"] = {p[at], p[at + 1]};
            z.shape = z.shape.translated(p[at], p[at + 1]);
        }
        return z;
    };
    try {
        if (type == "circle")
            return offset({json{{"type", "circle"}, {"radius", R}}, geometry::Shape::circle(R), R},
                          1);
        if (type == "hexagon")
            return offset(
                {json{{"type", "hexagon"}, {"radius", R}}, geometry::Shape::hexagon(R), R}, 1);
        if (type == "triangle")
            return offset(
                {json{{"type", "triangle"}, {"radius", R}}, geometry::Shape::triangle(R), R}, 1);
        if (type == "square")
            return offset({json{{"type", "square"}, {"radius", R}}, geometry::Shape::square(R), R},
                          1);
        if (type == "sphere")
            return offset({json{{"type", "sphere"}, {"radius", R}}, geometry::Shape::sphere(R), R},
                          1);
        if (type == "drum2d" && p.size() >= 2)
            return offset({json{{"type", "drum2d"}, {"radius", R}, {"neck_width", p[1]}},
                           geometry::Shape::drum2d(R, p[1]), R},
                          2);
        if (type == "ellipse" && p.size() >= 2)
            return offset({json{{"type", "ellipse"}, {"semi_axes", {p[0], p[1]}}},
                           geometry::Shape::ellipse(p[0], p[1]), R},
                          2);
        if (type == "rectangle") {
            auto b = rectangle_box(p);
            if (!b)
                return std::nullopt;
            return ZoneShape{corners(*b),
                             geometry::Shape::rectangle_corners((*b)[0], (*b)[1], (*b)[2], (*b)[3]),
                             R};
        }
        if (type == "rectangle_minus_rectangle" && p.size() == 12) {
            std::vector<double> o(p.begin(), p.begin() + 6), i(p.begin() + 6, p.end());
            auto bo = *rectangle_box(o), bi = *rectangle_box(i);
            return ZoneShape{
                json{{"type", "difference"}, {"base", corners(bo)}, {"minus", {corners(bi)}}},
                geometry::Shape::difference(
                    geometry::Shape::rectangle_corners(bo[0], bo[1], bo[2], bo[3]),
                    {geometry::Shape::rectangle_corners(bi[0], bi[1], bi[2], bi[3])}),
                R};
        }
    } catch (const InputError& e) {
        throw ConfigError(key, e.what());
    }
    return std::nullopt;
}

/// The boundary of a 2D mesh as a polygon (holes subtracted), collinear vertices removed.
std::optional<ZoneShape> mesh_outline(const model::RefMesh& m) {
    const int npc = m.nodes_per_cell;
    std::map<std::pair<int, int>, int> count;
    std::vector<std::pair<int, int>> directed;
    const std::size_t nc = m.cells.size() / static_cast<std::size_t>(npc);
    auto X = [&](int i) { return std::array<double, 2>{m.nodes[3 * i], m.nodes[3 * i + 1]}; };
    for (std::size_t c = 0; c < nc; ++c) {
        const int* v = &m.cells[c * static_cast<std::size_t>(npc)];
        // Orient every cell counter-clockwise so boundary edges chain consistently.
        double a2 = 0;
        for (int k = 0; k < npc; ++k) {
            auto p = X(v[k]), q = X(v[(k + 1) % npc]);
            a2 += p[0] * q[1] - q[0] * p[1];
        }
        for (int k = 0; k < npc; ++k) {
            int a = v[k], b = v[(k + 1) % npc];
            if (a2 < 0)
                std::swap(a, b);
            ++count[{std::min(a, b), std::max(a, b)}];
            directed.emplace_back(a, b);
        }
    }
    std::map<int, int> next;
    for (auto [a, b] : directed)
        if (count[{std::min(a, b), std::max(a, b)}] == 1) {
            if (next.count(a))
                return std::nullopt; // non-manifold boundary
            next[a] = b;
        }
    std::vector<std::vector<geometry::Vec2>> loops;
    std::vector<double> areas;
    std::set<int> seen;
    for (auto [start, unused] : next) {
        if (seen.count(start))
            continue;
        std::vector<int> loop;
        int v = start;
        while (!seen.count(v)) {
            seen.insert(v);
            loop.push_back(v);
            if (!next.count(v))
                return std::nullopt;
            v = next[v];
        }
        // Drop collinear vertices.
        std::vector<geometry::Vec2> poly;
        const std::size_t n = loop.size();
        for (std::size_t k = 0; k < n; ++k) {
            auto a = X(loop[(k + n - 1) % n]), b = X(loop[k]), c = X(loop[(k + 1) % n]);
            const double cr = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
            const double l =
                std::hypot(b[0] - a[0], b[1] - a[1]) * std::hypot(c[0] - b[0], c[1] - b[1]);
            if (std::abs(cr) > 1e-9 * l)
                poly.push_back({b[0], b[1]});
        }
        if (poly.size() < 3)
            continue;
        double a2 = 0;
        for (std::size_t k = 0; k < poly.size(); ++k) {
            const auto& p = poly[k];
            const auto& q = poly[(k + 1) % poly.size()];
            a2 += p[0] * q[1] - q[0] * p[1];
        }
        loops.push_back(std::move(poly));
        areas.push_back(std::abs(a2) / 2);
    }
    if (loops.empty())
        return std::nullopt;
    const auto outer =
        static_cast<std::size_t>(std::max_element(areas.begin(), areas.end()) - areas.begin());
    auto polygon = [](const std::vector<geometry::Vec2>& v) {
        json j{{"type", "polygon"}, {"vertices", json::array()}};
        for (const auto& p : v)
            j["vertices"].push_back({p[0], p[1]});
        return j;
    };
    ZoneShape z{polygon(loops[outer]), geometry::Shape::polygon(loops[outer]), 0};
    std::vector<geometry::Shape> holes;
    json minus = json::array();
    for (std::size_t k = 0; k < loops.size(); ++k)
        if (k != outer) {
            holes.push_back(geometry::Shape::polygon(loops[k]));
            minus.push_back(polygon(loops[k]));
        }
    if (!holes.empty()) {
        z.shape = geometry::Shape::difference(z.shape, holes);
        z.spec = json{{"type", "difference"}, {"base", z.spec}, {"minus", minus}};
    }
    return z;
}

/// Does the shape describe the mesh: every node inside (to 1e-6 R) and the mesh area within 3%?
bool fits(const geometry::Shape& s, const model::RefMesh& m, int dim) {
    const double tol = 1e-6 * s.bounding_radius();
    for (std::size_t i = 0; i < m.nodes.size() / 3; ++i)
        if (s.clearance(m.nodes[3 * i], m.nodes[3 * i + 1], m.nodes[3 * i + 2]) < -tol)
            return false;
    double v = 0;
    for (double x : mesh::nodal_volumes(m, dim))
        v += x;
    return std::abs(v / s.area_or_volume() - 1) < 0.03;
}

/// Zone_<i><j> (1-based, concatenated) -> (i, j) with i <= j, both in [1, n].
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

struct Zone {
    int k = 0; ///< 1-based
    bool wall = false, constrained = false, from_geom = false;
    std::string type;
    std::vector<double> params;
    std::vector<std::size_t> particles; ///< global ids
};

struct Particle {
    int zone = 0;
    std::array<double, 3> x{0, 0, 0};
    double r = 0, o = 0;
    bool scaled = true; ///< false: identity transform (wall or single particle)
    std::array<double, 3> v{0, 0, 0};
    bool fixed = false;
};

} // namespace

std::string peridem_to_scene(const std::string& yaml_path, const Log& log, bool parity) {
    Deck d;
    d.path = yaml_path;
    d.dir = fs::absolute(fs::path(yaml_path)).parent_path();
    try {
        d.root = YAML::LoadFile(yaml_path);
    } catch (const YAML::BadFile&) {
        throw InputError(fmt::format("{}: cannot read the PeriDEM deck", yaml_path));
    } catch (const YAML::Exception& e) {
        throw InputError(fmt::format("{}: not a valid YAML deck: {}", yaml_path, e.what()));
    }
    const YAML::Node& R = d.root;
    if (!R.IsMap())
        throw InputError(
            fmt::format("{}: not a PeriDEM deck (expected blocks Model, Zone, ...)", yaml_path));
    static const std::set<std::string> known = {
        "Model", "Container", "Zone",    "Particle", "Wall",     "Particle_Generation",
        "Mesh",  "Material",  "Contact", "Neighbor", "Force_BC", "Displacement_BC",
        "IC",    "Output",    "Restart", "Policy",   "HPX"};
    for (auto it = R.begin(); it != R.end(); ++it) {
        const auto k = it->first.as<std::string>();
        if (!known.count(k))
            log.warn("{}: deck block '{}' is not a PeriDEM 0.2 block: ignored", yaml_path, k);
    }
    for (const char* ignored : {"Policy", "HPX", "Neighbor"})
        if (R[ignored])
            log.info("deck block '{}' ignored (pdgrain chooses its own contact search and "
                     "threads)",
                     ignored);
    if (R["Restart"])
        throw ConfigError("Restart", "a PeriDEM restart (VTU state) cannot be imported; import "
                                     "the deck without it and use pd-solve --restart");

    // ---- Model
    const YAML::Node model = R["Model"];
    if (!model)
        throw ConfigError("Model", "missing (required)");
    const int dim = static_cast<int>(num_or(model, "Model", "Dimension", 0));
    if (dim != 2 && dim != 3)
        throw ConfigError("Model.Dimension", "expected 2 or 3 (required)");
    const double final_time = num_or(model, "Model", "Final_Time", 0);
    const double steps = num_or(model, "Model", "Time_Steps", 0);
    if (!(final_time > 0))
        throw ConfigError("Model.Final_Time", "must be > 0 (required)");
    if (!(steps >= 1))
        throw ConfigError("Model.Time_Steps", "must be >= 1 (required)");
    const double dt = final_time / steps;
    const YAML::Node disc = child(model, "Discretization_Type");
    const auto time_scheme =
        str_or(disc, "Model.Discretization_Type", "Time", "central_difference");
    if (time_scheme != "central_difference" && time_scheme != "velocity_verlet")
        throw ConfigError("Model.Discretization_Type.Time",
                          "'" + time_scheme + "': expected central_difference or velocity_verlet");
    const auto spatial = str_or(disc, "Model.Discretization_Type", "Spatial", "finite_difference");
    if (spatial != "finite_difference")
        throw ConfigError("Model.Discretization_Type.Spatial",
                          "'" + spatial + "': only finite_difference is imported");
    const bool single =
        str_or(model, "Model", "Particle_Sim_Type",
               R["Particle"] ? "Multi_Particle" : "Single_Particle") == "Single_Particle";
    const auto seed = static_cast<std::uint32_t>(num_or(model, "Model", "Seed", 1));
    if (steps < 10)
        log.warn("Model.Time_Steps = {} gives dt = {:.4g} s: far above any stable step; set "
                 "solver.dt before solving (pd-solve refuses it)",
                 steps, dt);

    // ---- Zones
    const bool old_format = static_cast<bool>(R["Wall"]);
    int nz = static_cast<int>(num_or(R["Zone"], "Zone", "Zones", 0));
    if (nz <= 0) {
        const YAML::Node mat = R["Material"];
        if (mat && mat.IsMap())
            for (auto it = mat.begin(); it != mat.end(); ++it)
                nz = std::max(nz, std::atoi(it->first.as<std::string>().c_str() + 5));
    }
    if (nz <= 0)
        throw ConfigError("Zone.Zones", "missing: the number of zones");
    if (single && nz != 1)
        throw ConfigError("Zone.Zones", "a Single_Particle deck has one zone");
    std::vector<Zone> zones(static_cast<std::size_t>(nz));
    for (int k = 1; k <= nz; ++k) {
        auto& z = zones[static_cast<std::size_t>(k - 1)];
        z.k = k;
        const std::string zk = fmt::format("Zone_{}", k);
        const YAML::Node zn = child(R["Zone"], zk);
        z.wall = flag_or(zn, "Zone." + zk, "Is_Wall", false);
        const YAML::Node pz = child(R["Particle"], zk);
        const YAML::Node wz = child(R["Wall"], zk);
        if (z.wall && old_format) {
            // Pre-2024 format: the wall's geometry is in Zone, its mesh used as is (spec 8.3).
            z.from_geom = true;
            z.constrained = true;
            z.type = str_or(zn, "Zone." + zk, "Type", "");
            z.params = nums(zn, "Zone." + zk, "Parameters");
            if (wz && !flag_or(wz, "Wall." + zk, "All_Dofs_Constrained", true))
                log.info("Wall.{}.All_Dofs_Constrained = false: pre-2024 walls are never "
                         "integrated, imported as constrained (moved only by its displacement "
                         "conditions)",
                         zk);
        } else {
            const std::string w = "Particle." + zk;
            z.type = str_or(pz, w, "Type", "");
            z.params = nums(pz, w, "Parameters");
            z.constrained = flag_or(pz, w, "All_Dofs_Constrained", false);
            z.from_geom =
                single || flag_or(pz, w, "Create_Particle_Using_ParticleZone_GeomObject", false);
            const YAML::Node rp = child(child(R["Mesh"], zk), "Reference_Particle");
            if (rp) {
                z.type = str_or(rp, "Mesh." + zk + ".Reference_Particle", "Type", z.type);
                auto p = nums(rp, "Mesh." + zk + ".Reference_Particle", "Parameters");
                if (!p.empty())
                    z.params = p;
            }
        }
    }

    // ---- Materials (one per zone; Copy_Material_Data copies an earlier zone's block)
    json materials = json::object();
    std::vector<double> horizon(zones.size(), 0), ratio(zones.size(), 0);
    bool plane_strain = false;
    bool lps_parity = false, lps_noted = false;
    // Is_Plane_Strain of any material (read ahead: the 2D bulk modulus of the note depends on it)
    bool plane_strain_deck = false;
    if (const YAML::Node mats = R["Material"]; mats && mats.IsMap())
        for (auto it = mats.begin(); it != mats.end(); ++it)
            if (it->second.IsMap() && it->second["Is_Plane_Strain"] &&
                it->second["Is_Plane_Strain"].as<std::string>() == "true")
                plane_strain_deck = true;
    std::vector<YAML::Node> mat_nodes(zones.size());
    for (int k = 1; k <= nz; ++k) {
        const std::string w = fmt::format("Material.Zone_{}", k);
        YAML::Node mn = child(R["Material"], fmt::format("Zone_{}", k));
        if (!mn)
            throw ConfigError(w, "missing: every zone needs a material");
        if (auto c = child(mn, "Copy_Material_Data")) {
            const int from = static_cast<int>(num(c, w + ".Copy_Material_Data"));
            if (from < 1 || from >= k)
                throw ConfigError(w + ".Copy_Material_Data",
                                  fmt::format("{} is not an earlier zone", from));
            mn.reset(mat_nodes[static_cast<std::size_t>(from - 1)]);
        }
        mat_nodes[static_cast<std::size_t>(k - 1)].reset(mn);
        const auto type = str_or(mn, w, "Type", "");
        std::string law;
        if (type == "PDState")
            law = "lps";
        else if (type == "PMBBond")
            law = "pmb";
        else if (type == "RNPBond")
            law = "rnp";
        else
            throw ConfigError(w + ".Type", type.empty()
                                               ? "missing (required): PDState, PMBBond or RNPBond"
                                               : "'" + type +
                                                     "' cannot be imported (PDState, "
                                                     "PMBBond or RNPBond)");
        const double rho = num_or(mn, w, "Density", 0);
        if (!(rho > 0))
            throw ConfigError(w + ".Density", "missing or not positive (required)");
        double E = num_or(mn, w, "E", 0), K = num_or(mn, w, "K", 0), G = num_or(mn, w, "G", 0),
               nu = num_or(mn, w, "Poisson_Ratio", std::nan(""));
        if (G == 0)
            G = num_or(mn, w, "Mu", 0);
        const double lambda = num_or(mn, w, "Lambda", 0);
        const bool has_nu = !std::isnan(nu);
        if (E > 0 && has_nu) {
        } else if (K > 0 && G > 0) {
            E = 9 * K * G / (3 * K + G);
            nu = (3 * K - 2 * G) / (2 * (3 * K + G));
        } else if (E > 0 && G > 0) {
            nu = E / (2 * G) - 1;
        } else if (K > 0 && has_nu) {
            E = 3 * K * (1 - 2 * nu);
        } else if (E > 0 && K > 0) {
            nu = (3 * K - E) / (6 * K);
        } else if (G > 0 && has_nu) {
            E = 2 * G * (1 + nu);
        } else if (lambda > 0 && G > 0) {
            E = G * (3 * lambda + 2 * G) / (lambda + G);
            nu = lambda / (2 * (lambda + G));
        } else if (law != "lps" && (E > 0 || K > 0)) {
            nu = 0.25;
            if (!(E > 0))
                E = 3 * K * (1 - 2 * nu);
            log.warn("{}: one elastic constant only, taking nu = 0.25", w);
        } else
            throw ConfigError(w, "give two of E, K, G, Poisson_Ratio (K and G in the examples)");
        if (!(E > 0))
            throw ConfigError(w, fmt::format("the elastic constants give E = {:.4g} Pa (must be "
                                             "positive)",
                                             E));
        double Gc = num_or(mn, w, "Gc", -1);
        if (Gc < 0 && child(mn, "KIc")) {
            const double kic = num_or(mn, w, "KIc", 0);
            Gc = kic * kic / E; // spec 1.2: plane-stress form, no nu
        }
        json m{{"law", law}, {"density", rho}, {"youngs_modulus", E}};
        if (law == "lps" && dim == 2) {
            // PeriDEM 0.2's 2D PDState uses the 3D LPS formulas (theta = 3/m sum, 3K/m, 15G/m,
            // the 3D critical stretch); pdgrain's 2D LPS is the consistent one (theta = 2/m
            // sum, 2 kappa/m, 8 mu/m, the 2D s0). The two agree for mu' = 15 G / 8 and
            // kappa' = 9 K / 4 (the 2D bulk modulus; plane strain: K3' = kappa' - mu' / 3) and
            // a Gc' that keeps PeriDEM's s0.
            const double G3 = E / (2 * (1 + nu)), K3 = E / (3 * (1 - 2 * nu));
            const double mu_p = 15 * G3 / 8, kappa_p = 9 * K3 / 4, K3_p = kappa_p - mu_p / 3;
            if (parity) {
                if (!(K3_p > 0) || !(3 * K3_p - 2 * mu_p < 2 * (3 * K3_p + mu_p)) ||
                    !(3 * K3_p - 2 * mu_p > -2 * (3 * K3_p + mu_p)))
                    throw ConfigError(w, fmt::format("--parity peridem: the equivalent 2D "
                                                     "material (mu' = {:.4g}, kappa' = {:.4g} Pa)"
                                                     " is not a stable isotropic solid",
                                                     mu_p, kappa_p));
                m.erase("youngs_modulus");
                m["bulk_modulus"] = K3_p;
                m["shear_modulus"] = mu_p;
                lps_parity = true;
                if (Gc > 0) {
                    const double d_peridem = 3 * G3 + std::pow(0.75, 4) * (K3 - 5 * G3 / 3);
                    const double d_pdgrain =
                        6 * mu_p / M_PI + 16 / (9 * M_PI * M_PI) * (kappa_p - 2 * mu_p);
                    const double Gc_p = Gc * d_pdgrain / d_peridem;
                    log.info("{}: --parity peridem: PDState in 2D as PeriDEM 0.2 computes it: "
                             "shear modulus {:.4g} -> {:.4g} Pa (15 G / 8), 2D bulk modulus "
                             "{:.4g} Pa (9 K / 4; plane strain K = {:.4g} Pa), Gc {:.4g} -> "
                             "{:.4g} J/m2 (same critical stretch)",
                             w, G3, mu_p, kappa_p, K3_p, Gc, Gc_p);
                    Gc = Gc_p;
                }
            } else {
                m["poisson_ratio"] = nu;
                if (!lps_noted) {
                    const double kappa_2d =
                        plane_strain_deck ? K3 + G3 / 3 : 9 * K3 * G3 / (3 * K3 + 4 * G3);
                    log.info("{}: PDState is imported as pdgrain's consistent 2D LPS with the "
                             "deck's K and G. PeriDEM 0.2 uses the 3D LPS formulas in 2D, so its "
                             "grains are {:.2f}x as stiff in shear and {:.2f}x in bulk as these "
                             "(contacts and wave speeds differ); --parity peridem maps the "
                             "material to PeriDEM's (mu' = 15 G/8, kappa' = 9 K/4, Gc' keeping "
                             "s0)",
                             w, 15.0 / 8.0, 9 * K3 / 4 / kappa_2d);
                    lps_noted = true;
                }
            }
        } else if (law == "lps")
            m["poisson_ratio"] = nu;
        else if (has_nu || (K > 0 && G > 0))
            log.info("{}: law {} fixes its Poisson ratio; the deck's nu = {:.4g} is not used", w,
                     law, nu);
        if (Gc > 0)
            m["fracture_energy"] = Gc;
        else
            log.warn("{}: no Gc or KIc: the material is unbreakable", w);
        const int inf = static_cast<int>(
            num_or(child(mn, "Influence_Function"), w + ".Influence_Function", "Type", 0));
        if (inf < 0 || inf > 2)
            throw ConfigError(
                w + ".Influence_Function.Type",
                fmt::format("{}: expected 0 (constant), 1 (linear) or 2 (gaussian)", inf));
        if (child(child(mn, "Influence_Function"), "Parameters"))
            log.warn("{}.Influence_Function.Parameters: ignored (pdgrain uses the normalised "
                     "default parameters; in the state-based law only the shape of J matters)",
                     w);
        if (law == "pmb") {
            if (inf != 0)
                log.warn("{}.Influence_Function.Type = {}: pdgrain's PMB law uses J = 1", w, inf);
        } else
            m["influence"] = inf == 0 ? "constant" : inf == 1 ? "linear" : "gaussian";
        if (auto bp = child(mn, "Bond_Potential"))
            if (num_or(bp, w + ".Bond_Potential", "Check_Sc_Factor", 1) != 1)
                log.warn("{}.Bond_Potential.Check_Sc_Factor: ignored (bonds break at s0)", w);
        plane_strain = plane_strain || flag_or(mn, w, "Is_Plane_Strain", false);
        horizon[static_cast<std::size_t>(k - 1)] = num_or(mn, w, "Horizon", 0);
        ratio[static_cast<std::size_t>(k - 1)] = num_or(mn, w, "Horizon_Mesh_Ratio", 0);
        materials[fmt::format("zone_{}", k)] = m;
    }
    // One horizon per scene: all absolute, or all a multiple of each particle's h.
    json discretization = json::object();
    {
        const bool by_ratio = ratio[0] > 0;
        for (std::size_t k = 0; k < zones.size(); ++k) {
            const double v = by_ratio ? ratio[k] : horizon[k];
            const std::string key = fmt::format("Material.Zone_{}.{}", k + 1,
                                                by_ratio ? "Horizon_Mesh_Ratio" : "Horizon");
            if (!(v > 0))
                throw ConfigError(key, "missing or not positive (required)");
            if (std::abs(v - (by_ratio ? ratio[0] : horizon[0])) > 1e-12 * v)
                throw ConfigError(key, "differs from Zone_1's: a pdgrain scene has one horizon "
                                       "(absolute, or a multiple of each particle's h)");
        }
        discretization["mesh_size"] = 0.0; // filled below
        if (by_ratio)
            discretization["horizon_mesh_ratio"] = ratio[0]; // x each particle's h (spec 2.3)
        else
            discretization["horizon"] = horizon[0];
        discretization["bond_cutoff"] = "strict";
        // PeriDEM runs horizons below 2 h (compression_small_set: 0.4 mm at h = 0.215 mm): warn.
        discretization["small_horizon"] = "warn";
    }

    // ---- Meshes and reference shapes
    json shapes = json::object();
    std::vector<ZoneShape> zshape(zones.size());
    double hmin = 0;
    for (auto& z : zones) {
        const std::string zk = fmt::format("Zone_{}", z.k);
        const std::string w = "Mesh." + zk;
        const YAML::Node mz = child(R["Mesh"], zk);
        if (!mz)
            throw ConfigError(w, "missing: the zone's mesh (File or CreateMesh)");
        const std::string geo_key = (z.wall && old_format ? "Zone." : "Particle.") + zk;
        ZoneShape zs;
        if (auto cm = child(mz, "CreateMesh");
            cm && flag_or(cm, w + ".CreateMesh", "Flag", false)) {
            const auto info = str_or(cm, w + ".CreateMesh", "Info", "uniform");
            if (info != "uniform")
                throw ConfigError(w + ".CreateMesh.Info", "'" + info + "': only uniform");
            const double h =
                num_or(mz, w, "Mesh_Size", num_or(cm, w + ".CreateMesh", "Mesh_Size", 0));
            if (!(h > 0))
                throw ConfigError(w + ".Mesh_Size", "missing or not positive");
            auto s = deck_shape(z.type, z.params, geo_key + ".Type");
            if (!s)
                throw ConfigError(geo_key + ".Type",
                                  fmt::format("'{}' with {} parameters: not a geometry pdgrain "
                                              "can mesh",
                                              z.type, z.params.size()));
            zs = *s;
            zs.spec["mesh"] = "grid";
            zs.spec["mesh_size"] = h;
            hmin = hmin > 0 ? std::min(hmin, h) : h;
        } else {
            const auto file = deck_file(d, w + ".File", str_or(mz, w, "File", ""));
            const auto mesh = mesh::read_msh(file, dim);
            const double h = mesh::min_edge_length(mesh);
            hmin = hmin > 0 ? std::min(hmin, h) : h;
            const double rb = mesh::bounding_radius(mesh);
            std::optional<ZoneShape> s = deck_shape(z.type, z.params, geo_key + ".Type");
            if (s && !fits(s->shape, mesh, dim)) {
                s = deck_shape(z.type, z.params, geo_key + ".Type", rb);
                if (s && fits(s->shape, mesh, dim)) {
                    s->p0 = z.params[0];
                    log.warn("{}.Parameters[0] = {:.4g} m but the mesh {} has bounding radius "
                             "{:.4g} m: the reference shape is the {} of the mesh's size",
                             geo_key, z.params[0], file, rb, z.type);
                } else
                    s.reset();
            }
            if (!s) {
                if (dim == 3)
                    throw ConfigError(geo_key + ".Type",
                                      fmt::format("'{}' does not describe the mesh {} (and a 3D "
                                                  "outline cannot be derived)",
                                                  z.type, file));
                s = mesh_outline(mesh);
                if (!s)
                    throw ConfigError(w + ".File", file + ": cannot trace the mesh boundary");
                s->p0 = z.params.empty() ? rb : z.params[0];
                if (!z.wall || !old_format || z.type != "rectangle")
                    log.info("{}: geometry '{}' does not describe the mesh {}: the shape is the "
                             "mesh's outline ({} vertices)",
                             geo_key, z.type.empty() ? "(none)" : z.type, file,
                             s->spec.contains("vertices") ? s->spec["vertices"].size()
                                                          : s->spec["base"]["vertices"].size());
            }
            zs = *s;
            zs.spec["mesh"] = "file";
            zs.spec["file"] = file;
        }
        if (zs.p0 <= 0)
            zs.p0 = zs.shape.bounding_radius();
        zshape[static_cast<std::size_t>(z.k - 1)] = zs;
        shapes[fmt::format("zone_{}", z.k)] = zs.spec;
    }
    discretization["mesh_size"] = hmin;

    // ---- Particles, zone by zone (global ids cumulative over zones, CSV order inside).
    std::vector<std::array<double, 6>> rows; // zone, x, y, z, r, o
    bool with_orient = true;
    std::string csv_key = "Particle_Generation.From_File";
    if (std::any_of(zones.begin(), zones.end(), [](const Zone& z) { return !z.from_geom; })) {
        const YAML::Node pg = R["Particle_Generation"];
        if (!pg || !child(pg, "From_File"))
            throw ConfigError(csv_key, "missing: the particle CSV (zone, x, y, z, r[, o])");
        const auto type = str_or(pg, "Particle_Generation", "File_Data_Type", "loc_rad");
        if (type != "loc_rad" && type != "loc_rad_orient")
            throw ConfigError("Particle_Generation.File_Data_Type",
                              "'" + type + "': expected loc_rad or loc_rad_orient");
        with_orient = type == "loc_rad_orient";
        const auto file = deck_file(d, csv_key, str_or(pg, "Particle_Generation", "From_File", ""));
        std::ifstream in(file);
        if (!in)
            throw ConfigError(csv_key, file + ": cannot read");
        std::string line;
        std::size_t ln = 0;
        while (std::getline(in, line)) {
            ++ln;
            for (char& c : line)
                if (c == ',')
                    c = ' ';
            std::istringstream ls(line);
            std::vector<double> v;
            std::string tok;
            bool numeric = true;
            while (ls >> tok) {
                try {
                    std::size_t used = 0;
                    v.push_back(std::stod(tok, &used));
                    numeric = numeric && used == tok.size();
                } catch (...) {
                    numeric = false;
                }
            }
            if (v.empty() && numeric)
                continue; // blank
            if (!numeric) {
                if (ln == 1)
                    continue; // header
                throw ConfigError(csv_key, fmt::format("{} line {}: not numbers", file, ln));
            }
            const std::size_t need = with_orient ? 6 : 5;
            if (v.size() < need)
                throw ConfigError(csv_key,
                                  fmt::format("{} line {}: expected {} columns (zone, x, "
                                              "y, z, r{}), found {}",
                                              file, ln, need, with_orient ? ", o" : "", v.size()));
            if (!(v[4] > 0))
                throw ConfigError(
                    csv_key, fmt::format("{} line {}: radius {} must be positive", file, ln, v[4]));
            if (v[0] < 0 || v[0] >= nz || v[0] != std::floor(v[0]))
                throw ConfigError(csv_key, fmt::format("{} line {}: zone {} is not in [0, {})",
                                                       file, ln, v[0], nz));
            rows.push_back({v[0], v[1], v[2], v[3], v[4], with_orient ? v[5] : 0.0});
        }
    }
    const bool two_particle = str_or(R["Particle"], "Particle", "Test_Name", "") == "two_particle";
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> angle(0.0, 2 * pi);
    if (!with_orient && !two_particle)
        log.warn("Particle_Generation.File_Data_Type = loc_rad: orientations drawn uniformly in "
                 "[0, 2 pi) with seed {} (not PeriDEM's draws)",
                 seed);
    std::vector<Particle> parts;
    for (auto& z : zones) {
        if (z.from_geom) {
            Particle p;
            p.zone = z.k;
            p.scaled = false;
            z.particles.push_back(parts.size());
            parts.push_back(p);
            continue;
        }
        for (const auto& row : rows) {
            if (static_cast<int>(row[0]) != z.k - 1)
                continue;
            Particle p;
            p.zone = z.k;
            p.x = {row[1], row[2], dim == 3 ? row[3] : 0.0};
            p.r = row[4];
            p.o = with_orient    ? row[5]
                  : two_particle ? static_cast<double>(parts.size()) * pi
                                 : angle(rng);
            z.particles.push_back(parts.size());
            parts.push_back(p);
        }
        if (z.particles.empty())
            log.warn("Particle.Zone_{}: no particle of this zone in the CSV", z.k);
    }
    if (parts.empty())
        throw ConfigError(csv_key, "no particle was placed");
    std::vector<std::size_t> wall_ids; // old format: Wall_List index -> particle id
    for (const auto& z : zones)
        if (z.wall)
            wall_ids.insert(wall_ids.end(), z.particles.begin(), z.particles.end());

    // ---- Loading: displacement conditions, force conditions, IC, gravity.
    json conditions = json::array();
    std::vector<std::uint8_t> driven(parts.size(), 0); // particles moved by a non-zero condition
    const std::vector<std::string> comp = {"x", "y", "z"};
    auto selection = [&](const YAML::Node& s, const std::string& w, json& c,
                         std::vector<std::size_t>* ids, bool& whole) {
        std::set<std::size_t> take;
        bool listed = false;
        for (const char* key : {"Particle_List", "Wall_List"}) {
            if (!child(s, key))
                continue;
            listed = true;
            for (long id : ints(s, w, key)) {
                const bool wall = std::string(key) == "Wall_List";
                const std::size_t n = wall ? wall_ids.size() : parts.size();
                if (id < 0 || static_cast<std::size_t>(id) >= n)
                    throw ConfigError(dot(w, key), fmt::format("{} is not a {} id in [0, {})", id,
                                                               wall ? "wall" : "particle", n));
                take.insert(wall ? wall_ids[static_cast<std::size_t>(id)]
                                 : static_cast<std::size_t>(id));
            }
        }
        if (child(s, "Particle_Exclude_List")) {
            if (!listed)
                for (std::size_t k = 0; k < parts.size(); ++k)
                    take.insert(k);
            listed = true;
            for (long id : ints(s, w, "Particle_Exclude_List"))
                take.erase(static_cast<std::size_t>(id));
        }
        whole = !child(s, "Region");
        if (auto rg = child(s, "Region")) {
            const YAML::Node g = child(rg, "Geometry");
            const std::string gw = w + ".Region.Geometry";
            const auto type = str_or(g, gw, "Type", "");
            const auto p = nums(g, gw, "Parameters");
            std::optional<std::array<double, 4>> b;
            if (type == "rectangle")
                b = rectangle_box(p);
            if (!b || dim == 3)
                throw ConfigError(gw, fmt::format("'{}' with {} parameters: only 2D rectangle "
                                                  "regions can be imported",
                                                  type, p.size()));
            c["region"] = {{"min", {(*b)[0], (*b)[1]}}, {"max", {(*b)[2], (*b)[3]}}};
        } else if (!listed)
            throw ConfigError(w, "selects nothing: give Particle_List or Region");
        if (listed) {
            c["particles"] = json::array();
            for (auto id : take) {
                c["particles"].push_back(id);
                if (ids)
                    ids->push_back(id);
            }
        }
    };
    auto sets = [&](const char* block, bool force) {
        const YAML::Node b = R[block];
        if (!b)
            return;
        const int n = static_cast<int>(num_or(b, block, "Sets", 0));
        for (int k = 1; k <= n; ++k) {
            const std::string w = fmt::format("{}.Set_{}", block, k);
            const YAML::Node s = b[fmt::format("Set_{}", k)];
            if (!s)
                throw ConfigError(w, fmt::format("missing ({}.Sets = {})", block, n));
            json c{{"name", fmt::format("{}_set_{}", force ? "force" : "displacement", k)},
                   {"kind", force ? "force_density" : "displacement"}};
            std::vector<std::size_t> ids;
            bool whole = false;
            selection(s, w, c, &ids, whole);
            c["components"] = json::array();
            std::set<long> dofs;
            for (long dof : ints(s, w, "Direction")) {
                if (dof < 1 || dof > dim)
                    throw ConfigError(w + ".Direction",
                                      fmt::format("{} is not a dof in [1, {}]", dof, dim));
                dofs.insert(dof);
                c["components"].push_back(comp[static_cast<std::size_t>(dof - 1)]);
            }
            if (dofs.empty())
                throw ConfigError(w + ".Direction", "missing: the list of dofs (1-based)");
            const YAML::Node tf = child(s, "Time_Function");
            const auto tt = str_or(tf, w + ".Time_Function", "Type", "constant");
            const auto tp = nums(tf, w + ".Time_Function", "Parameters");
            const double a = tp.empty() ? 0.0 : tp[0];
            const bool zero = !force && (flag_or(s, w, "Zero_Displacement", false) ||
                                         (tt == "constant" && a == 0));
            if (tt == "constant" || (force && tt == "none")) {
                c["time_function"] = "constant";
            } else if (tt == "linear") {
                c["time_function"] = "linear";
            } else if (tt == "quadratic" && !force) {
                // PeriDEM: u = a t + p1 t^2; pdgrain: u = a (t + p t^2).
                c["time_function"] = "quadratic";
                c["time_parameter"] = tp.size() > 1 && a != 0 ? tp[1] / a : 0.0;
                log.warn("{}.Time_Function: quadratic velocity is a + 2 p1 t in pdgrain (PeriDEM: "
                         "a + p1 t)",
                         w);
            } else if (tt == "sin") {
                c["time_function"] = "sine";
                c["time_parameter"] = tp.size() > 1 ? tp[1] : 0.0;
            } else if (tt == "rotation" && !force) {
                // Attrition drums (spec 5.6, 5.9): [omega, x0, y0, z0], a rigid-body rotation of
                // the reference positions about (x0, y0), counter-clockwise for omega > 0.
                if (tp.size() < 3)
                    throw ConfigError(w + ".Time_Function.Parameters",
                                      "rotation needs [omega, x0, y0(, z0)]");
                if (dim != 2)
                    throw ConfigError(w + ".Time_Function.Type",
                                      "rotation is an in-plane (2D) motion in PeriDEM 0.2");
                c["time_function"] = "rotation";
                c["rotation_center"] = json{tp[1], tp[2]};
                log.info("{}: rotation at {:.4g} rad/s about ({:.4g}, {:.4g}) m, prescribed on "
                         "every node of the selection (a rigid-body displacement)",
                         w, tp[0], tp[1], tp[2]);
            } else
                throw ConfigError(w + ".Time_Function.Type",
                                  fmt::format("'{}' cannot be expressed in a pdgrain scene ({})",
                                              tt,
                                              force ? "constant, linear, sin"
                                                    : "constant, linear, quadratic, sin, "
                                                      "rotation"));
            const YAML::Node sf = child(s, "Spatial_Function");
            const auto st = str_or(sf, w + ".Spatial_Function", "Type", "constant");
            const auto sp = nums(sf, w + ".Spatial_Function", "Parameters");
            double amplitude = a;
            if (st == "linear_x" || st == "sin_x") {
                c["space_function"] = st == "linear_x" ? "linear_x" : "sine_x";
                c["space_parameter"] = sp.empty() ? 1.0 : sp[0];
                if (force && st == "sin_x")
                    amplitude = a * (sp.empty() ? 1.0 : sp[0]); // p_s0 sin(pi p_s0 x)
            } else if (st != "constant")
                throw ConfigError(w + ".Spatial_Function.Type",
                                  "'" + st + "' cannot be expressed (constant, linear_x, sin_x)");
            c["value"] = zero ? 0.0 : amplitude;
            // Whole particles held at zero in every dof: a fixed obstacle.
            if (zero && whole && static_cast<int>(dofs.size()) == dim) {
                for (auto id : ids)
                    parts[id].fixed = true;
                continue;
            }
            if (!force && !zero)
                for (auto id : ids)
                    driven[id] = 1;
            if (!force && !zero && whole)
                // A constrained wall driven in some dofs is held in the others.
                for (auto id : ids)
                    if (zones[static_cast<std::size_t>(parts[id].zone - 1)].constrained &&
                        static_cast<int>(dofs.size()) < dim) {
                        json h{{"name", fmt::format("hold_{}_particle_{}", k, id)},
                               {"kind", "displacement"},
                               {"particles", {id}},
                               {"components", json::array()},
                               {"value", 0.0}};
                        for (int q = 1; q <= dim; ++q)
                            if (!dofs.count(q))
                                h["components"].push_back(comp[static_cast<std::size_t>(q - 1)]);
                        conditions.push_back(h);
                    }
            conditions.push_back(c);
        }
    };
    sets("Displacement_BC", false);
    sets("Force_BC", true);
    // Constrained zones not driven by a condition are fixed obstacles (spec 4.8).
    for (const auto& z : zones)
        if (z.constrained)
            for (auto id : z.particles)
                if (!driven[id])
                    parts[id].fixed = true;
    if (auto cv = child(R["IC"], "Constant_Velocity")) {
        const auto v = nums(cv, "IC.Constant_Velocity", "Velocity_Vector");
        if (v.size() < static_cast<std::size_t>(dim))
            throw ConfigError("IC.Constant_Velocity.Velocity_Vector",
                              fmt::format("expected {} components", dim));
        std::vector<long> ids =
            single ? std::vector<long>{0} : ints(cv, "IC.Constant_Velocity", "Particle_List");
        for (long id : ids) {
            if (id < 0 || static_cast<std::size_t>(id) >= parts.size())
                throw ConfigError(
                    "IC.Constant_Velocity.Particle_List",
                    fmt::format("{} is not a particle id in [0, {})", id, parts.size()));
            parts[static_cast<std::size_t>(id)].v = {v[0], v[1], dim == 3 ? v[2] : 0.0};
        }
    }
    if (auto ct = child(R["Particle"], "Compressive_Test"))
        log.info("Particle.Compressive_Test: pdgrain records the contact force every fixed or "
                 "driven body receives (/observables/body_force; pd-post walls.csv, "
                 "plot_wall_reaction.py --body B); examples/compressive_n500 is this test with "
                 "a rigid plate that enters the settled pack (walls[].start_time)");
    if (auto oc = child(R["Output"], "Output_Criteria"))
        log.warn("Output.Output_Criteria ({}): not imported (pdgrain stops only on blow-up or "
                 "NaN)",
                 str_or(oc, "Output.Output_Criteria", "Type", "?"));

    // ---- Contact table (groups = zones - 1).
    json contact = json::object();
    if (!single) {
        const YAML::Node cb = R["Contact"];
        std::map<std::pair<int, int>, json> table;
        std::map<std::pair<int, int>, YAML::Node> raw;
        bool beta_warned = false;
        if (cb && cb.IsMap()) {
            // Copies first need their source: walk in deck order, resolving as we go.
            for (auto it = cb.begin(); it != cb.end(); ++it) {
                const auto key = it->first.as<std::string>();
                if (key.rfind("Zone_", 0) != 0) {
                    log.warn("Contact.{}: not a zone pair, ignored", key);
                    continue;
                }
                raw[zone_pair(key, "Contact", nz)] = it->second;
            }
            for (auto& [ij, node] : raw) {
                const std::string w = fmt::format("Contact.Zone_{}{}", ij.first, ij.second);
                YAML::Node n;
                n.reset(node);
                if (auto cp = child(n, "Copy_Contact_Data")) {
                    auto src = ints(n, w, "Copy_Contact_Data");
                    if (src.size() != 2)
                        throw ConfigError(w + ".Copy_Contact_Data", "expected [i, j]");
                    auto s = std::make_pair(std::min(src[0], src[1]), std::max(src[0], src[1]));
                    auto f = raw.find({static_cast<int>(s.first), static_cast<int>(s.second)});
                    if (f == raw.end())
                        throw ConfigError(w + ".Copy_Contact_Data", "no such contact pair");
                    n.reset(f->second);
                }
                json law = json::object();
                if (child(n, "Contact_Radius"))
                    law["radius"] = num_or(n, w, "Contact_Radius", 0);
                else if (child(n, "Contact_Radius_Factor"))
                    law["radius_factor"] = num_or(n, w, "Contact_Radius_Factor", 0);
                else
                    throw ConfigError(w, "no Contact_Radius_Factor or Contact_Radius (PeriDEM "
                                         "would use R_c = 0: no contact)");
                const double kn = num_or(n, w, "Kn", 0) * num_or(n, w, "Kn_Factor", 1);
                if (kn > 0)
                    law["stiffness"] = kn;
                else {
                    law["stiffness"] = "auto";
                    log.warn("{}.Kn: missing or zero (PeriDEM: no contact force); imported as "
                             "\"auto\" (18 kappa / (pi delta^(d+2)) (0.95 h / R_c)^(d+1))",
                             w);
                }
                if (flag_or(n, w, "Damping_On", true)) {
                    if (!child(n, "Epsilon"))
                        throw ConfigError(w + ".Epsilon", "required when Damping_On is true");
                    law["restitution"] = num_or(n, w, "Epsilon", 1);
                    if (!beta_warned && num_or(n, w, "Beta_n_Factor", 1) != 1) {
                        log.info("{}.Beta_n_Factor: not used (pdgrain's damping achieves the "
                                 "restitution Epsilon directly)",
                                 w);
                        beta_warned = true;
                    }
                } else
                    law["restitution"] = 1.0;
                law["friction"] =
                    flag_or(n, w, "Friction_On", true) ? num_or(n, w, "Friction_Coeff", 0) : 0.0;
                table[ij] = law;
            }
        }
        std::set<int> used;
        for (const auto& z : zones)
            if (!z.particles.empty())
                used.insert(z.k);
        json pairs = json::array();
        for (int i : used)
            for (int j : used)
                if (j >= i) {
                    auto f = table.find({i, j});
                    if (f == table.end()) {
                        log.warn("Contact.Zone_{}{}: missing; pdgrain's default law applies "
                                 "(Kn auto, radius 0.95 h)",
                                 i, j);
                        continue;
                    }
                    json p = f->second;
                    p["groups"] = {i - 1, j - 1};
                    pairs.push_back(p);
                }
        if (!pairs.empty()) {
            for (auto it = pairs[0].begin(); it != pairs[0].end(); ++it)
                if (it.key() != "groups")
                    contact[it.key()] = *it;
            contact["pairs"] = pairs;
        }
    }

    // ---- Output, solver
    json solver{{"final_time", final_time},
                {"dt", dt},
                {"integrator",
                 time_scheme == "central_difference" ? "symplectic_euler" : "velocity_verlet"},
                {"surface_correction", false},
                {"quadrature_calibration", false}};
    if (auto out = R["Output"]) {
        const double every = num_or(out, "Output", "Output_Interval", 0);
        if (every > 0)
            solver["output_interval"] = std::min(every * dt, final_time);
        if (auto tags = child(out, "Tags"); tags && tags.IsSequence()) {
            json fields = json::array();
            std::set<std::string> have;
            for (const auto& t : tags) {
                const auto s = t.as<std::string>();
                std::string f = s == "Velocity"                    ? "velocity"
                                : s == "Displacement"              ? "displacement"
                                : s == "Force"                     ? "force"
                                : s == "Damage" || s == "Damage_Z" ? "damage"
                                                                   : "";
                if (!f.empty() && have.insert(f).second)
                    fields.push_back(f);
            }
            solver["fields"] = fields;
        }
    }

    // ---- The scene
    json scene;
    scene["title"] = fmt::format("imported from PeriDEM deck {}", fs::path(yaml_path).string());
    scene["dimension"] = dim;
    if (plane_strain || lps_parity)
        scene["planar"] = "plane_strain"; // parity: the equivalent material is given as K3', mu'
    scene["materials"] = materials;
    scene["discretization"] = discretization;
    scene["shapes"] = shapes;
    json plist = json::array();
    auto vec = [&](const std::array<double, 3>& v) {
        return dim == 3 ? json{v[0], v[1], v[2]} : json{v[0], v[1]};
    };
    for (const auto& p : parts) {
        const auto& zs = zshape[static_cast<std::size_t>(p.zone - 1)];
        json j{{"shape", fmt::format("zone_{}", p.zone)}, {"center", vec(p.x)}};
        if (p.scaled) {
            // PeriDEM scales by r / Parameters[0] (spec 2.5); pdgrain by radius / bounding radius.
            j["radius"] = p.r / zs.p0 * zs.shape.bounding_radius();
            if (p.o != 0)
                j["orientation"] = p.o;
        }
        j["material"] = fmt::format("zone_{}", p.zone);
        j["group"] = p.zone - 1;
        if (p.v != std::array<double, 3>{0, 0, 0})
            j["velocity"] = vec(p.v);
        if (p.fixed)
            j["fixed"] = true;
        plist.push_back(j);
    }
    scene["particles"] = plist;
    if (!contact.empty())
        scene["contact"] = contact;
    json loading = json::object();
    if (auto g = child(R["Force_BC"], "Gravity")) {
        auto gv = nums(R["Force_BC"], "Force_BC", "Gravity");
        if (gv.size() < static_cast<std::size_t>(dim))
            throw ConfigError("Force_BC.Gravity", fmt::format("expected {} components", dim));
        loading["gravity"] = vec({gv[0], gv[1], dim == 3 ? gv[2] : 0.0});
    }
    if (!conditions.empty())
        loading["conditions"] = conditions;
    if (!loading.empty())
        scene["loading"] = loading;
    scene["solver"] = solver;
    log.info("{}: {} zones, {} particles ({} fixed), {} conditions", yaml_path, nz, parts.size(),
             std::count_if(parts.begin(), parts.end(), [](const Particle& p) { return p.fixed; }),
             conditions.size());
    return scene.dump(2) + "\n";
}

} // namespace pd::pipeline
