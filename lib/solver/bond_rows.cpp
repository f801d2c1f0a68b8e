// SPDX-License-Identifier: MIT
// This rank's rows of the bond list: the per-body law constants, reference lengths, partial
// volumes, influence, ghosts, surface-correction factors and LPS weighted volumes.
#include "core/errors.hpp"
#include "model/functions.hpp"
#include "model/lps.hpp"
#include "model/pmb.hpp"
#include "model/quadrature.hpp"
#include "model/rnp.hpp"
#include "model/surface_correction.hpp"
#include "solver/bond_forces.hpp"
#include "solver/detail.hpp"

#include <algorithm>
#include <cmath>

namespace pd::solver::detail {

namespace {
/// Zero-sized per-body arrays of the laws (law_constants() fills them).
void size_law(BodyLaw& law, std::size_t nb, int dimension) {
    law.c.resize(nb);
    law.s0.resize(nb);
    law.s0_lo.assign(nb, 0.0);
    law.flaw_m.assign(nb, 0.0);
    law.flaw_len.assign(nb, 0.0);
    law.centre.assign(3 * nb, 0.0);
    law.flaw_seed.assign(nb, 0);
    law.first_node.assign(nb, 0);
    law.any_flaws = false;
    law.lps.assign(nb, 0);
    law.rnp.assign(nb, 0);
    law.rnp_c.assign(nb, 0.0);
    law.rnp_beta.assign(nb, 0.0);
    law.rnp_rbar.assign(nb, 0.0);
    law.rnp_inv.assign(nb, 1.0);
    law.kappa.assign(nb, 0.0);
    law.mu.assign(nb, 0.0);
    law.dimension = dimension;
    law.krep.assign(nb, 0.0);
    law.rrep.assign(nb, 0.0);
    law.delta.assign(nb, 0.0);
    law.h.assign(nb, 0.0);
    law.alpha = dimension == 3 ? 15.0 : 8.0;
}

/// Grain-level damping (and PeriDEM's particle damping) needs whole grains per rank.
void check_whole_grains(const Forces& f) {
    if (!(f.damping || f.approach) || !f.dom->distributed())
        return;
    for (std::size_t b = 0; b < f.m.bodies.num(); ++b) {
        const auto i0 = f.m.bodies.begin(b);
        for (auto i = i0; i < f.m.bodies.end(b); ++i)
            if (f.dom->owner(i) != f.dom->owner(i0))
                throw InputError(fmt::format(
                    "body {} is split between MPI ranks {} and {}, but grain-level damping "
                    "(restitution < 1, or PeriDEM's approach damping) needs whole grains per "
                    "rank: partition by grain "
                    "(pd-partition --by grain)",
                    b, f.dom->owner(i0), f.dom->owner(i)));
    }
}
/// The surface correction's factor G of every bond of the rows (model/surface_correction.hpp),
/// from bond weights relative to a complete family of the body; 1 for RNP and fixed bodies.
std::vector<double> surface_factors(Forces& f) {
    const std::size_t nr = f.s.rows.size(), n = f.s.n;
    std::vector<double> w(f.b.xi.size(), 0.0), angle(n, 0.0), ref(f.m.bodies.num(), 1.0);
    for (std::size_t b = 0; b < ref.size(); ++b) // a complete family's axis moment
        if (!f.m.bodies.fixed[b])
            ref[b] = std::max(model::quadrature_factors(f.m, b).axis_moment, 1e-300);
    for (std::size_t a = 0; a < nr; ++a) {
        const auto i = static_cast<std::size_t>(f.s.rows[a]);
        const auto body = static_cast<std::size_t>(f.s.body[i]);
        for (auto k = f.b.offsets[a]; k < f.b.offsets[a + 1]; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            const double r = f.b.xi[kk], vb = bond_beta(f.b, f.law, body, kk) *
                                              f.s.vol[static_cast<std::size_t>(f.b.neighbor[kk])] /
                                              ref[body];
            // RNP and fixed bodies: no bonds counted, factors 1.
            w[kk] = f.law.rnp[body] || f.m.bodies.fixed[body] ? 0.0
                    : f.law.lps[body]                         ? f.b.omega[kk] * r * r * vb
                                                              : r * vb;
        }
    }
    for (std::size_t i = 0; i < n; ++i)
        angle[i] = f.m.bodies.orientation[static_cast<std::size_t>(f.s.body[i])];
    const model::FamilyRows fr{f.b.offsets, f.b.neighbor, f.s.rows, f.s.x0, angle};
    return model::surface_bond_factors(
        fr, std::move(w), f.m.dimension, n,
        [&](std::vector<double>& g) { f.dom->exchange({&g}, 3); }, 1);
}
} // namespace

void law_constants(Forces& f) {
    const std::size_t nb = f.m.bodies.num();
    size_law(f.law, nb, f.m.dimension);
    for (std::size_t b = 0; b < nb; ++b) {
        const auto& mat = f.m.materials[static_cast<std::size_t>(f.m.bodies.material[b])];
        // Constants calibrated on the body's actual quadrature (model/quadrature.hpp); computed
        // from the reference nodes, so every rank gets the same factors.
        const auto qf = f.m.solver.quadrature_calibration && !f.m.bodies.fixed[b]
                            ? model::quadrature_factors(f.m, b)
                            : model::QuadratureFactors{};
        if (mat.law == model::Law::rnp) {
            auto k = model::rnp_constants(mat, f.m.bodies.horizon[b], f.m.dimension);
            f.law.rnp[b] = 1;
            f.law.rnp_c[b] = k.C;
            f.law.rnp_beta[b] = k.beta;
            f.law.rnp_rbar[b] = k.rbar;
            f.law.rnp_inv[b] = k.inv_factor / qf.pmb;
            f.law.s0[b] = k.rbar; // breakable (S_c depends on the bond length)
            f.law.c[b] = 4 * k.C * k.beta / f.law.rnp_inv[b]; // small-strain stiffness, dt estimate
            f.law.any_rnp = f.law.any_rnp || !f.m.bodies.fixed[b];
        } else if (mat.law == model::Law::lps) {
            auto k = model::lps_constants(mat, f.m.bodies.horizon[b], f.m.dimension, f.m.planar);
            f.law.lps[b] = 1;
            f.law.kappa[b] = k.kappa * qf.kappa;
            f.law.mu[b] = k.mu * qf.mu;
            f.law.s0[b] = k.s0;
            // Bond-based micromodulus of the same Young's modulus: for the dt estimate only.
            f.law.c[b] =
                model::pmb_constants(mat, f.m.bodies.horizon[b], f.m.dimension, f.m.planar).c;
            f.law.any_lps = f.law.any_lps || !f.m.bodies.fixed[b];
        } else {
            auto k = model::pmb_constants(mat, f.m.bodies.horizon[b], f.m.dimension, f.m.planar);
            f.law.c[b] = k.c * qf.pmb;
            f.law.s0[b] = k.s0;
            f.law.any_pmb = f.law.any_pmb || !f.m.bodies.fixed[b];
        }
        f.law.any_breakable =
            f.law.any_breakable || (std::isfinite(f.law.s0[b]) && !f.m.bodies.fixed[b]);
        if (mat.break_in_compression && std::isfinite(f.law.s0[b]) && !f.m.bodies.fixed[b]) {
            f.law.s0_lo[b] = mat.law == model::Law::rnp ? 1.0 : 1.0 - f.law.s0[b];
            f.law.any_compressive = true;
        }
        if (mat.has_flaws() && std::isfinite(f.law.s0[b]) && !f.m.bodies.fixed[b]) {
            f.law.flaw_m[b] = mat.flaw_modulus;
            f.law.flaw_seed[b] = mat.flaw_seed;
            f.law.flaw_len[b] = mat.flaw_length;
            for (std::size_t d = 0; d < 3; ++d)
                f.law.centre[3 * b + d] = f.m.bodies.center[3 * b + d];
            f.law.first_node[b] = f.m.bodies.begin(b);
            f.law.any_flaws = true;
        }
        f.law.krep[b] =
            18.0 * mat.bulk_modulus() / (M_PI * std::pow(f.m.bodies.horizon[b], f.m.dimension + 2));
        f.law.rrep[b] = 0.95 * f.m.bodies.mesh_size[b];
        f.law.delta[b] = f.m.bodies.horizon[b];
        f.law.h[b] = f.m.bodies.mesh_size[b];
    }
}

void build_bonds(Forces& f, std::vector<index_t>& row_neighbors) {
    // This rank's rows of the bond list (f.s.rows; all on one rank): reference lengths,
    // partial-volume factors and influence, computed once. Bond data of other ranks' rows is
    // never stored. The neighbour lists come from the model, or, when it was read without
    // them, from row_neighbors (the rows of f.s.rows, read by hyperslab).
    const auto& m = f.m;
    const std::size_t nr = f.s.rows.size();
    f.b.offsets.assign(nr + 1, 0);
    for (std::size_t a = 0; a < nr; ++a) {
        const auto i = static_cast<std::size_t>(f.s.rows[a]);
        f.b.offsets[a + 1] = f.b.offsets[a] + (m.bonds.offsets[i + 1] - m.bonds.offsets[i]);
    }
    const auto nbond = static_cast<std::size_t>(f.b.offsets[nr]);
    if (m.bonds.complete()) {
        f.b.neighbor = rows_of(m.bonds.neighbor, m.bonds.offsets, f.s.rows);
    } else {
        if (row_neighbors.size() != nbond)
            throw InternalError(fmt::format("{} neighbours given for {} bonds of this rank's rows",
                                            row_neighbors.size(), nbond));
        f.b.neighbor = std::move(row_neighbors);
        row_neighbors.clear();
    }
    f.b.xi.resize(nbond);
    // beta only where a kernel reads it per bond (RNP); PMB's is folded into kb, LPS's into wv,
    // and both are recomputed where needed (bond_beta: the same partial_volume call).
    const bool keep_beta = f.law.any_rnp;
    f.b.beta.assign(keep_beta ? nbond : 0, 0.0);
    f.b.beta.shrink_to_fit();
    f.b.alive.assign(nbond, 1);
    for (std::size_t a = 0; a < nr; ++a) {
        const auto i = static_cast<std::size_t>(f.s.rows[a]);
        const auto b = static_cast<std::size_t>(f.s.body[i]);
        for (auto k = f.b.offsets[a]; k < f.b.offsets[a + 1]; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            const auto j = f.b.neighbor[kk];
            const double r = bond_length(f.s.x0, i, static_cast<std::size_t>(j));
            if (!(r > 0))
                throw InputError(fmt::format("nodes {} and {} coincide (zero-length bond)", i, j));
            f.b.xi[kk] = r;
            if (keep_beta)
                f.b.beta[kk] = model::partial_volume(r, f.law.delta[b], f.law.h[b]);
        }
    }
    f.b.omega.clear();
    if (f.law.any_lps || f.law.any_rnp) {
        f.b.omega.resize(nbond);
        for (std::size_t a = 0; a < nr; ++a) {
            const auto b =
                static_cast<std::size_t>(f.s.body[static_cast<std::size_t>(f.s.rows[a])]);
            const auto inf = m.materials[static_cast<std::size_t>(m.bodies.material[b])].influence;
            for (auto k = f.b.offsets[a]; k < f.b.offsets[a + 1]; ++k) {
                const auto kk = static_cast<std::size_t>(k);
                f.b.omega[kk] = model::influence(inf, f.b.xi[kk] / m.bodies.horizon[b]);
            }
        }
    }
}

void family_factors(Forces& f) {
    // Per-node sums over a node's family, of the owned rows; the ghosts' values come from their
    // owners (the bond ghosts must be set).
    const std::size_t nr = f.s.rows.size(), n = f.s.n;
    // Surface correction (solver.surface_correction; model/surface_correction.hpp): per-node
    // axis factors relative to a complete family of the body, a directional factor per bond on
    // the PMB micromodulus or the LPS influence function (before m_i is summed from it).
    // `stiff` (beta G of a PMB bond, beta elsewhere) is built in the factors' array and becomes
    // kb in bond_constants: one per-bond array of doubles at a time (issue 29 item 3).
    const auto body_of = [&](std::size_t a) {
        return static_cast<std::size_t>(f.s.body[static_cast<std::size_t>(f.s.rows[a])]);
    };
    std::vector<double> stiff;
    if (f.m.solver.surface_correction)
        stiff = surface_factors(f);
    else
        stiff.assign(f.b.xi.size(), 1.0);
    for (std::size_t a = 0; a < nr; ++a) {
        const auto body = body_of(a);
        // RNP and fixed bodies keep factor 1; a fixed LPS body has no omega when no moving
        // body is LPS (the per-bond array is then empty).
        const bool scaled =
            f.m.solver.surface_correction && !f.law.rnp[body] && !f.m.bodies.fixed[body];
        for (auto k = f.b.offsets[a]; k < f.b.offsets[a + 1]; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            const double beta = bond_beta(f.b, f.law, body, kk);
            if (scaled && f.law.lps[body])
                f.b.omega[kk] *= stiff[kk];
            stiff[kk] = scaled && !f.law.lps[body] ? beta * stiff[kk] : beta;
        }
    }
    if (f.law.any_lps) {
        // LPS weighted volume m_i = sum_j w xi^2 beta V_j (spec 1.3), summed in bond order.
        f.law.m.assign(n, 0.0);
        for (std::size_t a = 0; a < nr; ++a) {
            const auto body = body_of(a);
            double sum = 0;
            for (auto k = f.b.offsets[a]; k < f.b.offsets[a + 1]; ++k) {
                const auto kk = static_cast<std::size_t>(k);
                sum += f.b.omega[kk] * f.b.xi[kk] * f.b.xi[kk] * bond_beta(f.b, f.law, body, kk) *
                       f.s.vol[static_cast<std::size_t>(f.b.neighbor[kk])];
            }
            f.law.m[static_cast<std::size_t>(f.s.rows[a])] = sum;
        }
        for (auto row : f.s.rows) {
            auto& w = f.law.m[static_cast<std::size_t>(row)];
            w = w > 0 ? w : 1.0; // a node with no bond has theta = 0 and no force
        }
        f.dom->exchange({&f.law.m}, 1);
        f.law.theta.assign(n, 0.0);
        f.law.q.assign(n, 0.0);
    }
    // Per-bond and per-node constants of the kernels, from the per-body law and the per-bond
    // factors above, so that a calibration of either composes.
    bond_constants(f.s, f.b, f.law, std::move(stiff));
}

void set_bond_ghosts(Forces& f) {
    f.bonds_cross_ranks = false;
    if (!f.dom->distributed())
        return;
    check_whole_grains(f);
    f.bond_ghosts.clear();
    for (auto j : f.b.neighbor)
        if (!f.dom->owns(j))
            f.bond_ghosts.push_back(j);
    std::sort(f.bond_ghosts.begin(), f.bond_ghosts.end());
    f.bond_ghosts.erase(std::unique(f.bond_ghosts.begin(), f.bond_ghosts.end()),
                        f.bond_ghosts.end());
    f.bonds_cross_ranks = f.dom->any(!f.bond_ghosts.empty());
    f.dom->set_ghosts(f.bond_ghosts);
}

std::vector<index_t> global_neighbors(const Forces& f) {
    if (f.m.bonds.complete())
        return f.m.bonds.neighbor;
    std::vector<index_t> full(f.m.bonds.num(), 0);
    put_rows(f.b.neighbor, f.b.offsets, f.s.rows, f.m.bonds.offsets, full);
    f.dom->allgather_csr(full, f.m.bonds.offsets);
    return full;
}

std::int64_t count_broken(const Forces& f) {
    return static_cast<std::int64_t>(std::count(f.b.alive.begin(), f.b.alive.end(), 0));
}

} // namespace pd::solver::detail
