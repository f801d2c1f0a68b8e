// SPDX-License-Identifier: MIT
// read_model (store/model_io.hpp): the static part of a pd-file, each dataset checked for presence,
// shape and range, one step per group.
#include "core/errors.hpp"
#include "h5/file.hpp"
#include "model/wall_mesh.hpp"
#include "store/model_io.hpp"
#include "store/model_io_detail.hpp"
#include "store/schema.hpp"

#include <algorithm>
#include <cmath>

namespace pd::store {

using namespace detail;

namespace {

/// The integrator attribute and the ranges of the solver settings.
void check_solver(const h5::File& f, model::SolverSettings& S) {
    const std::string s = path::solver;
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
}

/// Flaws of a material (1.7.0; absent = none): a Weibull modulus in [0.5, 1000] and a seed >= 0
/// of a breakable PMB or LPS material breaking in tension only.
void read_flaws(const h5::File& f, const std::string& g, model::Material& mat) {
    const bool m = f.exists(g + "/flaw_modulus"), seed = f.exists(g + "/flaw_seed");
    if (!m && !seed)
        return;
    if (!m || !seed)
        throw SchemaError(f.name(), g + (m ? "/flaw_seed" : "/flaw_modulus"),
                          "missing (flaw_modulus and flaw_seed come together)");
    mat.flaw_modulus = get_scalar<double>(f, g + "/flaw_modulus");
    mat.flaw_seed = get_scalar<std::int64_t>(f, g + "/flaw_seed");
    require_between(f, g + "/flaw_modulus", mat.flaw_modulus, 0.5, 1000, "1");
    if (mat.flaw_seed < 0)
        throw SchemaError(f.name(), g + "/flaw_seed", fmt::format("{} < 0", mat.flaw_seed));
    if (f.exists(g + "/flaw_length")) { // 1.8.0: patches of one factor; absent = per bond
        mat.flaw_length = get_scalar<double>(f, g + "/flaw_length");
        require_between(f, g + "/flaw_length", mat.flaw_length, 0, 1e10, "m");
    }
    if (!mat.breakable() || mat.law == model::Law::rnp || mat.break_in_compression)
        throw SchemaError(f.name(), g + "/flaw_modulus",
                          "flaws need a breakable PMB or LPS material breaking in tension only");
}

/// /materials, ordered by their index attribute.
void read_materials(const h5::File& f, model::Model& m) {
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
        // Absent (files before 1.4.0) = tension only.
        mat.break_in_compression = f.exists(g + "/break_in_compression") &&
                                   get_scalar<std::int32_t>(f, g + "/break_in_compression") != 0;
        if (!(mat.density > 0) || !(mat.youngs_modulus > 0))
            throw SchemaError(f.name(), g, "density and youngs_modulus must be positive");
        // Far beyond any solid (diamond: E ~ 1e12 Pa, osmium: 2.2e4 kg/m3); values past these
        // overflow the stable time step and the energies.
        require_between(f, g + "/youngs_modulus", mat.youngs_modulus, 1e-6, 1e15, "Pa");
        require_between(f, g + "/density", mat.density, 1e-6, 1e6, "kg m-3");
        require_between(f, g + "/poisson_ratio", mat.poisson_ratio, -1, 0.5, "1");
        require_between(f, g + "/fracture_energy", mat.fracture_energy, 0, 1e15, "J m-2");
        read_flaws(f, g, mat);
    }
}

/// /reference_meshes.
void read_reference_meshes(const h5::File& f, model::Model& m) {
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
}

/// /bodies.
void read_bodies(const h5::File& f, model::Model& m) {
    const std::string b = path::bodies;
    auto& B = m.bodies;
    B.material = get<std::int32_t>(f, b + "/material", {0});
    const std::uint64_t nb = B.material.size();
    B.node_offsets = get<std::int64_t>(f, b + "/node_offsets", {nb + 1});
    B.group = get<std::int32_t>(f, b + "/group", {nb});
    B.ref_mesh = get<std::int32_t>(f, b + "/ref_mesh", {nb});
    auto kind = get<std::uint8_t>(f, b + "/kind", {nb});
    for (auto k : kind) {
        if (k > static_cast<std::uint8_t>(model::BodyKind::wall)) // a cast: no such kind
            throw SchemaError(f.name(), b + "/kind",
                              fmt::format("{}: expected 0 (particle) or 1 (wall)", int(k)));
        B.kind.push_back(static_cast<model::BodyKind>(k));
    }
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
}

/// /nodes, checked against /bodies.
void read_nodes(const h5::File& f, model::Model& m) {
    const auto& B = m.bodies;
    const std::string b = path::bodies;
    const std::uint64_t nb = B.material.size();
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
}

/// /bonds (the neighbours only with `neighbors`).
void read_bonds(const h5::File& f, model::Model& m, bool neighbors) {
    const std::uint64_t n = m.nodes.volume.size();
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
        detail::check_bond_pairs(f, m.bonds.offsets, m.bonds.neighbor);
    }
}

/// The contact table.
void read_contact(const h5::File& f, model::Model& m) {
    const std::string c = path::contact;
    auto ga = get<std::int32_t>(f, c + "/group_a", {0});
    const std::uint64_t np = ga.size();
    auto gb = get<std::int32_t>(f, c + "/group_b", {np});
    auto rad = get<double>(f, c + "/radius", {np});
    auto kn = get<double>(f, c + "/stiffness", {np});
    auto eps = get<double>(f, c + "/restitution", {np});
    auto mu = get<double>(f, c + "/friction", {np});
    // /contact/law (pd-file 1.5): absent in older files, whose laws are all node-to-node.
    auto law = f.exists(c + "/law") ? get<std::uint8_t>(f, c + "/law", {np})
                                    : std::vector<std::uint8_t>(np, 0);
    require_range<std::uint8_t>(f, c + "/law", law, 0, 2);
    // /contact/approach_damping (pd-file 1.8.0): absent = 0 (no PeriDEM particle damping).
    auto appr = f.exists(c + "/approach_damping") ? get<double>(f, c + "/approach_damping", {np})
                                                  : std::vector<double>(np, 0.0);
    // 1.8.0 wrote A with kappa = K_i K_j / (K_i + K_j) for a solver that used the reduced mass:
    // half PeriDEM's damping (1.8.1: both 2 a b / (a + b), PeriDEM's util::equivalentMass).
    if (f.attr_string("/", "schema_version") == "1.8.0" &&
        std::any_of(appr.begin(), appr.end(), [](double a) { return a > 0; }))
        throw SchemaError(f.name(), c + "/approach_damping",
                          "written by pd-pack of pd-file 1.8.0, whose PeriDEM particle damping "
                          "was half PeriDEM's; import the deck again (pd-pack --from-peridem "
                          "--parity peridem)");
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
        if (!(appr[k] >= 0 && appr[k] < 1e30))
            bad("approach_damping", appr[k], "must be in [0, 1e30)");
        if (appr[k] > 0 && (law[k] != 0 || m.dimension != 2))
            bad("approach_damping", appr[k], "PeriDEM's particle damping is for the 2D node law");
        m.contact.push_back(
            {ga[k], gb[k], rad[k], kn[k], eps[k], mu[k], model::ContactLaw{law[k]}, appr[k]});
    }
}

/// Wall k of the /walls arrays.
model::Wall wall_at(const h5::File& f, const std::string& w, std::size_t k,
                    const std::vector<std::uint8_t>& shape, const std::vector<std::int32_t>& group,
                    const std::vector<double>& point, const std::vector<double>& normal,
                    const std::vector<double>& radius, const std::vector<double>& vel,
                    const std::vector<double>& omega, const std::vector<double>& centre,
                    const std::vector<std::int32_t>& motion, const std::vector<double>& mparams,
                    const std::vector<double>& start) {
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
    if ((x.shape == model::WallShape::circle_inside ||
         x.shape == model::WallShape::circle_outside) &&
        !(x.radius > 0))
        throw SchemaError(f.name(), w + "/radius",
                          fmt::format("wall {}: radius must be positive", k));
    return x;
}

/// The surface of triangulated wall k (1.7.0), checked as pd-pack checks a scene's.
std::shared_ptr<const model::WallMesh> read_wall_mesh(const h5::File& f, std::size_t k, int dim) {
    const std::string g = fmt::format("{}/{}", path::wall_meshes, k);
    auto points = get<double>(f, g + "/points", {0, 3});
    auto cells = get<std::int32_t>(f, g + "/cells", {0, static_cast<std::uint64_t>(dim)});
    const auto why = model::check_wall_mesh(dim, points, cells);
    if (!why.empty())
        throw SchemaError(f.name(), g, fmt::format("wall {}: the surface {}", k, why));
    return std::make_shared<const model::WallMesh>(dim, std::move(points), std::move(cells));
}

/// Rigid walls (optional group).
void read_walls(const h5::File& f, model::Model& m) {
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
        require_range<std::uint8_t>(f, w + "/shape", shape, 0, 4);
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
        std::vector<std::uint8_t> enter(nw, 0);
        std::vector<double> gap(nw, 0.0);
        if (f.exists(w + "/enter")) { // 1.6.0
            enter = get<std::uint8_t>(f, w + "/enter", {nw});
            gap = get<double>(f, w + "/gap", {nw});
            require_range<std::uint8_t>(f, w + "/enter", enter, 0, 2);
            for (std::size_t k = 0; k < nw; ++k)
                if (!(gap[k] >= 0) || !std::isfinite(gap[k]) || (enter[k] != 0 && shape[k] != 0))
                    throw SchemaError(f.name(), w + (gap[k] >= 0 ? "/enter" : "/gap"),
                                      fmt::format("wall {}: above_grains needs a plane and a gap "
                                                  ">= 0 (gap {})",
                                                  k, gap[k]));
        }
        // The scene's names (optional for external writers; "wall_k" without them).
        std::vector<std::string> names;
        if (f.has_attr(w, "names")) {
            names = f.attr_strings(w, "names");
            if (names.size() != nw)
                throw SchemaError(f.name(), w + "@names",
                                  fmt::format("{} names for {} walls", names.size(), nw));
        }
        for (std::size_t k = 0; k < nw; ++k) {
            m.walls.push_back(wall_at(f, w, k, shape, group, point, normal, radius, vel, omega,
                                      centre, motion, mparams, start));
            m.walls.back().enter = static_cast<model::WallEnter>(enter[k]);
            m.walls.back().gap = gap[k];
            if (!names.empty() && !names[k].empty())
                m.walls.back().name = names[k];
        }
        for (std::size_t k = 0; k < nw; ++k)
            if (m.walls[k].shape == model::WallShape::mesh)
                m.walls[k].mesh = read_wall_mesh(f, k, m.dimension);
    }
}

/// A node listed twice in a condition would get the load twice (a force density 8 x over).
void refuse_repeated_nodes(const h5::File& f, const std::string& p, std::vector<std::int32_t> v) {
    std::sort(v.begin(), v.end());
    if (const auto d = std::adjacent_find(v.begin(), v.end()); d != v.end())
        throw SchemaError(f.name(), p, fmt::format("node {} is listed more than once", *d));
}

/// Gravity, damping and the node conditions.
void read_loading(const h5::File& f, model::Model& m) {
    const std::uint64_t n = m.nodes.volume.size();
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
            refuse_repeated_nodes(f, gc + "/nodes", c.nodes);
            c.amplitude = get_scalar<double>(f, gc + "/amplitude");
            auto p = get<double>(f, gc + "/parameters", {4});
            c.params = {p[0], p[1], p[2], p[3]};
            if (c.time_fn == model::TimeFn::rotation) {
                auto ce = get<double>(f, gc + "/centre", {3});
                c.centre = {ce[0], ce[1], ce[2]};
            }
            m.loading.conditions.push_back(std::move(c));
        }
}

/// Pre-cracks.
void read_cracks(const h5::File& f, model::Model& m) {
    const std::string cs = std::string(path::cracks) + "/segments";
    if (f.exists(cs)) {
        auto seg = get<double>(f, cs, {0, 2, 3});
        for (std::size_t k = 0; k + 6 <= seg.size(); k += 6)
            m.cracks.push_back(
                {{seg[k], seg[k + 1], seg[k + 2]}, {seg[k + 3], seg[k + 4], seg[k + 5]}});
    }
}

/// Solver settings.
void read_solver(const h5::File& f, model::Model& m) {
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
    S.dt_above_estimate_warns = f.exists(s + "/dt_above_estimate") &&
                                get_scalar<std::int32_t>(f, s + "/dt_above_estimate") != 0;
    S.penetration_warns = f.exists(s + "/penetration_warns") && // 1.8.1; absent = stop
                          get_scalar<std::int32_t>(f, s + "/penetration_warns") != 0;
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
    check_solver(f, S);
}

/// The fields that depend on the dimension agree with it: a 2D file's positions, centres and
/// velocities lie in the plane z = 0 and its meshes are of triangles or quadrangles; a 3D file's
/// meshes are of tetrahedra or hexahedra; each body's mesh index exists and has its node count.
void check_dimension(const h5::File& f, const model::Model& m) {
    const bool plane = m.dimension == 2;
    auto flat = [&](const std::vector<double>& v, const std::string& p) {
        for (std::size_t i = 2; i < v.size(); i += 3) // 0, up to the rounding of a rotation
            if (plane && std::abs(v[i]) > 1e-12 * (std::abs(v[i - 2]) + std::abs(v[i - 1])))
                throw SchemaError(f.name(), p,
                                  fmt::format("row {}: z = {:g} in a 2D file (attribute "
                                              "dimension = 2; z must be 0)",
                                              i / 3, v[i]));
    };
    flat(m.nodes.x0, std::string(path::nodes) + "/reference_position");
    flat(m.bodies.center, std::string(path::bodies) + "/center");
    flat(m.bodies.initial_velocity, std::string(path::bodies) + "/initial_velocity");
    for (std::size_t k = 0; k < m.ref_meshes.size(); ++k) {
        const auto& rm = m.ref_meshes[k];
        const std::string g = fmt::format("{}/mesh_{}", path::reference_meshes, k);
        flat(rm.nodes, g + "/nodes");
        const int npc = rm.nodes_per_cell;
        if (plane ? npc != 3 && npc != 4 : npc != 4 && npc != 8)
            throw SchemaError(f.name(), g + "/cells",
                              fmt::format("{} nodes per cell in a {}D file (expected {})", npc,
                                          m.dimension, plane ? "3 or 4" : "4 or 8"));
    }
    const auto& B = m.bodies;
    for (std::size_t b = 0; b < B.num() && !m.ref_meshes.empty(); ++b) {
        const auto r = B.ref_mesh[b];
        if (r < 0 || static_cast<std::size_t>(r) >= m.ref_meshes.size())
            throw SchemaError(f.name(), std::string(path::bodies) + "/ref_mesh",
                              fmt::format("body {}: mesh {} does not exist ({} meshes)", b, r,
                                          m.ref_meshes.size()));
    }
}

} // namespace

model::Model read_model(const h5::File& f, bool neighbors) {
    check_version(f);
    model::Model m;
    m.dimension = f.attr<std::int32_t>("/", "dimension");
    if (m.dimension != 2 && m.dimension != 3)
        throw SchemaError(f.name(), "/",
                          fmt::format("attribute dimension = {}, expected 2 or 3", m.dimension));
    const std::string planar = f.attr_string("/", "planar");
    if (planar != "plane_stress" && planar != "plane_strain" &&
        (planar != "none" || m.dimension != 3))
        throw SchemaError(f.name(), "/",
                          fmt::format("attribute planar: expected plane_stress or plane_strain{}",
                                      m.dimension == 3 ? " or none" : " in a 2D file"));
    m.planar = planar == "plane_strain" ? model::Planar::plane_strain : model::Planar::plane_stress;
    m.title = f.has_attr("/", "title") ? f.attr_string("/", "title") : "";
    m.scene_json = f.exists(path::parameters_scene) ? f.read_string(path::parameters_scene) : "";

    read_materials(f, m);
    read_reference_meshes(f, m);
    read_bodies(f, m);
    read_nodes(f, m);
    read_bonds(f, m, neighbors);
    read_contact(f, m);
    read_walls(f, m);
    read_loading(f, m);
    read_cracks(f, m);
    read_solver(f, m);
    check_dimension(f, m);
    m.check_consistency();
    return m;
}

} // namespace pd::store
