// SPDX-License-Identifier: MIT
// PMB constants and the two-node bond force against the closed-form expressions (spec 1.5).
#include "model/model.hpp"
#include "model/pmb.hpp"
#include "solver/bond_forces.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace {

using namespace pd;

model::Material m1() {
    model::Material m;
    m.name = "m1";
    m.density = 1200;
    m.youngs_modulus = 3.24e7;
    m.fracture_energy = 50;
    return m;
}

TEST(Pmb, ConstantsPlaneStress) {
    const double delta = 6e-4, E = 3.24e7, G = 50;
    auto k = model::pmb_constants(m1(), delta, 2, model::Planar::plane_stress);
    EXPECT_DOUBLE_EQ(k.c, 9 * E / (std::numbers::pi * std::pow(delta, 3)));
    EXPECT_DOUBLE_EQ(k.s0, std::sqrt(4 * std::numbers::pi * G / (9 * E * delta)));
}

TEST(Pmb, Constants3D) {
    const double delta = 6e-4, E = 3.24e7, K = E / 1.5;
    auto k = model::pmb_constants(m1(), delta, 3, model::Planar::plane_stress);
    EXPECT_DOUBLE_EQ(k.c, 18 * K / (std::numbers::pi * std::pow(delta, 4)));
    EXPECT_DOUBLE_EQ(k.s0, std::sqrt(5 * 50.0 / (9 * K * delta)));
}

TEST(Pmb, UnbreakableHasInfiniteCriticalStretch) {
    auto m = m1();
    m.fracture_energy = 0;
    EXPECT_TRUE(std::isinf(model::pmb_constants(m, 1e-3, 2, model::Planar::plane_stress).s0));
}

TEST(Pmb, PartialVolume) {
    EXPECT_DOUBLE_EQ(model::partial_volume(0.5, 3.0, 1.0), 1.0);
    EXPECT_DOUBLE_EQ(model::partial_volume(2.5, 3.0, 1.0), 1.0);
    EXPECT_DOUBLE_EQ(model::partial_volume(2.9, 3.0, 1.0), 0.6);
}

/// Two nodes of one body, stretched by s: f_i = c s beta V_j along the bond.
TEST(Pmb, TwoNodeBondForce) {
    solver::State s;
    s.n = 2;
    s.rows = {0, 1};
    const double r = 1e-4, stretch = 0.01, vol = 1e-8;
    s.x0 = {0, 0, 0, r, 0, 0};
    s.x = {0, 0, 0, r * (1 + stretch) * std::cos(0.3), r * (1 + stretch) * std::sin(0.3), 0};
    s.f.assign(6, 0);
    s.vol = {vol, 2 * vol};
    s.body = {0, 0};
    s.moving = {1, 1};
    solver::BondData b;
    b.offsets = {0, 1, 2};
    b.neighbor = {1, 0};
    b.xi = {r, r};
    b.beta = {1, 1};
    b.alive = {1, 1};
    solver::BodyLaw law;
    law.lps = {0};
    law.rnp = {0};
    law.krep = {0};
    law.rrep = {0};
    law.c = {2.5e20};
    law.s0 = {0.05};
    law.any_breakable = true;
    auto res = solver::pmb_bond_forces(s, b, law);
    const double mag_i = 2.5e20 * stretch * 2 * vol; // c s V_j on node 0
    EXPECT_NEAR(s.f[0], mag_i * std::cos(0.3), 1e-9 * mag_i);
    EXPECT_NEAR(s.f[1], mag_i * std::sin(0.3), 1e-9 * mag_i);
    // Newton's third law on nodal forces f V.
    EXPECT_NEAR(s.f[0] * vol + s.f[3] * 2 * vol, 0.0, 1e-12 * mag_i * vol);
    EXPECT_NEAR(s.f[1] * vol + s.f[4] * 2 * vol, 0.0, 1e-12 * mag_i * vol);
    // Energy: 1/2 c s^2 xi V_i V_j for the pair.
    EXPECT_NEAR(res.elastic_energy, 0.5 * 2.5e20 * stretch * stretch * r * vol * 2 * vol,
                1e-12 * res.elastic_energy);
    EXPECT_EQ(res.newly_broken, 0);
}

/// Beyond s0 in tension the bond breaks from both ends in the same call; compression never breaks.
TEST(Pmb, BreakingIsSymmetricAndTensionOnly) {
    solver::State s;
    s.n = 2;
    s.rows = {0, 1};
    const double r = 1e-4;
    s.x0 = {0, 0, 0, r, 0, 0};
    s.f.assign(6, 0);
    s.v.assign(6, 0);
    s.vol = {1e-8, 1e-8};
    s.body = {0, 0};
    s.moving = {1, 1};
    solver::BondData b;
    b.offsets = {0, 1, 2};
    b.neighbor = {1, 0};
    b.xi = {r, r};
    b.beta = {1, 1};
    b.alive = {1, 1};
    solver::BodyLaw law;
    law.lps = {0};
    law.rnp = {0};
    law.krep = {0};
    law.rrep = {0};
    law.c = {1e20};
    law.s0 = {0.01};
    law.any_breakable = true;
    s.x = {0, 0, 0, r * 0.9, 0, 0}; // compression 10%
    solver::pmb_bond_forces(s, b, law);
    EXPECT_EQ(b.alive[0] + b.alive[1], 2);
    s.x = {0, 0, 0, r * 1.02, 0, 0}; // tension 2% > s0
    auto res = solver::pmb_bond_forces(s, b, law);
    EXPECT_EQ(b.alive[0], 0);
    EXPECT_EQ(b.alive[1], 0);
    EXPECT_EQ(res.newly_broken, 2);
    EXPECT_EQ(s.f[0], 0.0);
}

} // namespace
