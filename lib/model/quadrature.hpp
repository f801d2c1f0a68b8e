// SPDX-License-Identifier: MIT
// Calibration of the bond-law constants on the actual quadrature (issue 11).
//
// The continuum constants of model/pmb.hpp, lps.hpp and rnp.hpp assume that a family integrates
// the horizon exactly. A discrete family (nodes of spacing h, linear partial volumes beyond
// delta - h/2) does not: at delta = 3 h on a square grid the 2D PMB material is 4.5 % too stiff
// in uniaxial stress (3D: 7.7 %), and that error does not shrink as h -> 0 at fixed m = delta /
// h, so refining moves a static answer *away* from the local one. Here the small-strain
// stiffness tensor of the discrete families of a body's interior nodes (complete families,
// sampled from the body itself, so grids and gmsh meshes alike) is computed, and the law's
// constants are scaled so that its Young's modulus (and for LPS also its Poisson ratio) along
// the body's own axes equals the classical one:
//   PMB, RNP: one factor on the micromodulus (RNP: on C / invF; critical stretch unchanged);
//   LPS:      kappa and mu solved from C_1111 and C_1122 of the discrete family (2 x 2).
// A lattice family has cubic symmetry, not isotropy: matched along the axes, the modulus at
// 45 degrees remains off by the lattice anisotropy (2D PMB, m = 3: -1.3 %; see RESULTS in
// workflows/accuracy). Surface families are not used: the surface layer's error, O(delta / L),
// is the surface correction's (model/surface_correction.hpp, relative to these complete families).
// A body with no complete family (thinner than about 2 delta + h) keeps the continuum constants.
#pragma once

#include "model/model.hpp"

namespace pd::model {

/// Factors on a body's continuum constants; 1 = no change.
struct QuadratureFactors {
    double pmb = 1;   ///< PMB micromodulus c (and RNP: 1 / invF)
    double kappa = 1; ///< LPS bulk modulus
    double mu = 1;    ///< LPS shear modulus
    int samples = 0;  ///< interior families used (0: none found, factors 1)
    /// A complete family's axis moment sum_j J xi^p (n_a)^4 beta V_j (p = 1 and J = 1 for PMB and
    /// RNP, p = 2 and the law's influence for LPS), mean over the samples and the body's axes: the
    /// bulk reference of the surface correction (model/surface_correction.hpp). The continuum
    /// integral if no complete family was found.
    double axis_moment = 0;
};

/// Factors for body `b` of `m` (its material's law and influence function). Families are built
/// from the reference positions and volumes (every node of the body; deterministic, the same on
/// every MPI rank) with the cut-off the bond list used (delta + h/2 with linear partial volumes,
/// or PeriDEM's strict < delta, told apart by a row length of /bonds/offsets). Up to
/// `max_samples` nodes spread over the body are tried; those whose family covers the whole
/// horizon (the body's outermost nodes at least the reach away along a fan of directions; volume
/// within 3 % of the best sample and at least 95 % of the ball) are averaged.
QuadratureFactors quadrature_factors(const Model& m, std::size_t b, int max_samples = 48);

} // namespace pd::model
