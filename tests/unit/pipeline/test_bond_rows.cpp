// SPDX-License-Identifier: MIT
// Reading a rank's part of the bond list: store::read_bond_rows gives exactly the rows of the
// whole list, and a Solver built from them equals one built from the whole model; the bond
// data it keeps fits pd-pack's memory model (pipeline/resources.cpp).
#include "h5/file.hpp"
#include "pipeline/resources.hpp"
#include "pipeline/scene.hpp"
#include "solver/bond_forces.hpp"
#include "solver/solver.hpp"
#include "store/model_io.hpp"

#include <gtest/gtest.h>

#include <filesystem>

namespace {

using namespace pd;

TEST(BondRows, PartialReadEqualsTheRowsOfTheWholeList) {
    const Log quiet("test", 0, Verbosity::quiet);
    const std::string scene = R"({"dimension": 2,
      "materials": {"m1": {"law": "lps", "density": 1200, "youngs_modulus": 3.24e7,
                            "poisson_ratio": 0.25}},
      "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
      "particles": [{"radius": 1e-3, "center": [0, 0], "material": "m1"},
                    {"radius": 1e-3, "center": [3e-3, 0], "material": "m1"}],
      "solver": {"final_time": 1e-3, "surface_correction": true}})";
    const auto built = pipeline::build_scene(scene, "scene.json", quiet);
    const auto path = std::filesystem::temp_directory_path() / "pd_test_bond_rows.h5";
    {
        h5::File f(path.string(), h5::Mode::create_truncate);
        store::write_model(f, built);
    }
    h5::File f(path.string(), h5::Mode::read);
    const auto whole = store::read_model(f);
    const auto part = store::read_model(f, false);
    ASSERT_TRUE(whole.bonds.complete());
    ASSERT_FALSE(part.bonds.complete());
    EXPECT_EQ(part.bonds.num(), whole.bonds.num());
    const std::size_t n = whole.nodes.num();
    const std::vector<std::array<std::uint64_t, 2>> runs{{0, 7}, {40, 41}, {n - 30, n}};
    const auto rows = store::read_bond_rows(f, part, runs);
    std::vector<model::index_t> expect;
    for (const auto& r : runs)
        expect.insert(expect.end(), whole.bonds.neighbor.begin() + whole.bonds.offsets[r[0]],
                      whole.bonds.neighbor.begin() + whole.bonds.offsets[r[1]]);
    EXPECT_EQ(rows, expect);
    // A solver from the offsets plus every row's neighbours equals one from the whole model,
    // bond data, surface factors and LPS weighted volumes included.
    solver::Solver a(whole), b(part, nullptr, store::read_bond_rows(f, part, {{0, n}}));
    EXPECT_EQ(a.bonds().neighbor, b.bonds().neighbor);
    EXPECT_EQ(a.bonds().kb, b.bonds().kb);
    EXPECT_EQ(a.bonds().omega, b.bonds().omega);
    EXPECT_EQ(a.stable_dt().limit, b.stable_dt().limit);
    a.set_dt(1e-7);
    b.set_dt(1e-7);
    a.initialize();
    b.initialize();
    for (int k = 0; k < 5; ++k) {
        a.advance();
        b.advance();
    }
    EXPECT_EQ(a.state().f, b.state().f);
    std::filesystem::remove(path);
}

// A fixed LPS body beside a moving PMB body (ellipse_on_tip's tip): with no moving LPS body the
// solver keeps no per-bond influence function, and the surface correction must leave the fixed
// body alone instead of scaling that missing array (it wrote past it: pd-solve crashed).
TEST(BondRows, SurfaceCorrectionLeavesAFixedLpsBodyAlone) {
    const Log quiet("test", 0, Verbosity::quiet);
    const std::string scene = R"({"dimension": 2,
      "materials": {"ring": {"law": "pmb", "density": 1200, "youngs_modulus": 3.24e7},
                    "tip": {"law": "lps", "density": 1200, "youngs_modulus": 3.24e7,
                            "poisson_ratio": 0.25}},
      "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
      "particles": [{"radius": 1e-3, "center": [0, 0], "material": "ring"},
                    {"radius": 1e-3, "center": [0, -2.5e-3], "material": "tip", "fixed": true}],
      "solver": {"final_time": 1e-3, "surface_correction": true}})";
    const auto model = pipeline::build_scene(scene, "scene.json", quiet);
    solver::Solver a(model);
    EXPECT_TRUE(a.bonds().omega.empty());
    const auto& b = a.bonds();
    std::size_t fixed_bonds = 0, fixed_scaled = 0, ring_scaled = 0;
    for (std::size_t i = 0; i + 1 < b.offsets.size(); ++i)
        for (auto k = b.offsets[i]; k < b.offsets[i + 1]; ++k) {
            const auto kk = static_cast<std::size_t>(k);
            // kb = c beta G V_j / xi: G = 1 where kb is that of beta alone
            const auto body = static_cast<std::size_t>(model.nodes.body[i]);
            const double c = a.bond_law().c[body],
                         vj = a.state().vol[static_cast<std::size_t>(b.neighbor[kk])];
            const bool scaled =
                b.kb[kk] != c * solver::bond_beta(b, a.bond_law(), body, kk) * vj / b.xi[kk];
            if (model.nodes.body[i] == 1) {
                ++fixed_bonds;
                fixed_scaled += scaled;
            } else {
                ring_scaled += scaled;
            }
        }
    EXPECT_GT(fixed_bonds, 0u);
    EXPECT_EQ(fixed_scaled, 0u); // factor 1 on the fixed body
    EXPECT_GT(ring_scaled, 0u);  // the moving PMB disc's surface is corrected
}

// pd-pack's memory guard predicts pd-solve's peak from a measured cost per bond (issue 29 item
// 3); the per-bond arrays the solver keeps after set-up must fit in it, so that a new per-bond
// array fails here until the guard (and RESULTS.md's measurement) follows.
TEST(BondRows, PerBondStorageFitsTheMemoryGuard) {
    const Log quiet("test", 0, Verbosity::quiet);
    for (const std::string law : {"pmb", "lps", "rnp"}) {
        const std::string nu = law == "pmb" ? "" : R"("poisson_ratio": 0.25, )";
        const std::string scene = R"({"dimension": 2, "materials": {"m": {"law": ")" + law +
                                  R"(", "density": 1200, "youngs_modulus": 3.24e7, )" + nu +
                                  R"("fracture_energy": 10}},
          "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
          "particles": [{"radius": 1e-3, "center": [0, 0], "material": "m"}],
          "solver": {"final_time": 1e-3}})";
        const auto model = pipeline::build_scene(scene, "scene.json", quiet);
        solver::Solver s(model);
        s.set_dt(0.5 * s.stable_dt().limit);
        s.initialize();
        s.advance();
        const auto& b = s.bonds();
        auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
        const double per_bond =
            static_cast<double>(bytes(b.neighbor) + bytes(b.xi) + bytes(b.beta) + bytes(b.omega) +
                                bytes(b.alive) + bytes(b.kb) + bytes(b.wv) + bytes(b.lc) +
                                bytes(b.len) + bytes(b.inv_len)) /
            static_cast<double>(b.xi.size());
        const bool state_based = law != "pmb";
        const double guard = pipeline::solve_peak_bytes(0, 1, state_based) -
                             pipeline::solve_peak_bytes(0, 0, state_based);
        EXPECT_LE(per_bond, guard) << law;
        EXPECT_GT(per_bond, 0.5 * guard) << law; // the guard is not far above either
        if (law == "pmb") {
            EXPECT_EQ(per_bond, 21.0); // neighbour, xi, kb, alive
        } else if (law == "lps") {
            EXPECT_EQ(per_bond, 45.0); // neighbour, xi, omega, wv, alive, len, inv_len
        } else {
            EXPECT_EQ(per_bond, 29.0); // neighbour, xi, beta, omega, alive
        }
    }
}
} // namespace
