// SPDX-License-Identifier: MIT
#include "core/errors.hpp"
#include "geometry/packing.hpp"
#include "pipeline/resources.hpp"
#include "pipeline/scene/build.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace pd::pipeline::scene {

namespace {

/// The "particles" list: explicit entries and generators (random_pack, lattice, csv).
class ParticleParser {
  public:
    explicit ParticleParser(SceneBuild& s)
        : log(s.log)
        , m(s.m)
        , base_dir(s.base_dir)
        , h_ref(s.dz.h_ref)
        , max_nodes(s.max_nodes)
        , root(s.root)
        , shapes(s.shapes)
        , shape_order(s.shape_order)
        , inst(s.inst)
        , material_index(s.material_index)
        , dz(s.dz)
        , user_disc(shapes.count("disc") > 0) {}

    /// particles[k]: one grain, or the grains of a generator.
    void entry(std::size_t k) {
        const json& p = root["particles"][k];
        const std::string w = fmt::format("particles[{}]", k);
        if (!p.is_object())
            throw ConfigError(w, "expected an object");
        if (!p.contains("generate")) {
            check_keys(p, w,
                       {"shape", "radius", "center", "material", "velocity", "fixed", "group",
                        "orientation", "wall"});
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
            d.wall = boolean(p, w, "wall", false);
            common(p, w, d);
            shape_named(d.shape, w, d.radius);
            inst.push_back(d);
            return;
        }
        const auto type = text(p, w, "generate", "", {"random_pack", "lattice", "csv"});
        std::vector<geometry::Grain> grains;
        std::vector<std::string> names;
        if (type == "random_pack")
            generate_random_pack(p, w, grains, names);
        else if (type == "lattice")
            generate_lattice(p, w, grains, names);
        else
            read_csv(p, w, grains, names);
        add_grains(p, w, grains, names);
    }

    /// Refuses a scene whose node or bond estimate is above the limit, before any meshing.
    void check_estimate() const {
        if (inst.empty())
            throw ConfigError("particles", "no particle was placed");
        // Each shape's mesh once, then every grain: refused before any meshing.
        std::map<std::string, double> per_shape;
        double total = 0, bonds = 0;
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
            bonds += it->second * std::min(it->second - 1,
                                           bonds_per_node(family_reach(ratio_of(d)), m.dimension));
        }
        too_many(total, "particles",
                 fmt::format("the scene ({} grains; discretization.mesh_size {:g} m)", inst.size(),
                             h_ref));
        check_bond_budget(total, bonds, max_nodes, m.dimension, state_based(), dz.horizon_key,
                          fmt::format("the scene ({} grains; discretization.mesh_size {:g} m, "
                                      "horizon up to {:.3g} x the mesh size)",
                                      inst.size(), h_ref, max_ratio()));
    }

  private:
    /// Horizon / node spacing of grain `d` (place_grains: an absolute horizon or
    /// horizon_factor x the nominal mesh size, against the grain's scaled spacing).
    double ratio_of(const Instance& d) const {
        const auto it = shapes.find(d.shape);
        const double bound = it == shapes.end() ? 0 : it->second.shape.bounding_radius();
        const double s = d.radius > 0 && bound > 0 ? d.radius / bound : 1.0;
        const double h =
            it != shapes.end() && it->second.mesh_size > 0 ? it->second.mesh_size : h_ref;
        return dz.has_h   ? dz.horizon_abs / (h * s)
               : dz.has_m ? dz.horizon_factor / s
                          : dz.horizon_factor;
    }
    double max_ratio() const {
        double r = 0;
        for (const auto& d : inst)
            r = std::max(r, ratio_of(d));
        return r;
    }

    /// Nodes of shape `name`'s mesh: area / h^2 (volume / h^3), at least 1 (a shape meshed from
    /// a file or not yet known counts 1: a lower bound, so that a grain count alone is bounded).
    double shape_nodes(const std::string& name, double radius) const {
        const bool disc = name == "disc" && !user_disc;
        if (!disc && !shapes.count(name))
            return 1.0;
        const ShapeSpec* sp = disc ? nullptr : &shapes.at(name);
        if (sp && sp->method == "file")
            return 1.0; // the file's own size
        const double h = sp && sp->mesh_size > 0 ? sp->mesh_size : h_ref;
        const double size = disc ? std::numbers::pi * std::pow(radius, m.dimension) *
                                       (m.dimension == 3 ? 4.0 / 3.0 : 1.0)
                                 : sp->shape.area_or_volume();
        double nodes = std::max(1.0, size / std::pow(h, m.dimension));
        if (!sp)
            return nodes;
        // A thin or hollow shape has few nodes per area but a long boundary, and the grid
        // method visits every lattice point of the bounding box: both bounded too.
        const auto b = sp->shape.bounding_box();
        double boundary = 0, lattice = 1;
        for (int k = 0; k < m.dimension; ++k) {
            const double len =
                (b[static_cast<std::size_t>(k) + 3] - b[static_cast<std::size_t>(k)]) / h;
            lattice *= len + 1;
            double face = 2;
            for (int j = 0; j < m.dimension; ++j)
                if (j != k)
                    face *=
                        (b[static_cast<std::size_t>(j) + 3] - b[static_cast<std::size_t>(j)]) / h +
                        1;
            boundary += face;
        }
        nodes = std::max(nodes, sp->method == "grid" ? lattice : boundary);
        return std::isfinite(nodes) ? nodes : std::numeric_limits<double>::infinity();
    }

    /// Some material keeps per-bond state (LPS, RNP): more memory per bond (resources.cpp).
    bool state_based() const {
        return std::any_of(m.materials.begin(), m.materials.end(),
                           [](const auto& mat) { return mat.law != model::Law::pmb; });
    }

    void too_many(double estimate, const std::string& key, const std::string& what) const {
        check_node_budget(estimate, max_nodes, m.dimension, state_based(), key,
                          what); // pipeline/resources
    }

    void common(const json& p, const std::string& w, Instance& d) const {
        d.velocity = vec(p, w, "velocity", m.dimension, {0, 0, 0});
        d.fixed = boolean(p, w, "fixed", false);
        d.group = static_cast<std::int32_t>(std::clamp(number(p, w, "group", 0), -1e9, 1e9));
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
    }

    void shape_named(const std::string& name, const std::string& w, double radius) {
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
    }

    static std::vector<double> fractions_of(const json& g, const std::string& w,
                                            std::vector<std::string>& names) {
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
    }

    void generate_random_pack(const json& p, const std::string& w,
                              std::vector<geometry::Grain>& grains,
                              std::vector<std::string>& names) const {
        check_keys(p, w,
                   {"generate", "container", "count", "radius", "shapes", "gap", "seed",
                    "orientation", "material", "velocity", "fixed", "group"});
        if (!p.contains("container"))
            throw ConfigError(w + ".container", "missing: the region to fill (a shape)");
        const auto container = parse_shape(p["container"], w + ".container", m.dimension, base_dir);
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
        if (!(number(p, w, "seed", 1) >= 0 && number(p, w, "seed", 1) <= 0x1p53)) // cast: UB
            throw ConfigError(w + ".seed", "must be a number from 0 to 2^53");
        o.seed = static_cast<std::uint64_t>(number(p, w, "seed", 1));
        o.random_orientation = text(p, w, "orientation", "random", {"random", "zero"}) == "random";
        // Placement tries and relaxation steps grow with the node limit, not without bound.
        o.max_work = 50.0 * (max_nodes > 0 ? max_nodes : default_max_nodes(m.dimension));
        geometry::PackStats st;
        try {
            grains = geometry::random_pack(container, o, &st);
        } catch (const ConfigError&) {
            throw;
        } catch (const InputError& e) { // name the generator (a pack that cannot fit)
            throw ConfigError(w, e.what());
        }
        log.info("{}: packed {} grains (packing fraction {:.3f}, {} by relaxation)", w,
                 grains.size(), st.packing_fraction, st.relaxed);
    }

    void generate_lattice(const json& p, const std::string& w, std::vector<geometry::Grain>& grains,
                          std::vector<std::string>& names) const {
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
        double total = 1;
        for (int d = 0; d < m.dimension; ++d) {
            const json& c = p["counts"][static_cast<std::size_t>(d)];
            if (!c.is_number() || !(c.get<double>() >= 0) || c.get<double>() > 1e15 ||
                c.get<double>() != std::floor(c.get<double>())) // a cast of 1e300: undefined
                throw ConfigError(fmt::format("{}.counts[{}]", w, d),
                                  "expected a whole number of grains from 0 to 1e15");
            o.counts[static_cast<std::size_t>(d)] = c.get<std::size_t>();
            total *= c.get<double>();
        }
        // Every grain has a node at least: the count alone is bounded before anything else.
        too_many(total, w + ".counts", fmt::format("{:.3g} grains", total));
        if (!p.contains("radius") || !p["radius"].is_array() || p["radius"].size() != 2)
            throw ConfigError(w + ".radius", "expected [rmin, rmax] (m)");
        o.rmin = p["radius"][0].get<double>();
        o.rmax = p["radius"][1].get<double>();
        o.stagger = boolean(p, w, "stagger", false);
        o.jitter = number(p, w, "jitter", 0);
        o.gap = number(p, w, "gap", 0);
        if (!(number(p, w, "seed", 1) >= 0 && number(p, w, "seed", 1) <= 0x1p53)) // cast: UB
            throw ConfigError(w + ".seed", "must be a number from 0 to 2^53");
        o.seed = static_cast<std::uint64_t>(number(p, w, "seed", 1));
        o.random_orientation = text(p, w, "orientation", "random", {"random", "zero"}) == "random";
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
    }

    void read_csv(const json& p, const std::string& w, std::vector<geometry::Grain>& grains,
                  std::vector<std::string>& names) const {
        check_keys(p, w, {"generate", "file", "shapes", "material", "velocity", "fixed", "group"});
        const auto file = text(p, w, "file", "");
        if (file.empty())
            throw ConfigError(w + ".file", "missing: a CSV of x, y, z, r, orientation, shape");
        if (!p.contains("shapes") || !p["shapes"].is_array())
            throw ConfigError(w + ".shapes", "expected the list of shape names, by CSV index");
        for (const auto& n : p["shapes"])
            names.push_back(n.get<std::string>());
        grains = geometry::read_particle_csv(resolve(base_dir, file, w + ".file"));
    }

    /// The generated grains as instances of the generator's material, velocity and group.
    void add_grains(const json& p, const std::string& w, const std::vector<geometry::Grain>& grains,
                    const std::vector<std::string>& names) {
        Instance tmpl;
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

    const Log& log;
    const model::Model& m;
    const Folder& base_dir;
    const double h_ref;
    const double max_nodes;
    const json& root;
    std::map<std::string, ShapeSpec>& shapes;
    std::vector<std::string>& shape_order;
    std::vector<Instance>& inst;
    const std::map<std::string, std::int32_t>& material_index;
    const Discretization& dz;
    // Node estimate before anything is meshed or packed (a mesh_size far too small, a huge
    // radius or count would run for minutes or exhaust memory): a reference shape gets about
    // area / h^2 (volume / h^3) nodes, and each grain is an instance of its shape's mesh.
    const bool user_disc; // else a disc is made per particle radius
};

} // namespace

void parse_particles(SceneBuild& s) {
    const json& root = s.root;
    // Particles: explicit entries and generators (random_pack, lattice, csv).
    if (!root.contains("particles") || !root["particles"].is_array() || root["particles"].empty())
        throw ConfigError("particles", "missing: give a list of particles or generators");
    ParticleParser particles(s);
    for (std::size_t k = 0; k < root["particles"].size(); ++k)
        particles.entry(k);
    particles.check_estimate();
}

} // namespace pd::pipeline::scene
