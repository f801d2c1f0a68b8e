// SPDX-License-Identifier: MIT
// geometry::Shape -> gmsh OpenCASCADE entities (recursively, placements as OCC rotate/translate,
// CSG as fuse/cut, 2D and 3D), meshing, and extraction of linear cells into a RefMesh; closed
// surface meshes as gmsh discrete surfaces (classified, reparametrised, remeshed at h, bounding a
// built-in-kernel volume); uniform lattices; .msh reading through gmsh::open.
#include "mesh/shape_mesher.hpp"

#include "core/errors.hpp"
#include "core/files.hpp"
#include "mesh/gmsh_session.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <unordered_map>

namespace pd::mesh {

namespace {

using geometry::Shape;
using geometry::ShapeKind;

/// gmsh element type codes (linear cells) and their node counts.
constexpr int tri3 = 2, quad4 = 3, tet4 = 4, hex8 = 5;

/// OCC entities of `s` (placement applied), dimension 2 or 3.
gmsh::vectorpair build_occ(const Shape& s) {
    namespace occ = gmsh::model::occ;
    const auto& p = s.parameters();
    gmsh::vectorpair e;
    switch (s.kind()) {
    case ShapeKind::circle:
        e = {{2, occ::addDisk(0, 0, 0, p[0], p[0])}};
        break;
    case ShapeKind::ellipse:
        if (p[0] >= p[1]) {
            e = {{2, occ::addDisk(0, 0, 0, p[0], p[1])}};
        } else { // OCC wants rx >= ry: make it along x, turn it by 90 degrees
            e = {{2, occ::addDisk(0, 0, 0, p[1], p[0])}};
            occ::rotate(e, 0, 0, 0, 0, 0, 1, std::numbers::pi / 2);
        }
        break;
    case ShapeKind::rectangle:
        e = {{2, occ::addRectangle(-0.5 * p[0], -0.5 * p[1], 0, p[0], p[1])}};
        break;
    case ShapeKind::regular_polygon:
    case ShapeKind::drum2d:
    case ShapeKind::polygon: {
        const auto& v = s.vertices();
        std::vector<int> pts, lines;
        for (const auto& q : v)
            pts.push_back(occ::addPoint(q[0], q[1], 0));
        for (std::size_t i = 0; i < pts.size(); ++i)
            lines.push_back(occ::addLine(pts[i], pts[(i + 1) % pts.size()]));
        e = {{2, occ::addPlaneSurface({occ::addCurveLoop(lines)})}};
        break;
    }
    case ShapeKind::unite:
    case ShapeKind::difference: {
        gmsh::vectorpair object = build_occ(s.children()[0]), tools;
        for (std::size_t i = 1; i < s.children().size(); ++i) {
            const auto t = build_occ(s.children()[i]);
            tools.insert(tools.end(), t.begin(), t.end());
        }
        std::vector<gmsh::vectorpair> map;
        if (s.kind() == ShapeKind::unite)
            occ::fuse(object, tools, e, map);
        else
            occ::cut(object, tools, e, map);
        break;
    }
    case ShapeKind::sphere:
        e = {{3, occ::addSphere(0, 0, 0, p[0])}};
        break;
    case ShapeKind::box:
        e = {{3, occ::addBox(-0.5 * p[0], -0.5 * p[1], -0.5 * p[2], p[0], p[1], p[2])}};
        break;
    case ShapeKind::cylinder:
        e = {{3, occ::addCylinder(0, 0, -0.5 * p[1], 0, 0, p[1], p[0])}};
        break;
    case ShapeKind::surface_mesh:
        // gmsh 4.8 cannot turn a triangulation into an OCC solid (no STL import in OCC).
        throw InputError(fmt::format("{} inside a union/difference cannot be meshed by gmsh "
                                     "(OpenCASCADE booleans need CAD solids); use \"mesh\": "
                                     "\"grid\" for this shape",
                                     s.name()));
    }
    const auto& pl = s.placement();
    if (pl.theta != 0)
        occ::rotate(e, 0, 0, 0, 0, 0, 1, pl.theta);
    if (pl.t[0] != 0 || pl.t[1] != 0 || pl.t[2] != 0)
        occ::translate(e, pl.t[0], pl.t[1], pl.t[2]);
    return e;
}

double tri_area(const double* a, const double* b, const double* c) {
    return 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]));
}

double tet_volume(const double* a, const double* b, const double* c, const double* d) {
    double u[3], v[3], w[3];
    for (int i = 0; i < 3; ++i) {
        u[i] = b[i] - a[i];
        v[i] = c[i] - a[i];
        w[i] = d[i] - a[i];
    }
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
            u[2] * (v[0] * w[1] - v[1] * w[0])) /
           6.0;
}

/// Signed measure of one cell (2D: area, 3D: volume); positive for the orientation we emit.
double cell_measure(const model::RefMesh& m, const std::int32_t* k, int npc, int dim) {
    auto x = [&](int i) { return &m.nodes[3 * static_cast<std::size_t>(k[i])]; };
    if (dim == 2 && npc == 3)
        return tri_area(x(0), x(1), x(2));
    if (dim == 2 && npc == 4)
        return tri_area(x(0), x(1), x(2)) + tri_area(x(0), x(2), x(3));
    if (dim == 3 && npc == 4)
        return tet_volume(x(0), x(1), x(2), x(3));
    if (dim == 3 &&
        npc == 8) { // six tetrahedra around the diagonal 0-6 (exact for parallelepipeds)
        static constexpr int t[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6},
                                        {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
        double v = 0;
        for (const auto& q : t)
            v += tet_volume(x(q[0]), x(q[1]), x(q[2]), x(q[3]));
        return v;
    }
    throw InputError(
        fmt::format("mesh '{}': {}-node cells are not supported in {}D", m.name, npc, dim));
}

/// Nodes and cells of element type `type` in the current gmsh model; unused nodes dropped (kept
/// in gmsh's node order), cells turned to positive orientation.
model::RefMesh collect(const std::string& name, int type, int npc, int dim) {
    model::RefMesh m;
    m.name = name;
    m.nodes_per_cell = npc;
    std::vector<std::size_t> tags, elems, conn;
    std::vector<double> coord, param;
    gmsh::model::mesh::getNodes(tags, coord, param, -1, -1, false, false);
    gmsh::model::mesh::getElementsByType(type, elems, conn);
    std::unordered_map<std::size_t, std::size_t> slot;
    slot.reserve(tags.size());
    for (std::size_t k = 0; k < tags.size(); ++k)
        slot.emplace(tags[k], k);
    std::vector<std::int32_t> index(tags.size(), -1);
    for (std::size_t c : conn)
        index[slot.at(c)] = 0;
    std::int32_t next = 0;
    for (std::size_t k = 0; k < tags.size(); ++k)
        if (index[k] == 0) {
            index[k] = next++;
            m.nodes.insert(m.nodes.end(),
                           {coord[3 * k], coord[3 * k + 1], dim == 2 ? 0.0 : coord[3 * k + 2]});
        }
    m.cells.reserve(conn.size());
    for (std::size_t c : conn)
        m.cells.push_back(index[slot.at(c)]);
    for (std::size_t c = 0; c < m.cells.size(); c += static_cast<std::size_t>(npc)) {
        std::int32_t* k = &m.cells[c];
        if (cell_measure(m, k, npc, dim) < 0) {
            if (dim == 2)
                std::reverse(k + 1, k + npc);
            else
                std::swap(k[1], k[2]);
        }
    }
    return m;
}

/// Uniform midpoint subdivision of a triangulation (the surface is unchanged): at least once, then
/// until no edge is longer than h. gmsh 4.8's classifySurfaces(forReparametrization) loops
/// forever on a patch of one triangle (e.g. a face of a tetrahedron); after one subdivision every
/// patch has at least four.
void subdivide(std::vector<std::array<double, 3>>& x, std::vector<std::array<std::int32_t, 3>>& t,
               double h, const std::string& what) {
    for (int level = 0;; ++level) {
        double longest = 0;
        for (const auto& c : t)
            for (int k = 0; k < 3; ++k) {
                const auto& a = x[static_cast<std::size_t>(c[static_cast<std::size_t>(k)])];
                const auto& b =
                    x[static_cast<std::size_t>(c[static_cast<std::size_t>((k + 1) % 3)])];
                longest = std::max(longest, std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]));
            }
        if (level > 0 && longest <= h)
            return;
        if (t.size() > 1'000'000)
            throw InputError(fmt::format("mesh of {}: the surface would need more than 4e6 "
                                         "triangles to reach edges of h = {} m; coarsen h",
                                         what, h));
        std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> mid;
        auto middle = [&](std::int32_t a, std::int32_t b) {
            const auto key = std::minmax(a, b);
            auto [it, fresh] = mid.emplace(key, static_cast<std::int32_t>(x.size()));
            if (fresh) {
                const auto p = x[static_cast<std::size_t>(a)], q = x[static_cast<std::size_t>(b)];
                x.push_back({0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), 0.5 * (p[2] + q[2])});
            }
            return it->second;
        };
        std::vector<std::array<std::int32_t, 3>> next;
        next.reserve(4 * t.size());
        for (const auto& c : t) {
            const auto a = middle(c[0], c[1]), b = middle(c[1], c[2]), d = middle(c[2], c[0]);
            next.push_back({c[0], a, d});
            next.push_back({c[1], b, a});
            next.push_back({c[2], d, b});
            next.push_back({a, b, d});
        }
        t = std::move(next);
    }
}

/// Tetrahedra of a surface_mesh shape in the current (empty) gmsh model: its triangles (placement
/// applied, subdivided) as a discrete surface, classified into patches at 40 degrees that gmsh
/// can reparametrise, remeshed at size h and filled; the centroid embedded as a node if asked.
void build_surface_volume(const Shape& shape, double h, bool embed_centroid) {
    const auto& pl = shape.placement();
    std::vector<std::array<double, 3>> x;
    for (const auto& v : shape.surface_vertices())
        x.push_back(pl.apply(v));
    auto tris = shape.surface_triangles();
    subdivide(x, tris, h, shape.name());
    const int surface = gmsh::model::addDiscreteEntity(2);
    std::vector<std::size_t> tags;
    std::vector<double> coord;
    for (const auto& q : x) {
        tags.push_back(tags.size() + 1);
        coord.insert(coord.end(), q.begin(), q.end());
    }
    gmsh::model::mesh::addNodes(2, surface, tags, coord);
    std::vector<std::size_t> conn;
    for (const auto& t : tris)
        for (auto k : t)
            conn.push_back(static_cast<std::size_t>(k) + 1);
    gmsh::model::mesh::addElementsByType(surface, tri3, {}, conn);
    gmsh::model::mesh::classifySurfaces(40 * std::numbers::pi / 180, true, true, std::numbers::pi);
    gmsh::model::mesh::createGeometry();
    gmsh::vectorpair surfaces;
    gmsh::model::getEntities(surfaces, 2);
    std::vector<int> stags;
    for (const auto& [d, t] : surfaces)
        stags.push_back(t);
    const int volume = gmsh::model::geo::addVolume({gmsh::model::geo::addSurfaceLoop(stags)});
    gmsh::model::geo::synchronize();
    if (embed_centroid) {
        const auto c = shape.centroid();
        if (shape.clearance(c[0], c[1], c[2]) >= 0.5 * h) {
            const int pt = gmsh::model::geo::addPoint(c[0], c[1], c[2], h);
            gmsh::model::geo::synchronize();
            gmsh::model::mesh::embed(0, {pt}, 3, volume);
        }
    }
}

void check_size(const std::string& what, const Shape& shape, double h) {
    if (!(h > 0) || !std::isfinite(h) || h > shape.bounding_radius())
        throw InputError(fmt::format("{} of {}: need 0 < h <= bounding radius {} m, got h = {} m",
                                     what, shape.name(), shape.bounding_radius(), h));
}

} // namespace

// ------------------------------------------------------------------------------------------------
model::RefMesh mesh_shape(const geometry::Shape& shape, double h, const MeshOptions& opt) {
    check_size("mesh", shape, h);
    if (!(opt.min_size_factor > 0) || opt.min_size_factor > 1)
        throw InputError(fmt::format("mesh of {}: min_size_factor must be in (0, 1], got {}",
                                     shape.name(), opt.min_size_factor));
    const int dim = shape.dimension();
    if (opt.quads && dim != 2)
        throw InputError(fmt::format("mesh of {}: quadrangles are for 2D shapes", shape.name()));
    const std::string name = fmt::format("{}_h{:g}{}", shape.name(), h, opt.quads ? "_quad" : "");
    GmshSession session;
    return with_gmsh(fmt::format("mesh of {}", shape.name()), [&] {
        namespace occ = gmsh::model::occ;
        gmsh::model::add("shape");
        if (shape.kind() == ShapeKind::surface_mesh) {
            build_surface_volume(shape, h, opt.embed_centroid);
        } else {
            gmsh::vectorpair entities = build_occ(shape);
            if (opt.embed_centroid) {
                const auto c = shape.centroid();
                if (shape.clearance(c[0], c[1], c[2]) >= 0.5 * h) {
                    // Fragmenting with a point embeds it in the entity that contains it.
                    const int pt = occ::addPoint(c[0], c[1], c[2], h);
                    gmsh::vectorpair out;
                    std::vector<gmsh::vectorpair> map;
                    occ::fragment(entities, {{0, pt}}, out, map);
                }
            }
            occ::synchronize();
        }
        gmsh::option::setNumber("Mesh.MeshSizeMax", h);
        gmsh::option::setNumber("Mesh.MeshSizeMin", opt.min_size_factor * h);
        gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
        gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 1);
        // Frontal-Delaunay. (Algorithm 8, "Frontal-Delaunay for quads", segfaults in gmsh 4.8.4.)
        gmsh::option::setNumber("Mesh.Algorithm", 6);
        if (opt.quads) {
            gmsh::option::setNumber("Mesh.RecombineAll", 1);
            gmsh::option::setNumber("Mesh.RecombinationAlgorithm", 1); // Blossom
        }
        gmsh::model::mesh::generate(dim);
        if (opt.quads) {
            std::vector<std::size_t> tris, conn;
            gmsh::model::mesh::getElementsByType(tri3, tris, conn);
            if (!tris.empty()) {
                // Blossom left triangles: split every cell into quadrangles (Mesh.Subdivision),
                // starting from a mesh twice as coarse so that the final size stays near h.
                gmsh::model::mesh::clear();
                gmsh::option::setNumber("Mesh.MeshSizeMax", 2 * h);
                gmsh::option::setNumber("Mesh.MeshSizeMin", 2 * opt.min_size_factor * h);
                gmsh::option::setNumber("Mesh.SubdivisionAlgorithm", 1);
                gmsh::model::mesh::generate(2);
            }
        }
        const int type = dim == 3 ? tet4 : (opt.quads ? quad4 : tri3);
        model::RefMesh m = collect(name, type, dim == 3 ? 4 : (opt.quads ? 4 : 3), dim);
        if (m.cells.empty())
            throw InputError(
                fmt::format("mesh of {}: gmsh made no cells (h = {} m)", shape.name(), h));
        return m;
    });
}

// ------------------------------------------------------------------------------------------------
MassProperties occ_mass_properties(const geometry::Shape& shape) {
    GmshSession session;
    return with_gmsh(fmt::format("OpenCASCADE mass of {}", shape.name()), [&] {
        namespace occ = gmsh::model::occ;
        gmsh::model::add("mass");
        const gmsh::vectorpair entities = build_occ(shape);
        occ::synchronize();
        MassProperties mp;
        for (const auto& [d, tag] : entities) {
            if (d != shape.dimension())
                continue;
            double m = 0, x = 0, y = 0, z = 0;
            occ::getMass(d, tag, m);
            occ::getCenterOfMass(d, tag, x, y, z);
            mp.measure += m;
            mp.centroid[0] += m * x;
            mp.centroid[1] += m * y;
            mp.centroid[2] += m * z;
        }
        if (!(mp.measure > 0))
            throw InputError(fmt::format("OpenCASCADE mass of {}: empty", shape.name()));
        for (auto& c : mp.centroid)
            c /= mp.measure;
        return mp;
    });
}

// ------------------------------------------------------------------------------------------------
model::RefMesh uniform_grid(const geometry::Shape& shape, double h) {
    check_size("uniform grid", shape, h);
    const int dim = shape.dimension();
    const auto b = shape.bounding_box();
    std::array<long, 3> n{1, 1, 1};
    std::array<double, 3> dx{0, 0, 0};
    double total = 1;
    for (int k = 0; k < dim; ++k) {
        const double len = b[k + 3] - b[k];
        n[k] = std::max(1L, static_cast<long>(std::floor(len / h + 1e-9)));
        dx[k] = len / static_cast<double>(n[k]);
        total *= static_cast<double>(n[k] + 1);
    }
    if (total > 2e8)
        throw InputError(fmt::format("uniform grid of {}: h = {} m gives {:g} lattice points "
                                     "(limit 2e8)",
                                     shape.name(), h, total));
    const long nvx = n[0] + 1, nvy = n[1] + 1, nvz = dim == 3 ? n[2] + 1 : 1;
    auto vid = [&](long i, long j, long k) { return (k * nvy + j) * nvx + i; };
    std::vector<std::int32_t> cells;
    const long nz = dim == 3 ? n[2] : 1;
    for (long k = 0; k < nz; ++k)
        for (long j = 0; j < n[1]; ++j)
            for (long i = 0; i < n[0]; ++i) {
                const double x = b[0] + (static_cast<double>(i) + 0.5) * dx[0];
                const double y = b[1] + (static_cast<double>(j) + 0.5) * dx[1];
                const double z = dim == 3 ? b[2] + (static_cast<double>(k) + 0.5) * dx[2] : 0;
                if (!shape.contains(x, y, z))
                    continue;
                const long q[4] = {vid(i, j, k), vid(i + 1, j, k), vid(i + 1, j + 1, k),
                                   vid(i, j + 1, k)};
                for (long v : q)
                    cells.push_back(static_cast<std::int32_t>(v));
                if (dim == 3)
                    for (long v : q)
                        cells.push_back(static_cast<std::int32_t>(v + nvx * nvy));
            }
    if (cells.empty())
        throw InputError(fmt::format("uniform grid of {}: no cell centre lies inside (h = {} m)",
                                     shape.name(), h));
    // Keep only used lattice vertices, in lattice order.
    std::vector<std::int32_t> index(static_cast<std::size_t>(nvx * nvy * nvz), -1);
    for (auto v : cells)
        index[static_cast<std::size_t>(v)] = 0;
    model::RefMesh m;
    m.name = fmt::format("grid_{}_h{:g}", shape.name(), h);
    m.nodes_per_cell = dim == 3 ? 8 : 4;
    std::int32_t next = 0;
    for (long v = 0; v < nvx * nvy * nvz; ++v) {
        if (index[static_cast<std::size_t>(v)] < 0)
            continue;
        index[static_cast<std::size_t>(v)] = next++;
        const long i = v % nvx, j = (v / nvx) % nvy, k = v / (nvx * nvy);
        m.nodes.insert(m.nodes.end(), {b[0] + static_cast<double>(i) * dx[0],
                                       b[1] + static_cast<double>(j) * dx[1],
                                       dim == 3 ? b[2] + static_cast<double>(k) * dx[2] : 0.0});
    }
    for (auto& v : cells)
        v = index[static_cast<std::size_t>(v)];
    m.cells = std::move(cells);
    return m;
}

// ------------------------------------------------------------------------------------------------
model::RefMesh read_msh(const std::string& path, int dimension) {
    if (dimension != 0 && dimension != 2 && dimension != 3)
        throw InputError(
            fmt::format("{}: dimension must be 0 (auto), 2 or 3, got {}", path, dimension));
    note_input("mesh file", path);
    if (!std::ifstream(path))
        throw InputError(fmt::format("cannot open mesh file '{}'", path));
    GmshSession session;
    return with_gmsh(fmt::format("reading mesh file '{}'", path), [&] {
        gmsh::open(path);
        std::vector<int> types;
        std::vector<std::vector<std::size_t>> tags, conn;
        gmsh::model::mesh::getElements(types, tags, conn);
        auto count = [&](int type) {
            for (std::size_t i = 0; i < types.size(); ++i)
                if (types[i] == type)
                    return tags[i].size();
            return std::size_t{0};
        };
        for (int t : types) {
            std::string ename;
            int edim = 0, order = 0, nn = 0, nprim = 0;
            std::vector<double> local;
            gmsh::model::mesh::getElementProperties(t, ename, edim, order, nn, local, nprim);
            if (order > 1 && edim >= 2)
                throw InputError(fmt::format("{}: {} cells are second order; pdgrain reads "
                                             "linear triangles, quadrangles and tetrahedra",
                                             path, ename));
        }
        const std::size_t ntri = count(tri3), nquad = count(quad4), ntet = count(tet4);
        const int dim = dimension != 0 ? dimension : (ntet > 0 ? 3 : 2);
        const std::string name = std::filesystem::path(path).stem().string();
        if (dim == 3) {
            if (ntet == 0)
                throw InputError(fmt::format("{}: no tetrahedra in the file", path));
            return collect(name, tet4, 4, 3);
        }
        if (ntri > 0 && nquad > 0)
            throw InputError(fmt::format("{}: mixes {} triangles and {} quadrangles; use one "
                                         "cell type",
                                         path, ntri, nquad));
        if (ntri == 0 && nquad == 0)
            throw InputError(fmt::format("{}: no triangles or quadrangles in the file", path));
        return ntri > 0 ? collect(name, tri3, 3, 2) : collect(name, quad4, 4, 2);
    });
}

// ------------------------------------------------------------------------------------------------
std::vector<double> nodal_volumes(const model::RefMesh& m, int dimension) {
    const auto npc = static_cast<std::size_t>(m.nodes_per_cell);
    std::vector<double> v(m.nodes.size() / 3, 0.0);
    for (std::size_t c = 0; c + npc <= m.cells.size(); c += npc) {
        const double vol = std::abs(cell_measure(m, &m.cells[c], m.nodes_per_cell, dimension));
        for (std::size_t i = 0; i < npc; ++i)
            v[static_cast<std::size_t>(m.cells[c + i])] += vol / static_cast<double>(npc);
    }
    return v;
}

} // namespace pd::mesh
