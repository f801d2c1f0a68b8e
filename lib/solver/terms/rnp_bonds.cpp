// SPDX-License-Identifier: MIT
// RNP bond forces (solver/bond_forces.hpp); bonds break here.
#include "solver/terms/bond_terms.hpp"

namespace pd::solver {

namespace {
class RnpBonds final : public BondTerm {
  public:
    void add(Forces& f) override {
        ScopedTimer t(f.timers, f.t_bonds);
        book(f, rnp_bond_forces(f.s, f.b, f.law));
    }
};
} // namespace

std::unique_ptr<ForceTerm> make_rnp_bonds(Forces& f) {
    // Only moving RNP bodies count: a fixed body's bonds do not move its nodes.
    return f.law.any_rnp ? std::make_unique<RnpBonds>() : nullptr;
}

} // namespace pd::solver
