// SPDX-License-Identifier: MIT
#include "core/errors.hpp"
#include "mesh/discretize.hpp"
#include "mesh/shape_mesher.hpp"
#include "pipeline/peridem/import.hpp"

#include <algorithm>

namespace pd::pipeline::peridem {

namespace {

/// A zone meshed by pdgrain (CreateMesh): a grid of its deck geometry.
ZoneShape grid_shape(const Zone& z, const std::string& w, const YAML::Node& mz,
                     const YAML::Node& cm, const std::string& geo_key, double& hmin) {
    ZoneShape zs;
    const auto info = str_or(cm, w + ".CreateMesh", "Info", "uniform");
    if (info != "uniform")
        throw ConfigError(w + ".CreateMesh.Info", "'" + info + "': only uniform");
    const double h = num_or(mz, w, "Mesh_Size", num_or(cm, w + ".CreateMesh", "Mesh_Size", 0));
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
    return zs;
}

/// A zone with its own .msh: the deck geometry if it describes the mesh, else the mesh outline.
ZoneShape mesh_shape(const Import& im, const Zone& z, const std::string& w, const YAML::Node& mz,
                     const std::string& geo_key, double& hmin) {
    const Deck& d = im.d;
    const Log& log = im.log;
    const int dim = im.dim;
    const bool old_format = im.old_format;
    ZoneShape zs;
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
    return zs;
}

} // namespace

void read_meshes(Import& im) {
    const YAML::Node& R = im.R;
    const auto& zones = im.zones;
    const bool old_format = im.old_format;
    json& shapes = im.shapes;
    auto& zshape = im.zshape;
    // ---- Meshes and reference shapes
    zshape.resize(zones.size());
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
            zs = grid_shape(z, w, mz, cm, geo_key, hmin);
        } else {
            zs = mesh_shape(im, z, w, mz, geo_key, hmin);
        }
        if (zs.p0 <= 0)
            zs.p0 = zs.shape.bounding_radius();
        zshape[static_cast<std::size_t>(z.k - 1)] = zs;
        shapes[fmt::format("zone_{}", z.k)] = zs.spec;
    }
    im.discretization["mesh_size"] = hmin;
}

} // namespace pd::pipeline::peridem
