// SPDX-License-Identifier: MIT
// The surface law's material test for the interpenetration guard (ContactList::inside_material):
// a node of one body inside an intact cell of another body's mesh a layer below its boundary.
//
// The law's own count (surface_row: more than h/2 behind a facet the node came through) sees a
// node only through the facets, and facets cover only the reference boundary: where a boundary
// node broke off, its facets tear and the material behind them has none. In the n500 quick scene
// on the surface law (workflows/accuracy/ISSUE26_WHY.md) a node of grain 19 entered grain 27
// there and stayed 0.22-0.28 mm (1.4-1.8 h) deep among its intact nodes; the run ended with exit
// 0. This test needs no facet and no history: a node inside a cell of body B whose vertices are
// all interior nodes of B (none is a facet vertex, so the cell lies a layer of cells, about h/2
// or more, below B's reference boundary) and whose edges are all shorter than
// intact_cell_stretch x their reference length (no crack through it: a crack that lets a node of
// another body in opens the edges across it far more) and whose vertices each keep half their
// bonds (whole_, counted at the contact list's rebuilds: not rubble; two brittle discs
// shattering at 10 m/s had a detached node inside a cell of nodes that had lost every bond) is
// inside B's material; it is deep there
// when no standing facet of B is within h/2 of it (the law's own bound). That last test is
// needed: a cell of interior nodes can reach close to the boundary (a thin boundary-layer cell,
// or one squeezed at the contact); two unbreakable discs at 20 m/s had a node 0.14 h behind the
// other's boundary inside such a cell.
#include "solver/contact.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace pd::solver {

namespace {

/// Is x inside triangle (a, b, c) (xy plane; either orientation; on an edge counts)?
bool in_triangle(const double* x, const double* a, const double* b, const double* c) {
    auto cross = [](const double* p, const double* q, const double* r) {
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
    };
    const double s0 = cross(a, b, x), s1 = cross(b, c, x), s2 = cross(c, a, x);
    return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

/// Is x inside tetrahedron (a, b, c, d) (either orientation; on a face counts)?
bool in_tetrahedron(const double* x, const double* a, const double* b, const double* c,
                    const double* d) {
    auto vol = [](const double* p, const double* q, const double* r, const double* s) {
        const double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
        const double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
        const double w[3] = {s[0] - p[0], s[1] - p[1], s[2] - p[2]};
        return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
               u[2] * (v[0] * w[1] - v[1] * w[0]);
    };
    const double v0 = vol(x, b, c, d), v1 = vol(a, x, c, d), v2 = vol(a, b, x, d),
                 v3 = vol(a, b, c, x);
    return (v0 >= 0 && v1 >= 0 && v2 >= 0 && v3 >= 0) || (v0 <= 0 && v1 <= 0 && v2 <= 0 && v3 <= 0);
}

/// A grid hexahedron (bottom 0-3, top 4-7 above them) as six tetrahedra about its diagonal 0-6.
constexpr int hex_tets[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6},
                                {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};

} // namespace

void ContactList::interior_cells(const model::Model& m, const std::vector<std::uint8_t>& want) {
    icells_.clear();
    icell_npc_ = 0;
    icell_dim_ = m.dimension;
    const auto& B = m.bodies;
    const auto facet_vertex = [&](index_t k) {
        return facets_.offsets[static_cast<std::size_t>(k) + 1] >
               facets_.offsets[static_cast<std::size_t>(k)];
    };
    for (std::size_t b = 0; b < B.num(); ++b) {
        if (!want[b])
            continue;
        const auto& r = m.ref_meshes[static_cast<std::size_t>(B.ref_mesh[b])];
        const auto npc = static_cast<std::size_t>(r.nodes_per_cell);
        if (icell_npc_ != 0 && static_cast<std::size_t>(icell_npc_) != npc)
            continue; // one cell kind per model (mixed: the bodies of the first kind are tested)
        icell_npc_ = static_cast<int>(npc);
        const auto off = static_cast<index_t>(B.begin(b));
        for (std::size_t c = 0; c + npc <= r.cells.size(); c += npc) {
            bool interior = true;
            for (std::size_t a = 0; a < npc && interior; ++a)
                interior = !facet_vertex(off + r.cells[c + a]);
            if (interior)
                for (std::size_t a = 0; a < npc; ++a)
                    icells_.push_back(off + r.cells[c + a]);
        }
    }
    // Node -> its interior cells (CSR).
    const std::size_t n = m.nodes.num();
    icell_off_.assign(n + 1, 0);
    for (auto v : icells_)
        ++icell_off_[static_cast<std::size_t>(v) + 1];
    for (std::size_t i = 0; i < n; ++i)
        icell_off_[i + 1] += icell_off_[i];
    icell_of_.resize(icells_.size());
    auto next = icell_off_;
    const auto npc = static_cast<std::size_t>(std::max(icell_npc_, 1));
    for (std::size_t c = 0; c < icells_.size() / npc; ++c)
        for (std::size_t a = 0; a < npc; ++a) {
            const auto v = static_cast<std::size_t>(icells_[npc * c + a]);
            icell_of_[static_cast<std::size_t>(next[v]++)] = static_cast<std::int32_t>(c);
        }
}

bool ContactList::in_intact_cell(std::size_t i, std::size_t c, const State& s) const {
    const auto npc = static_cast<std::size_t>(icell_npc_);
    const index_t* v = &icells_[npc * c];
    // Every vertex a candidate of i (its position this step's, on every rank alike) and every
    // edge of the cell's pieces within intact_cell_stretch of its reference length.
    const auto* lo = &neighbor_[static_cast<std::size_t>(offsets_[i])];
    const auto* hi = &neighbor_[static_cast<std::size_t>(offsets_[i + 1])];
    for (std::size_t a = 0; a < npc; ++a)
        if (!std::binary_search(lo, hi, v[a]) ||
            (!whole_.empty() && !whole_[static_cast<std::size_t>(v[a])]))
            return false; // beyond the candidates, or a vertex that lost half its bonds
    const auto X = [&](index_t k) { return &s.x[3 * static_cast<std::size_t>(k)]; };
    const auto intact = [&](index_t p, index_t q) {
        double l2 = 0, r2 = 0;
        for (std::size_t d = 0; d < 3; ++d) {
            const auto P = 3 * static_cast<std::size_t>(p) + d,
                       Q = 3 * static_cast<std::size_t>(q) + d;
            const double e = s.x[Q] - s.x[P], e0 = e - (s.u[Q] - s.u[P]);
            l2 += e * e;
            r2 += e0 * e0;
        }
        return l2 <= intact_cell_stretch * intact_cell_stretch * r2;
    };
    const double* x = X(static_cast<index_t>(i));
    if (npc == 8) {
        for (const auto& t : hex_tets) {
            const index_t w[4] = {v[t[0]], v[t[1]], v[t[2]], v[t[3]]};
            if (in_tetrahedron(x, X(w[0]), X(w[1]), X(w[2]), X(w[3])))
                return intact(w[0], w[1]) && intact(w[0], w[2]) && intact(w[0], w[3]) &&
                       intact(w[1], w[2]) && intact(w[1], w[3]) && intact(w[2], w[3]);
        }
        return false;
    }
    if (npc == 4 && icell_dim_ == 3)
        return in_tetrahedron(x, X(v[0]), X(v[1]), X(v[2]), X(v[3])) && intact(v[0], v[1]) &&
               intact(v[0], v[2]) && intact(v[0], v[3]) && intact(v[1], v[2]) &&
               intact(v[1], v[3]) && intact(v[2], v[3]);
    for (std::size_t a = 1; a + 1 < npc; ++a) // 2D: a fan of triangles
        if (in_triangle(x, X(v[0]), X(v[a]), X(v[a + 1])))
            return intact(v[0], v[a]) && intact(v[a], v[a + 1]) && intact(v[a + 1], v[0]);
    return false;
}

bool ContactList::near_boundary(std::size_t a, std::size_t i, std::int32_t body,
                                const State& s) const {
    // Row a's facets of `body` (every facet its candidates are vertices of) that still stand
    // (sphere_: this evaluation's, reach -1 when torn): is i within h/2 of one?
    const auto nv = static_cast<std::size_t>(facets_.nv);
    const double d1 = 0.5 * h_body_[static_cast<std::size_t>(body)];
    for (auto q = sfac_off_[a]; q < sfac_off_[a + 1]; ++q) {
        const auto f = static_cast<std::size_t>(sfac_[static_cast<std::size_t>(q)]);
        if (facets_.body[f] != body || sphere_[4 * f + 3] < 0)
            continue;
        double p[3], w[3], n[3];
        facet_point(nv, &facets_.v[nv * f], s.x.data(), &s.x[3 * i], p, w, n);
        const double e[3] = {s.x[3 * i] - p[0], s.x[3 * i + 1] - p[1], s.x[3 * i + 2] - p[2]};
        if (e[0] * e[0] + e[1] * e[1] + e[2] * e[2] <= d1 * d1)
            return true;
    }
    return false;
}

Penetration ContactList::inside_material(const State& s) const {
    Penetration out;
    if (icells_.empty())
        return out;
    for (std::size_t a = 0; a < srows_.size(); ++a) {
        const auto i = static_cast<std::size_t>(srows_[a]);
        if (!owned_[i])
            continue;
        // Only an interior node of B within B's mesh size of i can be a vertex of a cell
        // holding i that lies a layer deep: a node at B's boundary is at least that far from
        // them.
        std::int32_t found = -1;
        for (auto k = offsets_[i]; k < offsets_[i + 1] && found < 0; ++k) {
            const auto j = static_cast<std::size_t>(neighbor_[static_cast<std::size_t>(k)]);
            if (icell_off_[j + 1] == icell_off_[j] ||
                laws_[static_cast<std::size_t>(law_[static_cast<std::size_t>(k)])].law !=
                    model::ContactLaw::surface)
                continue;
            const auto bj = s.body[j];
            const double h = h_body_[static_cast<std::size_t>(bj)];
            double r2 = 0;
            for (std::size_t d = 0; d < 3; ++d)
                r2 += (s.x[3 * j + d] - s.x[3 * i + d]) * (s.x[3 * j + d] - s.x[3 * i + d]);
            if (r2 > h * h)
                continue;
            for (auto q = icell_off_[j]; q < icell_off_[j + 1] && found < 0; ++q)
                if (in_intact_cell(
                        i, static_cast<std::size_t>(icell_of_[static_cast<std::size_t>(q)]), s))
                    found = bj;
        }
        if (found < 0 || near_boundary(a, i, found, s))
            continue;
        ++out.count;
        if (out.node < 0 || static_cast<std::int64_t>(i) < out.node) { // the smallest node
            out.node = static_cast<std::int64_t>(i);
            out.body = s.body[i];
            out.inside = found;
        }
    }
    return out;
}

} // namespace pd::solver
