// SPDX-License-Identifier: MIT
// Gravity: the body force rho g on this rank's rows.
#include "solver/forces.hpp"

namespace pd::solver {

namespace {
class Gravity final : public ForceTerm {
  public:
    void add(Forces& f) override {
        auto& s = f.s;
        const auto n = static_cast<std::int64_t>(s.rows.size());
        for_each_row(n, parallel_min_nodes, [&](std::int64_t a) {
            const std::int64_t i = s.rows[static_cast<std::size_t>(a)];
            for (int d = 0; d < 3; ++d)
                s.f[3 * i + d] += s.rho[static_cast<std::size_t>(i)] * f.g[d];
        });
    }
    std::vector<const char*> checkpointed() const override { return {"external_work", "power"}; }
};
} // namespace

std::unique_ptr<ForceTerm> make_gravity(Forces& f) {
    // g = 0: no force (its potential and power are 0 too).
    return f.has_gravity() ? std::make_unique<Gravity>() : nullptr;
}

} // namespace pd::solver
