// SPDX-License-Identifier: MIT
#include "core/errors.hpp"
#include "mesh/discretize.hpp"
#include "mesh/gmsh_mesher.hpp"
#include "mesh/shape_mesher.hpp"
#include "model/wall_mesh.hpp"
#include "pipeline/scene/build.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>

namespace pd::pipeline::scene {

namespace {

const std::vector<std::string> shape_keys = {
    "type",    "radius",     "semi_axes", "sides",    "phase", "size",
    "corners", "neck_width", "vertices",  "parts",    "base",  "minus",
    "length",  "offset",     "rotation",  "centered", "file"};

/// [x, y] or [x, y, z] at `key` of shape `o`.
std::array<double, 3> pair_of(const json& o, const std::string& w, const char* key) {
    if (!o.contains(key) || !o[key].is_array() || o[key].size() < 2)
        throw ConfigError(join(w, key), "expected a list of numbers");
    return std::array<double, 3>{o[key][0].get<double>(), o[key][1].get<double>(),
                                 o[key].size() > 2 ? o[key][2].get<double>() : 0.0};
}

/// The 2D primitives (circle to polygon); nullopt for other types.
std::optional<geometry::Shape> plane_shape(const std::string& type, const json& o,
                                           const std::string& w) {
    auto pair = [&](const char* key) { return pair_of(o, w, key); };
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
        return geometry::Shape::regular_polygon(
            static_cast<int>(sides), positive(o, w, "radius", 0, true), number(o, w, "phase", 0));
    }
    if (type == "rectangle") {
        if (o.contains("corners")) {
            const auto& c = o["corners"];
            if (!c.is_array() || c.size() != 2 || !c[0].is_array() || c[0].size() != 2 ||
                !c[1].is_array() || c[1].size() != 2) // c[0][1] of [[0], ...]: out of bounds
                throw ConfigError(w + ".corners", "expected [[x0, y0], [x1, y1]]");
            return geometry::Shape::rectangle_corners(c[0][0].get<double>(), c[0][1].get<double>(),
                                                      c[1][0].get<double>(), c[1][1].get<double>());
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
        for (const auto& p : o["vertices"]) {
            if (!p.is_array() || p.size() < 2) // p[1] of [x]: out of bounds
                throw ConfigError(w + ".vertices", "expected [[x, y], ...]");
            v.push_back({p[0].get<double>(), p[1].get<double>()});
        }
        return geometry::Shape::polygon(v);
    }
    return std::nullopt;
}

/// The compounds (union, difference) and the 3D shapes.
geometry::Shape other_shape(const std::string& type, const json& o, const std::string& w, int dim,
                            const Folder& base) {
    auto pair = [&](const char* key) { return pair_of(o, w, key); };
    auto list = [&](const json& arr, const std::string& ww) {
        if (!arr.is_array() || arr.empty())
            throw ConfigError(ww, "expected a list of shapes");
        std::vector<geometry::Shape> v;
        for (std::size_t k = 0; k < arr.size(); ++k)
            v.push_back(parse_shape(arr[k], fmt::format("{}[{}]", ww, k), dim, base));
        return v;
    };
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
        const std::string path = resolve(base, file, w + ".file");
        // As a mesh wall's STL (wall_mesh.cpp): the file's size bounds its triangles before
        // CGAL reads it and checks it for self-intersections.
        std::error_code ec;
        const auto size = std::filesystem::file_size(path, ec);
        const std::uintmax_t limit = 8 * (84 + 50 * std::uintmax_t{model::max_wall_mesh_cells});
        if (!ec && size > limit)
            throw ConfigError(w + ".file", fmt::format("'{}' has {} bytes: too large for a "
                                                       "surface of at most {} triangles",
                                                       path, size, model::max_wall_mesh_cells));
        try {
            return geometry::Shape::surface_mesh(path);
        } catch (const ConfigError&) {
            throw;
        } catch (const InputError& e) {
            throw ConfigError(w + ".file", e.what());
        }
    }
    return geometry::Shape::cylinder(positive(o, w, "radius", 0, true),
                                     positive(o, w, "length", 0, true));
}

} // namespace

/// A shape; relative surface_mesh files are resolved against `base` (the scene file's folder).
geometry::Shape parse_shape(const json& o, const std::string& w, int dim, const Folder& base) {
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
    auto pair = [&](const char* key) { return pair_of(o, w, key); };
    geometry::Shape sh = [&]() {
        if (auto plane = plane_shape(type, o, w))
            return *plane;
        return other_shape(type, o, w, dim, base);
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

namespace {

ShapeSpec parse_shape_spec(const json& o, const std::string& w, int dim, const Folder& base) {
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
        sp.file = text(o, w, "file", "").empty()
                      ? std::string()
                      : resolve(base, text(o, w, "file", ""), w + ".file");
        if (sp.file.empty())
            throw ConfigError(w + ".file", "missing: the .msh file of this shape");
    }
    sp.quads = boolean(o, w, "quads", false);
    sp.mesh_size = o.contains("mesh_size") ? positive(o, w, "mesh_size", 0) : 0.0;
    return sp;
}

} // namespace

void parse_discretization(SceneBuild& s) {
    const json& root = s.root;
    auto& z = s.dz;
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

    z = {small_horizon_warns, partial_cutoff, h_ref,         has_h, has_m, has_r,
         horizon_key,         horizon_abs,    horizon_factor};
}

void parse_shapes(SceneBuild& s) {
    check_shape_budget(s); // every shape of the scene, before any is built
    const json& root = s.root;
    const model::Model& m = s.m;
    const Folder& base_dir = s.base_dir;
    auto& shapes = s.shapes;
    // Reference shapes: named in "shapes", or the implicit "disc" (a circle whose radius is the
    // first disc particle's).
    if (root.contains("shapes")) {
        if (!root["shapes"].is_object())
            throw ConfigError("shapes", "expected an object of named shapes");
        for (auto it = root["shapes"].begin(); it != root["shapes"].end(); ++it)
            shapes.emplace(it.key(),
                           parse_shape_spec(*it, "shapes." + it.key(), m.dimension, base_dir));
    }
}

void mesh_reference_shapes(SceneBuild& s) {
    model::Model& m = s.m;
    const Log& log = s.log;
    const double h_ref = s.dz.h_ref;
    const auto& shapes = s.shapes;
    const auto& shape_order = s.shape_order;
    auto& refs = s.refs;
    // Mesh each reference shape once (spec 2.5).
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
}

} // namespace pd::pipeline::scene
