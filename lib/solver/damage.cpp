// SPDX-License-Identifier: MIT
// Damage, fragments and broken-bond counts: the one place frames (pipeline/run) and the
// observables take them from.
#include "solver/bond_forces.hpp"
#include "solver/detail.hpp"
#include "solver/solver.hpp"

#include <cmath>

namespace pd::solver {

void Solver::damage(std::vector<double>& phi) const {
    damage_phi(f_.s, f_.b, f_.law, phi);
}

void Solver::broken_per_node(std::vector<double>& count) const {
    count.assign(f_.s.n, 0.0);
    for (std::size_t a = 0; a < f_.s.rows.size(); ++a) {
        const auto i = static_cast<std::size_t>(f_.s.rows[a]);
        for (auto k = f_.b.offsets[a]; k < f_.b.offsets[a + 1]; ++k)
            count[i] += f_.b.alive[static_cast<std::size_t>(k)] ? 0.0 : 1.0;
    }
}

void Solver::fragments(std::vector<double>& id) const {
    // Union-find over intact bonds; the smaller root becomes the root, so every id is the
    // smallest node index of its component whatever the order of the unions. Each rank unites
    // over its rows' bonds (a bond to a ghost included); when bonds join two ranks, the ranks'
    // labels are merged by element-wise minimum and united again until no label changes (the
    // rounds: the number of rank crossings along a component's path, plus one). Memory: one
    // label per node, not the gathered bond list; the ids are the same at any rank count.
    std::vector<index_t> parent(f_.s.n);
    for (std::size_t i = 0; i < f_.s.n; ++i)
        parent[i] = static_cast<index_t>(i);
    auto find = [&](index_t a) {
        while (parent[static_cast<std::size_t>(a)] != a) {
            auto& p = parent[static_cast<std::size_t>(a)];
            p = parent[static_cast<std::size_t>(p)]; // path halving
            a = p;
        }
        return a;
    };
    auto unite = [&](index_t i, index_t j) {
        const index_t a = find(i), b = find(j);
        if (a != b)
            parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
    };
    for (std::size_t a = 0; a < f_.s.rows.size(); ++a)
        for (auto k = f_.b.offsets[a]; k < f_.b.offsets[a + 1]; ++k)
            if (f_.b.alive[static_cast<std::size_t>(k)])
                unite(f_.s.rows[a], f_.b.neighbor[static_cast<std::size_t>(k)]);
    std::vector<index_t> label(f_.s.n);
    auto labels = [&] {
        for (std::size_t i = 0; i < f_.s.n; ++i)
            label[i] = find(static_cast<index_t>(i));
    };
    labels();
    if (f_.bonds_cross_ranks)
        for (bool changed = true; changed;) {
            f_.dom->min(label); // every rank's smallest label of each node
            changed = false;
            for (std::size_t i = 0; i < f_.s.n; ++i)
                if (find(static_cast<index_t>(i)) != find(label[i])) {
                    unite(static_cast<index_t>(i), label[i]);
                    changed = true;
                }
            changed = f_.dom->any(changed);
            labels();
        }
    id.resize(f_.s.n);
    for (std::size_t i = 0; i < f_.s.n; ++i)
        id[i] = static_cast<double>(label[i]);
}

void Solver::damage_z(std::vector<double>& z) const {
    z.assign(f_.s.n, 0.0);
    const auto n = static_cast<std::int64_t>(f_.s.rows.size());
#pragma omp parallel for schedule(static) if (n > parallel_min)
    for (std::int64_t a = 0; a < n; ++a) {
        const auto ii = static_cast<std::size_t>(f_.s.rows[static_cast<std::size_t>(a)]);
        const auto b = static_cast<std::size_t>(f_.s.body[ii]);
        const double s0 = f_.law.s0[b];
        if (!std::isfinite(s0) || !f_.s.moving[ii])
            continue;
        double zmax = 0;
        for (auto k = f_.b.offsets[a]; k < f_.b.offsets[a + 1]; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            const auto j = static_cast<std::size_t>(f_.b.neighbor[kk]);
            const double r = f_.b.xi[kk];
            double st;
            if (f_.law.rnp[b]) {
                double dot = 0;
                for (std::size_t d = 0; d < 3; ++d)
                    dot += (f_.s.u[3 * j + d] - f_.s.u[3 * ii + d]) *
                           (f_.s.x0[3 * j + d] - f_.s.x0[3 * ii + d]);
                st = std::abs(dot / (r * r)) / (f_.law.rnp_rbar[b] / std::sqrt(r));
            } else {
                double l2 = 0;
                for (std::size_t d = 0; d < 3; ++d)
                    l2 += (f_.s.x[3 * j + d] - f_.s.x[3 * ii + d]) *
                          (f_.s.x[3 * j + d] - f_.s.x[3 * ii + d]);
                st = std::abs(std::sqrt(l2) - r) / r / s0;
            }
            zmax = std::max(zmax, st);
        }
        z[ii] = zmax;
    }
}

void Solver::alive_into(std::vector<std::uint8_t>& full) const {
    full.resize(f_.m.bonds.num());
    detail::put_rows(f_.b.alive, f_.b.offsets, f_.s.rows, f_.m.bonds.offsets, full);
}

std::vector<std::uint8_t> Solver::global_alive() const {
    std::vector<std::uint8_t> full(f_.m.bonds.num(), 1);
    alive_into(full);
    f_.dom->allgather_csr(full, f_.m.bonds.offsets);
    return full;
}

} // namespace pd::solver
