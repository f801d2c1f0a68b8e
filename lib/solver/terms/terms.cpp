// SPDX-License-Identifier: MIT
// The registry of force terms: terms.def, one line per term.
#include "solver/forces.hpp"

namespace pd::solver {

#define PD_TERM(name) std::unique_ptr<ForceTerm> make_##name(Forces& f);
#include "solver/terms/terms.def"
#undef PD_TERM

TermList make_terms(Forces& f) {
    TermList list;
    auto add = [&](std::unique_ptr<ForceTerm> t) {
        if (t)
            list.push_back(std::move(t));
    };
#define PD_TERM(name) add(make_##name(f));
#include "solver/terms/terms.def"
#undef PD_TERM
    return list;
}

} // namespace pd::solver
