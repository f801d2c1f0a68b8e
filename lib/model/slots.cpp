// SPDX-License-Identifier: MIT
// Notch slots (see slots.hpp): point-in-rectangle and Liang-Barsky segment clipping in the
// slot's own frame (along, across), then one compaction pass over nodes and bonds.
#include "model/slots.hpp"

#include "core/errors.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace pd::model {

namespace {

struct Frame {
    double o[2], t[2], n[2], length, half;
};

Frame frame(const Slot& s) {
    const double dx = s.p1[0] - s.p0[0], dy = s.p1[1] - s.p0[1];
    const double L = std::hypot(dx, dy);
    return {{s.p0[0], s.p0[1]}, {dx / L, dy / L}, {-dy / L, dx / L}, L, 0.5 * s.width};
}

void local(const Frame& f, const double* x, double& u, double& v) {
    const double rx = x[0] - f.o[0], ry = x[1] - f.o[1];
    u = rx * f.t[0] + ry * f.t[1];
    v = rx * f.n[0] + ry * f.n[1];
}

} // namespace

bool segments_cross(const double* a, const double* b, const double* c, const double* d) {
    auto orient = [](const double* p, const double* q, const double* r) {
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
    };
    const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a),
                 o4 = orient(c, d, b);
    return ((o1 > 0) != (o2 > 0) || o1 == 0 || o2 == 0) &&
           ((o3 > 0) != (o4 > 0) || o3 == 0 || o4 == 0) &&
           std::max(a[0], b[0]) >= std::min(c[0], d[0]) &&
           std::max(c[0], d[0]) >= std::min(a[0], b[0]) &&
           std::max(a[1], b[1]) >= std::min(c[1], d[1]) &&
           std::max(c[1], d[1]) >= std::min(a[1], b[1]);
}

bool slot_contains(const Slot& s, const double* x) {
    if (!(s.width > 0))
        return false;
    const Frame f = frame(s);
    double u, v;
    local(f, x, u, v);
    return u > 0 && u < f.length && std::abs(v) < f.half;
}

double slot_distance(const Slot& s, const double* x) {
    const Frame f = frame(s);
    double u, v;
    local(f, x, u, v);
    const double du = std::max({0.0, -u, u - f.length});
    const double dv = std::max(0.0, std::abs(v) - std::max(0.0, f.half));
    return std::hypot(du, dv);
}

bool slot_cuts(const Slot& s, const double* a, const double* b) {
    if (!(s.width > 0))
        return segments_cross(a, b, s.p0.data(), s.p1.data());
    const Frame f = frame(s);
    double ua, va, ub, vb;
    local(f, a, ua, va);
    local(f, b, ub, vb);
    // Liang-Barsky: clip a + t (b - a), t in [0, 1], to [0, L] x [-w/2, w/2].
    double t0 = 0, t1 = 1;
    const double du = ub - ua, dv = vb - va;
    const double p[4] = {-du, du, -dv, dv};
    const double q[4] = {ua, f.length - ua, va + f.half, f.half - va};
    for (int k = 0; k < 4; ++k) {
        if (p[k] == 0) {
            if (q[k] < 0)
                return false;
            continue;
        }
        const double r = q[k] / p[k];
        if (p[k] < 0)
            t0 = std::max(t0, r);
        else
            t1 = std::min(t1, r);
    }
    if (!(t1 > t0))
        return false;
    // A piece of positive length: reject one lying on an edge (its midpoint on the boundary).
    const double tm = 0.5 * (t0 + t1);
    const double um = ua + tm * du, vm = va + tm * dv;
    return um > 0 && um < f.length && std::abs(vm) < f.half;
}

namespace {

void check_slots(const std::vector<Slot>& slots) {
    for (std::size_t k = 0; k < slots.size(); ++k) {
        const auto& s = slots[k];
        if (!(std::hypot(s.p1[0] - s.p0[0], s.p1[1] - s.p0[1]) > 0))
            throw ConfigError(fmt::format("slots[{}]", k),
                              "\"from\" and \"to\" must differ in x/y");
        if (!(s.width >= 0) || !std::isfinite(s.width))
            throw ConfigError(fmt::format("slots[{}].width", k), "must be a finite value >= 0");
    }
}

/// New index of each node, -1 for those inside a slot (counted in `cut`).
std::vector<index_t> renumber_nodes(const Model& m, const std::vector<Slot>& slots, SlotCut& cut) {
    const std::size_t n = m.nodes.num();
    std::vector<index_t> new_index(n, -1);
    index_t next = 0;
    for (std::size_t i = 0; i < n; ++i) {
        bool inside = false;
        for (std::size_t k = 0; k < slots.size() && !inside; ++k)
            if (slot_contains(slots[k], &m.nodes.x0[3 * i])) {
                inside = true;
                ++cut.nodes_per_slot[k];
            }
        if (inside)
            ++cut.nodes_removed;
        else
            new_index[i] = next++;
    }
    return new_index;
}

/// Body offsets: count the kept nodes of each body.
std::vector<offset_t> body_offsets(const Bodies& B, const std::vector<index_t>& new_index) {
    std::vector<offset_t> offsets(B.num() + 1, 0);
    for (std::size_t b = 0; b < B.num(); ++b) {
        offset_t kept = 0;
        for (auto i = B.begin(b); i < B.end(b); ++i)
            kept += new_index[static_cast<std::size_t>(i)] >= 0;
        if (kept == 0 && B.end(b) > B.begin(b))
            throw ConfigError("slots",
                              fmt::format("particle {} lies entirely inside the slots", b));
        offsets[b + 1] = offsets[b] + kept;
    }
    return offsets;
}

/// Bonds: drop the rows of removed nodes and entries through a slot, renumber neighbours.
Bonds cut_bonds(const Model& m, const std::vector<Slot>& slots,
                const std::vector<index_t>& new_index, std::size_t kept, SlotCut& cut) {
    Bonds nb;
    nb.offsets.assign(kept + 1, 0);
    nb.neighbor.reserve(m.bonds.neighbor.size());
    std::size_t through = 0;
    for (std::size_t i = 0; i < new_index.size(); ++i) {
        if (new_index[i] < 0)
            continue;
        const double* xi = &m.nodes.x0[3 * i];
        for (auto e = m.bonds.offsets[i]; e < m.bonds.offsets[i + 1]; ++e) {
            const auto j = static_cast<std::size_t>(m.bonds.neighbor[static_cast<std::size_t>(e)]);
            if (new_index[j] < 0)
                continue;
            bool keep = true;
            for (std::size_t k = 0; k < slots.size() && keep; ++k)
                if (slot_cuts(slots[k], xi, &m.nodes.x0[3 * j])) {
                    keep = false;
                    if (i < j)
                        ++cut.bonds_per_slot[k];
                }
            if (keep)
                nb.neighbor.push_back(new_index[j]);
            else
                ++through;
        }
        nb.offsets[static_cast<std::size_t>(new_index[i]) + 1] =
            static_cast<offset_t>(nb.neighbor.size());
    }
    cut.bonds_removed = through / 2;
    return nb;
}

/// The node arrays of the kept nodes.
Nodes kept_nodes(const Nodes& nodes, const std::vector<index_t>& new_index, std::size_t kept) {
    Nodes nn;
    nn.x0.reserve(3 * kept);
    for (std::size_t i = 0; i < new_index.size(); ++i) {
        if (new_index[i] < 0)
            continue;
        nn.x0.insert(nn.x0.end(), nodes.x0.begin() + 3 * i, nodes.x0.begin() + 3 * i + 3);
        nn.volume.push_back(nodes.volume[i]);
        nn.body.push_back(nodes.body[i]);
        if (!nodes.surface.empty())
            nn.surface.push_back(nodes.surface[i]);
    }
    return nn;
}

} // namespace

SlotCut apply_slots(Model& m, const std::vector<Slot>& slots) {
    SlotCut cut;
    cut.nodes_per_slot.assign(slots.size(), 0);
    cut.bonds_per_slot.assign(slots.size(), 0);
    if (slots.empty())
        return cut;
    check_slots(slots);
    PD_CHECK(m.bonds.complete(), "apply_slots needs the whole bond list");
    const auto new_index = renumber_nodes(m, slots, cut);
    const std::size_t kept = m.nodes.num() - cut.nodes_removed;
    auto offsets = body_offsets(m.bodies, new_index);
    Bonds nb = cut_bonds(m, slots, new_index, kept, cut);
    m.nodes = kept_nodes(m.nodes, new_index, kept);
    m.bonds = std::move(nb);
    m.bodies.node_offsets = std::move(offsets);
    return cut;
}

} // namespace pd::model
