// SPDX-License-Identifier: MIT
// The registry of force terms: terms.def, one line per term.
#include "solver/forces.hpp"

namespace pd::solver {

#define PD_TERM(name) std::unique_ptr<ForceTerm> make_##name(Forces& f);
#include "solver/terms/terms.def"
#undef PD_TERM

TermList make_terms(Forces& f, std::vector<std::string>* names) {
    TermList list;
    auto add = [&](std::unique_ptr<ForceTerm> t, const char* name) {
        if (!t)
            return;
        list.push_back(std::move(t));
        if (names)
            names->push_back(name);
    };
#define PD_TERM(name) add(make_##name(f), #name);
#include "solver/terms/terms.def"
#undef PD_TERM
    return list;
}

} // namespace pd::solver
