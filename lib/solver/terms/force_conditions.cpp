// SPDX-License-Identifier: MIT
// Force conditions (spec 5.6): a force density amplitude T(t) S(X) on the components of their
// nodes; kept per component (fbc) for the external power.
#include "model/functions.hpp"
#include "solver/forces.hpp"

#include <algorithm>

namespace pd::solver {

namespace {
class ForceConditions final : public ForceTerm {
  public:
    void add(Forces& f) override {
        auto& s = f.s;
        std::fill(f.fbc.begin(), f.fbc.end(), 0.0);
        const auto& conditions = f.m.loading.conditions;
        for (const auto& c : conditions) {
            if (!c.is_force)
                continue;
            double rate = 0;
            const double T = model::time_function(c.time_fn, c.params, s.time, &rate);
            const auto& box = f.cond_box[static_cast<std::size_t>(&c - conditions.data())];
            for (auto i : c.nodes) {
                const auto ii = static_cast<std::size_t>(i);
                const double S = model::space_value(c.space_fn, c.params[0], &s.x0[3 * ii], box);
                for (std::size_t d = 0; d < 3; ++d)
                    if (c.dofs & (1u << d)) {
                        s.f[3 * ii + d] += c.amplitude * T * S;
                        f.fbc[3 * ii + d] += c.amplitude * T * S;
                    }
            }
        }
    }
    std::vector<const char*> checkpointed() const override { return {"external_work", "power"}; }
};
} // namespace

std::unique_ptr<ForceTerm> make_force_conditions(Forces& f) {
    // fbc is sized when some condition is a force condition: without one there is nothing to add.
    return f.fbc.empty() ? nullptr : std::make_unique<ForceConditions>();
}

} // namespace pd::solver
