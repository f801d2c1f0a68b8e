// SPDX-License-Identifier: MIT
// Material flaws (issue 31): a bond's critical stretch is s0 * w, w drawn from a Weibull law of
// modulus m and median 1, P(w' <= w) = 1 - exp(-ln 2 * w^m) (scale lambda = (ln 2)^(-1/m)), so
// the median bond breaks at the material's deterministic s0 and a larger grain (more bonds)
// holds a weaker one (McDowell & Bolton, Geotechnique 48 (1998) 667). w is a pure function of
// the material's seed, the body and the bond's two node indices within the body (unordered), so
// both ends of a bond, every rank count and every partition draw the same value.
#pragma once

#include <cstdint>

namespace pd::model {

/// Uniform number in (0, 1) from (seed, body, a, b), a and b the bond's node indices within the
/// body (their order does not matter): a SplitMix64 hash chain.
double flaw_uniform(std::int64_t seed, std::int64_t body, std::int64_t a, std::int64_t b);

/// The Weibull factor w = (ln 2)^(-1/m) (-ln(1 - u))^(1/m) of u = flaw_uniform(...), median 1.
double flaw_factor(double modulus, std::int64_t seed, std::int64_t body, std::int64_t a,
                   std::int64_t b);

/// The Weibull factor of a patch (correlated flaws, `length` L > 0): every bond whose midpoint
/// lies in the cell (cx, cy, cz) of a grid of spacing L (in the body's frame: reference position
/// minus the body's placement centre, floor(./L)) shares it, so the body is a mosaic of patches
/// of one strength each, weakest-link between patches (issue 31 item 3: per-bond factors average
/// out over the bonds a crack must cut, the grain's strength scatters 2-3 % for m = 4).
double flaw_cell_factor(double modulus, std::int64_t seed, std::int64_t body, std::int64_t cx,
                        std::int64_t cy, std::int64_t cz);

} // namespace pd::model
