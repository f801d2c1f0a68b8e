// SPDX-License-Identifier: MIT
// Peridynamic bond forces over the full CSR rows of the owned nodes (State::rows): each thread
// writes only its own rows (no atomics). Fracture bookkeeping is compiled out for unbreakable
// scenes.
#pragma once

#include "model/pmb.hpp"
#include "solver/state.hpp"

#include <functional>

namespace pd::solver {

struct BondResult {
    double elastic_energy = 0;     ///< J (2D: per unit thickness), of intact bonds
    std::int64_t newly_broken = 0; ///< bonds (each counted from both ends) broken this call
    /// J: elastic energy the bonds broken in this call held at the positions of this call,
    /// E(x, bonds before) - E(x, bonds after): what fracture dissipates.
    double released_energy = 0;
    /// J: energy of the repulsion across broken bonds (fragments of one grain, spec 4.7),
    /// 1/2 k_rep (r_rep - l)^2 V_i V_j per pair closer than r_rep: a contact energy.
    double repulsion_energy = 0;
};

/// Sets f = PMB force density of every node of a moving body (0 elsewhere); breaks bonds whose
/// stretch exceeds s0 (tension only) when `law.any_breakable`. Spec 1.5 with J = 1; constants in
/// model/pmb.hpp, per bond in b.kb and b.lc. The elastic and repulsion energies are summed only
/// when `law.energy` (else 0).
BondResult pmb_bond_forces(State& s, BondData& b, const BodyLaw& law);

/// The PMB loop as it was before issue 15 (the stretch and two divisions per bond, one
/// thread), for solver_bench's side-by-side; the same forces to rounding.
BondResult pmb_bond_forces_reference(State& s, BondData& b, const BodyLaw& law);

/// Sets f = LPS force density of every node of a moving LPS body (spec 1.3, model/lps.hpp),
/// two passes: dilatation (and bond breaking), then forces. Rows of PMB bodies are untouched.
/// `between` runs between the passes (the ghost exchange of law.theta under MPI).
BondResult lps_bond_forces(State& s, BondData& b, BodyLaw& law,
                           const std::function<void()>& between = {});

/// Sets f = RNP force density of every node of a moving RNP body (spec 1.4, model/rnp.hpp).
BondResult rnp_bond_forces(State& s, BondData& b, const BodyLaw& law);

/// Fills the kernels' per-bond constants (b.kb when keeps_kb(); b.wv and the work arrays b.len,
/// b.inv_len with an LPS body; b.lc and b.op with flaws) and the LPS per-node constants (law.lps_k,
/// the A_i of law.lps_ap) from the per-body law and the per-bond factors. `stiff`: per bond, beta
/// times the bond's surface-correction factor (PMB), turned into b.kb in place (no second per-bond
/// array); empty: bond_beta(). Call again whenever either
/// changes; the kernels call it themselves when the sizes do not match.
void bond_constants(const State& s, BondData& b, BodyLaw& law, std::vector<double> stiff = {});

/// Bond k's partial-volume factor: b.beta[k], or, when the solver keeps none (no moving RNP
/// body), model::partial_volume of its xi in its body (the bits build_bonds computed).
inline double bond_beta(const BondData& b, const BodyLaw& law, std::size_t body, std::size_t k) {
    return b.beta.empty() ? model::partial_volume(b.xi[k], law.delta[body], law.h[body])
                          : b.beta[k];
}

/// Whether the solver keeps b.kb: when the PMB kernel runs (the pmb_bonds term's condition: a
/// moving PMB body, or no moving body of another law). Otherwise no bond's stiffness carries a
/// surface-correction factor (only a moving PMB body's bonds are scaled in kb; LPS scales
/// omega), so kb is c beta V_j / xi and bond_kb() gives it.
inline bool keeps_kb(const BodyLaw& law) {
    return law.any_pmb || (!law.any_lps && !law.any_rnp);
}

/// Bond k's kb (row of body `body`, neighbour volume vj): b.kb[k], or when not kept, c beta V_j
/// / xi in bond_constants' order of operations (the same bits it would have stored).
inline double bond_kb(const BondData& b, const BodyLaw& law, std::size_t body, std::size_t k,
                      double vj) {
    return b.kb.empty() ? law.c[body] * bond_beta(b, law, body, k) * vj / b.xi[k] : b.kb[k];
}

/// The sum of kb over row a's bonds in bond order (c beta G V_j / xi, as the all-prescribed
/// fallback of the stability estimate once summed it; bond_kb where kb is not kept).
inline double row_kb_sum(const State& s, const BondData& b, const BodyLaw& law, std::size_t a) {
    const auto body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(s.rows[a])]);
    double k = 0;
    for (auto kk = b.offsets[a]; kk < b.offsets[a + 1]; ++kk) {
        const auto k1 = static_cast<std::size_t>(kk);
        k += bond_kb(b, law, body, k1, s.vol[static_cast<std::size_t>(b.neighbor[k1])]);
    }
    return k;
}

/// The LPS weighted volume of row a's intact bonds, sum omega xi^2 beta V_j in bond order (the
/// m_intact of the kernel's q_i); `damaged`: the row has a broken bond.
inline double intact_weighted_volume(const State& s, const BondData& b, const BodyLaw& law,
                                     std::size_t a, bool& damaged) {
    const auto body = static_cast<std::size_t>(s.body[static_cast<std::size_t>(s.rows[a])]);
    double mi = 0;
    for (auto k = b.offsets[a]; k < b.offsets[a + 1]; ++k) {
        const auto kk = static_cast<std::size_t>(k);
        if (!b.alive[kk]) {
            damaged = true;
            continue;
        }
        mi += b.omega[kk] * b.xi[kk] * b.xi[kk] * bond_beta(b, law, body, kk) *
              s.vol[static_cast<std::size_t>(b.neighbor[kk])];
    }
    return mi;
}

/// Damage phi_i = sum of beta V_j over broken bonds / sum over all bonds (spec decision 4).
void damage_phi(const State& s, const BondData& b, const BodyLaw& law, std::vector<double>& phi);

} // namespace pd::solver
