// SPDX-License-Identifier: MIT
#include "post/outline.hpp"

#include <algorithm>
#include <array>
#include <map>

namespace pd::post {

namespace {

using Facet = std::array<std::int32_t, 4>; ///< local node ids; the 4th is -1 for a triangle

/// The facets of one cell (local ids): edges in 2D, faces in 3D.
std::vector<Facet> facets(const std::int32_t* c, int npc, int dim) {
    std::vector<Facet> f;
    if (dim == 2 && (npc == 3 || npc == 4)) {
        for (int k = 0; k < npc; ++k)
            f.push_back({c[k], c[(k + 1) % npc], -1, -1});
    } else if (dim == 3 && npc == 4) {
        f = {{c[0], c[1], c[2], -1},
             {c[0], c[1], c[3], -1},
             {c[0], c[2], c[3], -1},
             {c[1], c[2], c[3], -1}};
    } else if (dim == 3 && npc == 8) { // VTK hexahedron: bottom 0-3, top 4-7
        f = {{c[0], c[3], c[2], c[1]}, {c[4], c[5], c[6], c[7]}, {c[0], c[1], c[5], c[4]},
             {c[1], c[2], c[6], c[5]}, {c[2], c[3], c[7], c[6]}, {c[3], c[0], c[4], c[7]}};
    }
    return f;
}

/// The facet's key: its nodes sorted (the same facet seen from both cells).
Facet key(Facet f) {
    const auto end = f[3] < 0 ? f.begin() + (f[2] < 0 ? 2 : 3) : f.end();
    std::sort(f.begin(), end);
    return f;
}

/// Appends the boundary facets of one body (nodes from `first`) to `out`.
void body_outline(const model::RefMesh& mesh, int dim, std::int64_t first, std::int64_t count,
                  GrainOutline& out) {
    const int npc = mesh.nodes_per_cell;
    if (npc < 2 || mesh.cells.empty())
        return;
    if (std::any_of(mesh.cells.begin(), mesh.cells.end(),
                    [&](std::int32_t i) { return i < 0 || i >= count; }))
        return;
    std::map<Facet, std::pair<int, Facet>> seen; // key -> (count, the facet as oriented)
    std::vector<Facet> order;
    for (std::size_t c = 0; c + static_cast<std::size_t>(npc) <= mesh.cells.size(); c += npc)
        for (const auto& f : facets(&mesh.cells[c], npc, dim)) {
            auto [it, fresh] = seen.try_emplace(key(f), 0, f);
            if (fresh)
                order.push_back(it->first);
            ++it->second.first;
        }
    for (const auto& k : order) {
        const auto& [n, f] = seen.at(k);
        if (n != 1)
            continue;
        if (dim == 2) {
            out.cells.insert(out.cells.end(), {first + f[0], first + f[1]});
            continue;
        }
        out.cells.insert(out.cells.end(), {first + f[0], first + f[1], first + f[2]});
        if (f[3] >= 0) // a quadrilateral face: its second triangle
            out.cells.insert(out.cells.end(), {first + f[0], first + f[2], first + f[3]});
    }
}

} // namespace

GrainOutline grain_outline(const model::Model& m) {
    GrainOutline out;
    out.points_per_cell = m.dimension == 2 ? 2 : 3;
    for (std::size_t b = 0; b < m.bodies.num(); ++b) {
        const auto r = m.bodies.ref_mesh[b];
        if (r < 0 || static_cast<std::size_t>(r) >= m.ref_meshes.size())
            continue;
        const auto first = static_cast<std::int64_t>(m.bodies.begin(b));
        body_outline(m.ref_meshes[static_cast<std::size_t>(r)], m.dimension, first,
                     static_cast<std::int64_t>(m.bodies.end(b)) - first, out);
    }
    return out;
}

} // namespace pd::post
