// SPDX-License-Identifier: MIT
// Surface correction of truncated families (issue 11; solver.surface_correction).
//
// A node within a horizon of a free surface has a truncated family: its discrete family sums
// lack the bonds that would cross the surface, so the layer of width ~delta along every free
// surface is softer (PMB) than the bulk, an error of order delta / L that does not shrink at a
// fixed horizon factor faster than delta. The correction is the directional "energy method"
// (Madenci & Oterkus 2014, ch. 4; compared with the other corrections in Le & Bobaru 2018,
// Comput. Mech. 61): for each node i and each axis a of its body's frame, the family's moment
//   M_a(i) = sum_j J(xi / delta) xi^p (n_a)^4 beta V_j       (n = bond direction)
// is proportional to its strain energy density in a uniaxial strain along a; the node's factor
//   g_a(i) = M_a(bulk) / M_a(i)
// is 1 for a complete family and > 1 for a truncated one, and bond ij is scaled by
//   G_ij = [ sum_a (n_a / gbar_a)^2 ]^(-1/2),   gbar_a = (g_a(i) + g_a(j)) / 2,
// the ellipsoid through the axis factors (symmetric in i and j). The reference M_a(bulk) is the
// discrete sum of a complete family of the same body (model/quadrature.hpp), not the continuum
// integral: the correction then is exactly 1 in the bulk and composes with the bulk calibration
// instead of repeating it (the former isotropic factor, continuum integral / discrete sum,
// moved the bulk by the quadrature's own error, 1-4 %).
// PMB: p = 1, J = 1, G scales the bond's micromodulus. LPS: G scales the bond's influence
// function (position-aware weights; p = 2, J = the law's influence): m_i, the dilatation and the
// deviatoric sum all use the scaled weights, so the state stays consistent; a uniform factor
// would cancel in LPS (everything is divided by m_i), only the direction dependence acts.
// On by default (issue 11: with it every accuracy row converges to within 0.5 %). Not covered:
// RNP bodies and fixed bodies (factor 1; their bonds do not count). A notch or slot (bonds that
// never exist) is a surface and is corrected; pre-cracks and bonds broken in a run are not (the
// factors come from the reference families, once, so a restart gets the same ones). The factors
// are the same on any rank count: each row's sums run over its bonds in the same order, and the
// ghosts' g come from their owners.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace pd::model {

/// u^4, bit for bit what std::pow(u, 4) returns, for a fraction of its cost: (u^2)^2 carried in
/// two doubles (Dekker's exact products), rounded, and kept only where it lies within 0.45 ulp
/// of u^4, so that glibc's pow (error at most 0.54 ulp) cannot return another double; else
/// (about one call in ten, and near underflow) std::pow itself. 8 ns against pow's 13 here.
double pow4(double u);

/// Per-node axis factors (g_0, g_1, g_2): `bulk` / `family` per axis a < d (family[a] > 0),
/// 1 where the family has no bond or a >= d. Limited to [1/limit, limit] (an isolated node with a
/// single bond must not get a huge factor).
std::array<double, 3> surface_axis_factors(const std::array<double, 3>& family, double bulk, int d,
                                           double limit = 4.0);

/// The bond factor G for a bond of unit direction n (body frame) between nodes with axis factors
/// gi and gj (see above).
double surface_bond_factor(const double* n, const std::array<double, 3>& gi,
                           const std::array<double, 3>& gj, int d);

/// The rows' families (CSR, as the solver's bond rows): row a is node rows[a], bond k of it joins
/// neighbor[k] (a node index). Directions come from the reference positions x0 (3 per node),
/// turned into the body frame by the per-node angle `angle` about z (a grid's axes).
struct FamilyRows {
    std::span<const std::int64_t> offsets;
    std::span<const std::int32_t> neighbor;
    std::span<const std::int32_t> rows;
    std::span<const double> x0;
    std::span<const double> angle; ///< per node (empty = 0)
};

/// Axis moments M_a of each row (3 per node index, n nodes): sum_k weight[k] (n_a)^4, weight =
/// J xi^p beta V_j per bond.
std::vector<double> family_axis_moments(const FamilyRows& f, std::span<const double> weight, int d,
                                        std::size_t n);

/// The bond factors G of every bond of the rows, from the axis factors g (3 per node, ghosts
/// included).
std::vector<double> surface_bond_factors(const FamilyRows& f, std::span<const double> g, int d);

/// The whole correction: the bond factors G of every bond of the rows, for bond weights
/// `weight` = J xi^p beta V_j / M_bulk (so that a complete family's axis moment is 1). The axis
/// factors start at 1 / M_a and are refined `iterations` times, g_a <- g_a / M_a^G with M_a^G the
/// axis moment of the corrected family (sum_j G weight n_a^4): the ellipsoid raises the diagonal
/// bonds too, so the one-shot factors over-correct a truncated family along the surface. The
/// solver does one refinement: measured (workflows/accuracy), 0 leaves a plate's error flat at
/// -0.16 % from h = 0.2 mm on (PMB), 1 converges monotonically (+1.06, +0.47, +0.15 %) and
/// takes a 3D bar from +1.85 to +0.73 % at h = 0.2 mm; more iterations do not settle (the
/// factors of neighbours interact through gbar) and move the 2D errors away again.
/// `exchange` sets the ghosts' g (3 per node) from their owners (a no-op on one rank). The
/// factors are returned in the storage of `weight` (move it in: no second per-bond array).
std::vector<double> surface_bond_factors(const FamilyRows& f, std::vector<double> weight, int d,
                                         std::size_t n,
                                         const std::function<void(std::vector<double>&)>& exchange,
                                         int iterations);

} // namespace pd::model
