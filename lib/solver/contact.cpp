// SPDX-License-Identifier: MIT
#include "solver/contact.hpp"

#include "core/errors.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <unordered_map>

namespace pd::solver {

ContactList::ContactList(const model::Model& m, double skin)
    : skin_(skin)
    , body_group_(m.bodies.group)
    , body_offsets_(m.bodies.node_offsets) {
    for (auto g : body_group_)
        ngroups_ = std::max(ngroups_, g + 1);
    law_of_.assign(static_cast<std::size_t>(ngroups_ * ngroups_), -1);
    for (const auto& p : m.contact) {
        if (p.group_a >= ngroups_ || p.group_b >= ngroups_ || p.stiffness <= 0 || p.radius <= 0)
            continue;
        const auto k = static_cast<std::int32_t>(laws_.size());
        laws_.push_back(p);
        law_of_[static_cast<std::size_t>(p.group_a * ngroups_ + p.group_b)] = k;
        law_of_[static_cast<std::size_t>(p.group_b * ngroups_ + p.group_a)] = k;
        if (p.law == model::ContactLaw::node)
            rc_max_ = std::max(rc_max_, p.radius);
        any_friction_ = any_friction_ || p.friction > 0;
        any_surface_ = any_surface_ || p.law == model::ContactLaw::surface;
        any_node_ = any_node_ || p.law == model::ContactLaw::node;
    }
    active_ = m.bodies.num() > 1 && !laws_.empty();
    owned_.assign(m.nodes.num(), 1);
    // Nodes below their grain's surface layer (pd-pack: deeper than R_c + h/2 + min(R_c, h)
    // from the reference boundary): a node of another grain within min(R_c, h) of one is more
    // than R_c + h/2 inside this grain. Files without the layer flag: no check.
    if (!m.nodes.surface.empty()) {
        deep_.resize(m.nodes.num());
        bool any = false;
        for (std::size_t i = 0; i < deep_.size(); ++i) {
            deep_[i] = m.nodes.surface[i] ? 0 : 1;
            any = any || deep_[i];
        }
        if (!any)
            deep_.clear();
    }
    // Guard distance per body: min(R_c, h) (the layer is R_c + h/2 + that deep); files whose
    // layer is 2 R_c + h/2 deep (pd-file 1.2) satisfy the same bound.
    rho_.resize(m.bodies.num());
    for (std::size_t b = 0; b < rho_.size(); ++b)
        rho_[b] = std::min(rc_max_, m.bodies.mesh_size[b]);
    if (active_ && any_surface_)
        init_surface(m); // (raises rc_max_ to the surface law's search radius)
}

bool moved_farther_than(const State& s, const std::vector<double>& x_ref, double limit) {
    if (limit <= 0)
        return true;
    const double lim2 = limit * limit;
    const auto n = static_cast<std::int64_t>(s.rows.size());
    const index_t* rows = s.rows.data();
    const double *x = s.x.data(), *xr = x_ref.data();
    const auto moved = [&](std::int64_t a) {
        const std::int64_t i = rows[a];
        double d2 = 0;
        for (int d = 0; d < 3; ++d) {
            const double e = x[3 * i + d] - xr[3 * i + d];
            d2 += e * e;
        }
        return d2 > lim2;
    };
    bool far = false;
    if (threaded(n)) { // (no one-thread region on every step: see threaded())
#pragma omp parallel for schedule(static) reduction(|| : far)
        for (std::int64_t a = 0; a < n; ++a)
            far = far || moved(a);
        return far;
    }
    for (std::int64_t a = 0; a < n; ++a)
        if (moved(a))
            return true;
    return false;
}

double max_moved(const State& s, const std::vector<double>& x_ref) {
    const auto n = static_cast<std::int64_t>(s.rows.size());
    const index_t* rows = s.rows.data();
    const double *x = s.x.data(), *xr = x_ref.data();
    double m2 = 0;
#pragma omp parallel for schedule(static) reduction(max : m2) if (threaded(n))
    for (std::int64_t a = 0; a < n; ++a) {
        const std::int64_t i = rows[a];
        double d2 = 0;
        for (int d = 0; d < 3; ++d) {
            const double e = x[3 * i + d] - xr[3 * i + d];
            d2 += e * e;
        }
        m2 = std::max(m2, d2);
    }
    return std::sqrt(m2);
}

namespace {
/// The record of the touching pair (i, j) at distance r (d = x_j - x_i): the force on j's body
/// from i's body, Kn (R_c - r) V_i V_j along d/r, stored as (smaller, larger) node.
BodyPairForce pair_record(const State& s, const model::ContactPair& law, std::int64_t i, index_t j,
                          double r, const double* d) {
    const auto ii = static_cast<std::size_t>(i);
    const double c =
        law.stiffness * (law.radius - r) * (s.vol[ii] * s.vol[static_cast<std::size_t>(j)]) / r;
    const double sg = i < j ? c : -c;
    BodyPairForce rec{s.body[ii],
                      s.body[static_cast<std::size_t>(j)],
                      static_cast<index_t>(std::min<std::int64_t>(i, j)),
                      static_cast<index_t>(std::max<std::int64_t>(i, j)),
                      {sg * d[0], sg * d[1], sg * d[2]},
                      law.friction,
                      law.restitution < 1};
    if (j < i)
        std::swap(rec.a, rec.b);
    return rec;
}

/// The records in a deterministic order whatever the thread schedule, normalised to a < b.
std::vector<BodyPairForce> sorted(std::vector<BodyPairForce> records) {
    // (i, j), then the force: a pair can have two records under the surface law (each node
    // inside the other's boundary), whose order must not depend on the threads or ranks.
    std::sort(records.begin(), records.end(), [](const auto& p, const auto& q) {
        return std::tie(p.i, p.j, p.force[0], p.force[1], p.force[2]) <
               std::tie(q.i, q.j, q.force[0], q.force[1], q.force[2]);
    });
    for (auto& r : records)
        if (r.a > r.b) { // normalise to a < b: force on the higher-numbered body
            std::swap(r.a, r.b);
            for (double& c : r.force)
                c = -c;
        }
    return records;
}
} // namespace

std::int64_t ContactList::add_forces_impl(State& s, double& energy,
                                          std::vector<BodyPairForce>* normal) const {
    const auto n = static_cast<std::int64_t>(s.rows.size());
    std::int64_t touching = 0, inside = 0;
    double e = 0;
    std::vector<BodyPairForce> records;
    inside_ = {};
    if (!any_node_) {
        // surface law only: no node-pair forces
    } else if (threaded(n)) { // (no one-thread region on every step: see threaded())
#pragma omp parallel reduction(+ : touching, e, inside)
        add_rows(s, normal, records, touching, e, inside);
    } else {
        add_rows(s, normal, records, touching, e, inside);
    }
    energy = e;
    inside_.count = inside;
    if (any_surface_)
        touching += add_surface(s, energy, normal ? &records : nullptr);
    if (normal)
        *normal = sorted(std::move(records));
    return touching;
}

// The rows on the calling thread or, inside add_forces_impl's region, this thread's share of
// them (an orphaned `omp for`: outside a region a plain loop); the sums are the thread's own.
void ContactList::add_rows(State& s, std::vector<BodyPairForce>* normal,
                           std::vector<BodyPairForce>& records, std::int64_t& touching, double& e,
                           std::int64_t& inside) const {
    const auto n = static_cast<std::int64_t>(s.rows.size());
    std::vector<BodyPairForce> mine;
    std::int64_t first_node = -1;
    std::int32_t first_body = -1;
#pragma omp for schedule(static) nowait
    for (std::int64_t a = 0; a < n; ++a) {
        const std::int64_t i = s.rows[static_cast<std::size_t>(a)];
        const double* xi = &s.x[3 * i];
        double fi[3] = {0, 0, 0};
        const auto ii = static_cast<std::size_t>(i);
        for (auto k = offsets_[ii]; k < offsets_[ii + 1]; ++k) {
            const index_t j = neighbor_[static_cast<std::size_t>(k)];
            const auto& law = laws_[static_cast<std::size_t>(law_[static_cast<std::size_t>(k)])];
            if (law.law != model::ContactLaw::node)
                continue; // (surface_contact.cpp)
            const double d0 = s.x[3 * j] - xi[0], d1 = s.x[3 * j + 1] - xi[1],
                         d2 = s.x[3 * j + 2] - xi[2];
            const double r2 = d0 * d0 + d1 * d1 + d2 * d2;
            if (r2 >= law.radius * law.radius)
                continue;
            const double r = std::sqrt(r2);
            if (!deep_.empty() && deep_[static_cast<std::size_t>(j)] &&
                r < rho_[static_cast<std::size_t>(s.body[static_cast<std::size_t>(j)])]) {
                ++inside; // i is more than R_c + h/2 inside j's grain
                if (first_node < 0) {
                    first_node = i;
                    first_body = s.body[static_cast<std::size_t>(j)];
                }
            }
            const double fn = law.stiffness * (law.radius - r) * s.vol[j]; // density, > 0
            const double a = -fn / r; // along d: pushes i away from j
            fi[0] += a * d0;
            fi[1] += a * d1;
            fi[2] += a * d2;
            e += 0.25 * law.stiffness * (law.radius - r) * (law.radius - r) * s.vol[ii] * s.vol[j];
            if (i < j)
                ++touching; // each pair once, from the row of its smaller node
            // A record per touching pair, once on every rank that owns one of its nodes:
            // from the row of the smaller node, or of the larger one if the smaller is a
            // ghost. Stored as (smaller, larger), the force computed symmetrically, so the
            // records do not depend on which side computed them.
            if (normal && (law.restitution < 1 || law.friction > 0) &&
                (i < j || !owned_[static_cast<std::size_t>(j)])) {
                const double d[3] = {d0, d1, d2};
                mine.push_back(pair_record(s, law, i, j, r, d));
            }
        }
        s.f[3 * i] += fi[0];
        s.f[3 * i + 1] += fi[1];
        s.f[3 * i + 2] += fi[2];
    }
    if (first_node >= 0) {
#pragma omp critical(pd_contact_inside)
        if (inside_.node < 0 || first_node < inside_.node) {
            inside_.node = first_node;
            inside_.body = s.body[static_cast<std::size_t>(first_node)];
            inside_.inside = first_body;
        }
    }
    if (normal) {
#pragma omp critical(pd_contact_records)
        records.insert(records.end(), mine.begin(), mine.end());
    }
}

void ContactList::set_owned(const Domain& dom) {
    std::fill(owned_.begin(), owned_.end(), std::uint8_t{0});
    for (auto i : dom.rows())
        owned_[static_cast<std::size_t>(i)] = 1;
    facet_rows_stale_ = true; // count_whole's rows follow the owned rows
}

bool ContactList::last_build(std::vector<double>& x, std::vector<std::uint8_t>& whole) const {
    x.clear();
    whole.clear();
    if (!any_surface_ || !built_)
        return false;
    x = x_build_;
    whole = whole_;
    return true;
}

bool ContactList::update(State& s, const Domain& dom, const BondData* b, std::int64_t broken) {
    if (!active_)
        return false;
    if (!restore_x_.empty()) {
        // A restart: the run's last rebuild, at its positions and torn facets (every rank holds
        // the whole arrays), then the usual test of how far the nodes moved since.
        PD_CHECK(restore_x_.size() == s.x.size() && restore_whole_.size() == s.n,
                 "restored contact build sizes");
        if (dom.distributed())
            dom.allgather(s.x, 3);
        std::swap(s.x, restore_x_);
        rebuild(s);
        std::swap(s.x, restore_x_);
        whole_ = std::move(restore_whole_);
        restore_x_.clear();
        restore_whole_.clear();
        if (any_surface_) {
            update_surface(s, dom, b, broken); // this step's tears, as the run had them
            return true;
        }
        moved_ = dom.max(max_moved(s, x_build_));
        if (!(moved_ > 0.5 * skin_))
            return true;
    }
    if (any_surface_)
        return update_surface(s, dom, b, broken); // surface_tear.cpp
    // Collective: every rank rebuilds when any rank needs it.
    if (!dom.any(!built_ || moved_farther_than(s, x_build_, 0.5 * skin_)))
        return false;
    if (dom.distributed())
        dom.allgather(s.x, 3); // every node where its owner has it
    rebuild(s);
    return true;
}

void ContactList::ghosts(std::vector<index_t>& out) const {
    for (auto j : neighbor_)
        if (!owned_[static_cast<std::size_t>(j)])
            out.push_back(j);
    if (!any_surface_)
        return;
    // The surface law reads every vertex of the facets at the candidates, and in 2D of the
    // facets across their vertices (surface_blend.cpp, vertex_blend).
    const auto nv = static_cast<std::size_t>(facets_.nv);
    const auto add = [&](std::size_t f) {
        for (std::size_t a = 0; a < nv; ++a) {
            const auto v = facets_.v[nv * f + a];
            if (!owned_[static_cast<std::size_t>(v)])
                out.push_back(v);
        }
    };
    for (auto j : neighbor_)
        for (auto q = facets_.offsets[static_cast<std::size_t>(j)];
             q < facets_.offsets[static_cast<std::size_t>(j) + 1]; ++q) {
            const auto f = static_cast<std::size_t>(facets_.of_node[static_cast<std::size_t>(q)]);
            add(f);
            for (std::size_t e = 0; e < 2 && !facets_.across.empty(); ++e)
                if (facets_.across[2 * f + e] >= 0)
                    add(static_cast<std::size_t>(facets_.across[2 * f + e]));
        }
}

namespace {
/// A cell list of the active nodes, cell size `reach`: cells sorted by key, (key, node) pairs,
/// one sort, no per-cell allocation.
struct CellGrid {
    struct Cell {
        std::size_t begin, end; ///< range in `keyed`
        std::int32_t body;      ///< the one body with nodes in the cell, or -1 if several
        bool quiet;             ///< this cell and its neighbours hold nodes of `body` only
    };
    double reach = 0;
    double origin[3] = {0, 0, 0};
    int zr = 1; ///< 0 when every node lies in z = 0
    std::vector<std::pair<std::int64_t, index_t>> keyed;
    std::unordered_map<std::int64_t, Cell> cells;

    std::int64_t cell_of(const double* x, int dx, int dy, int dz) const {
        const auto cx = static_cast<std::int64_t>((x[0] - origin[0]) / reach) + dx;
        const auto cy = static_cast<std::int64_t>((x[1] - origin[1]) / reach) + dy;
        const auto cz = static_cast<std::int64_t>((x[2] - origin[2]) / reach) + dz;
        return (cx << 42) | (cy << 21) | cz;
    }

    /// Exact cell keys: integer cell coordinates from the box of the active nodes, 21 bits
    /// each.
    void frame(const State& s, const std::vector<index_t>& active_nodes) {
        if (!active_nodes.empty())
            for (int d = 0; d < 3; ++d) {
                origin[d] = std::numeric_limits<double>::infinity();
                double top = -origin[d];
                for (auto i : active_nodes) {
                    origin[d] = std::min(origin[d], s.x[3 * i + d]);
                    top = std::max(top, s.x[3 * i + d]);
                }
                if ((top - origin[d]) / reach > double(1 << 20))
                    throw NumericalError(fmt::format(
                        "contact search: the scene spans {:.3g} m, over 2^20 contact cells of "
                        "{:.3g} m (did a node fly away?)",
                        top - origin[d], reach));
                origin[d] -= reach; // keeps every cell coordinate >= 1, so neighbours >= 0
            }
        const bool flat = [&] {
            for (auto i : active_nodes)
                if (s.x[3 * i + 2] != 0.0)
                    return false;
            return true;
        }();
        zr = flat ? 0 : 1;
    }

    void fill(const State& s, const std::vector<index_t>& active_nodes) {
        keyed.resize(active_nodes.size());
        for (std::size_t a = 0; a < active_nodes.size(); ++a)
            keyed[a] = {cell_of(&s.x[3 * active_nodes[a]], 0, 0, 0), active_nodes[a]};
        std::sort(keyed.begin(), keyed.end());
        cells.reserve(keyed.size() / 2 + 1);
        for (std::size_t a = 0; a < keyed.size();) {
            std::size_t e = a;
            std::int32_t body = s.body[static_cast<std::size_t>(keyed[a].second)];
            while (e < keyed.size() && keyed[e].first == keyed[a].first) {
                if (s.body[static_cast<std::size_t>(keyed[e].second)] != body)
                    body = -1;
                ++e;
            }
            cells.emplace(keyed[a].first, Cell{a, e, body, false});
            a = e;
        }
    }

    /// Exact skip: a candidate j of node i lies within `reach` of it, so in i's cell or one of
    /// its 3^d neighbours. When all of them hold nodes of i's own body only (a grain's inside,
    /// away from every other grain), i has no candidate and its cells need not be scanned.
    void mark_quiet(const State& s) {
        for (auto& [key, c] : cells) {
            if (c.body < 0)
                continue;
            const double* x = &s.x[3 * static_cast<std::size_t>(keyed[c.begin].second)];
            bool quiet = true;
            for (int dx = -1; dx <= 1 && quiet; ++dx)
                for (int dy = -1; dy <= 1 && quiet; ++dy)
                    for (int dz = -zr; dz <= zr && quiet; ++dz) {
                        auto it = cells.find(cell_of(x, dx, dy, dz));
                        quiet = it == cells.end() || it->second.body == c.body;
                    }
            c.quiet = quiet;
        }
    }
};
} // namespace

std::vector<std::uint8_t> ContactList::near_bodies(const State& s, double reach) const {
    // Broad phase: body boxes in current configuration; keep bodies near another body they
    // have a contact law with.
    const std::size_t nb = body_offsets_.size() - 1;
    std::vector<double> lo(3 * nb, std::numeric_limits<double>::infinity()),
        hi(3 * nb, -std::numeric_limits<double>::infinity());
    for (std::size_t b = 0; b < nb; ++b)
        for (auto i = body_offsets_[b]; i < body_offsets_[b + 1]; ++i)
            for (int d = 0; d < 3; ++d) {
                lo[3 * b + d] = std::min(lo[3 * b + d], s.x[3 * i + d]);
                hi[3 * b + d] = std::max(hi[3 * b + d], s.x[3 * i + d]);
            }
    std::vector<std::size_t> order(nb);
    for (std::size_t b = 0; b < nb; ++b)
        order[b] = b;
    std::sort(order.begin(), order.end(), [&](auto a, auto b) { return lo[3 * a] < lo[3 * b]; });
    std::vector<std::uint8_t> near(nb, 0);
    for (std::size_t ia = 0; ia < nb; ++ia) {
        const auto a = order[ia];
        for (std::size_t ib = ia + 1; ib < nb && lo[3 * order[ib]] <= hi[3 * a] + reach; ++ib) {
            const auto b = order[ib];
            bool overlap = true;
            for (int d = 1; d < 3; ++d)
                overlap = overlap && lo[3 * b + d] <= hi[3 * a + d] + reach &&
                          lo[3 * a + d] <= hi[3 * b + d] + reach;
            if (overlap &&
                law_of_[static_cast<std::size_t>(body_group_[a] * ngroups_ + body_group_[b])] >= 0)
                near[a] = near[b] = 1;
        }
    }
    return near;
}

void ContactList::store_rows(std::size_t n, const std::vector<std::vector<index_t>>& rows,
                             const std::vector<std::vector<std::int32_t>>& laws) {
    offsets_.assign(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i)
        offsets_[i + 1] = offsets_[i] + static_cast<model::offset_t>(rows[i].size());
    neighbor_.clear();
    law_.clear();
    neighbor_.reserve(static_cast<std::size_t>(offsets_.back()));
    law_.reserve(static_cast<std::size_t>(offsets_.back()));
    std::vector<std::size_t> idx;
    for (std::size_t i = 0; i < n; ++i) {
        // Sorted rows: the force sum order is independent of thread count and hash layout.
        idx.resize(rows[i].size());
        for (std::size_t k = 0; k < idx.size(); ++k)
            idx[k] = k;
        std::sort(idx.begin(), idx.end(), [&](auto a, auto b) { return rows[i][a] < rows[i][b]; });
        for (auto k : idx) {
            neighbor_.push_back(rows[i][k]);
            law_.push_back(laws[i][k]);
        }
    }
}

// Under MPI the surface law also computes the rows of the ghost candidates of owned rows: a node
// of another rank inside a body of this rank pushes this rank's facet nodes (every rank builds
// such a row from the same positions, so alike).
template <class Keyed, class RowOf>
void ContactList::ghost_rows(const Keyed& keyed, const std::vector<std::vector<index_t>>& rows,
                             const std::vector<std::vector<std::int32_t>>& laws,
                             const RowOf& row_of) const {
    std::vector<std::uint8_t> need(rows.size(), 0);
    bool any = false;
    for (std::size_t i = 0; i < rows.size(); ++i)
        if (owned_[i])
            for (std::size_t k = 0; k < rows[i].size(); ++k)
                if (!owned_[static_cast<std::size_t>(rows[i][k])] &&
                    laws_[static_cast<std::size_t>(laws[i][k])].law == model::ContactLaw::surface)
                    need[static_cast<std::size_t>(rows[i][k])] = any = true;
    if (any)
        for (std::size_t a = 0; a < keyed.size(); ++a)
            if (need[static_cast<std::size_t>(keyed[a].second)])
                row_of(a);
}

void ContactList::rebuild(const State& s) {
    ++rebuilds_;
    built_ = true;
    x_build_ = s.x;
    const std::size_t nb = body_offsets_.size() - 1;
    const double reach = rc_max_ + skin_;
    const auto near = near_bodies(s, reach);
    // Cell list over EVERY node of the near bodies, cell size = reach. No node is left out by
    // its depth in the grain: a node deep inside a grain can meet a node of another grain that
    // was pressed deep into it, and leaving it out lets grains tunnel through each other.
    std::vector<index_t> active_nodes;
    for (std::size_t b = 0; b < nb; ++b)
        if (near[b])
            for (auto i = body_offsets_[b]; i < body_offsets_[b + 1]; ++i)
                active_nodes.push_back(static_cast<index_t>(i));
    CellGrid grid;
    grid.reach = reach;
    grid.frame(s, active_nodes);
    grid.fill(s, active_nodes);
    grid.mark_quiet(s);
    const auto& keyed = grid.keyed;
    const int zr = grid.zr;
    // The rows of the last rebuild, emptied: their capacity stays (no allocation per row and
    // rebuild once the rows have grown).
    auto& rows = cand_rows_;
    auto& laws = cand_laws_;
    rows.resize(s.n);
    laws.resize(s.n);
    for (std::size_t i = 0; i < s.n; ++i) {
        rows[i].clear();
        laws[i].clear();
    }
    const double r2max = reach * reach;
    const auto na = static_cast<std::int64_t>(keyed.size());
    // Node i's candidates: the nodes of other bodies within reach that i's body has a law with.
    const auto row_of = [&](std::size_t a) {
        const index_t i = keyed[a].second;
        const double* xi = &s.x[3 * i];
        if (grid.cells.find(keyed[a].first)->second.quiet)
            return;
        const auto gi = body_group_[static_cast<std::size_t>(s.body[i])];
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -zr; dz <= zr; ++dz) {
                    auto it = grid.cells.find(grid.cell_of(xi, dx, dy, dz));
                    if (it == grid.cells.end())
                        continue;
                    for (auto q = it->second.begin; q < it->second.end; ++q) {
                        const index_t j = keyed[q].second;
                        if (s.body[j] == s.body[i])
                            continue; // same grain: bonds (and broken-bond repulsion) act there
                        const auto law = law_of_[static_cast<std::size_t>(
                            gi * ngroups_ + body_group_[static_cast<std::size_t>(s.body[j])])];
                        if (law < 0)
                            continue;
                        double r2 = 0;
                        for (int d = 0; d < 3; ++d)
                            r2 += (s.x[3 * j + d] - xi[d]) * (s.x[3 * j + d] - xi[d]);
                        if (r2 < r2max) {
                            rows[static_cast<std::size_t>(i)].push_back(j);
                            laws[static_cast<std::size_t>(i)].push_back(law);
                        }
                    }
                }
    };
#pragma omp parallel for schedule(dynamic, 256) if (na > parallel_min)
    for (std::int64_t a = 0; a < na; ++a)
        if (owned_[static_cast<std::size_t>(keyed[static_cast<std::size_t>(a)].second)])
            row_of(static_cast<std::size_t>(a)); // rows of owned nodes; the cells hold all
    if (any_surface_)
        ghost_rows(keyed, rows, laws, row_of);
    store_rows(s.n, rows, laws);
    if (any_surface_)
        surface_rows(s);
}

std::int64_t ContactList::add_forces(State& s, double& energy,
                                     std::vector<BodyPairForce>* normal) const {
    energy = 0;
    if (!active_ || !built_)
        return 0;
    return add_forces_impl(s, energy, normal);
}

double contact_max_stiffness(const model::ContactPair& p) {
    return p.stiffness; // node law: f = Kn (R_c - R) V_j; surface law: f = c (p - y_i)
}

} // namespace pd::solver
