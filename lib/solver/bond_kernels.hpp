// SPDX-License-Identifier: MIT
// What the bond kernels of bond_forces.cpp (PMB, RNP) and lps_kernel.cpp (LPS) share: the row
// loop with its reductions, the two-lane SSE2 helpers, the lazy constants. Private to lib/solver.
#pragma once

#include "solver/bond_forces.hpp"

#include <cstdint>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace pd::solver::kernels {

/// Runs row(a, acc...) for every row a in [0, n), on the OpenMP team when the loop is long
/// enough (threaded()), else serially without entering a parallel region.
struct Sums {
    double energy = 0, released = 0, repulsion = 0;
    std::int64_t broken = 0;
};

template <class Row>
Sums over_rows(std::int64_t n, Row&& row) {
    double energy = 0, released = 0, repulsion = 0;
    std::int64_t broken = 0;
    if (threaded(n, parallel_min_bonds)) {
#pragma omp parallel for schedule(static) reduction(+ : energy, broken, released, repulsion)
        for (std::int64_t a = 0; a < n; ++a)
            row(a, energy, released, repulsion, broken);
    } else {
        for (std::int64_t a = 0; a < n; ++a)
            row(a, energy, released, repulsion, broken);
    }
    return {energy, released, repulsion, broken};
}

#if defined(__SSE2__)
/// d = x_j - x_i of two bonds (neighbours ja, jb), component by component, lane 0 = ja.
inline void gather2(const double* x, index_t ja, index_t jb, __m128d X0, __m128d X1, __m128d X2,
                    __m128d& d0, __m128d& d1, __m128d& d2) {
    const double* pa = x + 3 * static_cast<std::int64_t>(ja);
    const double* pb = x + 3 * static_cast<std::int64_t>(jb);
    const __m128d xa = _mm_loadu_pd(pa), xb = _mm_loadu_pd(pb);
    d0 = _mm_sub_pd(_mm_unpacklo_pd(xa, xb), X0);
    d1 = _mm_sub_pd(_mm_unpackhi_pd(xa, xb), X1);
    d2 = _mm_sub_pd(_mm_loadh_pd(_mm_load_sd(pa + 2), pb + 2), X2);
}
inline void lanes(__m128d v, double& lane0, double& lane1) {
    alignas(16) double t[2];
    _mm_store_pd(t, v);
    lane0 = t[0];
    lane1 = t[1];
}
#endif

/// Callers that fill BondData and BodyLaw by hand (tests) get the constants on the first call.
inline void ensure_constants(const State& s, BondData& b, const BodyLaw& law) {
    if (b.kb.size() != b.xi.size() || b.lc.size() != b.xi.size() ||
        (!b.omega.empty() && (b.wv.size() != b.xi.size() || b.len.size() != b.xi.size())) ||
        (law.m.size() == s.n && law.lps_a.size() != s.n))
        bond_constants(s, b, const_cast<BodyLaw&>(law));
}

} // namespace pd::solver::kernels
