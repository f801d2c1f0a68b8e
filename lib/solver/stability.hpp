// SPDX-License-Identifier: MIT
// Stability limit of the explicit integrators (velocity Verlet and symplectic Euler are both
// stable for omega_max dt < 2): omega_max^2 is the largest eigenvalue of the mass-scaled tangent
// stiffness M^-1/2 K M^-1/2. The bond part is computed, not bounded: a few tens of Lanczos
// steps on the actual discrete operator of the bonds (PMB, LPS with its dilatation coupling,
// RNP) at the current configuration. Contacts, which come and go, are bounded instead: each
// contact law that can act gives the Gershgorin bound of the densest contact it can form (its
// largest stiffness from the contact law, solver/contact.hpp). pd-solve takes the smaller step
// of the two, not the strict bound of their sum (see Solver::stable_dt and the measured map in
// workflows/accuracy/stability/RESULTS.md).
#pragma once

#include "model/model.hpp"
#include "solver/domain.hpp"
#include "solver/state.hpp"

namespace pd::solver {

/// Largest eigenvalue of the bonds' mass-scaled stiffness (s^-2).
struct BondSpectrum {
    double ritz = 0;     ///< largest Ritz value (a lower bound of lambda_max)
    double residual = 0; ///< its residual norm: lambda_max is within [ritz, ritz + residual]
                         ///< if the Ritz vector has converged to the top eigenvector
    int iterations = 0;  ///< Lanczos steps taken
    /// The value the time step uses: ritz + residual (from above once converged).
    double lambda() const { return ritz + residual; }
};

/// Lanczos on y = D^-1/2 K D^-1/2 x (D_i = rho_i V_i, K the nodal tangent stiffness of the
/// intact bonds at the positions s.x; prescribed dofs and fixed bodies are held at zero). Every
/// bond of a PMB body counts as intact: a broken bond's repulsion (spec 4.7) is never stiffer
/// than the bond was, so the estimate holds as bonds break. The start vector depends on global
/// node ids only, so every rank count takes the same steps. Collective over `dom`'s ranks.
/// `law` needs the LPS weighted volumes (law.m) when a body is LPS.
///
/// It stops when the top Ritz value is steady (3 steps within `tolerance`) and its residual is
/// below 10 `tolerance` of it, or, with `step_digits` > 0, as soon as the time step is
/// decided: the bracket [ritz, ritz + residual] of lambda_max gives steps 2 / sqrt(.) that
/// round_step(., step_digits) takes to the same value (and the last step moved the Ritz value by
/// less than its residual). The step is then floor(2 / sqrt(lambda_max)) to those digits, at or
/// below the limit under the assumption the old stop made too (the top Ritz value tracks the
/// top eigenvalue). Further steps raise the Ritz value and, as measured, lower ritz + residual:
/// both stay in the bracket and round to the same step (issue 29 item 3: 23 -> 19 steps on
/// the 1.03 M-node block, 20 -> 18 at 2.6e5 nodes, the same step). Only a residual that grew
/// again could have made the old stop return one unit of the last digit less.
///
/// `compact` (issue 29 item 3): the PMB rows run on a float copy of kb / |d|^2 per bond, 8 B a
/// bond a step instead of 13 and no division; that operator's lambda_max is within a stated
/// margin m of the exact one's (4 u times a row-sum bound of the bonds' terms, u = 2^-24: about
/// 1e-6 of it), and the bracket returned is widened by m at both ends, so a decided step is
/// that of the exact operator. With no LPS or RNP body the copy takes b.xi's storage during the
/// call (no memory added at the start-up's peak) and xi is recomputed from x0 after it, the same
/// bits (checked before each is overwritten). `compact` false: every row through the reference
/// kernel (row_force), b untouched.
BondSpectrum bond_spectrum(const State& s, BondData& b, const BodyLaw& law, Domain& dom,
                           int max_iterations = 80, double tolerance = 1e-4, int step_digits = 0,
                           bool compact = true);

/// The time step the solver reports (s): dt rounded down to `digits` significant digits (the
/// Lanczos sums differ in their last bits between rank counts, the step must not); dt itself
/// when it is not finite and positive.
double round_step(double dt, int digits);

/// The significant digits of the bonds' step limit (Solver::stable_dt).
inline constexpr int step_digits = 3;

/// Upper bound of the largest eigenvalue (s^-2) that contact can add, over every contact law of
/// `m` that can act (two bodies of its groups, or a body and a wall, one of them moving): a node
/// pressed into a neighbour body whose nodes fill a contact disc (sphere in 3D) of radius R_c at
/// the densest nodal spacing of the two groups, each pair at the law's largest stiffness
/// (contact_max_stiffness); Gershgorin (twice the row sum). 0 if no law can act.
double contact_lambda_bound(const model::Model& m, const State& s);

/// Time step limit 2 / sqrt(lambda) (s); infinity for lambda <= 0.
double critical_dt(double lambda);

} // namespace pd::solver
