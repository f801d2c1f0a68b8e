// SPDX-License-Identifier: MIT
// PeriDEM compatibility: bonds also break when compressed beyond the critical stretch
// (Material::break_in_compression, length < xi (1 - s0), PeriDEM's |s| > s0, spec 1.3), off by
// default (pdgrain decision 4). The switch breaks exactly the bonds shorter than xi (1 - s0) on
// every kernel path (portable, SSE2, AVX2: same bits), breaks none without it, keeps the energy
// balance closed.
#include "core/log.hpp"
#include "pipeline/scene.hpp"
#include "solver/bond_kernels.hpp"
#include "solver/solver.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace pd;
using solver::kernels::Isa;

const Log quiet("test", 0, Verbosity::quiet);

/// One disc (2D) or box (3D) of `law`, breakable at a low fracture energy.
std::string grain(const std::string& law, int dim, bool compressive) {
    const std::string mat = law == "lps" ? R"("law": "lps", "poisson_ratio": 0.25, )" : "";
    const std::string z = dim == 3 ? ", 0" : "";
    const std::string shape = dim == 3 ? R"("shape": "b", )" : R"("radius": 1e-3, )";
    return R"({"dimension": )" + std::to_string(dim) + R"(, "title": "t",
      "materials": {"m": {)" +
           mat + R"("density": 1200, "youngs_modulus": 3.24e7, "fracture_energy": 0.05,
                 "break_in_compression": )" +
           (compressive ? "true" : "false") + R"(}},
      "discretization": {"mesh_size": )" +
           (dim == 3 ? "3e-4" : "2e-4") + R"(, "horizon_factor": 3},
      )" +
           (dim == 3
                ? R"("shapes": {"b": {"type": "box", "size": [1.6e-3, 1.6e-3, 1.6e-3], "mesh": "grid"}},)"
                : "") +
           R"(
      "particles": [{)" +
           shape + R"("center": [0, 0)" + z + R"(], "material": "m"}],
      "solver": {"final_time": 1e-3}})";
}

struct Eval {
    std::vector<double> f, x, xi;
    double s0 = 0; ///< the grain's critical stretch (no flaws: every bond breaks at xi (1 + s0))
    std::vector<std::uint8_t> alive;
    std::vector<std::int64_t> off;
    std::vector<std::int32_t> nb, rows;
    double elastic = 0, fracture = 0;
};

/// One bond-force evaluation on path `isa`: the nodes left of the centre squeezed towards it by
/// 3 s0 (their bonds to each other at stretch -3 s0), the others moved at random by 1e-4 h.
Eval evaluate(const model::Model& m, Isa isa) {
    solver::Solver s(m);
    s.set_dt(0.5 * s.stable_dt().limit);
    s.initialize();
    const auto& b = s.bonds();
    const double s0 = s.bond_law().s0[0];
    std::mt19937_64 rng(12);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto& x = s.state().x;
    for (std::size_t i = 0; 3 * i < x.size(); ++i)
        for (std::size_t c = 0; c < 3; ++c)
            if (m.dimension == 3 || c < 2)
                x[3 * i + c] =
                    x[3 * i] < 0 ? x[3 * i + c] * (1 - 3 * s0) : x[3 * i + c] + 2e-8 * u(rng);
    const Isa before = solver::kernels::isa();
    solver::kernels::isa() = isa;
    s.bond_forces_only();
    solver::kernels::isa() = before;
    const auto o = s.observe();
    return {s.state().f,      s.state().x,      b.xi,       s0,
            b.alive,          b.offsets,        b.neighbor, s.state().rows,
            o.elastic_energy, o.fracture_energy};
}

std::vector<Isa> paths() {
    std::vector<Isa> p{Isa::portable};
#if defined(__SSE2__)
    p.push_back(Isa::sse2);
#endif
    if (solver::kernels::best_isa() == Isa::avx2)
        p.push_back(Isa::avx2);
    return p;
}

TEST(CompressiveBreaking, BreaksBelowXiOneMinusS0OnlyWithTheSwitchOnEveryPath) {
    for (const std::string law : {"pmb", "lps"})
        for (int dim : {2, 3})
            for (bool on : {false, true}) {
                const auto m = pipeline::build_scene(grain(law, dim, on), "t", quiet);
                ASSERT_EQ(m.materials[0].break_in_compression, on);
                const std::string what =
                    law + " " + std::to_string(dim) + "D switch " + (on ? "on" : "off");
                const auto all = paths();
                const Eval ref = evaluate(m, all[0]);
                std::int64_t squeezed = 0, stretched = 0, broken = 0, intact = 0;
                for (std::size_t a = 0; a < ref.rows.size(); ++a) {
                    const auto i = static_cast<std::size_t>(ref.rows[a]);
                    for (auto k = ref.off[a]; k < ref.off[a + 1]; ++k) {
                        const auto kk = static_cast<std::size_t>(k);
                        const auto j = static_cast<std::size_t>(ref.nb[kk]);
                        double l2 = 0;
                        for (std::size_t c = 0; c < 3; ++c)
                            l2 += std::pow(ref.x[3 * j + c] - ref.x[3 * i + c], 2);
                        const double l = std::sqrt(l2), xi = ref.xi[kk];
                        const double s0 = ref.s0;
                        if (l > xi * (1 + s0) * (1 + 1e-9)) { // across the squeeze's edge
                            ++stretched;
                            EXPECT_EQ(ref.alive[kk], 0) << what << " bond " << k;
                        } else if (l < xi * (1 - s0) * (1 - 1e-9)) {
                            ++squeezed;
                            EXPECT_EQ(ref.alive[kk], on ? 0 : 1) << what << " bond " << k;
                        } else if (l > xi * (1 - s0) * (1 + 1e-9) &&
                                   l < xi * (1 + s0) * (1 - 1e-9)) {
                            ++intact;
                            EXPECT_EQ(ref.alive[kk], 1) << what << " bond " << k;
                        }
                        broken += ref.alive[kk] == 0;
                    }
                }
                EXPECT_GT(squeezed, static_cast<std::int64_t>(ref.xi.size()) / 5) << what;
                EXPECT_GT(intact, static_cast<std::int64_t>(ref.xi.size()) / 5) << what;
                EXPECT_EQ(broken, on ? squeezed + stretched : stretched) << what;
                for (std::size_t p = 1; p < all.size(); ++p) {
                    const Eval r = evaluate(m, all[p]);
                    const std::string on_path = what + ", path " + std::to_string(int(all[p]));
                    EXPECT_EQ(r.f, ref.f) << on_path;
                    EXPECT_EQ(r.alive, ref.alive) << on_path;
                    EXPECT_EQ(r.elastic, ref.elastic) << on_path;
                    EXPECT_EQ(r.fracture, ref.fracture) << on_path;
                }
            }
}

/// A plate squeezed at 1 m/s top and bottom.
std::string squeezed_plate(const std::string& law, bool on) {
    return R"({"dimension": 2, "title": "plate",
      "materials": {"m": {"law": ")" +
           law + R"(", "density": 1200, "youngs_modulus": 3.24e7,)" +
           (law == "lps" ? R"( "poisson_ratio": 0.25,)" : "") +
           R"( "fracture_energy": 5, "break_in_compression": )" + (on ? "true" : "false") +
           R"(}},
      "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
      "shapes": {"plate": {"type": "rectangle", "corners": [[0, 0], [0.01, 0.005]],
                           "mesh": "grid"}},
      "particles": [{"shape": "plate", "center": [0, 0], "material": "m"}],
      "loading": {"conditions": [
        {"name": "top", "kind": "displacement", "region": {"min": [-1, 0.0046], "max": [1, 1]},
         "components": ["y"], "time_function": "linear", "value": -1.0},
        {"name": "bottom", "kind": "displacement", "region": {"min": [-1, -1], "max": [1, 4e-4]},
         "components": ["y"], "time_function": "linear", "value": 1.0}]},
      "solver": {"final_time": 1e-4}})";
}

TEST(CompressiveBreaking, EnergyBalanceClosesThroughCompressiveBreaking) {
    // KE + elastic + repulsion + fracture - external work keeps its t = 0 value while bonds
    // break in compression (the released energy is counted as for tension); without the switch
    // the same squeeze breaks only the bonds the lateral (Poisson) expansion stretches.
    for (const char* law : {"pmb", "lps"}) {
        std::int64_t broken_off = 0;
        for (bool on : {false, true}) {
            const auto m = pipeline::build_scene(squeezed_plate(law, on), "t", quiet);
            solver::Solver s(m);
            s.set_dt(0.7 * s.stable_dt().limit);
            s.initialize();
            const double b0 = solver::energy_balance(s.observe());
            double worst = 0, scale = solver::energy_in_play(s.observe());
            const auto steps = static_cast<int>(1e-4 / s.dt());
            for (int k = 0; k < steps; ++k) {
                s.advance();
                const auto o = s.observe();
                scale = std::max(scale, solver::energy_in_play(o));
                worst = std::max(worst, std::abs(solver::energy_balance(o) - b0));
            }
            const auto o = s.observe();
            const std::string what = std::string(law) + (on ? " on" : " off");
            EXPECT_LT(worst / scale, 5e-3) << what;
            std::printf("%s: %lld bonds broken, fracture energy %.3g of %.3g J in play, drift "
                        "%.2g\n",
                        what.c_str(), static_cast<long long>(o.broken_bonds), o.fracture_energy,
                        scale, worst / scale);
            if (!on) {
                broken_off = o.broken_bonds;
                continue;
            }
            EXPECT_GT(o.broken_bonds, broken_off + 500) << what;
            EXPECT_GT(o.fracture_energy, 0.01 * scale) << what;
        }
    }
}

} // namespace
