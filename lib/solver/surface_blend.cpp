// SPDX-License-Identifier: MIT
// The surface contact law's smoothed depth across a convex vertex of a 2D boundary
// (ContactList::vertex_blend, used by surface_row in surface_contact.cpp).
#include "solver/contact.hpp"

#include <cmath>

namespace pd::solver {

// Inside a body the distance to its boundary has a ridge along the bisector of each convex
// vertex (its medial axis): the closest facet, and with it the push direction, jumps there by
// the angle theta between the facets' normals, so a node pressed under a convex vertex (a disc's
// lowest node on another body) is pushed along one facet's normal, theta / 2 off the symmetric
// direction (the smaller facet id of the tie). Within a band |t| < delta of the bisector,
// t = g_f - g_g (g_f, g_g the node's depths behind the two facets' lines; delta = c sin(theta /
// 2), c of surface_facets.cpp, theta of the current facets), the depth is their smoothed minimum
//   d = (g_f + g_g) / 2 - rho(t),   rho(t) = t^2 / (4 delta) + delta / 4,
// C1 with min(g_f, g_g) at the band's edges (rho = |t| / 2, rho' = sign(t) / 2), symmetric in f
// and g: the push (1/2 - rho') n_f + (1/2 + rho') n_g turns continuously from n_f to n_g across
// the band. d <= min(g_f, g_g): the vertex is rounded off, the level d = 0 a fillet at most
// delta / 4 inside the polygon (delta ~ 0.25 h^2 / R at a gmsh disc's vertex: 0.006 h at R =
// 10 h); a node between the fillet and the vertex has no force, and the energy is 0 wherever the
// node leaves the body. Each line depth is exact for its reaction (the gradient of g_f with
// respect to f's vertices is its normal times the foot's weights 1 - t_f, t_f, inside the
// segment or not), and so is delta's (below), so the force is the gradient of U(d) V_i (checked
// by finite differences, test_convex_vertex.cpp): energy, momentum and angular momentum are
// conserved. Only a vertex of a polygonised curve is smoothed (contact.hpp,
// vertex_blend_max_angle); 3D facets are not (a triangle mesh's convex edges keep the tie).
// Finite-element node-to-segment contact meets the same jump of the master normal at master
// vertices and smooths the master surface (Hermite, Bezier or Gregory patches from averaged
// nodal normals: Puso and Laursen, Int. J. Numer. Meth. Engng 54 (2002) 1161-1194; Wriggers,
// Computational Contact Mechanics, 2nd ed., Springer 2006); here the gap itself is smoothed
// near the vertex, which keeps the force the exact gradient of a penalty energy.
bool ContactList::vertex_blend(std::int32_t f, const double* w, const double* xi, const State& s,
                               Blend& out) const {
    if (facets_.across.empty())
        return false;
    const auto fe = 2 * static_cast<std::size_t>(f) + (w[1] >= w[0] ? 1 : 0); // the nearer end
    const auto g = facets_.across[fe];
    const double c = facets_.blend[fe];
    if (g < 0 || !(c > 0) || sphere_[4 * static_cast<std::size_t>(g) + 3] < 0)
        return false; // no vertex there, a corner of the shape, or g torn
    const std::int32_t k[2] = {f, g};
    double depth[2], e[2][2], L[2];
    for (std::size_t a = 0; a < 2; ++a) {
        const index_t* v = &facets_.v[2 * static_cast<std::size_t>(k[a])];
        const double *A = &s.x[3 * static_cast<std::size_t>(v[0])],
                     *B = &s.x[3 * static_cast<std::size_t>(v[1])];
        L[a] = std::hypot(B[0] - A[0], B[1] - A[1]);
        e[a][0] = (B[0] - A[0]) / L[a];
        e[a][1] = (B[1] - A[1]) / L[a];
        out.n[a][0] = e[a][1];
        out.n[a][1] = -e[a][0];
        depth[a] = out.n[a][0] * (A[0] - xi[0]) + out.n[a][1] * (A[1] - xi[1]);
        out.t[a] = ((xi[0] - A[0]) * e[a][0] + (xi[1] - A[1]) * e[a][1]) / L[a];
    }
    // Convex now: g's far vertex behind f's line (f's end vertex is on both lines).
    const auto vf = facets_.v[fe];
    const index_t* vg = &facets_.v[2 * static_cast<std::size_t>(g)];
    const auto q = static_cast<std::size_t>(vg[0] == vf ? vg[1] : vg[0]);
    const double* V = &s.x[3 * static_cast<std::size_t>(vf)];
    if (out.n[0][0] * (s.x[3 * q] - V[0]) + out.n[0][1] * (s.x[3 * q + 1] - V[1]) >= 0)
        return false;
    // delta = c sin(theta / 2) of the current normals: 0 as the vertex flattens, so the smoothing
    // fades out continuously, and the band's half-width across the bisector stays c / 2.
    const double u[2] = {out.n[0][0] - out.n[1][0], out.n[0][1] - out.n[1][1]};
    const double un = std::hypot(u[0], u[1]), S = 0.5 * un, delta = c * S;
    const double t = depth[0] - depth[1];
    if (!(std::abs(t) < delta))
        return false;
    out.depth = 0.5 * (depth[0] + depth[1]) - (t * t / (4 * delta) + 0.25 * delta);
    out.share[0] = 0.5 - t / (2 * delta);
    out.share[1] = 0.5 + t / (2 * delta);
    // d depth / d delta = -(delta^2 - t^2) / (4 delta^2), and delta moves with the facets' turn:
    // d S = (u / |u|) . (d n_f - d n_g) / 2, d n = -e (n . (d B - d A)) / L. Its force on each
    // facet's two vertices is along the facet's normal, equal and opposite: it shifts the foot's
    // weights by (u . e_f) (delta + t) / (4 S L_f) on f, -(u . e_g) (delta - t) / (4 S L_g) on g
    // (the shares' factors delta -+ t cancel), so the force stays the gradient of U(d) V_i.
    out.t[0] += (u[0] * e[0][0] + u[1] * e[0][1]) / un * (delta + t) / (4 * S * L[0]);
    out.t[1] -= (u[0] * e[1][0] + u[1] * e[1][1]) / un * (delta - t) / (4 * S * L[1]);
    out.g = g;
    return true;
}

} // namespace pd::solver
