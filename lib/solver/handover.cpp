// SPDX-License-Identifier: MIT
// Hand-overs of the state: a checkpoint's (restore), another decomposition's (redistribute),
// the ghosts after a contact-list rebuild.
#include "core/errors.hpp"
#include "solver/detail.hpp"
#include "solver/solver.hpp"

#include <algorithm>

namespace pd::solver {

using detail::rows_of;

namespace detail {
void exchange_motion(Forces& f) {
    // x = x0 + u holds bit for bit on every owner (the integrator, prescribed displacements
    // and restores all write it so), so a ghost's position is recomputed from its u, not sent:
    // 48 bytes per ghost and step instead of 72.
    f.dom->exchange({&f.s.u, &f.s.v}, 3);
    double* x = f.s.x.data();
    const double *x0 = f.s.x0.data(), *u = f.s.u.data();
    f.dom->for_each_ghost([&](index_t i) {
        for (std::size_t k = 3 * static_cast<std::size_t>(i), e = k + 3; k < e; ++k)
            x[k] = x0[k] + u[k];
    });
}
} // namespace detail

void set_ghosts(Forces& f) {
    std::vector<index_t> c;
    f.contact->ghosts(c);
    std::sort(c.begin(), c.end());
    c.erase(std::unique(c.begin(), c.end()), c.end());
    f.contact_ghosts = c.size();
    std::vector<index_t> g = f.bond_ghosts;
    g.insert(g.end(), c.begin(), c.end());
    f.dom->set_ghosts(g);
    detail::exchange_motion(f); // new ghosts' velocities too (friction, damping)
}

void Solver::take_rows() {
    f_.s.rows = f_.dom->rows();
    f_.contact->set_owned(*f_.dom);
    f_.reactions.set_rows(f_.s);
}

void Solver::restore(std::int64_t step, double time, const std::vector<double>& u,
                     const std::vector<double>& v, const std::vector<double>& f,
                     const std::vector<std::uint8_t>& alive, std::int64_t broken_total) {
    PD_CHECK(u.size() == f_.s.u.size() && v.size() == f_.s.v.size() && f.size() == f_.s.f.size() &&
                 alive.size() == f_.m.bonds.num(),
             "checkpoint sizes");
    initialized_ = true;
    f_.s.step = step;
    f_.s.time = time;
    f_.s.u = u;
    f_.s.v = v;
    f_.s.f = f;
    for (std::size_t k = 0; k < f_.s.x.size(); ++k)
        f_.s.x[k] = f_.s.x0[k] + f_.s.u[k];
    f_.b.alive = rows_of(alive, f_.m.bonds.offsets, f_.s.rows);
    // This rank's share of the broken bonds (`broken_total` counts every rank's).
    f_.broken_total = detail::count_broken(f_);
    if (f_.dom->sum(f_.broken_total) != broken_total)
        throw InputError(fmt::format("checkpoint: {} broken bond ends recorded, {} in its bond "
                                     "state",
                                     broken_total, f_.dom->sum(f_.broken_total)));
}

void Solver::surface_depths(std::vector<std::int64_t>& pairs, std::vector<double>& depths,
                            double& time) const {
    f_.contact->depth_history(pairs, depths, time);
}

void Solver::set_surface_depths(const std::vector<std::int64_t>& pairs,
                                const std::vector<double>& depths, double time) {
    f_.contact->set_depth_history(pairs, depths, time);
}

bool Solver::surface_build(std::vector<double>& x, std::vector<std::uint8_t>& whole) const {
    return f_.contact->last_build(x, whole);
}

void Solver::restore_surface_build(std::vector<double> x, std::vector<std::uint8_t> whole) {
    f_.contact->restore_build(std::move(x), std::move(whole));
}

void Solver::redistribute(Domain* dom) {
    // Everything where its old owner has it, on every rank.
    f_.dom->allgather(f_.s.x, 3);
    f_.dom->allgather(f_.s.u, 3);
    f_.dom->allgather(f_.s.v, 3);
    f_.dom->allgather(f_.s.f, 3);
    const auto alive = global_alive();
    std::vector<index_t> neighbors;
    if (!f_.m.bonds.complete())
        neighbors = detail::global_neighbors(f_);
    // The unloading factors of the last evaluation (friction limits of the next one).
    std::vector<double> mine;
    for (const auto& [key, value] : f_.unload)
        mine.insert(mine.end(), {double(key.first), double(key.second), value});
    const double work = f_.dom->sum(external_work_), power = f_.dom->sum(power_);
    std::vector<double> diss{f_.diss.fracture,    f_.diss.damping,      f_.diss.friction,
                             f_.diss.viscous,     f_.diss.damping_rate, f_.diss.friction_rate,
                             f_.diss.viscous_rate};
    f_.dom->sum(diss);
    if (f_.dom->distributed()) {
        int len = static_cast<int>(mine.size());
        std::vector<int> lens(static_cast<std::size_t>(f_.dom->size()));
        MPI_Allgather(&len, 1, MPI_INT, lens.data(), 1, MPI_INT, f_.dom->comm());
        std::vector<int> disp(lens.size() + 1, 0);
        for (std::size_t p = 0; p < lens.size(); ++p)
            disp[p + 1] = disp[p] + lens[p];
        std::vector<double> all(static_cast<std::size_t>(disp.back()));
        MPI_Allgatherv(mine.data(), len, MPI_DOUBLE, all.data(), lens.data(), disp.data(),
                       MPI_DOUBLE, f_.dom->comm());
        for (std::size_t k = 0; k + 2 < all.size(); k += 3)
            f_.unload[{static_cast<std::int32_t>(all[k]), static_cast<std::int32_t>(all[k + 1])}] =
                all[k + 2];
    }
    // The new rows; the new domain continues the old one's message counts (rank_report).
    dom->continue_traffic(f_.dom->traffic());
    f_.dom = dom;
    if (f_.dom->num_nodes() != f_.s.n)
        throw InternalError("redistribute: a domain of another model");
    take_rows();
    const auto& B = f_.m.bonds;
    if (!B.complete()) // the new rows' neighbour lists
        row_neighbors_ = rows_of(neighbors, B.offsets, f_.s.rows);
    detail::build_bonds(f_, row_neighbors_);
    f_.b.alive = rows_of(alive, B.offsets, f_.s.rows);
    detail::set_bond_ghosts(f_); // contact ghosts join at the next (forced) rebuild
    detail::family_factors(f_);
    external_work_ = f_.dom->rank() == 0 ? work : 0.0;
    power_ = f_.dom->rank() == 0 ? power : 0.0;
    for (double& d : diss)
        d = f_.dom->rank() == 0 ? d : 0.0;
    f_.diss = {diss[0], diss[1], diss[2], diss[3], diss[4], diss[5], diss[6]};
    f_.broken_total = detail::count_broken(f_);
    f_.contact->invalidate();
    f_.walls->invalidate();
}

} // namespace pd::solver
