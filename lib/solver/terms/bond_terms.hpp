// SPDX-License-Identifier: MIT
// What the bond terms of the three laws share: the book-keeping of a kernel's result and the
// stable-step limit of the bonds.
#pragma once

#include "solver/bond_forces.hpp"
#include "solver/forces.hpp"

namespace pd::solver {

class BondTerm : public ForceTerm {
  public:
    /// The bonds of every law form one stiffness matrix: the first bond term of the list computes
    /// its largest eigenvalue (Lanczos, solver/stability.hpp), the others find it done.
    void limit_dt(const Forces& f, StableDt& dt) const override;
    std::vector<const char*> checkpointed() const override {
        return {"alive", "broken_total", "fracture"};
    }

  protected:
    /// Adds a kernel's energies, broken bonds and released energy to the evaluation's sums.
    static void book(Forces& f, const BondResult& r) {
        f.elastic += r.elastic_energy;
        f.broken_total += r.newly_broken;
        f.diss.fracture += r.released_energy;
        f.repulsion += r.repulsion_energy;
    }
};

} // namespace pd::solver
