// SPDX-License-Identifier: MIT
// Viscous relaxation (loading.viscous_damping c_d): f -= c_d rho v on this rank's rows.
#include "solver/forces.hpp"

namespace pd::solver {

namespace {
class ViscousDamping final : public ForceTerm {
  public:
    void add(Forces& f) override {
        auto& s = f.s;
        const double cd = f.m.loading.viscous_damping;
        const auto n = static_cast<std::int64_t>(s.rows.size());
        // Dissipation rate cd rho |v|^2 V of every moving node, prescribed components included:
        // there the reaction that imposes the motion works against the viscous force, and that
        // work is counted as external work.
        f.diss.viscous_rate = sum_rows(n, parallel_min_nodes, [&](std::int64_t a) {
            const std::int64_t i = s.rows[static_cast<std::size_t>(a)];
            const auto ii = static_cast<std::size_t>(i);
            double rate = 0;
            for (int d = 0; d < 3; ++d) {
                s.f[3 * i + d] -= cd * s.rho[ii] * s.v[3 * i + d];
                if (s.moving[ii])
                    rate += cd * s.rho[ii] * s.v[3 * i + d] * s.v[3 * i + d] * s.vol[ii];
            }
            return rate;
        });
    }
    std::vector<const char*> checkpointed() const override { return {"viscous", "viscous_rate"}; }
};
} // namespace

std::unique_ptr<ForceTerm> make_viscous_damping(Forces& f) {
    // c_d = 0: no force and no dissipation.
    return f.m.loading.viscous_damping > 0 ? std::make_unique<ViscousDamping>() : nullptr;
}

} // namespace pd::solver
