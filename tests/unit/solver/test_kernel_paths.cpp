// SPDX-License-Identifier: MIT
// Issue 15: the bond kernels' three paths (portable two lanes, SSE2, AVX2 four bonds per step,
// chosen at run time) give the same bits: forces, energies, broken bonds, on families of every
// length (row lengths of every residue mod 4) with random bond lengths, intact rows and rows
// with broken or breaking bonds, PMB and LPS, 2D and 3D.
#include "core/log.hpp"
#include "pipeline/scene.hpp"
#include "solver/bond_kernels.hpp"
#include "solver/solver.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace {

using namespace pd;
using solver::kernels::Isa;

const Log quiet("test", 0, Verbosity::quiet);

/// Two discs (2D) or boxes (3D) of one law, bonds breaking at a low fracture energy.
std::string scene(const std::string& law, int dim) {
    const std::string mat = law == "lps" ? R"("law": "lps", "poisson_ratio": 0.25, )" : "";
    const std::string z = dim == 3 ? ", 0" : "";
    const std::string shape = dim == 3 ? R"("shape": "b", )" : R"("radius": 1e-3, )";
    return R"({"dimension": )" + std::to_string(dim) + R"(,
      "materials": {"m": {)" +
           mat + R"("density": 1200, "youngs_modulus": 3.24e7, "fracture_energy": 0.05}},
      "discretization": {"mesh_size": )" +
           (dim == 3 ? "3e-4" : "2e-4") + R"(, "horizon_factor": 3},
      )" +
           (dim == 3
                ? R"("shapes": {"b": {"type": "box", "size": [1.6e-3, 1.6e-3, 1.6e-3], "mesh": "grid"}},)"
                : "") +
           R"(
      "particles": [{)" +
           shape + R"("center": [-1.1e-3, 0)" + z + R"(], "material": "m", "velocity": [5, 0)" + z +
           R"(]},
                    {)" +
           shape + R"("center": [1.1e-3, 0)" + z + R"(], "material": "m", "velocity": [-5, 0)" + z +
           R"(]}],
      "solver": {"final_time": 1e-3}, "title": "t"})";
}

struct Result {
    std::vector<double> f;
    std::vector<std::uint8_t> alive;
    double elastic = 0, fracture = 0;
    std::int64_t broken = 0;
};

/// One bond-force evaluation on path `isa` of a solver a few steps in, its positions moved at
/// random (the same for every path): every node by up to 1e-4 of the mesh size (random bond
/// lengths, none breaking), every 40th by a tenth of it (its bonds break in this evaluation).
Result evaluate(const model::Model& m, Isa isa, bool energies) {
    solver::Solver s(m);
    s.set_dt(0.5 * s.stable_dt().limit);
    s.initialize();
    for (int k = 0; k < 3; ++k)
        s.advance();
    std::mt19937_64 rng(15);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto& x = s.state().x;
    const double h = m.dimension == 3 ? 3e-4 : 2e-4;
    for (std::size_t k = 0; k < x.size(); ++k)
        if (m.dimension == 3 || k % 3 != 2)
            x[k] += (k / 3 % 40 == 0 ? 0.1 : 1e-4) * h * u(rng);
    s.set_energies(energies);
    const Isa before = solver::kernels::isa();
    solver::kernels::isa() = isa;
    s.bond_forces_only();
    solver::kernels::isa() = before;
    const auto o = s.observe();
    const auto& alive = s.bonds().alive;
    return {s.state().f, alive, o.elastic_energy, o.fracture_energy,
            std::count(alive.begin(), alive.end(), std::uint8_t{0})};
}

TEST(KernelPaths, PortableSse2AndAvx2GiveTheSameBits) {
    std::vector<Isa> paths{Isa::portable};
#if defined(__SSE2__)
    paths.push_back(Isa::sse2);
#endif
    if (solver::kernels::best_isa() == Isa::avx2)
        paths.push_back(Isa::avx2);
    else
        std::printf("(no AVX2 on this CPU: portable and SSE2 only)\n");
    for (const std::string law : {"pmb", "lps"})
        for (int dim : {2, 3})
            for (bool energies : {true, false}) {
                const auto m = pipeline::build_scene(scene(law, dim), "t", quiet);
                const std::string what =
                    law + " " + std::to_string(dim) + "D" + (energies ? " with energies" : "");
                // Rows of every length mod 4 (the four-bond step, the pair, the odd bond).
                std::set<std::int64_t> residues;
                const solver::Solver probe(m);
                const auto& off = probe.bonds().offsets;
                for (std::size_t a = 0; a + 1 < off.size(); ++a)
                    residues.insert((off[a + 1] - off[a]) % 4);
                EXPECT_EQ(residues.size(), 4u) << what;
                const Result ref = evaluate(m, paths[0], energies);
                ASSERT_GT(ref.broken, 0) << what << ": the test needs bonds breaking";
                std::int64_t intact_rows = 0;
                for (std::size_t a = 0; a + 1 < off.size(); ++a) {
                    bool all = true;
                    for (auto k = off[a]; k < off[a + 1]; ++k)
                        all = all && ref.alive[static_cast<std::size_t>(k)] == 1;
                    intact_rows += all;
                }
                EXPECT_GT(intact_rows, static_cast<std::int64_t>(off.size()) / 4)
                    << what << ": the hot loop must see many rows";
                for (std::size_t p = 1; p < paths.size(); ++p) {
                    const Result r = evaluate(m, paths[p], energies);
                    const std::string on = what + ", path " + std::to_string(int(paths[p]));
                    EXPECT_EQ(r.f, ref.f) << on;
                    EXPECT_EQ(r.alive, ref.alive) << on;
                    EXPECT_EQ(r.broken, ref.broken) << on;
                    EXPECT_EQ(r.elastic, ref.elastic) << on;
                    EXPECT_EQ(r.fracture, ref.fracture) << on;
                }
            }
}

} // namespace
