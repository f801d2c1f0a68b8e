// SPDX-License-Identifier: MIT
// PMB bond forces (solver/bond_forces.hpp); bonds break here.
#include "solver/terms/bond_terms.hpp"

namespace pd::solver {

namespace {
class PmbBonds final : public BondTerm {
  public:
    void add(Forces& f) override {
        ScopedTimer t(f.timers, f.t_bonds);
        book(f, pmb_bond_forces(f.s, f.b, f.law));
    }
};
} // namespace

std::unique_ptr<ForceTerm> make_pmb_bonds(Forces& f) {
    // Also when no moving body has a law of its own (only fixed bodies): the PMB kernel then runs
    // over the bonds as it always did, so the list is never without a bond term.
    if (f.law.any_pmb || (!f.law.any_lps && !f.law.any_rnp))
        return std::make_unique<PmbBonds>();
    return nullptr;
}

} // namespace pd::solver
