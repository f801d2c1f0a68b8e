// SPDX-License-Identifier: MIT
#include "mesh/gmsh_mesher.hpp"

#include "core/errors.hpp"
#include "mesh/gmsh_session.hpp"

#include <gmsh.h>

#include <unordered_map>

namespace pd::mesh {

namespace {

/// Nodes and linear triangles of the current 2D model, renumbered from 0.
model::RefMesh collect_triangles(const std::string& name) {
    model::RefMesh m;
    m.name = name;
    m.nodes_per_cell = 3;
    std::vector<std::size_t> tags;
    std::vector<double> coord, param;
    gmsh::model::mesh::getNodes(tags, coord, param, -1, -1, false, false);
    std::unordered_map<std::size_t, std::int32_t> index;
    for (std::size_t k = 0; k < tags.size(); ++k) {
        index[tags[k]] = static_cast<std::int32_t>(k);
        m.nodes.insert(m.nodes.end(), {coord[3 * k], coord[3 * k + 1], 0.0});
    }
    std::vector<std::size_t> elems, conn;
    gmsh::model::mesh::getElementsByType(2, elems, conn); // 3-node triangles
    // Drop nodes used by no triangle (none expected, but gmsh may keep geometry points).
    std::vector<std::int32_t> used(tags.size(), -1);
    std::vector<double> nodes;
    for (std::size_t c : conn) {
        auto i = index.at(c);
        if (used[i] < 0) {
            used[i] = static_cast<std::int32_t>(nodes.size() / 3);
            nodes.insert(nodes.end(), {m.nodes[3 * i], m.nodes[3 * i + 1], 0.0});
        }
        m.cells.push_back(used[i]);
    }
    m.nodes = std::move(nodes);
    if (m.cells.empty())
        throw InputError(fmt::format("gmsh produced no triangles for '{}'", name));
    return m;
}

} // namespace

model::RefMesh mesh_disc(double radius, double h) {
    if (!(radius > 0) || !(h > 0) || h > radius)
        throw InputError(
            fmt::format("disc mesh: need 0 < h <= radius, got h = {}, radius = {}", h, radius));
    GmshSession session;
    gmsh::model::add("disc");
    const int disc = gmsh::model::occ::addDisk(0, 0, 0, radius, radius);
    const int centre = gmsh::model::occ::addPoint(0, 0, 0, h);
    gmsh::model::occ::synchronize();
    gmsh::model::mesh::embed(0, {centre}, 2, disc);
    gmsh::option::setNumber("Mesh.MeshSizeMax", h);
    gmsh::option::setNumber("Mesh.MeshSizeMin", 0.5 * h);
    gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
    gmsh::option::setNumber("Mesh.Algorithm", 6); // Frontal-Delaunay
    gmsh::model::mesh::generate(2);
    return collect_triangles(fmt::format("disc_r{:g}_h{:g}", radius, h));
}

} // namespace pd::mesh
