// SPDX-License-Identifier: MIT
#include "store/model_io.hpp"

#include "core/errors.hpp"
#include "core/version.hpp"
#include "h5/file.hpp"
#include "store/schema.hpp"

#include <algorithm>
#include <cmath>

namespace pd::store {

namespace {

using h5::dims_t;

template <class T>
void put(h5::File& f, const std::string& p, const std::vector<T>& v, const dims_t& dims,
         const char* unit) {
    f.write(p, v, dims);
    f.set_attr(p, "unit", unit);
}

template <class T>
void put_scalar(h5::File& f, const std::string& p, T v, const char* unit) {
    f.write_scalar(p, v);
    f.set_attr(p, "unit", unit);
}

/// Reads `p` and checks its shape against `want` (0 in `want` = any extent).
template <class T>
std::vector<T> get(const h5::File& f, const std::string& p, const dims_t& want) {
    if (!f.exists(p))
        throw SchemaError(f.name(), p, "missing dataset");
    dims_t got;
    auto v = f.read<T>(p, &got);
    bool ok = got.size() == want.size();
    for (std::size_t i = 0; ok && i < want.size(); ++i)
        ok = want[i] == 0 || want[i] == got[i];
    if (!ok) {
        auto fmt_dims = [](const dims_t& d) {
            std::string s = "(";
            for (std::size_t i = 0; i < d.size(); ++i)
                s += (i ? ", " : "") + (d[i] ? std::to_string(d[i]) : std::string("any"));
            return s + (d.size() == 1 ? ",)" : ")");
        };
        throw SchemaError(f.name(), p,
                          fmt::format("shape {}, expected {} (pd-file {})", fmt_dims(got),
                                      fmt_dims(want), schema_version));
    }
    if constexpr (std::is_floating_point_v<T>) {
        for (std::size_t i = 0; i < v.size(); ++i)
            if (!std::isfinite(v[i]))
                throw SchemaError(f.name(), p, fmt::format("entry {} is not finite", i));
    }
    return v;
}

template <class T>
T get_scalar(const h5::File& f, const std::string& p) {
    if (!f.exists(p))
        throw SchemaError(f.name(), p, "missing dataset");
    const T v = f.read_scalar<T>(p);
    if constexpr (std::is_floating_point_v<T>)
        if (!std::isfinite(v))
            throw SchemaError(f.name(), p, fmt::format("{} is not finite", v));
    return v;
}

/// `v` in [lo, hi] (a physical scalar of a material or the solver).
void require_between(const h5::File& f, const std::string& p, double v, double lo, double hi,
                     const char* what) {
    if (!(v >= lo && v <= hi))
        throw SchemaError(f.name(), p,
                          fmt::format("{} outside [{:g}, {:g}] ({})", v, lo, hi, what));
}

/// Contact and wall groups index a groups x groups law table: the scene's range.
constexpr std::int32_t max_group = 1000;

template <class T>
void require_range(const h5::File& f, const std::string& p, const std::vector<T>& v, T lo, T hi) {
    for (std::size_t i = 0; i < v.size(); ++i)
        if (v[i] < lo || v[i] >= hi)
            throw SchemaError(f.name(), p,
                              fmt::format("entry {} = {} outside [{}, {})", i, v[i], lo, hi));
}

const char* law_name(model::Law l) {
    return l == model::Law::lps ? "lps" : l == model::Law::rnp ? "rnp" : "pmb";
}

const char* influence_name(model::Influence f) {
    return f == model::Influence::linear     ? "linear"
           : f == model::Influence::gaussian ? "gaussian"
                                             : "constant";
}

} // namespace

void write_model(h5::File& f, const model::Model& m) {
    m.check_consistency();
    const std::uint64_t nb = m.bodies.num(), n = m.nodes.num();
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

    // Materials.
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
    }
    // Reference meshes.
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
    // Bodies.
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
    // Contact table.
    const std::string c = path::contact;
    const std::uint64_t np = m.contact.size();
    std::vector<std::int32_t> ga, gb;
    std::vector<double> rad, kn, eps, mu;
    for (const auto& p : m.contact) {
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
    // Rigid walls (optional group).
    f.remove(path::walls);
    if (!m.walls.empty()) {
        const std::string w = path::walls;
        const std::uint64_t nw = m.walls.size();
        std::vector<std::uint8_t> shape;
        std::vector<std::int32_t> group, motion;
        std::vector<double> point, normal, radius, vel, omega, centre, mparams, start;
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
    }
    // Pre-cracks.
    f.remove(path::cracks);
    if (!m.cracks.empty()) {
        std::vector<double> seg;
        for (const auto& c : m.cracks) {
            seg.insert(seg.end(), c.p0.begin(), c.p0.end());
            seg.insert(seg.end(), c.p1.begin(), c.p1.end());
        }
        put(f, std::string(path::cracks) + "/segments", seg, {m.cracks.size(), 2, 3}, "m");
    }
    // Loading and solver settings.
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
    {
        std::string fl;
        for (const auto& x : S.fields)
            fl += (fl.empty() ? "" : ",") + x;
        f.set_attr(s, "fields", fl);
    }
    f.set_attr(s, "integrator",
               S.integrator == model::Integrator::velocity_verlet ? "velocity_verlet"
                                                                  : "symplectic_euler");
    f.flush();
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
            out.insert(out.end(), part.begin(), part.end());
        }
    }
    require_range<std::int32_t>(f, p, out, 0, static_cast<std::int32_t>(m.nodes.num()));
    return out;
}

model::Model read_model(const h5::File& f, bool neighbors) {
    check_version(f);
    model::Model m;
    m.dimension = f.attr<std::int32_t>("/", "dimension");
    if (m.dimension != 2 && m.dimension != 3)
        throw SchemaError(f.name(), "/",
                          fmt::format("attribute dimension = {}, expected 2 or 3", m.dimension));
    const std::string planar = f.attr_string("/", "planar");
    m.planar = planar == "plane_strain" ? model::Planar::plane_strain : model::Planar::plane_stress;
    m.title = f.has_attr("/", "title") ? f.attr_string("/", "title") : "";
    m.scene_json = f.exists(path::parameters_scene) ? f.read_string(path::parameters_scene) : "";

    // Materials (ordered by their index attribute).
    if (!f.exists(path::materials))
        throw SchemaError(f.name(), path::materials, "missing group");
    auto names = f.list(path::materials);
    m.materials.resize(names.size());
    for (const auto& name : names) {
        const std::string g = std::string(path::materials) + "/" + name;
        auto k = f.attr<std::int32_t>(g, "index");
        if (k < 0 || static_cast<std::size_t>(k) >= names.size())
            throw SchemaError(f.name(), g, fmt::format("index {} out of range", k));
        auto& mat = m.materials[static_cast<std::size_t>(k)];
        mat.name = name;
        const auto law = f.attr_string(g, "law");
        if (law != "pmb" && law != "lps" && law != "rnp")
            throw SchemaError(f.name(), g, "law '" + law + "' unknown (pmb, lps, rnp)");
        mat.law = law == "lps" ? model::Law::lps : law == "rnp" ? model::Law::rnp : model::Law::pmb;
        const auto inf = f.has_attr(g, "influence") ? f.attr_string(g, "influence") : "constant";
        if (inf != "constant" && inf != "linear" && inf != "gaussian")
            throw SchemaError(f.name(), g, "influence '" + inf + "' unknown");
        mat.influence = inf == "linear"     ? model::Influence::linear
                        : inf == "gaussian" ? model::Influence::gaussian
                                            : model::Influence::constant;
        mat.density = get_scalar<double>(f, g + "/density");
        mat.youngs_modulus = get_scalar<double>(f, g + "/youngs_modulus");
        mat.poisson_ratio = get_scalar<double>(f, g + "/poisson_ratio");
        mat.fracture_energy = get_scalar<double>(f, g + "/fracture_energy");
        if (!(mat.density > 0) || !(mat.youngs_modulus > 0))
            throw SchemaError(f.name(), g, "density and youngs_modulus must be positive");
        // Far beyond any solid (diamond: E ~ 1e12 Pa, osmium: 2.2e4 kg/m3); values past these
        // overflow the stable time step and the energies.
        require_between(f, g + "/youngs_modulus", mat.youngs_modulus, 1e-6, 1e15, "Pa");
        require_between(f, g + "/density", mat.density, 1e-6, 1e6, "kg m-3");
        require_between(f, g + "/poisson_ratio", mat.poisson_ratio, -1, 0.5, "1");
        require_between(f, g + "/fracture_energy", mat.fracture_energy, 0, 1e15, "J m-2");
    }
    // Reference meshes.
    if (f.exists(path::reference_meshes)) {
        for (std::size_t k = 0;; ++k) {
            const std::string g = fmt::format("{}/mesh_{}", path::reference_meshes, k);
            if (!f.exists(g))
                break;
            model::RefMesh rm;
            rm.name = f.attr_string(g, "name");
            rm.nodes = get<double>(f, g + "/nodes", {0, 3});
            h5::dims_t d;
            rm.cells = f.read<std::int32_t>(g + "/cells", &d);
            rm.nodes_per_cell = d.size() == 2 ? static_cast<int>(d[1]) : 3;
            m.ref_meshes.push_back(std::move(rm));
        }
    }
    // Bodies.
    const std::string b = path::bodies;
    auto& B = m.bodies;
    B.material = get<std::int32_t>(f, b + "/material", {0});
    const std::uint64_t nb = B.material.size();
    B.node_offsets = get<std::int64_t>(f, b + "/node_offsets", {nb + 1});
    B.group = get<std::int32_t>(f, b + "/group", {nb});
    B.ref_mesh = get<std::int32_t>(f, b + "/ref_mesh", {nb});
    auto kind = get<std::uint8_t>(f, b + "/kind", {nb});
    for (auto k : kind)
        B.kind.push_back(static_cast<model::BodyKind>(k));
    B.fixed = get<std::uint8_t>(f, b + "/fixed", {nb});
    B.center = get<double>(f, b + "/center", {nb, 3});
    B.bounding_radius = get<double>(f, b + "/bounding_radius", {nb});
    B.orientation = get<double>(f, b + "/orientation", {nb});
    B.scale = get<double>(f, b + "/scale", {nb});
    B.initial_velocity = get<double>(f, b + "/initial_velocity", {nb, 3});
    B.mesh_size = get<double>(f, b + "/mesh_size", {nb});
    B.horizon = get<double>(f, b + "/horizon", {nb});
    require_range<std::int32_t>(f, b + "/material", B.material, 0,
                                static_cast<std::int32_t>(m.materials.size()));
    require_range<std::int32_t>(f, b + "/group", B.group, 0, max_group + 1);
    for (std::size_t i = 0; i < nb; ++i)
        if (!(B.horizon[i] > 0) || !(B.mesh_size[i] > 0))
            throw SchemaError(f.name(), b + "/horizon",
                              fmt::format("body {}: horizon and mesh_size must be positive", i));
    // Nodes.
    const std::string nd = path::nodes;
    m.nodes.volume = get<double>(f, nd + "/volume", {0});
    const std::uint64_t n = m.nodes.volume.size();
    m.nodes.x0 = get<double>(f, nd + "/reference_position", {n, 3});
    m.nodes.body = get<std::int32_t>(f, nd + "/body", {n});
    if (f.exists(nd + "/surface"))
        m.nodes.surface = get<std::uint8_t>(f, nd + "/surface", {n});
    require_range<std::int32_t>(f, nd + "/body", m.nodes.body, 0, static_cast<std::int32_t>(nb));
    for (std::size_t i = 0; i < n; ++i)
        if (!(m.nodes.volume[i] > 0))
            throw SchemaError(
                f.name(), nd + "/volume",
                fmt::format("node {} has non-positive volume {}", i, m.nodes.volume[i]));
    if (B.node_offsets.front() != 0 || B.node_offsets.back() != static_cast<std::int64_t>(n) ||
        !std::is_sorted(B.node_offsets.begin(), B.node_offsets.end()))
        throw SchemaError(f.name(), b + "/node_offsets",
                          fmt::format("must rise from 0 to the node count {}", n));
    for (std::size_t k = 0; k < nb; ++k)
        for (auto i = B.node_offsets[k]; i < B.node_offsets[k + 1]; ++i)
            if (m.nodes.body[static_cast<std::size_t>(i)] != static_cast<std::int32_t>(k))
                throw SchemaError(
                    f.name(), nd + "/body",
                    fmt::format("node {} is of body {}, but /bodies/node_offsets puts it in body "
                                "{} (the two datasets disagree)",
                                i, m.nodes.body[static_cast<std::size_t>(i)], k));
    // Bonds.
    const std::string bo = path::bonds;
    m.bonds.offsets = get<std::int64_t>(f, bo + "/offsets", {n + 1});
    const auto shape = f.shape(bo + "/neighbor");
    const std::uint64_t nbond = shape.size() == 1 ? shape[0] : 0;
    if (shape.size() != 1)
        throw SchemaError(f.name(), bo + "/neighbor", "must be one-dimensional");
    if (m.bonds.offsets.front() != 0 ||
        m.bonds.offsets.back() != static_cast<std::int64_t>(nbond) ||
        !std::is_sorted(m.bonds.offsets.begin(), m.bonds.offsets.end()))
        throw SchemaError(f.name(), bo + "/offsets",
                          fmt::format("must rise from 0 to the bond count {}", nbond));
    if (neighbors) {
        m.bonds.neighbor = get<std::int32_t>(f, bo + "/neighbor", {0});
        require_range<std::int32_t>(f, bo + "/neighbor", m.bonds.neighbor, 0,
                                    static_cast<std::int32_t>(n));
    }
    // Contact.
    const std::string c = path::contact;
    auto ga = get<std::int32_t>(f, c + "/group_a", {0});
    const std::uint64_t np = ga.size();
    auto gb = get<std::int32_t>(f, c + "/group_b", {np});
    auto rad = get<double>(f, c + "/radius", {np});
    auto kn = get<double>(f, c + "/stiffness", {np});
    auto eps = get<double>(f, c + "/restitution", {np});
    auto mu = get<double>(f, c + "/friction", {np});
    require_range<std::int32_t>(f, c + "/group_a", ga, 0, max_group + 1);
    require_range<std::int32_t>(f, c + "/group_b", gb, 0, max_group + 1);
    for (std::size_t k = 0; k < np; ++k) {
        auto bad = [&](const char* name, double v, const char* why) {
            throw SchemaError(f.name(), c + "/" + name,
                              fmt::format("entry {} = {}: {}", k, v, why));
        };
        if (!(kn[k] >= 0) || kn[k] > 1e30)
            bad("stiffness", kn[k], "must be in [0, 1e30] (0: no contact)");
        if (!(rad[k] >= 0))
            bad("radius", rad[k], "must be >= 0");
        if (!(eps[k] >= 0 && eps[k] <= 1))
            bad("restitution", eps[k], "must be in [0, 1]");
        if (!(mu[k] >= 0))
            bad("friction", mu[k], "must be >= 0");
        m.contact.push_back({ga[k], gb[k], rad[k], kn[k], eps[k], mu[k]});
    }
    // Rigid walls.
    if (f.exists(path::walls)) {
        const std::string w = path::walls;
        auto shape = get<std::uint8_t>(f, w + "/shape", {0});
        const std::uint64_t nw = shape.size();
        auto group = get<std::int32_t>(f, w + "/group", {nw});
        auto point = get<double>(f, w + "/point", {nw, 3});
        auto normal = get<double>(f, w + "/normal", {nw, 3});
        auto radius = get<double>(f, w + "/radius", {nw});
        auto vel = get<double>(f, w + "/velocity", {nw, 3});
        auto omega = get<double>(f, w + "/angular_velocity", {nw, 3});
        auto centre = get<double>(f, w + "/centre", {nw, 3});
        require_range<std::uint8_t>(f, w + "/shape", shape, 0, 3);
        require_range<std::int32_t>(f, w + "/group", group, 0, max_group + 1);
        std::vector<std::int32_t> motion(nw, static_cast<std::int32_t>(model::TimeFn::linear));
        std::vector<double> mparams(4 * nw, 0.0);
        if (f.exists(w + "/motion")) {
            motion = get<std::int32_t>(f, w + "/motion", {nw});
            mparams = get<double>(f, w + "/motion_parameters", {nw, 4});
            for (auto mo : motion)
                if (mo < 1 || mo > 6 || mo == 4)
                    throw SchemaError(f.name(), w + "/motion",
                                      fmt::format("{} is not a wall motion (1-3, 5, 6)", mo));
        }
        std::vector<double> start(nw, 0.0);
        if (f.exists(w + "/start_time")) {
            start = get<double>(f, w + "/start_time", {nw});
            for (std::size_t k = 0; k < nw; ++k)
                if (!(start[k] >= 0) || !std::isfinite(start[k]))
                    throw SchemaError(f.name(), w + "/start_time",
                                      fmt::format("wall {}: {} is not a time >= 0", k, start[k]));
        }
        for (std::size_t k = 0; k < nw; ++k) {
            model::Wall x;
            x.name = fmt::format("wall_{}", k);
            x.shape = static_cast<model::WallShape>(shape[k]);
            x.group = group[k];
            for (std::size_t d = 0; d < 3; ++d) {
                x.point[d] = point[3 * k + d];
                x.normal[d] = normal[3 * k + d];
                x.velocity[d] = vel[3 * k + d];
                x.angular_velocity[d] = omega[3 * k + d];
                x.centre[d] = centre[3 * k + d];
            }
            x.radius = radius[k];
            x.motion = static_cast<model::TimeFn>(motion[k]);
            for (std::size_t q = 0; q < 4; ++q)
                x.motion_params[q] = mparams[4 * k + q];
            x.start_time = start[k];
            const double nn = std::sqrt(x.normal[0] * x.normal[0] + x.normal[1] * x.normal[1] +
                                        x.normal[2] * x.normal[2]);
            if (x.shape == model::WallShape::plane && std::abs(nn - 1) > 1e-9)
                throw SchemaError(f.name(), w + "/normal",
                                  fmt::format("wall {}: normal must be a unit vector", k));
            if (x.shape != model::WallShape::plane && !(x.radius > 0))
                throw SchemaError(f.name(), w + "/radius",
                                  fmt::format("wall {}: radius must be positive", k));
            m.walls.push_back(x);
        }
    }
    // Loading and solver.
    auto g = get<double>(f, std::string(path::loading) + "/gravity", {3});
    m.loading.gravity = {g[0], g[1], g[2]};
    const std::string lvd = std::string(path::loading) + "/viscous_damping";
    m.loading.viscous_damping = f.exists(lvd) ? get_scalar<double>(f, lvd) : 0.0;
    const std::string lc = std::string(path::loading) + "/conditions";
    if (f.exists(lc))
        for (const auto& name : f.list(lc)) {
            const std::string gc = lc + "/" + name;
            model::NodeCondition c;
            c.name = f.attr_string(gc, "name");
            const auto kind = f.attr_string(gc, "kind");
            if (kind != "displacement" && kind != "force_density")
                throw SchemaError(f.name(), gc, "kind '" + kind + "' unknown");
            c.is_force = kind == "force_density";
            c.dofs = static_cast<std::uint8_t>(f.attr<std::int32_t>(gc, "dofs"));
            const auto tf = f.attr<std::int32_t>(gc, "time_function");
            const auto sf = f.attr<std::int32_t>(gc, "space_function");
            if (tf < 0 || tf > 6 || sf < 0 || sf > 5 || c.dofs == 0 || c.dofs > 7)
                throw SchemaError(f.name(), gc, "bad dofs, time_function or space_function");
            c.time_fn = static_cast<model::TimeFn>(tf);
            c.space_fn = static_cast<model::SpaceFn>(sf);
            c.nodes = get<std::int32_t>(f, gc + "/nodes", {0});
            require_range<std::int32_t>(f, gc + "/nodes", c.nodes, 0, static_cast<std::int32_t>(n));
            c.amplitude = get_scalar<double>(f, gc + "/amplitude");
            auto p = get<double>(f, gc + "/parameters", {4});
            c.params = {p[0], p[1], p[2], p[3]};
            if (c.time_fn == model::TimeFn::rotation) {
                auto ce = get<double>(f, gc + "/centre", {3});
                c.centre = {ce[0], ce[1], ce[2]};
            }
            m.loading.conditions.push_back(std::move(c));
        }
    const std::string cs = std::string(path::cracks) + "/segments";
    if (f.exists(cs)) {
        auto seg = get<double>(f, cs, {0, 2, 3});
        for (std::size_t k = 0; k + 6 <= seg.size(); k += 6)
            m.cracks.push_back(
                {{seg[k], seg[k + 1], seg[k + 2]}, {seg[k + 3], seg[k + 4], seg[k + 5]}});
    }
    const std::string s = path::solver;
    auto& S = m.solver;
    S.final_time = get_scalar<double>(f, s + "/final_time");
    S.dt = get_scalar<double>(f, s + "/dt");
    S.dt_safety = get_scalar<double>(f, s + "/dt_safety");
    S.output_interval = get_scalar<double>(f, s + "/output_interval");
    S.checkpoint_interval = f.exists(s + "/checkpoint_interval")
                                ? get_scalar<double>(f, s + "/checkpoint_interval")
                                : 0.0;
    S.observe_every = get_scalar<std::int64_t>(f, s + "/observe_every");
    S.contact_skin = get_scalar<double>(f, s + "/contact_skin");
    S.surface_correction = f.exists(s + "/surface_correction") &&
                           get_scalar<std::int32_t>(f, s + "/surface_correction") != 0;
    // Absent (files before 1.3.0) = off: such a file solves as it did when it was written.
    S.quadrature_calibration = f.exists(s + "/quadrature_calibration") &&
                               get_scalar<std::int32_t>(f, s + "/quadrature_calibration") != 0;
    if (f.has_attr(s, "fields")) {
        S.fields.clear();
        std::string fl = f.attr_string(s, "fields");
        for (std::size_t a = 0; a < fl.size();) {
            auto b = fl.find(',', a);
            if (b == std::string::npos)
                b = fl.size();
            const auto x = fl.substr(a, b - a);
            if (x != "velocity" && x != "displacement" && x != "force" && x != "damage" &&
                x != "damage_z" && x != "fragment" && x != "broken_bonds")
                throw SchemaError(f.name(), s, "fields: '" + x + "' is not a frame field");
            S.fields.push_back(x);
            a = b + 1;
        }
    }
    const std::string integ = f.attr_string(s, "integrator");
    if (integ == "velocity_verlet")
        S.integrator = model::Integrator::velocity_verlet;
    else if (integ == "symplectic_euler")
        S.integrator = model::Integrator::symplectic_euler;
    else
        throw SchemaError(f.name(), s, "integrator '" + integ + "' unknown");
    if (!(S.final_time > 0))
        throw SchemaError(f.name(), s + "/final_time", "must be positive");
    if (!(S.dt >= 0))
        throw SchemaError(f.name(), s + "/dt", fmt::format("{} s: must be > 0 (0: auto)", S.dt));
    if (!(S.dt_safety > 0))
        throw SchemaError(f.name(), s + "/dt_safety", fmt::format("{}: must be > 0", S.dt_safety));
    if (!(S.output_interval >= 0))
        throw SchemaError(f.name(), s + "/output_interval",
                          fmt::format("{} s: must be >= 0", S.output_interval));
    if (!(S.checkpoint_interval >= 0))
        throw SchemaError(f.name(), s + "/checkpoint_interval",
                          fmt::format("{} s: must be >= 0", S.checkpoint_interval));
    if (S.observe_every < 1)
        throw SchemaError(f.name(), s + "/observe_every",
                          fmt::format("{}: must be at least 1", S.observe_every));
    if (!(S.contact_skin >= 0))
        throw SchemaError(f.name(), s + "/contact_skin",
                          fmt::format("{}: must be >= 0", S.contact_skin));
    m.check_consistency();
    return m;
}

} // namespace pd::store
