// SPDX-License-Identifier: MIT
#include "store/model_io.hpp"

#include "core/version.hpp"
#include "h5/file.hpp"
#include "model/wall_mesh.hpp"
#include "store/model_io_detail.hpp"
#include "store/schema.hpp"

#include <algorithm>

namespace pd::store {

using namespace detail;

namespace {

/// Root attributes, the H5MD header and the scene text.
void write_header(h5::File& f, const model::Model& m) {
    // Root attributes and H5MD header.
    f.set_attr("/", "schema", schema_name);
    f.set_attr("/", "schema_version", schema_version);
    f.set_attr("/", "units", "SI");
    f.set_attr("/", "dimension", static_cast<std::int32_t>(m.dimension));
    f.set_attr("/", "planar",
               m.dimension == 3                          ? "none"
               : m.planar == model::Planar::plane_stress ? "plane_stress"
                                                         : "plane_strain");
    f.set_attr("/", "thickness", 1.0);
    f.set_attr("/", "title", m.title);
    f.create_group("/h5md/author");
    f.create_group("/h5md/creator");
    f.create_group("/h5md/modules/units");
    f.set_attr("/h5md", "version", std::vector<std::int32_t>{1, 1});
    f.set_attr("/h5md/author", "name", "pdgrain user");
    f.set_attr("/h5md/creator", "name", "pdgrain");
    f.set_attr("/h5md/creator", "version", pd::version);
    f.set_attr("/h5md/modules/units", "version", std::vector<std::int32_t>{1, 0});
    f.set_attr("/h5md/modules/units", "system", "SI");
    f.write_string(path::parameters_scene, m.scene_json);
}

/// /materials/<name>.
void write_materials(h5::File& f, const model::Model& m) {
    f.create_group(path::materials);
    for (std::size_t k = 0; k < m.materials.size(); ++k) {
        const auto& mat = m.materials[k];
        const std::string g = std::string(path::materials) + "/" + mat.name;
        f.create_group(g);
        f.set_attr(g, "law", law_name(mat.law));
        f.set_attr(g, "influence", influence_name(mat.influence));
        f.set_attr(g, "index", static_cast<std::int32_t>(k));
        put_scalar(f, g + "/density", mat.density, "kg m-3");
        put_scalar(f, g + "/youngs_modulus", mat.youngs_modulus, "Pa");
        put_scalar(f, g + "/poisson_ratio", mat.poisson_ratio, "1");
        put_scalar(f, g + "/fracture_energy", mat.fracture_energy, "J m-2");
        put_scalar(f, g + "/break_in_compression",
                   static_cast<std::int32_t>(mat.break_in_compression), "1");
        if (mat.has_flaws()) { // 1.7.0, written only with flaws
            put_scalar(f, g + "/flaw_modulus", mat.flaw_modulus, "1");
            put_scalar(f, g + "/flaw_seed", mat.flaw_seed, "1");
            if (mat.flaw_length > 0) // 1.8.0
                put_scalar(f, g + "/flaw_length", mat.flaw_length, "m");
        }
    }
}

/// /reference_meshes/mesh_<k>.
void write_reference_meshes(h5::File& f, const model::Model& m) {
    for (std::size_t k = 0; k < m.ref_meshes.size(); ++k) {
        const auto& rm = m.ref_meshes[k];
        const std::string g = fmt::format("{}/mesh_{}", path::reference_meshes, k);
        f.create_group(g);
        f.set_attr(g, "name", rm.name);
        f.set_attr(g, "cell_type",
                   rm.nodes_per_cell == 4 && m.dimension == 3 ? "tetra"
                   : rm.nodes_per_cell == 4                   ? "quad"
                                                              : "triangle");
        put(f, g + "/nodes", rm.nodes, {rm.nodes.size() / 3, 3}, "m");
        put(f, g + "/cells", rm.cells,
            {rm.cells.size() / static_cast<std::size_t>(rm.nodes_per_cell),
             static_cast<std::uint64_t>(rm.nodes_per_cell)},
            "1");
    }
}

/// /bodies, /nodes and /bonds.
void write_bodies(h5::File& f, const model::Model& m) {
    const std::uint64_t nb = m.bodies.num(), n = m.nodes.num();
    const std::string b = path::bodies;
    const auto& B = m.bodies;
    put(f, b + "/node_offsets", B.node_offsets, {nb + 1}, "1");
    put(f, b + "/material", B.material, {nb}, "1");
    put(f, b + "/group", B.group, {nb}, "1");
    put(f, b + "/ref_mesh", B.ref_mesh, {nb}, "1");
    std::vector<std::uint8_t> kind(nb);
    std::transform(B.kind.begin(), B.kind.end(), kind.begin(),
                   [](model::BodyKind k) { return static_cast<std::uint8_t>(k); });
    put(f, b + "/kind", kind, {nb}, "1");
    put(f, b + "/fixed", B.fixed, {nb}, "1");
    put(f, b + "/center", B.center, {nb, 3}, "m");
    put(f, b + "/bounding_radius", B.bounding_radius, {nb}, "m");
    put(f, b + "/orientation", B.orientation, {nb}, "rad");
    put(f, b + "/scale", B.scale, {nb}, "1");
    put(f, b + "/initial_velocity", B.initial_velocity, {nb, 3}, "m s-1");
    put(f, b + "/mesh_size", B.mesh_size, {nb}, "m");
    put(f, b + "/horizon", B.horizon, {nb}, "m");
    // Nodes and bonds.
    put(f, std::string(path::nodes) + "/reference_position", m.nodes.x0, {n, 3}, "m");
    put(f, std::string(path::nodes) + "/volume", m.nodes.volume, {n}, "m3");
    put(f, std::string(path::nodes) + "/body", m.nodes.body, {n}, "1");
    if (!m.nodes.surface.empty())
        put(f, std::string(path::nodes) + "/surface", m.nodes.surface, {n}, "1");
    put(f, std::string(path::bonds) + "/offsets", m.bonds.offsets, {n + 1}, "1");
    put(f, std::string(path::bonds) + "/neighbor", m.bonds.neighbor, {m.bonds.num()}, "1");
}

/// The contact table.
void write_contact(h5::File& f, const model::Model& m) {
    const std::string c = path::contact;
    const std::uint64_t np = m.contact.size();
    std::vector<std::int32_t> ga, gb;
    std::vector<double> rad, kn, eps, mu, appr;
    std::vector<std::uint8_t> law;
    bool approach = false;
    for (const auto& p : m.contact) {
        appr.push_back(p.approach);
        approach = approach || p.approach > 0;
        law.push_back(static_cast<std::uint8_t>(p.law));
        ga.push_back(p.group_a);
        gb.push_back(p.group_b);
        rad.push_back(p.radius);
        kn.push_back(p.stiffness);
        eps.push_back(p.restitution);
        mu.push_back(p.friction);
    }
    f.create_group(c);
    put(f, c + "/group_a", ga, {np}, "1");
    put(f, c + "/group_b", gb, {np}, "1");
    put(f, c + "/radius", rad, {np}, "m");
    put(f, c + "/stiffness", kn, {np}, "N m-7");
    put(f, c + "/restitution", eps, {np}, "1");
    put(f, c + "/friction", mu, {np}, "1");
    put(f, c + "/law", law, {np}, "1");
    if (approach) // pd-file 1.8.0, written only when some pair has it
        put(f, c + "/approach_damping", appr, {np}, "kg1/2 m-1/2 s-1");
}

/// Rigid walls (optional group).
void write_walls(h5::File& f, const model::Model& m) {
    f.remove(path::walls);
    if (!m.walls.empty()) {
        const std::string w = path::walls;
        const std::uint64_t nw = m.walls.size();
        std::vector<std::uint8_t> shape;
        std::vector<std::int32_t> group, motion;
        std::vector<double> point, normal, radius, vel, omega, centre, mparams, start, gap;
        std::vector<std::uint8_t> enter;
        std::vector<std::string> names;
        for (const auto& x : m.walls) {
            names.push_back(x.name);
            shape.push_back(static_cast<std::uint8_t>(x.shape));
            group.push_back(x.group);
            point.insert(point.end(), x.point.begin(), x.point.end());
            normal.insert(normal.end(), x.normal.begin(), x.normal.end());
            radius.push_back(x.radius);
            vel.insert(vel.end(), x.velocity.begin(), x.velocity.end());
            omega.insert(omega.end(), x.angular_velocity.begin(), x.angular_velocity.end());
            centre.insert(centre.end(), x.centre.begin(), x.centre.end());
            motion.push_back(static_cast<std::int32_t>(x.motion));
            mparams.insert(mparams.end(), x.motion_params.begin(), x.motion_params.end());
            start.push_back(x.start_time);
            enter.push_back(static_cast<std::uint8_t>(x.enter));
            gap.push_back(x.gap);
        }
        f.create_group(w);
        f.set_attr(w, "names", names);
        put(f, w + "/shape", shape, {nw}, "1");
        put(f, w + "/group", group, {nw}, "1");
        put(f, w + "/point", point, {nw, 3}, "m");
        put(f, w + "/normal", normal, {nw, 3}, "1");
        put(f, w + "/radius", radius, {nw}, "m");
        put(f, w + "/velocity", vel, {nw, 3}, "m s-1");
        put(f, w + "/angular_velocity", omega, {nw, 3}, "rad s-1");
        put(f, w + "/centre", centre, {nw, 3}, "m");
        put(f, w + "/motion", motion, {nw}, "1");
        put(f, w + "/motion_parameters", mparams, {nw, 4}, "1");
        // 1.3.0: written only when a wall enters later (older files stay as they were).
        if (std::any_of(start.begin(), start.end(), [](double t) { return t != 0; }))
            put(f, w + "/start_time", start, {nw}, "s");
        // 1.6.0: written only when a wall enters above the grains.
        if (std::any_of(enter.begin(), enter.end(), [](std::uint8_t e) { return e != 0; })) {
            put(f, w + "/enter", enter, {nw}, "1");
            put(f, w + "/gap", gap, {nw}, "m");
        }
        // 1.7.0: the surface of each triangulated wall, in its t = 0 pose.
        for (std::size_t k = 0; k < m.walls.size(); ++k)
            if (const auto& mesh = m.walls[k].mesh; mesh) {
                const std::string g = fmt::format("{}/{}", path::wall_meshes, k);
                const auto dim = static_cast<std::uint64_t>(mesh->dim());
                put(f, g + "/points", mesh->points(), {mesh->points().size() / 3, 3}, "m");
                put(f, g + "/cells", mesh->cells(), {mesh->cells().size() / dim, dim}, "1");
            }
    }
}

/// Pre-cracks.
void write_cracks(h5::File& f, const model::Model& m) {
    f.remove(path::cracks);
    if (!m.cracks.empty()) {
        std::vector<double> seg;
        for (const auto& c : m.cracks) {
            seg.insert(seg.end(), c.p0.begin(), c.p0.end());
            seg.insert(seg.end(), c.p1.begin(), c.p1.end());
        }
        put(f, std::string(path::cracks) + "/segments", seg, {m.cracks.size(), 2, 3}, "m");
    }
}

/// Gravity, damping and the node conditions.
void write_loading(h5::File& f, const model::Model& m) {
    put(f, std::string(path::loading) + "/gravity",
        std::vector<double>(m.loading.gravity.begin(), m.loading.gravity.end()), {3}, "m s-2");
    put_scalar(f, std::string(path::loading) + "/viscous_damping", m.loading.viscous_damping,
               "s-1");
    f.remove(std::string(path::loading) + "/conditions");
    for (std::size_t k = 0; k < m.loading.conditions.size(); ++k) {
        const auto& c = m.loading.conditions[k];
        const std::string g = fmt::format("{}/conditions/{:03d}", path::loading, k);
        f.create_group(g);
        f.set_attr(g, "name", c.name);
        f.set_attr(g, "kind", c.is_force ? "force_density" : "displacement");
        f.set_attr(g, "dofs", static_cast<std::int32_t>(c.dofs));
        f.set_attr(g, "time_function", static_cast<std::int32_t>(c.time_fn));
        f.set_attr(g, "space_function", static_cast<std::int32_t>(c.space_fn));
        put(f, g + "/nodes", c.nodes, {c.nodes.size()}, "1");
        put_scalar(f, g + "/amplitude", c.amplitude, c.is_force ? "N m-3" : "m");
        put(f, g + "/parameters", std::vector<double>(c.params.begin(), c.params.end()), {4}, "1");
        if (c.time_fn == model::TimeFn::rotation)
            put(f, g + "/centre", std::vector<double>(c.centre.begin(), c.centre.end()), {3}, "m");
    }
}

/// Solver settings.
void write_solver(h5::File& f, const model::Model& m) {
    const std::string s = path::solver;
    const auto& S = m.solver;
    put_scalar(f, s + "/final_time", S.final_time, "s");
    put_scalar(f, s + "/dt", S.dt, "s");
    put_scalar(f, s + "/dt_safety", S.dt_safety, "1");
    put_scalar(f, s + "/output_interval", S.output_interval, "s");
    put_scalar(f, s + "/checkpoint_interval", S.checkpoint_interval, "s");
    put_scalar(f, s + "/observe_every", S.observe_every, "1");
    put_scalar(f, s + "/contact_skin", S.contact_skin, "m");
    put_scalar(f, s + "/surface_correction", static_cast<std::int32_t>(S.surface_correction), "1");
    put_scalar(f, s + "/quadrature_calibration",
               static_cast<std::int32_t>(S.quadrature_calibration), "1");
    if (S.dt_above_estimate_warns) // 1.6.0, written only when set
        put_scalar(f, s + "/dt_above_estimate", std::int32_t{1}, "1");
    if (S.penetration_warns) // 1.8.1, written only when set
        put_scalar(f, s + "/penetration_warns", std::int32_t{1}, "1");
    {
        std::string fl;
        for (const auto& x : S.fields)
            fl += (fl.empty() ? "" : ",") + x;
        f.set_attr(s, "fields", fl);
    }
    f.set_attr(s, "integrator",
               S.integrator == model::Integrator::velocity_verlet ? "velocity_verlet"
                                                                  : "symplectic_euler");
}

} // namespace

void write_model(h5::File& f, const model::Model& m) {
    m.check_consistency();
    write_header(f, m);
    write_materials(f, m);
    write_reference_meshes(f, m);
    write_bodies(f, m);
    write_contact(f, m);
    write_walls(f, m);
    write_cracks(f, m);
    write_loading(f, m);
    write_solver(f, m);
    f.flush();
}

void write_walls_and_loading(h5::File& f, const model::Model& m) {
    write_walls(f, m);
    write_loading(f, m);
    raise_version(f);
    f.flush();
}

void write_wall_position(h5::File& f, std::size_t k, const model::Wall& w) {
    const std::string p = path::walls;
    f.write_rows<double>(p + "/point", w.point, k, 1);
    f.write_rows<double>(p + "/centre", w.centre, k, 1);
}

std::vector<model::index_t> read_bond_rows(const h5::File& f, const model::Model& m,
                                           const std::vector<std::array<std::uint64_t, 2>>& runs) {
    const std::string p = std::string(path::bonds) + "/neighbor";
    std::vector<model::index_t> out;
    for (const auto& r : runs) {
        const auto b = static_cast<std::uint64_t>(m.bonds.offsets[r[0]]),
                   e = static_cast<std::uint64_t>(m.bonds.offsets[r[1]]);
        if (e > b) {
            auto part = f.read_rows<std::int32_t>(p, b, e - b);
            if (out.empty())
                out = std::move(part); // one run (one rank): no copy
            else
                out.insert(out.end(), part.begin(), part.end());
        }
    }
    require_range<std::int32_t>(f, p, out, 0, static_cast<std::int32_t>(m.nodes.num()));
    if (runs.size() == 1 && runs[0][0] == 0 && runs[0][1] == m.nodes.num())
        detail::check_bond_pairs(f, m.bonds.offsets, out); // the whole list: as read_model
    return out;
}

} // namespace pd::store
