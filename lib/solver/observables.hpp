// SPDX-License-Identifier: MIT
// What the solver reports: the stable time step and the observables of a step.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pd::solver {

/// Stable time step estimate (s) and the limit that governs it (solver/stability.hpp).
struct StableDt {
    double pd = 0;         ///< bond limit 2 / sqrt(lambda_max) of the bonds' mass-scaled stiffness,
                           ///< 3 significant digits, rounded down
    double contact = 0;    ///< contact limit 2 / sqrt(lambda) of the densest contact that can form
    double limit = 0;      ///< min(pd, contact)
    int lanczos_steps = 0; ///< steps the bond eigenvalue took
    std::string governing; ///< "peridynamic bonds" or "contact stiffness"
};

/// Quantities observed after a step (2D: per unit thickness).
struct Observables {
    double kinetic_energy = 0; ///< J
    double elastic_energy = 0; ///< J, intact bonds
    double contact_energy = 0; ///< J, contact springs
    double external_work = 0;  ///< J, work of gravity, force and displacement conditions,
                               ///< moving walls since t = 0
    // Energy dissipated since t = 0 (J, cumulative): with them the balance
    // KE + elastic + contact + fracture + damping + friction + viscous - external_work
    // stays at its t = 0 value (to the integrator's error; pd-solve's guard checks it).
    double fracture_energy = 0; ///< energy bonds (and torn facets' contacts) held when they broke
    double damping_dissipation = 0;  ///< removed by hysteretic contact damping
    double friction_dissipation = 0; ///< removed by Coulomb friction
    double viscous_dissipation = 0;  ///< removed by viscous relaxation
    double gravity_potential = 0;    ///< J, -sum m g . u of moving nodes (part of external_work)
    /// Node pairs with a node more than R_c + h/2 inside another grain (solver/contact.hpp
    /// Penetration), over all ranks, and one of them as this rank saw it (-1: none here). Not
    /// written to the file.
    std::int64_t inside_pairs = 0;
    std::int64_t inside_node = -1;
    std::int32_t inside_body = -1, inside_of = -1;
    /// Nodes more than h/2 beyond a rigid wall's surface (solver/walls.hpp), over all ranks, and
    /// one of them with its wall as this rank saw it. Not written to the file.
    std::int64_t beyond_wall = 0;
    std::int64_t beyond_node = -1;
    std::int32_t beyond_wall_index = -1;
    double momentum[3] = {0, 0, 0};  ///< kg m s-1
    std::int64_t contact_count = 0;  ///< node pairs (and node-wall pairs) closer than R_c
    std::int64_t broken_bonds = 0;   ///< broken bonds (pairs)
    std::vector<double> wall_force;  ///< 3 per wall, N, received by the wall
    std::vector<double> wall_moment; ///< 3 per wall, N m, about its rotation centre
    /// Contact reactions of the fixed or driven meshed bodies (Solver::reaction_bodies()):
    /// 3 per body, N, and moment about its centroid, N m.
    std::vector<double> body_force;
    std::vector<double> body_moment;
};

/// KE + elastic + contact + dissipated - external work: constant in an exact integration (J).
double energy_balance(const Observables& o);
/// The energy in play, the scale the balance drift is measured against: KE + elastic + contact
/// + dissipated + |external work| (J).
double energy_in_play(const Observables& o);

} // namespace pd::solver
