// SPDX-License-Identifier: MIT
// The surface contact law (model::ContactLaw::surface): node-to-boundary penalty contact.
//
// Every node i that lies inside another body B (behind B's deformed boundary facets) gets the
// force density U'(d) (p - y_i) / d, p the closest point of B's boundary to y_i, d = |p - y_i|,
// U the penalty of surface_penalty.hpp (c d, c the pair's stiffness in N m-5, past a C1 onset
// over 0.01 h); the nodes of the facet that holds p get the reaction, shared by p's barycentric
// weights, so momentum is conserved exactly and, p - y_i being normal to the facet when p is
// inside it, so is angular momentum. The force derives from the potential U(|p - y_i|) V_i
// (the closest point is stationary), so the contact energy is exact. Both bodies play both parts
// (each node against the other's facets): no node can slip between two nodes of the other body,
// since the boundary between them is a facet, whatever the mesh size; and the force acts at
// contact (no radius), so grains at rest touch.
//
// This is the node-to-segment / node-to-surface penalty of finite-element contact (Wriggers,
// Computational Contact Mechanics, 2nd ed., Springer 2006, ch. 4 and 8: two-pass, closest-point
// projection) with a penalty that scales as the material's modulus over h^2 (a pressure ~ E/h
// per unit gap: the penalty layer is ~ h thick and vanishes with the mesh), as in peridynamic
// contact of deformable bodies against their boundaries (Kamensky et al., CMAME 344 (2019):
// a penalty ~ E / h between a PD body and a surface).
//
// Inside or out: the closest point of B's boundary decides. The facets tried are those incident
// to B's boundary nodes among i's candidates (within the search radius, which is 1.5 x B's
// longest facet edge + skin, so a node less than half an edge inside B always finds the facet
// it entered through). Among the facets at the smallest distance, i is inside when its offset
// y_i - p points against every one of their outward normals (a shared vertex or edge: inside a
// reflex corner both normals point away; outside a convex corner one does not).
#include "solver/contact.hpp"
#include "solver/surface_penalty.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pd::solver {

namespace {

/// Closest point of segment (a, b) to x: weights (1 - t, t).
void closest_on_segment(const double* x, const double* a, const double* b, double* p, double* w) {
    double ab[3], ax[3];
    for (int d = 0; d < 3; ++d) {
        ab[d] = b[d] - a[d];
        ax[d] = x[d] - a[d];
    }
    const double l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    double t = l2 > 0 ? (ax[0] * ab[0] + ax[1] * ab[1] + ax[2] * ab[2]) / l2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    for (int d = 0; d < 3; ++d)
        p[d] = a[d] + t * ab[d];
    w[0] = 1 - t;
    w[1] = t;
    w[2] = 0;
}

/// Closest point of triangle (a, b, c) to x, with its barycentric weights (Ericson, Real-Time
/// Collision Detection, 5.1.5: the Voronoi regions of vertices, edges and face).
void closest_on_triangle(const double* x, const double* a, const double* b, const double* c,
                         double* p, double* w) {
    auto dot = [](const double* u, const double* v) {
        return u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    };
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    for (int d = 0; d < 3; ++d) {
        ab[d] = b[d] - a[d];
        ac[d] = c[d] - a[d];
        ap[d] = x[d] - a[d];
        bp[d] = x[d] - b[d];
        cp[d] = x[d] - c[d];
    }
    auto set = [&](double u, double v, double t) {
        w[0] = u;
        w[1] = v;
        w[2] = t;
        for (int d = 0; d < 3; ++d)
            p[d] = u * a[d] + v * b[d] + t * c[d];
    };
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0)
        return set(1, 0, 0);
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3)
        return set(0, 1, 0);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double v = d1 / (d1 - d3);
        return set(1 - v, v, 0);
    }
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6)
        return set(0, 0, 1);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double t = d2 / (d2 - d6);
        return set(1 - t, 0, t);
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return set(0, 1 - t, t);
    }
    const double den = 1.0 / (va + vb + vc);
    const double v = vb * den, t = vc * den;
    set(1 - v - t, v, t);
}

} // namespace

void facet_point(std::size_t nv, const index_t* v, const double* x, const double* xi, double* p,
                 double* w, double* n) {
    const double *A = &x[3 * static_cast<std::size_t>(v[0])],
                 *B = &x[3 * static_cast<std::size_t>(v[1])];
    if (nv == 2) {
        closest_on_segment(xi, A, B, p, w);
        n[0] = B[1] - A[1];
        n[1] = -(B[0] - A[0]);
        n[2] = 0;
        return;
    }
    const double* C = &x[3 * static_cast<std::size_t>(v[2])];
    closest_on_triangle(xi, A, B, C, p, w);
    const double u[3] = {B[0] - A[0], B[1] - A[1], B[2] - A[2]};
    const double t[3] = {C[0] - A[0], C[1] - A[1], C[2] - A[2]};
    n[0] = u[1] * t[2] - u[2] * t[1];
    n[1] = u[2] * t[0] - u[0] * t[2];
    n[2] = u[0] * t[1] - u[1] * t[0];
}

void ContactList::init_surface(const model::Model& m) {
    const std::size_t nb = m.bodies.num();
    std::vector<std::uint8_t> want(nb, 0);
    for (std::size_t a = 0; a < nb; ++a)
        for (std::size_t b = 0; b < nb; ++b)
            if (a != b) {
                const auto k =
                    law_of_[static_cast<std::size_t>(body_group_[a] * ngroups_ + body_group_[b])];
                if (k >= 0 && laws_[static_cast<std::size_t>(k)].law == model::ContactLaw::surface)
                    want[a] = want[b] = 1;
            }
    facets_ = boundary_facets(m, want);
    interior_cells(m, want);
    h_body_ = m.bodies.mesh_size;
    // A node less than half an edge (the guard's bound) inside a body has every vertex of the
    // facet it entered through within 1.5 edges; so do the nodes of any facet it can push.
    rc_max_ = std::max(rc_max_, 1.5 * facets_.max_edge);
}

void ContactList::surface_rows(const State& s) {
    // Per row, the facets its surface-law candidates are vertices of, each once (sorted): the
    // step then visits a row's facets straight, not candidate -> incident facets, and a facet
    // that up to nv candidates of the row reach is evaluated once. The same facets as going
    // through the candidates, so the same closest points and forces.
    srows_.clear();
    sfac_off_.assign(1, 0);
    sfac_.clear();
    slack_.clear();
    facet_spheres(s, false); // at the rebuild's positions, torn or not
    std::vector<std::int32_t> row;
    for (std::size_t i = 0; i < s.n; ++i) {
        if (offsets_[i + 1] == offsets_[i]) // owned rows, and the ghost rows made for this law
            continue;
        row.clear();
        for (auto k = offsets_[i]; k < offsets_[i + 1]; ++k) {
            if (laws_[static_cast<std::size_t>(law_[static_cast<std::size_t>(k)])].law !=
                model::ContactLaw::surface)
                continue;
            const auto j = static_cast<std::size_t>(neighbor_[static_cast<std::size_t>(k)]);
            for (auto q = facets_.offsets[j]; q < facets_.offsets[j + 1]; ++q)
                row.push_back(facets_.of_node[static_cast<std::size_t>(q)]);
        }
        std::sort(row.begin(), row.end());
        row.erase(std::unique(row.begin(), row.end()), row.end());
        srows_.push_back(static_cast<index_t>(i));
        double slack = std::numeric_limits<double>::infinity();
        for (const auto f : row) {
            const double* c = &sphere_[4 * static_cast<std::size_t>(f)];
            const double* x = &s.x[3 * i];
            slack = std::min(slack, std::sqrt((x[0] - c[0]) * (x[0] - c[0]) +
                                              (x[1] - c[1]) * (x[1] - c[1]) +
                                              (x[2] - c[2]) * (x[2] - c[2])) -
                                        c[3]);
        }
        slack_.push_back(slack);
        sfac_.insert(sfac_.end(), row.begin(), row.end());
        sfac_off_.push_back(static_cast<model::offset_t>(sfac_.size()));
    }
}

bool ContactList::torn(std::int32_t f, const State& s) const {
    // A facet whose edge grew to twice its length has no material under it any more (its
    // grain broke there): it pushes nothing. Broken pieces then meet through the other body's
    // facets and the broken-bond repulsion.
    const auto nv = static_cast<std::size_t>(facets_.nv);
    const index_t* v = &facets_.v[nv * static_cast<std::size_t>(f)];
    const double lim = 4.0 * facets_.edge2[static_cast<std::size_t>(f)];
    for (std::size_t a = 0; a < nv; ++a) {
        if (!whole_.empty() && !whole_[static_cast<std::size_t>(v[a])])
            return true; // a node that lost half its bonds: the boundary there is gone
        const double* p = &s.x[3 * static_cast<std::size_t>(v[a])];
        const double* q = &s.x[3 * static_cast<std::size_t>(v[(a + 1) % nv])];
        const double d2 = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                          (p[2] - q[2]) * (p[2] - q[2]);
        if (d2 > lim)
            return true;
    }
    return false;
}

/// Per facet, this evaluation: its vertices' centroid c and reach r + h (r the largest distance
/// of a vertex from c, h its body's mesh size), or reach -1 if torn. The skip in surface_row is
/// safe: the closest point p of a facet lies in its vertices' hull, within r of c, so a node
/// farther than r + h from c is farther than h from the facet, where the potential is zero
/// (the force acts for d < h only). Such a facet can be neither a body's closest facet with a
/// force nor tie with one (a tie is equal distance; the one with a force is nearer than h).
void ContactList::facet_spheres(const State& s, bool torn_flag) const {
    const auto nv = static_cast<std::size_t>(facets_.nv);
    const auto nf = static_cast<std::int64_t>(facets_.num());
    sphere_.resize(4 * facets_.num());
#pragma omp parallel for schedule(static) if (threaded(nf))
    for (std::int64_t fi = 0; fi < nf; ++fi) {
        const auto f = static_cast<std::size_t>(fi);
        double* c = &sphere_[4 * f];
        if (torn_flag && torn(static_cast<std::int32_t>(f), s)) {
            c[0] = c[1] = c[2] = 0;
            c[3] = -1;
            continue;
        }
        const index_t* v = &facets_.v[nv * f];
        for (std::size_t d = 0; d < 3; ++d) {
            double sum = 0;
            for (std::size_t a = 0; a < nv; ++a)
                sum += s.x[3 * static_cast<std::size_t>(v[a]) + d];
            c[d] = sum / static_cast<double>(nv);
        }
        double r2 = 0;
        for (std::size_t a = 0; a < nv; ++a) {
            const double* x = &s.x[3 * static_cast<std::size_t>(v[a])];
            r2 = std::max(r2, (x[0] - c[0]) * (x[0] - c[0]) + (x[1] - c[1]) * (x[1] - c[1]) +
                                  (x[2] - c[2]) * (x[2] - c[2]));
        }
        // (1 + 1e-12): the rounding of c and r, so that no facet within h is skipped.
        c[3] = (std::sqrt(r2) + h_body_[static_cast<std::size_t>(facets_.body[f])]) * (1 + 1e-12);
    }
}

/// The closest boundary point of each other body to node i, among the facets at i's candidates.
struct ContactList::Best {
    std::int32_t body, facet;
    double d2;
    bool inside;
    double p[3], w[3];
    const model::ContactPair* law;
};

/// Per body, the closest of row a's facets to node i (not torn, within reach), and whether i is
/// inside it (surface_row).
void ContactList::closest_facets(std::size_t a, std::size_t i, const State& s,
                                 std::vector<Best>& best) const {
    const auto nv = static_cast<std::size_t>(facets_.nv);
    const double* xi = &s.x[3 * i];
    const auto gi = body_group_[static_cast<std::size_t>(s.body[i])];
    best.clear();
    for (auto q = sfac_off_[a]; q < sfac_off_[a + 1]; ++q) {
        const auto f = sfac_[static_cast<std::size_t>(q)];
        const double* c = &sphere_[4 * static_cast<std::size_t>(f)];
        const double r2 = (xi[0] - c[0]) * (xi[0] - c[0]) + (xi[1] - c[1]) * (xi[1] - c[1]) +
                          (xi[2] - c[2]) * (xi[2] - c[2]);
        if (c[3] < 0 || r2 > c[3] * c[3])
            continue; // torn, or farther than its body's h: no force (facet_spheres)
        const index_t* v = &facets_.v[nv * static_cast<std::size_t>(f)];
        double p[3], w[3], n[3];
        facet_point(nv, v, s.x.data(), xi, p, w, n);
        const double o[3] = {xi[0] - p[0], xi[1] - p[1], xi[2] - p[2]};
        const double d2 = o[0] * o[0] + o[1] * o[1] + o[2] * o[2];
        const bool neg = o[0] * n[0] + o[1] * n[1] + o[2] * n[2] < 0;
        const auto body = facets_.body[static_cast<std::size_t>(f)];
        auto it =
            std::find_if(best.begin(), best.end(), [&](const Best& b) { return b.body == body; });
        if (it == best.end()) {
            const auto& law = laws_[static_cast<std::size_t>(law_of_[static_cast<std::size_t>(
                gi * ngroups_ + body_group_[static_cast<std::size_t>(body)])])];
            best.push_back({body, f, d2, neg, {p[0], p[1], p[2]}, {w[0], w[1], w[2]}, &law});
            continue;
        }
        const double tol = 1e-10 * std::max(d2, it->d2);
        if (d2 < it->d2 - tol) {
            *it = {body, f, d2, neg, {p[0], p[1], p[2]}, {w[0], w[1], w[2]}, it->law};
        } else if (d2 <= it->d2 + tol) {
            it->inside = it->inside && neg; // a shared vertex or edge: all must agree
            if (f < it->facet) {            // the smallest facet of a tie: the same on every rank
                it->facet = f;
                std::copy(p, p + 3, it->p);
                std::copy(w, w + 3, it->w);
            }
        }
    }
}

void ContactList::surface_row(std::size_t a, const State& s, std::vector<Event>& out,
                              std::vector<Best>& best, std::vector<Touched>* marks) const {
    // Since the rebuild a node, a facet's centroid moved at most `moved_` and a facet's radius
    // grew at most 2 moved_, so a facet is still farther than r + h from node i (no force) when
    // its slack exceeds 4 moved_ (the factor 1e-9: rounding of the slack).
    if (slack_[a] > 4 * moved_ + 1e-9 * std::abs(slack_[a]))
        return;
    const auto i = static_cast<std::size_t>(srows_[a]);
    const double* xi = &s.x[3 * i];
    closest_facets(a, i, s, best);
    std::sort(best.begin(), best.end(),
              [](const Best& x, const Best& y) { return x.facet < y.facet; });
    // A held pair found outside (or on its boundary) is free again.
    auto outside = [&](const Best& b) {
        if (marks && held_count_ > 0 && held(i, b.body))
            marks->push_back({static_cast<index_t>(i), b.body, free_mark});
    };
    for (const auto& b : best) {
        if (!b.inside || !(b.d2 > 0)) {
            outside(b);
            continue;
        }
        // The potential: U(d) V (surface_penalty.hpp) up to d1 = h / 2 (the facet body's mesh size
        // h), then falling back to 0 at d2 = h: a node that deep has not come through this facet
        // (contact failed there, and the guard says so, or it lies in a crack of a broken
        // grain behind a facet that still stands) and is left alone, with no jump in the
        // energy.
        Blend bl{};
        const bool blended = vertex_blend(b.facet, b.w, xi, s, bl);
        const double d = blended ? bl.depth : std::sqrt(b.d2);
        if (!(d > 0)) {
            outside(b); // between a convex vertex and its fillet (vertex_blend)
            continue;
        }
        const double d1 = 0.5 * h_body_[static_cast<std::size_t>(b.body)], d2 = 2 * d1;
        // Depth grows continuously, and a node enters from the boundary (depth_continuous,
        // surface_history.cpp): a jumped depth is not a node that came through this boundary,
        // and a force from it would create its energy at once; the pair is held (no force)
        // until an evaluation finds the node outside that body.
        const double d0 = onset_share * b.law->radius;
        const bool continuous =
            !touched_known_ || depth_continuous(i, b.body, b.facet, b.w, d0, d, s);
        if (d >= d2) {
            // Beyond the law's reach: no force. A pair that got here continuously from contact
            // (the last evaluation's event, or already beyond then) went through this boundary:
            // contact failed, and an event without force says so to the guard for as long as
            // the node stays within this body's facets' reach (every evaluation: the guard
            // cannot miss it between its observations). A pair that jumped here (a node in a
            // crack of a broken grain behind a facet that still stands, or a new closest
            // facet) is left alone. The force does not change: none here; a node that comes
            // back to d < h continues its contact on U, continuous (0 at h).
            if (touched_known_ && continuous && in_contact(i, b.body))
                out.push_back({static_cast<index_t>(i),
                               b.facet,
                               {b.w[0], b.w[1], b.w[2]},
                               {0.0, 0.0, 0.0},
                               -1,
                               {0.0, 0.0},
                               {0.0, 0.0, 0.0},
                               0.0,
                               d,
                               true,
                               true});
            continue;
        }
        if (!continuous) {
            if (marks)
                marks->push_back({static_cast<index_t>(i), b.body, held_mark});
            continue;
        }
        push_pair(i, b, blended ? &bl : nullptr, d, d0, s, out);
    }
}

void ContactList::push_pair(std::size_t i, const Best& b, const Blend* bl, double d, double d0,
                            const State& s, std::vector<Event>& out) const {
    // The potential: U(d) V (surface_penalty.hpp) up to d1 = h / 2 (the facet body's mesh size
    // h), then falling back to 0 at d2 = h (surface_row).
    const double d1 = 0.5 * h_body_[static_cast<std::size_t>(b.body)], d2 = 2 * d1;
    const double* xi = &s.x[3 * i];
    const auto pen = surface_penalty(b.law->stiffness * s.vol[i], std::min(d, d1), d0);
    const double roll = (d2 - d) / (d2 - d1); // 1 at d1, 0 at d2
    const double fmag = d <= d1 ? pen.force : -2 * pen.energy * roll / (d2 - d1); // along p - y
    const double energy = d <= d1 ? pen.energy : pen.energy * roll * roll;
    if (bl) { // each share along its facet's normal, its reaction at its foot
        const double f0 = fmag * bl->share[0], f1 = fmag * bl->share[1];
        out.push_back({static_cast<index_t>(i),
                       b.facet,
                       {1 - bl->t[0], bl->t[0], 0.0},
                       {f0 * bl->n[0][0], f0 * bl->n[0][1], 0.0},
                       bl->g,
                       {1 - bl->t[1], bl->t[1]},
                       {f1 * bl->n[1][0], f1 * bl->n[1][1], 0.0},
                       energy,
                       d,
                       d > d1,
                       false});
        return;
    }
    const double a = fmag / d;
    out.push_back({static_cast<index_t>(i),
                   b.facet,
                   {b.w[0], b.w[1], b.w[2]},
                   {a * (b.p[0] - xi[0]), a * (b.p[1] - xi[1]), a * (b.p[2] - xi[2])},
                   -1,
                   {0.0, 0.0},
                   {0.0, 0.0, 0.0},
                   energy,
                   d,
                   d > d1,
                   false});
}

void ContactList::apply_events(State& s, Sums& sums, std::vector<BodyPairForce>* normal) const {
    const auto nv = static_cast<std::size_t>(facets_.nv);
    // The forces: on the node inside, then the reactions on the facets' nodes, in event order
    // (the same on every rank and thread count, so frames do not depend on them).
    for (const auto& ev : events_) {
        const auto i = static_cast<std::size_t>(ev.i);
        const auto bi = s.body[i];
        const auto bj = facets_.body[static_cast<std::size_t>(ev.facet)];
        const auto& law = laws_[static_cast<std::size_t>(
            law_of_[static_cast<std::size_t>(body_group_[static_cast<std::size_t>(bi)] * ngroups_ +
                                             body_group_[static_cast<std::size_t>(bj)])])];
        if (ev.beyond) { // failed contact, no force (surface_row): counted, nothing else
            if (owned_[i]) {
                ++sums.inside;
                if (sums.first_node < 0) {
                    sums.first_node = ev.i;
                    sums.first_body = bj;
                }
            }
            continue;
        }
        const double total[3] = {ev.force[0] + ev.force2[0], ev.force[1] + ev.force2[1],
                                 ev.force[2] + ev.force2[2]};
        if (owned_[i]) {
            for (std::size_t d = 0; d < 3; ++d)
                s.f[3 * i + d] += total[d] / s.vol[i];
            sums.energy += ev.energy;
            ++sums.touching;
            if (ev.deep) {
                ++sums.inside; // more than h/2 inside the other body: contact failed there
                if (sums.first_node < 0) {
                    sums.first_node = ev.i;
                    sums.first_body = bj;
                }
            }
        }
        const index_t* v = &facets_.v[nv * static_cast<std::size_t>(ev.facet)];
        for (std::size_t a = 0; a < nv; ++a) {
            const auto kk = static_cast<std::size_t>(v[a]);
            if (!owned_[kk] || ev.w[a] == 0)
                continue;
            for (std::size_t d = 0; d < 3; ++d)
                s.f[3 * kk + d] -= ev.w[a] * ev.force[d] / s.vol[kk];
        }
        if (ev.facet2 >= 0) // the share across a convex vertex (vertex_blend), on 2 vertices
            for (std::size_t a = 0; a < 2; ++a) {
                const auto kk = static_cast<std::size_t>(
                    facets_.v[2 * static_cast<std::size_t>(ev.facet2) + a]);
                if (!owned_[kk] || ev.w2[a] == 0)
                    continue;
                for (std::size_t d = 0; d < 3; ++d)
                    s.f[3 * kk + d] -= ev.w2[a] * ev.force2[d] / s.vol[kk];
            }
        if (normal) {
            // The record of a touching pair for damping and friction: the node inside and the
            // facet node of the largest weight, on every rank that owns one of them; the force
            // on the body of the larger node.
            std::size_t amax = 0;
            for (std::size_t a = 1; a < nv; ++a)
                if (ev.w[a] > ev.w[amax])
                    amax = a;
            const index_t j = v[amax];
            if ((law.restitution < 1 || law.friction > 0) &&
                (owned_[i] || owned_[static_cast<std::size_t>(j)])) {
                const double sg = ev.i < j ? -1.0 : 1.0; // on j's body: -F; on i's: +F
                BodyPairForce rec{ev.i < j ? bi : bj,
                                  ev.i < j ? bj : bi,
                                  std::min(ev.i, j),
                                  std::max(ev.i, j),
                                  {sg * total[0], sg * total[1], sg * total[2]},
                                  law.friction,
                                  law.restitution < 1};
                normal->push_back(rec);
            }
        }
    }
}

double ContactList::surface_energy(const State& s) const {
    facet_spheres(s, true);
    std::vector<Event> events;
    std::vector<Best> best;
    for (std::size_t a = 0; a < srows_.size(); ++a)
        surface_row(a, s, events, best, nullptr);
    double e = 0;
    for (const auto& ev : events)
        if (owned_[static_cast<std::size_t>(ev.i)])
            e += ev.energy;
    return e;
}

std::int64_t ContactList::add_surface(State& s, double& energy,
                                      std::vector<BodyPairForce>* normal) const {
    const auto nrows = static_cast<std::int64_t>(srows_.size());
    events_.clear();
    facet_spheres(s, true);
    std::vector<Touched> marks;
    if (threaded(nrows)) {
#pragma omp parallel
        {
            std::vector<Event> mine;
            std::vector<Touched> my_marks;
            std::vector<Best> best;
#pragma omp for schedule(static) nowait
            for (std::int64_t a = 0; a < nrows; ++a)
                surface_row(static_cast<std::size_t>(a), s, mine, best, &my_marks);
#pragma omp critical(pd_surface_events)
            {
                events_.insert(events_.end(), mine.begin(), mine.end());
                marks.insert(marks.end(), my_marks.begin(), my_marks.end());
            }
        }
        // Every thread's rows in row order, whatever the schedule.
        std::sort(events_.begin(), events_.end(), [](const Event& a, const Event& b) {
            return a.i != b.i ? a.i < b.i : a.facet < b.facet;
        });
    } else {
        std::vector<Best> best;
        for (std::int64_t a = 0; a < nrows; ++a)
            surface_row(static_cast<std::size_t>(a), s, events_, best, &marks);
    }
    Sums sums;
    apply_events(s, sums, normal);
    remember_depths(s.time, marks);
    energy += sums.energy;
    if (sums.inside > 0) {
        inside_.count += sums.inside;
        if (inside_.node < 0 || sums.first_node < inside_.node) {
            inside_.node = sums.first_node;
            inside_.body = s.body[static_cast<std::size_t>(sums.first_node)];
            inside_.inside = sums.first_body;
        }
    }
    return sums.touching;
}

} // namespace pd::solver
