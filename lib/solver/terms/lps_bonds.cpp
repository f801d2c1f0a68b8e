// SPDX-License-Identifier: MIT
// LPS bond forces (solver/bond_forces.hpp): two passes, the dilatation of the ghosts exchanged
// between them under MPI; bonds break here.
#include "solver/terms/bond_terms.hpp"

#include <functional>

namespace pd::solver {

namespace {
class LpsBonds final : public BondTerm {
  public:
    void add(Forces& f) override {
        ScopedTimer t(f.timers, f.t_bonds);
        std::function<void()> between;
        if (f.dom->distributed())
            between = [&f] {
                ScopedTimer th(f.timers, f.t_halo);
                f.dom->exchange({&f.law.theta, &f.law.q}, 1);
                f.dom->exchange({&f.law.lps_ap}, 2); // P_j (and the constant A_j beside it)
            };
        book(f, lps_bond_forces(f.s, f.b, f.law, between));
    }
};
} // namespace

std::unique_ptr<ForceTerm> make_lps_bonds(Forces& f) {
    // Only moving LPS bodies count: a fixed body's bonds do not move its nodes.
    return f.law.any_lps ? std::make_unique<LpsBonds>() : nullptr;
}

} // namespace pd::solver
