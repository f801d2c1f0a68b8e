// SPDX-License-Identifier: MIT
// The work of building the scene's shapes, counted from its JSON before any shape is built
// (issue 27, bounded work): a shape's geometry is computed as it is parsed (2D unions and
// differences by CGAL's exact Boolean operations, 3D ones by octree quadrature), before the node
// estimate can refuse anything, so a scene of many parts or of huge polygons took unbounded time
// and memory in pd-pack. Limits and their measured costs: geometry/shapes.hpp
// (max_polygon_vertices, max_csg_parts, max_csg_vertex_work, max_csg_part_work).
#include "core/errors.hpp"
#include "pipeline/scene/build.hpp"

#include <algorithm>
#include <cmath>

namespace pd::pipeline::scene {

namespace {

/// What building one shape costs, in the units of geometry/shapes.hpp.
struct ShapeWork {
    double parts = 0;    ///< primitive parts: the leaves of the union/difference tree
    double vertices = 0; ///< 2D: their boundary vertices (a circle or ellipse: curve_segments)
    double work = 0;     ///< vertex (2D) or part (3D) evaluations of the unions/differences
};

/// Boundary vertices of a 2D primitive as the Boolean operations see it (0: not 2D).
double primitive_vertices(const json& o, const std::string& type, const std::string& w) {
    if (type == "circle" || type == "ellipse")
        return geometry::curve_segments;
    if (type == "polygon") {
        const double n = o.contains("vertices") && o["vertices"].is_array()
                             ? static_cast<double>(o["vertices"].size())
                             : 0.0;
        if (n > geometry::max_polygon_vertices)
            throw ConfigError(w + ".vertices",
                              fmt::format("a polygon of {:.0f} vertices, above the limit of {} "
                                          "(its exact Boolean operations, containment and "
                                          "meshing grow with the vertex count): simplify the "
                                          "outline",
                                          n, geometry::max_polygon_vertices));
        return n;
    }
    if (type == "regular_polygon") // the parser refuses sides outside [3, 10000]
        return o.contains("sides") && o["sides"].is_number()
                   ? std::clamp(o["sides"].get<double>(), 3.0, 10000.0)
                   : 3.0;
    if (type == "triangle")
        return 3;
    if (type == "square" || type == "rectangle")
        return 4;
    return type == "hexagon" || type == "drum2d" ? 6 : 0;
}

/// The work of shape `o` at key `w`; a surface_mesh part counts surface_mesh_weight parts (its
/// distance queries cost that many primitive ones). Values of the wrong kind count 0: the
/// parser names them afterwards.
ShapeWork count(const json& o, const std::string& w, int dim) {
    ShapeWork c;
    if (!o.is_object() || !o.contains("type") || !o["type"].is_string())
        return c;
    const auto type = o["type"].get<std::string>();
    if (type != "union" && type != "difference") {
        c.parts = type == "surface_mesh" ? geometry::surface_mesh_weight : 1.0;
        c.vertices = primitive_vertices(o, type, w);
        return c;
    }
    std::vector<ShapeWork> kids;
    auto add = [&](const json& j, const std::string& ww) { kids.push_back(count(j, ww, dim)); };
    const char* list = type == "union" ? "parts" : "minus";
    if (type == "difference" && o.contains("base"))
        add(o["base"], w + ".base");
    if (o.contains(list) && o[list].is_array())
        for (std::size_t k = 0; k < o[list].size(); ++k)
            add(o[list][k], fmt::format("{}.{}[{}]", w, list, k));
    for (const auto& k : kids) {
        c.parts += k.parts;
        c.vertices += k.vertices;
        c.work += k.work;
    }
    // This node rebuilds its whole subtree (2D: every part's region, then one Boolean operation
    // per child against the result so far, which holds up to all the vertices; 3D: the octree
    // evaluates every part at each cell).
    c.work += dim == 2 ? static_cast<double>(kids.size()) * c.vertices : c.parts;
    return c;
}

/// Refuses shape `o` (key `w`) above the part limit; adds its work to `total`, refused above the
/// work limit (the scene's shapes together).
void check_one(const json& o, const std::string& w, int dim, double& total) {
    const auto c = count(o, w, dim);
    const bool csg =
        o.is_object() && o.contains("type") && (o["type"] == "union" || o["type"] == "difference");
    if (csg && c.parts > geometry::max_csg_parts)
        throw ConfigError(w, fmt::format("a union/difference of {:g} parts (a surface_mesh "
                                         "counts {:g}), above the limit of {}: each part is "
                                         "evaluated wherever the shape's geometry is computed; "
                                         "use fewer parts, or separate grains",
                                         c.parts, geometry::surface_mesh_weight,
                                         geometry::max_csg_parts));
    total += c.work;
    const double limit = dim == 2 ? geometry::max_csg_vertex_work : geometry::max_csg_part_work;
    if (total > limit)
        throw ConfigError(w, fmt::format("the unions and differences of the scene's shapes up "
                                         "to this one need {:.3g} {} (this one {:.3g}: {:g} "
                                         "parts, {:g} boundary vertices), above the limit of "
                                         "{:.3g}: use fewer parts{}",
                                         total, dim == 2 ? "vertex operations" : "part evaluations",
                                         c.work, c.parts, c.vertices, limit,
                                         dim == 2 ? fmt::format(", or polygons of fewer vertices "
                                                                "(a circle or ellipse counts {})",
                                                                geometry::curve_segments)
                                                  : std::string{}));
}

} // namespace

void check_shape_budget(const SceneBuild& s) {
    const json& root = s.root;
    const int dim = s.m.dimension;
    double total = 0;
    if (root.contains("shapes") && root["shapes"].is_object())
        for (auto it = root["shapes"].begin(); it != root["shapes"].end(); ++it)
            check_one(*it, "shapes." + it.key(), dim, total);
    if (root.contains("particles") && root["particles"].is_array())
        for (std::size_t k = 0; k < root["particles"].size(); ++k) {
            const json& p = root["particles"][k];
            if (p.is_object() && p.contains("container"))
                check_one(p["container"], fmt::format("particles[{}].container", k), dim, total);
        }
}

} // namespace pd::pipeline::scene
