// SPDX-License-Identifier: MIT
// Contact reactions of meshed walls (solver/reactions.hpp): a snapshot of the force before the
// contact terms (reactions_begin) and the difference after them (reactions_end), so the terms
// between the two in terms.def are what a meshed wall's reaction counts.
#include "solver/forces.hpp"

namespace pd::solver {

namespace {
class ReactionsBegin final : public ForceTerm {
  public:
    void add(Forces& f) override { f.reactions.before(f.s); }
};
class ReactionsEnd final : public ForceTerm {
  public:
    void add(Forces& f) override { f.reactions.after(f.s); }
};
} // namespace

// Not needed without a fixed or driven meshed body: before() and after() then loop over no row
// and the reported reactions are empty.
std::unique_ptr<ForceTerm> make_reactions_begin(Forces& f) {
    return f.reactions.empty() ? nullptr : std::make_unique<ReactionsBegin>();
}
std::unique_ptr<ForceTerm> make_reactions_end(Forces& f) {
    return f.reactions.empty() ? nullptr : std::make_unique<ReactionsEnd>();
}

} // namespace pd::solver
