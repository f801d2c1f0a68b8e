// SPDX-License-Identifier: MIT
// Solver state: structure of arrays over all n nodes of the model, 3-vectors interleaved; a rank
// computes its owned `rows` and keeps ghosts current (solver/domain.hpp). Bonds in CSR with
// per-bond reference length, partial-volume factor and alive flag. Built once from a model::Model.
#pragma once

#include "model/model.hpp"

#include <cstdint>
#include <map>
#include <utility>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace pd::solver {

using model::index_t;
using model::offset_t;

/// Loops over fewer items than this run on one thread: a parallel region costs microseconds,
/// more than a small grain's whole step. Measured on the shared 2-core CI machine under load
/// (issue 15, workflows/bench/RESULTS.md): a second thread made compressive_small (2 643 nodes)
/// 10x more expensive in CPU time and slower in wall time (each region waits for a descheduled
/// thread), so the bond kernels keep 4096 rows and the short node loops (integration,
/// observables, external power) go parallel only from 16 384 nodes.
inline constexpr std::int64_t parallel_min = 4096;
inline constexpr std::int64_t parallel_min_bonds = 4096;
inline constexpr std::int64_t parallel_min_nodes = 16384;

/// Should a loop over `n` items run on the OpenMP team? Callers branch on it rather than use an
/// `if` clause: libgomp enters (and leaves, with a futex call) a one-thread region even when the
/// clause is false, some 2-5 us per loop, a third of a small deck's step (issue 15).
inline bool threaded(std::int64_t n, std::int64_t min = parallel_min) {
#ifdef _OPENMP
    return n > min && omp_get_max_threads() > 1;
#else
    (void)n;
    (void)min;
    return false;
#endif
}

/// f(a) for a in [0, n): on the OpenMP team if threaded(n, min), else serially.
template <class F>
void for_each_row(std::int64_t n, std::int64_t min, F&& f) {
#ifdef _OPENMP
    if (threaded(n, min)) {
#pragma omp parallel for schedule(static)
        for (std::int64_t a = 0; a < n; ++a)
            f(a);
        return;
    }
#endif
    for (std::int64_t a = 0; a < n; ++a)
        f(a);
}

/// The sum of f(a) over a in [0, n), like for_each_row (the order of the sum depends on the
/// thread count: energies and rates only, never a force).
template <class F>
double sum_rows(std::int64_t n, std::int64_t min, F&& f) {
    double sum = 0;
#ifdef _OPENMP
    if (threaded(n, min)) {
#pragma omp parallel for schedule(static) reduction(+ : sum)
        for (std::int64_t a = 0; a < n; ++a)
            sum += f(a);
        return sum;
    }
#endif
    for (std::int64_t a = 0; a < n; ++a)
        sum += f(a);
    return sum;
}

struct State {
    std::size_t n = 0;
    std::vector<double> x0;  ///< reference position (3n), m
    std::vector<double> x;   ///< current position (3n), m
    std::vector<double> u;   ///< displacement (3n), m
    std::vector<double> v;   ///< velocity (3n), m s-1
    std::vector<double> f;   ///< force density (3n), N m-3
    std::vector<double> vol; ///< nodal volume, m3
    std::vector<double> rho; ///< density, kg m-3
    std::vector<std::int32_t> body;
    std::vector<std::uint8_t> moving;    ///< 1 = integrated (free body)
    std::vector<std::uint8_t> fixed_dof; ///< bit d: component d prescribed by a condition
    /// Nodes this rank computes and integrates, ascending (all nodes on one rank; see
    /// solver/domain.hpp). Loops over nodes run over these.
    std::vector<index_t> rows;
    std::int64_t step = 0;
    double time = 0;
};

/// Share of the normal contact force a grain pair (a < b) or grain-wall pair (body, -1 - wall)
/// transmits while its contact unloads under hysteretic damping (eps^2); absent = 1. Friction
/// capacity follows it, so damping does not inflate the friction limit of a resting grain.
using UnloadMap = std::map<std::pair<std::int32_t, std::int32_t>, double>;

/// The bond rows of this rank's nodes only: row a is node State::rows[a] (all rows on one rank),
/// neighbours are global node ids. Other ranks' rows are never stored, so bond memory per rank
/// shrinks with the rank count. Per bond the solver keeps what its loops read: a PMB bond 21
/// bytes (neighbour, xi, kb, alive), 29 with flaws (lc); an LPS bond 45 (neighbour, xi, omega,
/// wv, alive and the work arrays len, inv_len), an RNP bond 29 (neighbour, xi, beta, omega, alive).
/// Set-up quantities (the partial volume beta outside RNP, kb outside PMB, a PMB bond's
/// surface-correction factor) are recomputed or folded into kb (issue 29 item 3).
struct BondData {
    std::vector<offset_t> offsets; ///< rows.size() + 1
    std::vector<index_t> neighbor;
    std::vector<double> xi; ///< reference bond length, m
    /// Partial-volume factor (spec 1.3), kept only when an RNP body is moving (its kernel reads
    /// it per bond); else empty, and bond_beta() recomputes it from xi (the same bits: the same
    /// model::partial_volume call build_bonds makes).
    std::vector<double> beta;
    std::vector<double> omega;       ///< influence J(xi / delta) (state-based law; else empty)
    std::vector<std::uint8_t> alive; ///< 1 intact, 0 broken
    // Per-bond constants of the kernels, precomputed from the above and the body's law
    // (Solver::family_factors; recomputed whenever the rows change), so the bond loops do one
    // sqrt and one division per bond:
    /// PMB: c beta G V_j / xi (force density = kb (l - xi) / l; G the surface correction's
    /// factor, 1 without it), N m-7. Kept only when the PMB kernel runs (keeps_kb()); else empty
    /// and bond_kb() recomputes c beta V_j / xi (no moving PMB body: no factor G in any bond's).
    std::vector<double> kb;
    std::vector<double> wv; ///< LPS: omega beta V_j, m3
    /// With flaws only (else empty: the length is xi (1 + s0) of the row's body, the same
    /// product): the length at which the bond breaks, xi (1 + s0 w) (inf: never), m
    std::vector<double> lc;
    /// With flaws only (else empty): per row, 1 + the least critical stretch of its bonds, the
    /// threshold of the hot loops' "a bond may break" test (the bond's own is lc).
    std::vector<double> op;
    /// LPS work arrays from the dilatation pass for the force pass: `len` holds
    /// omega beta V_j e / l and `inv_len` omega beta V_j xi / l (e = l - xi, l = |x_j - x_i|), so
    /// both passes do one sqrt and one division per bond, and the force pass's bond force is
    /// (A_i + A_j) len + (P_i + P_j) inv_len. (One array of l instead, the force pass dividing,
    /// saves 8 B per bond but made the 3D LPS hot loop 6-9 % slower: workflows/bench/RESULTS.md.)
    std::vector<double> len, inv_len;
};

/// True if some node moved farther than `limit` (m) from where it was in `x_ref` (3 per node):
/// the skin test of the contact and wall candidate lists.
/// Checks the owned rows only.
bool moved_farther_than(const State& s, const std::vector<double>& x_ref, double limit);
/// The largest distance of an owned row's node from x_ref, m (this rank only).
double max_moved(const State& s, const std::vector<double>& x_ref);

/// Per-body constants of the bond law (bonds never cross bodies).
struct BodyLaw {
    std::vector<std::uint8_t> lps;                          ///< 1 = LPS body
    std::vector<std::uint8_t> rnp;                          ///< 1 = RNP body (neither: PMB)
    std::vector<double> rnp_c, rnp_beta, rnp_rbar, rnp_inv; ///< RNP constants per body
    std::vector<double> c;                                  ///< PMB micromodulus, N m-6
    std::vector<double> s0; ///< critical stretch (inf = unbreakable)
    /// Compressive breaking (Material::break_in_compression): 1 - s0, bonds shorter than
    /// xi (1 - s0) break; 0 = tension only (no length is below 0). RNP: 1 = S < -S_c breaks.
    std::vector<double> s0_lo;
    /// Flaws (model/flaws.hpp) per body: Weibull modulus (0 = none), seed, first node index
    /// (the bond's node indices within the body are counted from it); any_flaws: some has them.
    std::vector<double> flaw_m;
    std::vector<double> flaw_len, centre; ///< per body: patch size (0: per bond); 3 per body
    std::vector<std::int64_t> flaw_seed, first_node;
    bool any_flaws = false;
    std::vector<double> kappa; ///< LPS bulk modulus of the d-dimensional problem, Pa
    std::vector<double> mu;    ///< LPS shear modulus, Pa
    double alpha = 15;         ///< LPS shear factor: 15 (3D), 8 (2D)
    std::vector<double> krep;  ///< broken-bond repulsion stiffness 18 K / (pi delta^(d+2)), N m-7
    std::vector<double> rrep;  ///< broken-bond repulsion radius 0.95 h, m (spec 4.7)
    std::vector<double> delta, h; ///< per body: horizon and mesh size, m (bond_beta)
    int dimension = 2;
    double dt = 0; ///< time step (s): the fracture energy's step correction
    bool any_breakable = false;
    bool any_compressive = false; ///< some moving breakable body breaks in compression
    bool any_pmb = false;
    bool any_lps = false;
    bool any_rnp = false;
    std::vector<double> m;     ///< LPS weighted volume per node, m^(d+2)
    std::vector<double> theta; ///< LPS dilatation per node (work array)
    /// LPS: theta / d (1 - m_intact / m) per node, 0 for a whole family (work array; see the
    /// LPS kernel in bond_forces.cpp)
    std::vector<double> q;
    /// LPS per node: d kappa / m_i (constant), and in `lps_ap` two values per node side by side,
    /// A_i = alpha mu / m_i (constant) and the node's share of the bond force, P_i = d kappa
    /// theta_i / m_i - A_i (theta_i / d + q_i) (work array): t_ij + t_ji = omega ((A_i + A_j) e +
    /// xi (P_i + P_j)). Side by side, the force pass loads A_j and P_j of a bond in one load.
    std::vector<double> lps_k, lps_ap;
    /// Compute the elastic and repulsion energies in the next force evaluation (observation
    /// steps); the released (fracture) energy is always computed.
    bool energy = true;
};

} // namespace pd::solver
