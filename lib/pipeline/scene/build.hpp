// SPDX-License-Identifier: MIT
// The scene parser's working state (internal to build_scene, lib/pipeline/scene.cpp): one step per
// section of the scene file (lib/pipeline/scene/<section>.cpp), run in the order of
// build_scene, each reading the state the steps before it left.
#pragma once

#include "core/log.hpp"
#include "geometry/shapes.hpp"
#include "model/model.hpp"
#include "pipeline/scene/fields.hpp"

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace pd::pipeline::scene {

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
    bool wall = false; ///< a PeriDEM wall (BodyKind::wall; contact.approach_damping)
    std::string where; ///< scene key, for messages
};

/// A meshed reference shape (spec 2.5).
struct Ref {
    std::int32_t index;
    std::vector<double> volume, bdist;
    double h, bound;
};

/// The "discretization" section.
struct Discretization {
    bool small_horizon_warns = false;
    bool partial_cutoff = true;
    double h_ref = 0;
    bool has_h = false, has_m = false, has_r = false;
    std::string horizon_key;
    double horizon_abs = 0;
    double horizon_factor = 0;
};

/// What the steps share while the model `m` is built.
struct SceneBuild {
    SceneBuild(const json& root_, const Log& log_, double max_nodes_, Folder base_dir_,
               model::Model& m_)
        : root(root_)
        , log(log_)
        , max_nodes(max_nodes_)
        , base_dir(std::move(base_dir_))
        , m(m_) {}

    const json& root;
    const Log& log;
    double max_nodes;
    Folder base_dir; ///< the scene file's folder (relative files)
    model::Model& m;
    std::map<std::string, std::int32_t> material_index;
    Discretization dz;
    std::map<std::string, ShapeSpec> shapes;
    std::vector<std::string> shape_order; ///< in order of first use
    std::vector<Instance> inst;
    std::map<std::string, Ref> refs;
    std::vector<double> h_nominal_of; ///< per body: its shape's nominal mesh size
    /// Per row of m.contact: 1 if its stiffness is the surface law's rule (kappa / h^2, times
    /// any stiffness_factor), which raise_for_speed may raise; 0 if given or a node law.
    std::vector<std::uint8_t> contact_auto;
};

/// "materials" (materials.cpp).
void parse_materials(SceneBuild& s);
/// "discretization" (shapes.cpp).
void parse_discretization(SceneBuild& s);
/// Refuses shapes (named, random_pack containers) whose union/difference parts, polygon vertices
/// or Boolean work are above the limits of geometry/shapes.hpp, counted from the JSON before any
/// shape is built (shape_budget.cpp).
void check_shape_budget(const SceneBuild& s);
/// "shapes": the named reference shapes (shapes.cpp).
void parse_shapes(SceneBuild& s);
/// "particles": explicit entries and generators, with the node estimate (particles.cpp).
void parse_particles(SceneBuild& s);
/// Meshes each reference shape once (shapes.cpp).
void mesh_reference_shapes(SceneBuild& s);
/// Places the grains, their horizons, checks overlaps, builds the bonds (placement.cpp).
void place_particles(SceneBuild& s);
/// "walls" (walls.cpp).
void parse_walls(SceneBuild& s);
/// "contact": the contact table (contact.cpp).
void parse_contact(SceneBuild& s);
/// Warns of grains within a wall's contact radius at t = 0 (walls.cpp).
void warn_close_to_walls(SceneBuild& s);
/// Walls present at t = 0 that enter above the grains: placed on the packed grains (after
/// parse_contact: the reach is the wall's contact radius with each grain's group).
void place_walls(SceneBuild& s);
/// Marks the surface-layer nodes (placement.cpp).
void mark_surface_layer(SceneBuild& s);
/// "slots": notch slots (cracks.cpp).
void parse_slots(SceneBuild& s);
/// "loading" (loading.cpp).
void parse_loading(SceneBuild& s);
/// "cracks": pre-cracks (cracks.cpp).
void parse_cracks(SceneBuild& s);
/// "solver" (solver_settings.cpp).
void parse_solver(SceneBuild& s);
/// Raises the surface law's automatic stiffness where the scene's speeds need it: the penalty
/// must hold an impact's pressure within h/4 (contact_speed.cpp; after the walls, the loading
/// and the solver's final time are known).
void raise_for_speed(SceneBuild& s);

/// A shape (a container, a named shape's geometry); relative surface_mesh files are resolved
/// against `base` (the scene file's folder) (shapes.cpp).
geometry::Shape parse_shape(const json& o, const std::string& w, int dim, const Folder& base);
/// walls[k] of "type": "mesh" (key prefix `w`): its surface, from an STL file (3D, relative to
/// `base`) or a polyline (2D), checked; sets wall.mesh and wall.point (wall_mesh.cpp).
void parse_wall_mesh(const json& wj, const std::string& w, model::Wall& wall, int dim,
                     const Folder& base);

} // namespace pd::pipeline::scene
