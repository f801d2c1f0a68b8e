// SPDX-License-Identifier: MIT
// The PeriDEM importer's working state (internal to peridem_to_scene, lib/pipeline/
// peridem_import.cpp): one step per deck block (lib/pipeline/peridem/<block>.cpp), run in the
// order of peridem_to_scene, each filling the parts of the scene its block gives.
#pragma once

#include "core/log.hpp"
#include "pipeline/peridem/deck.hpp"
#include "pipeline/peridem/geometry.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace pd::pipeline::peridem {

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

/// The deck being read and the scene blocks made so far.
struct Import {
    Import(const Deck& d_, const Log& log_, bool parity_)
        : d(d_)
        , R(d_.root)
        , log(log_)
        , parity(parity_) {}

    const Deck& d;
    const YAML::Node& R;
    const Log& log;
    bool parity; ///< --parity peridem
    // Model
    int dim = 0;
    double final_time = 0, dt = 0;
    std::string time_scheme;
    bool single = false;
    std::uint32_t seed = 1;
    // Zones
    bool old_format = false;
    int nz = 0;
    std::vector<Zone> zones;
    // Material
    json materials = json::object();
    std::vector<double> zone_bulk; ///< the deck's K per zone (PeriDEM's contact kappa), Pa
    bool plane_strain = false, lps_parity = false;
    json discretization = json::object();
    // Mesh
    json shapes = json::object();
    std::vector<ZoneShape> zshape;
    // Particles
    std::vector<Particle> parts;
    std::vector<std::size_t> wall_ids; ///< old format: Wall_List index -> particle id
    // Displacement_BC, Force_BC, IC
    json conditions = json::array();
    // Contact, Output
    json contact = json::object();
    json solver;
};

/// Model (model.cpp).
void read_model(Import& im);
/// Zone, with Particle / Wall geometry (model.cpp).
void read_zones(Import& im);
/// Material, one per zone, and the horizon (materials.cpp).
void read_materials(Import& im);
/// Mesh: each zone's reference shape (meshes.cpp).
void read_meshes(Import& im);
/// Particle_Generation: the particles, zone by zone (particles.cpp).
void read_particles(Import& im);
/// Displacement_BC, Force_BC, IC (loading.cpp).
void read_loading(Import& im);
/// Contact (contact.cpp).
void read_contact(Import& im);
/// Output (scene.cpp).
void read_output(Import& im);
/// The scene JSON text (scene.cpp).
std::string scene_text(const Import& im, const std::string& yaml_path);

} // namespace pd::pipeline::peridem
