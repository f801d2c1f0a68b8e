// SPDX-License-Identifier: MIT
// Weibull flaw factors (see flaws.hpp). SplitMix64 (Steele, Lea & Flood, OOPSLA 2014) mixes
// each input into the state in turn; the top 53 bits give u in (0, 1).
#include "model/flaws.hpp"

#include <algorithm>
#include <cmath>

namespace pd::model {

namespace {
std::uint64_t mix(std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}
} // namespace

double flaw_uniform(std::int64_t seed, std::int64_t body, std::int64_t a, std::int64_t b) {
    std::uint64_t h = mix(static_cast<std::uint64_t>(seed));
    h = mix(h ^ static_cast<std::uint64_t>(body));
    h = mix(h ^ static_cast<std::uint64_t>(std::min(a, b)));
    h = mix(h ^ static_cast<std::uint64_t>(std::max(a, b)));
    return (static_cast<double>(h >> 11) + 0.5) * 0x1.0p-53;
}

double flaw_cell_factor(double modulus, std::int64_t seed, std::int64_t body, std::int64_t cx,
                        std::int64_t cy, std::int64_t cz) {
    std::uint64_t h = mix(static_cast<std::uint64_t>(seed) ^ 0x6365'6c6cULL); // "cell"
    for (std::int64_t v : {body, cx, cy, cz})
        h = mix(h ^ static_cast<std::uint64_t>(v));
    const double u = (static_cast<double>(h >> 11) + 0.5) * 0x1.0p-53;
    return std::pow(-std::log1p(-u) / std::log(2.0), 1.0 / modulus);
}

double flaw_factor(double modulus, std::int64_t seed, std::int64_t body, std::int64_t a,
                   std::int64_t b) {
    const double u = flaw_uniform(seed, body, a, b);
    return std::pow(-std::log1p(-u) / std::log(2.0), 1.0 / modulus);
}

} // namespace pd::model
