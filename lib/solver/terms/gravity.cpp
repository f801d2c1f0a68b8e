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
        const double g[3] = {f.g[0], f.g[1], f.g[2]}; // in registers (s.f could alias f.g)
        const index_t* rows = s.rows.data();
        const double* rho = s.rho.data();
        double* fd = s.f.data();
        for_each_row(n, parallel_min_nodes, [&](std::int64_t a) {
            const std::int64_t i = rows[a];
            for (int d = 0; d < 3; ++d)
                fd[3 * i + d] += rho[i] * g[d];
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
