// SPDX-License-Identifier: MIT
// The surface contact law's boundary facets (surface_contact.cpp): the faces of each body's
// reference mesh that belong to one cell only, oriented outward, and the node -> facet index.
#include "core/errors.hpp"
#include "solver/contact.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace pd::solver {

namespace {

/// The facets of one reference mesh (local node ids, oriented outward), nv per facet.
std::vector<std::int32_t> mesh_facets(const model::RefMesh& r, int dim) {
    const auto npc = static_cast<std::size_t>(r.nodes_per_cell);
    const auto X = [&](std::int32_t k) { return &r.nodes[3 * static_cast<std::size_t>(k)]; };
    // key (sorted vertices, -1 padded) -> (count, oriented facet, a point inside the cell)
    struct Seen {
        int count = 0;
        std::array<std::int32_t, 4> v{-1, -1, -1, -1};
        std::array<double, 3> inside{0, 0, 0};
    };
    std::map<std::array<std::int32_t, 4>, Seen> seen;
    auto add = [&](std::array<std::int32_t, 4> f, const double* in) {
        auto k = f;
        std::sort(k.begin(), k.end());
        auto& e = seen[k];
        ++e.count;
        e.v = f;
        e.inside = {in[0], in[1], in[2]};
    };
    for (std::size_t c = 0; c + npc <= r.cells.size(); c += npc) {
        const std::int32_t* v = &r.cells[c];
        double cen[3] = {0, 0, 0};
        for (std::size_t a = 0; a < npc; ++a)
            for (int d = 0; d < 3; ++d)
                cen[d] += X(v[a])[d] / static_cast<double>(npc);
        if (dim == 2) {
            for (std::size_t e = 0; e < npc; ++e)
                add({v[e], v[(e + 1) % npc], -1, -1}, cen);
        } else if (npc == 4) {
            add({v[0], v[1], v[2], -1}, cen);
            add({v[0], v[1], v[3], -1}, cen);
            add({v[0], v[2], v[3], -1}, cen);
            add({v[1], v[2], v[3], -1}, cen);
        } else if (npc == 8) { // grid hexahedron: bottom 0-3, top 4-7 above them
            const int q[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                 {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
            for (const auto& f : q)
                add({v[f[0]], v[f[1]], v[f[2]], v[f[3]]}, cen);
        } else {
            throw InputError(
                fmt::format("mesh '{}': {}-node cells have no surface contact", r.name, npc));
        }
    }
    std::vector<std::int32_t> out;
    const auto orient = [&](std::int32_t a, std::int32_t b, std::int32_t c, const double* in) {
        const double *A = X(a), *B = X(b);
        double n[3];
        if (dim == 2) {
            n[0] = B[1] - A[1];
            n[1] = -(B[0] - A[0]);
            n[2] = 0;
        } else {
            const double* C = X(c);
            const double u[3] = {B[0] - A[0], B[1] - A[1], B[2] - A[2]};
            const double w[3] = {C[0] - A[0], C[1] - A[1], C[2] - A[2]};
            n[0] = u[1] * w[2] - u[2] * w[1];
            n[1] = u[2] * w[0] - u[0] * w[2];
            n[2] = u[0] * w[1] - u[1] * w[0];
        }
        const double dot = n[0] * (in[0] - A[0]) + n[1] * (in[1] - A[1]) + n[2] * (in[2] - A[2]);
        if (dot > 0) // points into the cell: reverse
            std::swap(dim == 2 ? a : b, dim == 2 ? b : c);
        out.push_back(a);
        out.push_back(b);
        if (dim == 3)
            out.push_back(c);
    };
    for (const auto& [k, e] : seen) {
        if (e.count != 1)
            continue;
        if (dim == 2)
            orient(e.v[0], e.v[1], -1, e.inside.data());
        else {
            orient(e.v[0], e.v[1], e.v[2], e.inside.data());
            if (e.v[3] >= 0) // quad face: the second triangle
                orient(e.v[0], e.v[2], e.v[3], e.inside.data());
        }
    }
    return out;
}

/// 2D: F.across and F.blend (contact.hpp) from the reference positions x0. At a vertex shared
/// by two facets f and g of outward unit normals n_f, n_g (angle theta between them), the line
/// depths g_f, g_g of a node differ by (n_g - n_f).(v - y), |n_g - n_f| = 2 sin(theta / 2): the
/// band |g_f - g_g| < c sin(theta / 2), c = kappa min(L_f, L_g), is c / 2 wide on either side of
/// the bisector. Only convex vertices of a polygonised curve (theta up to
/// vertex_blend_max_angle in the reference) are smoothed.
void vertex_blends(Facets& F, const std::vector<double>& x0) {
    const std::size_t nf = F.num();
    F.across.assign(2 * nf, -1);
    F.blend.assign(2 * nf, 0.0);
    const auto X = [&](index_t k) { return &x0[3 * static_cast<std::size_t>(k)]; };
    // Unit outward normal and length of facet k (a, b): (b - a) rotated by -90 deg.
    const auto normal = [&](std::size_t k, double* n) {
        const double *A = X(F.v[2 * k]), *B = X(F.v[2 * k + 1]);
        const double L = std::hypot(B[0] - A[0], B[1] - A[1]);
        n[0] = (B[1] - A[1]) / L;
        n[1] = -(B[0] - A[0]) / L;
        return L;
    };
    for (std::size_t f = 0; f < nf; ++f)
        for (std::size_t e = 0; e < 2; ++e) {
            const auto v = static_cast<std::size_t>(F.v[2 * f + e]);
            if (F.offsets[v + 1] - F.offsets[v] != 2)
                continue; // not a vertex of exactly two facets
            auto g = static_cast<std::size_t>(F.of_node[static_cast<std::size_t>(F.offsets[v])]);
            if (g == f)
                g = static_cast<std::size_t>(F.of_node[static_cast<std::size_t>(F.offsets[v]) + 1]);
            if (F.body[g] != F.body[f])
                continue;
            F.across[2 * f + e] = static_cast<std::int32_t>(g);
            double nf_[2], ng[2];
            const double Lf = normal(f, nf_), Lg = normal(g, ng);
            const auto q = F.v[2 * g] == F.v[2 * f + e] ? F.v[2 * g + 1] : F.v[2 * g];
            const double* V = X(F.v[2 * f + e]);
            const double* Q = X(q);
            // Convex: g's other vertex lies behind f's line (by more than rounding).
            if (nf_[0] * (Q[0] - V[0]) + nf_[1] * (Q[1] - V[1]) >= -1e-9 * Lg)
                continue;
            const double half = 0.5 * std::hypot(ng[0] - nf_[0], ng[1] - nf_[1]);
            if (half > std::sin(0.5 * vertex_blend_max_angle))
                continue; // a corner of the shape, not a facet of a curve
            F.blend[2 * f + e] = vertex_blend_share * std::min(Lf, Lg);
        }
}

} // namespace

Facets boundary_facets(const model::Model& m, const std::vector<std::uint8_t>& want) {
    Facets F;
    F.nv = m.dimension == 3 ? 3 : 2;
    const auto nv = static_cast<std::size_t>(F.nv);
    std::map<std::int32_t, std::vector<std::int32_t>> by_mesh;
    const auto& B = m.bodies;
    for (std::size_t b = 0; b < B.num(); ++b) {
        if (!want[b])
            continue;
        const auto r = B.ref_mesh[b];
        const std::size_t n = static_cast<std::size_t>(B.end(b) - B.begin(b));
        if (r < 0 || static_cast<std::size_t>(r) >= m.ref_meshes.size() ||
            m.ref_meshes[static_cast<std::size_t>(r)].cells.empty() ||
            m.ref_meshes[static_cast<std::size_t>(r)].nodes.size() != 3 * n)
            throw InputError(fmt::format(
                "body {}: the surface contact law needs its mesh's cells (it has none, or not "
                "its {} nodes); give this pair the node law (contact \"law\": \"node\")",
                b, n));
        auto it = by_mesh.find(r);
        if (it == by_mesh.end())
            it =
                by_mesh
                    .emplace(r, mesh_facets(m.ref_meshes[static_cast<std::size_t>(r)], m.dimension))
                    .first;
        const auto off = static_cast<index_t>(B.begin(b));
        for (std::size_t k = 0; k + nv <= it->second.size(); k += nv) {
            for (std::size_t a = 0; a < nv; ++a)
                F.v.push_back(off + it->second[k + a]);
            F.body.push_back(static_cast<std::int32_t>(b));
        }
    }
    // Node -> facets (CSR), longest edge.
    const std::size_t n = m.nodes.num();
    F.offsets.assign(n + 1, 0);
    for (auto v : F.v)
        ++F.offsets[static_cast<std::size_t>(v) + 1];
    for (std::size_t i = 0; i < n; ++i)
        F.offsets[i + 1] += F.offsets[i];
    F.of_node.resize(F.v.size());
    F.edge2.assign(F.num(), 0.0);
    auto next = F.offsets;
    for (std::size_t f = 0; f < F.num(); ++f)
        for (std::size_t a = 0; a < nv; ++a) {
            const auto v = static_cast<std::size_t>(F.v[nv * f + a]);
            F.of_node[static_cast<std::size_t>(next[v]++)] = static_cast<std::int32_t>(f);
            const auto u = static_cast<std::size_t>(F.v[nv * f + (a + 1) % nv]);
            double l2 = 0;
            for (std::size_t d = 0; d < 3; ++d) {
                const double e = m.nodes.x0[3 * u + d] - m.nodes.x0[3 * v + d];
                l2 += e * e;
            }
            F.max_edge = std::max(F.max_edge, std::sqrt(l2));
            F.edge2[f] = std::max(F.edge2[f], l2);
        }
    if (F.nv == 2)
        vertex_blends(F, m.nodes.x0);
    return F;
}

} // namespace pd::solver
