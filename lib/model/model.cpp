// SPDX-License-Identifier: MIT
#include "model/model.hpp"

#include "core/errors.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace pd::model {

double Material::bulk_modulus() const {
    return youngs_modulus / (3.0 * (1.0 - 2.0 * poisson_ratio));
}

const ContactPair* Model::contact_between(std::int32_t a, std::int32_t b) const {
    for (const auto& c : contact)
        if ((c.group_a == a && c.group_b == b) || (c.group_a == b && c.group_b == a))
            return &c;
    return nullptr;
}

void Model::check_consistency() const {
    const std::size_t nb = bodies.num(), n = nodes.num();
    auto same = [&](std::size_t got, std::size_t want, const char* what) {
        PD_CHECK(got == want, fmt::format("{} has {} entries, expected {}", what, got, want));
    };
    same(bodies.material.size(), nb, "bodies.material");
    same(bodies.group.size(), nb, "bodies.group");
    same(bodies.ref_mesh.size(), nb, "bodies.ref_mesh");
    same(bodies.kind.size(), nb, "bodies.kind");
    same(bodies.fixed.size(), nb, "bodies.fixed");
    same(bodies.center.size(), 3 * nb, "bodies.center");
    same(bodies.bounding_radius.size(), nb, "bodies.bounding_radius");
    same(bodies.orientation.size(), nb, "bodies.orientation");
    same(bodies.scale.size(), nb, "bodies.scale");
    same(bodies.initial_velocity.size(), 3 * nb, "bodies.initial_velocity");
    same(bodies.mesh_size.size(), nb, "bodies.mesh_size");
    same(bodies.horizon.size(), nb, "bodies.horizon");
    same(nodes.x0.size(), 3 * n, "nodes.x0");
    same(nodes.body.size(), n, "nodes.body");
    PD_CHECK(nodes.surface.empty() || nodes.surface.size() == n, "nodes.surface size");
    PD_CHECK(bodies.node_offsets.front() == 0 &&
                 bodies.node_offsets.back() == static_cast<offset_t>(n),
             "body offsets must span all nodes");
    PD_CHECK(std::is_sorted(bodies.node_offsets.begin(), bodies.node_offsets.end()),
             "body offsets must be monotone");
    same(bonds.offsets.size(), n + 1, "bonds.offsets");
    PD_CHECK(bonds.neighbor.empty() ||
                 bonds.offsets.back() == static_cast<offset_t>(bonds.neighbor.size()),
             "bond offsets must end at the number of bonds (or the lists are not loaded)");
    for (auto m : bodies.material)
        PD_CHECK(m >= 0 && static_cast<std::size_t>(m) < materials.size(), "material index");
}

Bonds build_bonds(const Nodes& nodes, const Bodies& bodies, bool partial_cutoff) {
    const std::size_t n = nodes.num();
    Bonds bonds;
    bonds.offsets.assign(n + 1, 0);
    std::vector<std::vector<index_t>> rows(n);
    for (std::size_t b = 0; b < bodies.num(); ++b) {
        const double delta = bodies.horizon[b];
        const double reach = delta + (partial_cutoff ? 0.5 * bodies.mesh_size[b] : 0.0);
        const auto i0 = bodies.begin(b), i1 = bodies.end(b);
        if (i1 <= i0)
            continue;
        // Cell list with cell size delta over this body's nodes.
        double lo[3] = {1e300, 1e300, 1e300};
        for (auto i = i0; i < i1; ++i)
            for (int d = 0; d < 3; ++d)
                lo[d] = std::min(lo[d], nodes.x0[3 * i + d]);
        auto key = [&](const double* x, int off[3]) {
            std::int64_t c[3];
            for (int d = 0; d < 3; ++d)
                c[d] = static_cast<std::int64_t>(std::floor((x[d] - lo[d]) / reach)) + off[d];
            return (c[0] * 1000003LL + c[1]) * 1000003LL + c[2];
        };
        std::unordered_map<std::int64_t, std::vector<index_t>> cells;
        int zero[3] = {0, 0, 0};
        for (auto i = i0; i < i1; ++i)
            cells[key(&nodes.x0[3 * i], zero)].push_back(static_cast<index_t>(i));
        const double d2 = reach * reach;
        for (auto i = i0; i < i1; ++i) {
            const double* xi = &nodes.x0[3 * i];
            auto& row = rows[i];
            for (int a = -1; a <= 1; ++a)
                for (int bb = -1; bb <= 1; ++bb)
                    for (int c = -1; c <= 1; ++c) {
                        int off[3] = {a, bb, c};
                        auto it = cells.find(key(xi, off));
                        if (it == cells.end())
                            continue;
                        for (index_t j : it->second) {
                            if (j == i)
                                continue;
                            const double* xj = &nodes.x0[3 * j];
                            double r2 = 0;
                            for (int d = 0; d < 3; ++d)
                                r2 += (xj[d] - xi[d]) * (xj[d] - xi[d]);
                            if (r2 < d2) // strict
                                row.push_back(j);
                        }
                    }
            std::sort(row.begin(), row.end());
        }
    }
    for (std::size_t i = 0; i < n; ++i)
        bonds.offsets[i + 1] = bonds.offsets[i] + static_cast<offset_t>(rows[i].size());
    bonds.neighbor.reserve(static_cast<std::size_t>(bonds.offsets[n]));
    for (auto& r : rows)
        bonds.neighbor.insert(bonds.neighbor.end(), r.begin(), r.end());
    return bonds;
}

} // namespace pd::model
