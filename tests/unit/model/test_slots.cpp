// SPDX-License-Identifier: MIT
// Notch slots (model/slots.hpp): on a uniform grid, the nodes inside a slot are removed and the
// bonds through it never exist, counted against a brute-force census of the original bond list;
// a bond passing beyond the slot's end survives; width 0 cuts like a pre-crack; the KW scene key
// removes the same bonds through pd-pack's scene builder.
#include "core/errors.hpp"
#include "model/slots.hpp"
#include "pipeline/scene.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

namespace {

using namespace pd::model;

constexpr double h = 1e-3;

/// nx x ny grid nodes at (i h, j h), one body, horizon 3h, strict cut-off.
Model grid(int nx, int ny) {
    Model m;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            m.nodes.x0.insert(m.nodes.x0.end(), {i * h, j * h, 0.0});
            m.nodes.volume.push_back(h * h);
            m.nodes.body.push_back(0);
        }
    m.bodies.node_offsets.push_back(static_cast<offset_t>(m.nodes.num()));
    m.bodies.horizon.push_back(3 * h);
    m.bodies.mesh_size.push_back(h);
    m.bonds = build_bonds(m.nodes, m.bodies, false);
    return m;
}

using Pair = std::pair<std::pair<long, long>, std::pair<long, long>>; // grid coordinates

std::set<Pair> bond_set(const Model& m) {
    std::set<Pair> s;
    auto c = [&](std::size_t i) {
        return std::pair<long, long>{std::lround(m.nodes.x0[3 * i] / h),
                                     std::lround(m.nodes.x0[3 * i + 1] / h)};
    };
    for (std::size_t i = 0; i < m.nodes.num(); ++i)
        for (auto e = m.bonds.offsets[i]; e < m.bonds.offsets[i + 1]; ++e)
            s.insert({c(i), c(static_cast<std::size_t>(m.bonds.neighbor[e]))});
    return s;
}

void expect_symmetric_csr(const Model& m) {
    ASSERT_EQ(m.bonds.offsets.size(), m.nodes.num() + 1);
    EXPECT_EQ(static_cast<std::size_t>(m.bonds.offsets.back()), m.bonds.neighbor.size());
    const auto s = bond_set(m);
    for (const auto& p : s)
        EXPECT_TRUE(s.count({p.second, p.first})) << "asymmetric bond";
    EXPECT_EQ(m.bodies.node_offsets.back(), static_cast<offset_t>(m.nodes.num()));
    EXPECT_EQ(m.nodes.x0.size(), 3 * m.nodes.num());
    EXPECT_EQ(m.nodes.body.size(), m.nodes.num());
}

TEST(Slots, FullHeightSlotSeparatesTheHalves) {
    // A slot along x = 10 h over the whole height, 1.5 h wide: the column x = 10 h (11 nodes)
    // goes, and every bond from x < 10 h to x > 10 h never exists.
    Model m = grid(21, 11);
    const auto before = bond_set(m);
    std::size_t crossing = 0, touching_column = 0;
    for (const auto& [a, b] : before) {
        crossing += a.first < 10 && b.first > 10;
        touching_column += a.first == 10 || b.first == 10;
    }
    ASSERT_GT(crossing, 40u); // 49 at dx = 2, plus dx = 3 pairs that round below delta
    const auto cut = apply_slots(m, {{{10 * h, -1 * h, 0}, {10 * h, 11 * h, 0}, 1.5 * h}});
    EXPECT_EQ(cut.nodes_removed, 11u);
    EXPECT_EQ(m.nodes.num(), 21u * 11u - 11u);
    EXPECT_EQ(cut.bonds_removed, crossing);
    EXPECT_EQ(cut.bonds_per_slot[0], crossing);
    const auto after = bond_set(m);
    EXPECT_EQ(before.size() - after.size(), 2 * crossing + touching_column);
    for (const auto& [a, b] : after) {
        EXPECT_NE(a.first, 10);
        EXPECT_FALSE((a.first < 10) != (b.first < 10)) << "a bond crosses the slot";
    }
    expect_symmetric_csr(m);
}

TEST(Slots, NotchEndsAtItsTip) {
    // A notch from below the edge to y = 5 h: nodes (10, 0..4) go, (10, 5) is the tip and stays.
    Model m = grid(21, 11);
    const auto before = bond_set(m);
    const auto cut = apply_slots(m, {{{10 * h, -1 * h, 0}, {10 * h, 5 * h, 0}, 1.5 * h}});
    EXPECT_EQ(cut.nodes_removed, 5u);
    const auto after = bond_set(m);
    using P = std::pair<long, long>;
    auto has = [&](P a, P b) { return after.count({a, b}) > 0; };
    EXPECT_FALSE(has({9, 2}, {11, 2})); // through the slot
    EXPECT_FALSE(has({8, 4}, {11, 4})); // through the slot
    EXPECT_TRUE(has({9, 5}, {11, 5}));  // along the tip's edge line: kept
    EXPECT_TRUE(has({9, 7}, {11, 7}));  // above the tip
    EXPECT_TRUE(has({10, 5}, {10, 7})); // the tip node keeps its bonds upwards
    EXPECT_FALSE(has({9, 4}, {11, 6})); // through the corner region (inside the rectangle)
    EXPECT_TRUE(has({9, 6}, {11, 5}));  // passes above the end (u > 6 h at x = 10 h)
    // Brute force: a bond is gone iff an end is a removed node or it crosses x = 10 h below
    // y = 5 h + (the end of the slot), computed in the slot's frame by sampling the segment.
    std::size_t expect_cut = 0;
    for (const auto& [a, b] : before) {
        if (a >= b || (a.first == 10 && a.second < 5) || (b.first == 10 && b.second < 5))
            continue;
        bool inside = false;
        for (int k = 1; k < 1000 && !inside; ++k) {
            const double t = k / 1000.0;
            const double x = (a.first + t * (b.first - a.first)) * h;
            const double y = (a.second + t * (b.second - a.second)) * h;
            inside = std::abs(x - 10 * h) < 0.75 * h && y > -h && y < 5 * h;
        }
        expect_cut += inside;
    }
    EXPECT_EQ(cut.bonds_removed, expect_cut);
    expect_symmetric_csr(m);
}

TEST(Slots, ZeroWidthIsACut) {
    // Width 0 between grid columns (x = 10.5 h, y up to 5.4 h: no bond ends on it): no node
    // removed; a bond goes iff it crosses x = 10.5 h at y <= 5.4 h.
    Model m = grid(21, 11);
    const auto before = bond_set(m);
    std::size_t crossing = 0;
    for (const auto& [a, b] : before) {
        if (!(a.first <= 10 && b.first >= 11))
            continue;
        const double y = a.second + (10.5 - a.first) / (b.first - a.first) * (b.second - a.second);
        crossing += y <= 5.4;
    }
    ASSERT_GT(crossing, 20u);
    const auto cut = apply_slots(m, {{{10.5 * h, -1 * h, 0}, {10.5 * h, 5.4 * h, 0}, 0.0}});
    EXPECT_EQ(cut.nodes_removed, 0u);
    EXPECT_EQ(cut.bonds_removed, crossing);
    EXPECT_EQ(before.size() - bond_set(m).size(), 2 * crossing);
    expect_symmetric_csr(m);
}

TEST(Slots, BadSlotsAreRefused) {
    Model m = grid(5, 5);
    EXPECT_THROW(apply_slots(m, {{{h, h, 0}, {h, h, 0}, h}}), pd::InputError);
    EXPECT_THROW(apply_slots(m, {{{h, 0, 0}, {h, 2 * h, 0}, -h}}), pd::InputError);
    EXPECT_THROW(apply_slots(m, {{{2 * h, -h, 0}, {2 * h, 10 * h, 0}, 10 * h}}), pd::InputError);
}

TEST(Slots, SceneKeyRemovesNodesAndBonds) {
    // The scene builder applies "slots" (the KW plate in miniature: 40 x 20 mm, h = 1 mm, two
    // notches 10 mm deep and 1.5 mm wide): 2 x 10 nodes go and the bond count drops by the
    // bonds of those nodes plus twice the bonds through the slots.
    const pd::Log quiet("test", 0, pd::Verbosity::quiet);
    auto scene = [](const std::string& slots) {
        return R"({"dimension": 2, "materials": {"s": {"density": 8000, "youngs_modulus": 191e9,
          "fracture_energy": 42408}}, "discretization": {"mesh_size": 0.001, "horizon_factor": 3},
          "shapes": {"plate": {"type": "rectangle", "corners": [[-0.02, -0.01], [0.02, 0.01]],
          "mesh": "grid"}}, "particles": [{"shape": "plate", "center": [0, 0], "material": "s"}],
          )" + slots +
               R"( "solver": {"final_time": 1e-5}})";
    };
    const auto plain = pd::pipeline::build_scene(scene(""), "s", quiet);
    const auto notched = pd::pipeline::build_scene(
        scene(R"("slots": [{"from": [-0.005, -0.011], "to": [-0.005, 0], "width": 0.0015},
                           {"from": [0.005, -0.011], "to": [0.005, 0], "width": 0.0015}],)"),
        "s", quiet);
    EXPECT_EQ(plain.nodes.num() - notched.nodes.num(), 20u);
    Model check = plain;
    const auto cut = apply_slots(check, {{{-0.005, -0.011, 0}, {-0.005, 0, 0}, 0.0015},
                                         {{0.005, -0.011, 0}, {0.005, 0, 0}, 0.0015}});
    EXPECT_EQ(notched.bonds.num(), check.bonds.num());
    EXPECT_GT(cut.bonds_removed, 0u);
    // Nodes with x in (-5.75, -4.25) mm and y < 0 are gone, (-5, 0) (the notch tip) stays.
    bool tip = false;
    for (std::size_t i = 0; i < notched.nodes.num(); ++i) {
        const double x = notched.nodes.x0[3 * i], y = notched.nodes.x0[3 * i + 1];
        EXPECT_FALSE(std::abs(std::abs(x) - 0.005) < 0.00075 && y < -1e-9) << x << " " << y;
        tip = tip || (std::abs(x + 0.005) < 1e-9 && std::abs(y) < 1e-9);
    }
    EXPECT_TRUE(tip);
    // Nodes next to a notch face are in the surface layer (2 R_c + h/2 = 2.4 mm);
    // x = -1 mm, 3.25 mm from the face (x = -4.25 mm) at y = -5 mm, is not.
    for (std::size_t i = 0; i < notched.nodes.num(); ++i) {
        const double x = notched.nodes.x0[3 * i], y = notched.nodes.x0[3 * i + 1];
        if (std::abs(y + 0.005) < 1e-9 && std::abs(x + 0.004) < 1e-9) {
            EXPECT_EQ(notched.nodes.surface[i], 1);
        }
        if (std::abs(y + 0.005) < 1e-9 && std::abs(x + 0.001) < 1e-9) {
            EXPECT_EQ(notched.nodes.surface[i], 0);
        }
    }
    EXPECT_DOUBLE_EQ(
        slot_distance({{0, 0, 0}, {0, 1, 0}, 0.5}, std::array<double, 3>{1, 2, 0}.data()),
        std::hypot(0.75, 1.0));
}

} // namespace
