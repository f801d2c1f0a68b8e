// SPDX-License-Identifier: MIT
#include "solver/terms/bond_terms.hpp"

#include "solver/stability.hpp"

namespace pd::solver {

void BondTerm::limit_dt(const Forces& f, StableDt& dt) const {
    if (dt.lanczos_steps > 0)
        return;
    // Lanczos stops once the step, rounded as Solver::stable_dt rounds it, is decided. It
    // borrows the storage of the bonds' xi and gives it back with the same bits (stability.hpp):
    // f.b is not changed, hence the const_cast (Forces lives in a non-const Solver).
    const auto spec =
        bond_spectrum(f.s, const_cast<BondData&>(f.b), f.law, *f.dom, 80, 1e-4, step_digits);
    dt.pd = critical_dt(spec.lambda());
    dt.lanczos_steps = spec.iterations;
}

} // namespace pd::solver
