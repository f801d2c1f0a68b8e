// SPDX-License-Identifier: MIT
#include "solver/reactions.hpp"

#include <algorithm>

namespace pd::solver {

BodyReactions::BodyReactions(const model::Model& m) {
    const std::size_t nb = m.bodies.num();
    std::vector<std::uint8_t> driven(m.nodes.num(), 0);
    for (const auto& c : m.loading.conditions)
        if (!c.is_force)
            for (auto i : c.nodes)
                driven[static_cast<std::size_t>(i)] = 1;
    index_.assign(nb, -1);
    for (std::size_t b = 0; b < nb; ++b) {
        bool all = true;
        for (auto i = m.bodies.begin(b); i < m.bodies.end(b) && all; ++i)
            all = driven[static_cast<std::size_t>(i)] != 0;
        if (m.bodies.fixed[b] || (all && m.bodies.end(b) > m.bodies.begin(b))) {
            index_[b] = static_cast<std::int32_t>(bodies_.size());
            bodies_.push_back(static_cast<std::int32_t>(b));
        }
    }
    load_.assign(10 * bodies_.size(), 0.0);
}

void BodyReactions::set_rows(const State& s) {
    rows_.clear();
    for (auto i : s.rows)
        if (index_[static_cast<std::size_t>(s.body[static_cast<std::size_t>(i)])] >= 0)
            rows_.push_back(i);
    f0_.assign(3 * rows_.size(), 0.0);
}

void BodyReactions::before(const State& s) {
    std::fill(load_.begin(), load_.end(), 0.0);
    for (std::size_t a = 0; a < rows_.size(); ++a)
        for (std::size_t d = 0; d < 3; ++d)
            f0_[3 * a + d] = s.f[3 * static_cast<std::size_t>(rows_[a]) + d];
}

void BodyReactions::after(const State& s) {
    // Rows come body by body: each run of rows of one body sums into registers, which start
    // from and go back to the body's load (the same additions in the same order).
    const auto body_of = [&](std::size_t a) {
        const auto i = static_cast<std::size_t>(rows_[a]);
        return index_[static_cast<std::size_t>(s.body[i])];
    };
    for (std::size_t a = 0; a < rows_.size();) {
        const std::int32_t k = body_of(a);
        double* L = &load_[10 * static_cast<std::size_t>(k)];
        double acc[10];
        std::copy(L, L + 10, acc);
        for (; a < rows_.size() && body_of(a) == k; ++a) {
            const auto i = static_cast<std::size_t>(rows_[a]);
            const double* x = &s.x[3 * i];
            double F[3];
            for (std::size_t d = 0; d < 3; ++d)
                F[d] = (s.f[3 * i + d] - f0_[3 * a + d]) * s.vol[i];
            const double mass = s.rho[i] * s.vol[i];
            for (std::size_t d = 0; d < 3; ++d) {
                acc[d] += F[d];
                acc[6 + d] += mass * x[d];
            }
            acc[3] += x[1] * F[2] - x[2] * F[1];
            acc[4] += x[2] * F[0] - x[0] * F[2];
            acc[5] += x[0] * F[1] - x[1] * F[0];
            acc[9] += mass;
        }
        std::copy(acc, acc + 10, L);
    }
}

void BodyReactions::add_damping(std::int32_t b, const double* F, const double* point,
                                const double* centroid, bool fixed) {
    const auto k = index_[static_cast<std::size_t>(b)];
    if (k < 0)
        return;
    double* L = &load_[10 * static_cast<std::size_t>(k)];
    // Sum x cross F gets point x F in all; after() adds centroid x F for a driven body.
    double p[3];
    for (std::size_t d = 0; d < 3; ++d) {
        p[d] = fixed ? point[d] : point[d] - centroid[d];
        if (fixed)
            L[d] += F[d];
    }
    L[3] += p[1] * F[2] - p[2] * F[1];
    L[4] += p[2] * F[0] - p[0] * F[2];
    L[5] += p[0] * F[1] - p[1] * F[0];
}

void BodyReactions::result(const Domain& dom, std::vector<double>& force,
                           std::vector<double>& moment, const std::vector<double>* load,
                           std::int64_t steps) const {
    std::vector<double> all = load ? *load : load_;
    if (dom.distributed())
        dom.sum(all);
    if (steps > 1) {
        // The average over the interval: the centroid is the mean centroid, the moment about it
        // mean(sum x cross F) - mean(c) x mean(F) (exact for a fixed body).
        for (auto& a : all)
            a /= static_cast<double>(steps);
    }
    const std::size_t nr = bodies_.size();
    force.assign(3 * nr, 0.0);
    moment.assign(3 * nr, 0.0);
    for (std::size_t k = 0; k < nr; ++k) {
        const double* L = &all[10 * k];
        double c[3] = {0, 0, 0};
        if (L[9] > 0)
            for (std::size_t d = 0; d < 3; ++d)
                c[d] = L[6 + d] / L[9];
        // Moment about the centroid: sum (x - c) x F = sum x x F - c x sum F.
        for (std::size_t d = 0; d < 3; ++d)
            force[3 * k + d] = L[d];
        moment[3 * k + 0] = L[3] - (c[1] * L[2] - c[2] * L[1]);
        moment[3 * k + 1] = L[4] - (c[2] * L[0] - c[0] * L[2]);
        moment[3 * k + 2] = L[5] - (c[0] * L[1] - c[1] * L[0]);
    }
}

} // namespace pd::solver
