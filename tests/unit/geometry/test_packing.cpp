// SPDX-License-Identifier: MIT
// Packing: no two grains overlap (brute force), every grain lies inside its container, the same
// seed reproduces the output bit for bit, PeriDEM's n500 scene and 10 000 grains pack quickly;
// lattices and the particle CSV format.
#include "core/errors.hpp"
#include "geometry/packing.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>

namespace {

using namespace pd::geometry;
constexpr double mm = 1e-3;
constexpr double pi = std::numbers::pi;

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// O(N^2) check: every pair at least r_i + r_j + gap apart.
void expect_no_overlap(const std::vector<Grain>& g, double gap) {
    std::size_t bad = 0;
    for (std::size_t i = 0; i < g.size(); ++i)
        for (std::size_t j = i + 1; j < g.size(); ++j) {
            const double d = std::sqrt(std::pow(g[i].center[0] - g[j].center[0], 2) +
                                       std::pow(g[i].center[1] - g[j].center[1], 2) +
                                       std::pow(g[i].center[2] - g[j].center[2], 2));
            if (d < g[i].radius + g[j].radius + gap)
                ++bad;
        }
    EXPECT_EQ(bad, 0u);
}

/// Every grain's bounding circle (sampled) lies in the container, checked with contains().
void expect_inside(const Shape& container, const std::vector<Grain>& g, double gap) {
    std::size_t bad = 0;
    for (const auto& x : g) {
        if (container.dimension() == 3) {
            for (int k = 0; k < 6; ++k) {
                Vec3 p = x.center;
                p[k / 2] += (k % 2 ? 1 : -1) * (x.radius + gap);
                bad += !container.contains(p[0], p[1], p[2]);
            }
            continue;
        }
        for (int k = 0; k < 64; ++k) {
            const double t = 2 * pi * k / 64;
            bad += !container.contains(x.center[0] + (x.radius + gap) * std::cos(t),
                                       x.center[1] + (x.radius + gap) * std::sin(t));
        }
        bad += container.clearance(x.center[0], x.center[1]) < x.radius + gap;
    }
    EXPECT_EQ(bad, 0u);
}

PackOptions n500() {
    PackOptions o;
    o.count = 500;
    o.rmin = 0.9 * mm;
    o.rmax = 1.1 * mm;
    o.fractions = {0.5, 0.5}; // circles and hexagons
    o.seed = 7;
    return o;
}

TEST(Packing, PeriDemCompressiveScene) {
    const Shape box = Shape::rectangle_corners(0, 0, 68.5 * mm, 41 * mm);
    const auto t0 = std::chrono::steady_clock::now();
    PackStats st;
    const auto g = random_pack(box, n500(), &st);
    const double t = seconds_since(t0);
    std::printf("[ n500     ] %zu grains, phi %.3f, rsa %zu, relaxed %zu in %zu sweeps, %.3f s\n",
                g.size(), st.packing_fraction, st.placed_by_rsa, st.relaxed, st.sweeps, t);
    ASSERT_EQ(g.size(), 500u);
    EXPECT_LT(t, 5.0);
    expect_no_overlap(g, 0);
    expect_inside(box, g, 0);
    std::size_t hex = 0;
    for (const auto& x : g) {
        EXPECT_GE(x.radius, 0.9 * mm);
        EXPECT_LE(x.radius, 1.1 * mm);
        EXPECT_GE(x.orientation, 0.0);
        EXPECT_LT(x.orientation, 2 * pi);
        EXPECT_EQ(x.center[2], 0.0);
        hex += x.shape == 1;
    }
    EXPECT_EQ(hex, 250u);
    EXPECT_NEAR(packing_fraction(box, g), st.packing_fraction, 1e-12);
}

TEST(Packing, SameSeedSameOutputOtherSeedDiffers) {
    const Shape box = Shape::rectangle_corners(0, 0, 68.5 * mm, 41 * mm);
    auto o = n500();
    o.count = 300;
    const auto a = random_pack(box, o), b = random_pack(box, o);
    EXPECT_TRUE(a == b);
    o.seed = 8;
    const auto c = random_pack(box, o);
    ASSERT_EQ(c.size(), a.size());
    EXPECT_FALSE(a == c);
}

TEST(Packing, TenThousandGrains) {
    // Side chosen for a packing fraction of 0.5: N pi E[r^2] / L^2, E[r^2] = 0.98333 mm^2.
    const double side = std::sqrt(10000 * pi * 0.98333 / 0.5) * mm;
    const Shape box = Shape::rectangle(side, side);
    auto o = n500();
    o.count = 10000;
    o.seed = 3;
    PackStats st;
    const auto t0 = std::chrono::steady_clock::now();
    const auto g = random_pack(box, o, &st);
    const double t = seconds_since(t0);
    std::printf("[ n10000   ] box %.1f mm, phi %.3f, rsa %zu, relaxed %zu in %zu sweeps, %.3f s\n",
                side / mm, st.packing_fraction, st.placed_by_rsa, st.relaxed, st.sweeps, t);
    ASSERT_EQ(g.size(), 10000u);
    EXPECT_LT(t, 60.0);
    EXPECT_GT(st.packing_fraction, 0.45);
    expect_no_overlap(g, 0);
    expect_inside(box, g, 0);
}

TEST(Packing, GapAndCsgContainer) {
    // Attrition-like drum: inside of a 20 mm circle, minus a bar at +x and everything above
    // y = 0.2 R (spec 8.5); 30 small and 10 large grains from explicit lists.
    const double R = 20 * mm;
    const Shape room = Shape::difference(
        Shape::circle(R), {Shape::rectangle_corners(15 * mm, -1.5 * mm, 21 * mm, 1.5 * mm),
                           Shape::rectangle_corners(-R, 0.2 * R, R, R)});
    PackOptions o;
    for (int i = 0; i < 40; ++i) {
        o.radii.push_back(i < 10 ? 3 * mm : 1 * mm);
        o.shapes.push_back(i < 10 ? i % 3 : 3);
    }
    o.gap = 0.2 * mm;
    o.seed = 30;
    const auto g = random_pack(room, o);
    ASSERT_EQ(g.size(), 40u);
    expect_no_overlap(g, o.gap);
    expect_inside(room, g, o.gap);
    for (int i = 0; i < 40; ++i)
        EXPECT_EQ(g[static_cast<std::size_t>(i)].shape, o.shapes[static_cast<std::size_t>(i)]);
}

TEST(Packing, DenseSceneNeedsRelaxation) {
    // phi = 0.62 is beyond random sequential addition (jams near 0.55): relaxation must finish.
    const Shape box = Shape::rectangle(30, 30);
    PackOptions o;
    o.count = 180;
    o.rmin = o.rmax = 1;
    o.seed = 5;
    o.attempts_per_grain = 200;
    PackStats st;
    const auto g = random_pack(box, o, &st);
    std::printf("[ dense    ] phi %.3f, rsa %zu, relaxed %zu in %zu sweeps\n", st.packing_fraction,
                st.placed_by_rsa, st.relaxed, st.sweeps);
    EXPECT_GT(st.relaxed, 0u);
    expect_no_overlap(g, 0);
    expect_inside(box, g, 0);
    o.relax = false;
    EXPECT_THROW(random_pack(box, o), pd::InputError);
}

TEST(Packing, Spheres) {
    const Shape cyl = Shape::cylinder(10, 30);
    PackOptions o;
    o.count = 400;
    o.rmin = 0.8;
    o.rmax = 1.2;
    o.gap = 0.05;
    const auto g = random_pack(cyl, o);
    ASSERT_EQ(g.size(), 400u);
    expect_no_overlap(g, o.gap);
    expect_inside(cyl, g, o.gap);
}

TEST(Packing, BadOptions) {
    const Shape box = Shape::rectangle(10, 10);
    PackOptions o;
    o.count = 10;
    EXPECT_THROW(random_pack(box, o), pd::InputError); // no radii
    o.rmin = 1;
    o.rmax = 0.5;
    EXPECT_THROW(random_pack(box, o), pd::InputError);
    o.rmax = 6; // does not fit at all
    EXPECT_THROW(random_pack(box, o), pd::InputError);
    o.rmax = 1;
    o.fractions = {};
    EXPECT_THROW(random_pack(box, o), pd::InputError);
    o.fractions = {1};
    o.count = 100; // phi = 3.1: impossible
    o.max_relax_sweeps = 200;
    EXPECT_THROW(random_pack(box, o), pd::InputError);
}

TEST(Lattice, RowsJitterAndContainer) {
    LatticeOptions o;
    o.origin = {1, 1, 0};
    o.counts = {10, 6, 1};
    o.spacing = {2.6, 2.3, 0};
    o.stagger = true;
    o.rmin = 0.9;
    o.rmax = 1.1;
    o.jitter = 0.05;
    o.fractions = {0.7, 0.3};
    const auto g = lattice(o);
    ASSERT_EQ(g.size(), 60u);
    EXPECT_NEAR(g[10].center[0], 1 + 1.3, 0.05 * 2.6 + 1e-12); // row 1 is shifted
    EXPECT_NEAR(g[10].center[1], 1 + 2.3, 0.05 * 2.3 + 1e-12);
    expect_no_overlap(g, 0);
    std::size_t circles = 0;
    for (const auto& x : g)
        circles += x.shape == 0;
    EXPECT_EQ(circles, 42u);
    EXPECT_TRUE(lattice(o) == g);
    // Only the grains that fit stay.
    const auto inside = lattice(Shape::rectangle_corners(0, 0, 15, 100), o);
    EXPECT_LT(inside.size(), g.size());
    EXPECT_GT(inside.size(), 0u);
    for (const auto& x : inside)
        EXPECT_LE(x.center[0] + x.radius, 15.0);
    o.spacing = {1.7, 2.3, 0}; // below 2 rmin: neighbours in a row overlap
    EXPECT_THROW(lattice(o), pd::InputError);
}

TEST(ParticleCsv, RoundTripHeaderAndErrors) {
    const auto dir = std::filesystem::temp_directory_path() / "pd_test_particle_csv";
    std::filesystem::create_directories(dir);
    const Shape box = Shape::rectangle(20, 20);
    PackOptions o;
    o.count = 25;
    o.rmin = 0.5;
    o.rmax = 1;
    o.fractions = {1, 1, 1};
    const auto g = random_pack(box, o);
    const std::string path = (dir / "grains.csv").string();
    write_particle_csv(path, g);
    EXPECT_TRUE(read_particle_csv(path) == g); // 17 digits: exact

    const std::string plain = (dir / "plain.csv").string();
    std::ofstream(plain) << "# comment\n1, 2, 0, 0.5, 0.25, 1\n\n3,4,0,0.5,0,0\n";
    const auto p = read_particle_csv(plain);
    ASSERT_EQ(p.size(), 2u);
    EXPECT_EQ(p[0].shape, 1);
    EXPECT_DOUBLE_EQ(p[0].orientation, 0.25);
    EXPECT_DOUBLE_EQ(p[1].center[1], 4.0);

    const std::string bad = (dir / "bad.csv").string();
    std::ofstream(bad) << "x,y,z,r,o,s\n1,2,0,0.5,0\n";
    try {
        read_particle_csv(bad);
        ADD_FAILURE() << "no error";
    } catch (const pd::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("bad.csv:2"), std::string::npos) << e.what();
    }
    std::ofstream(bad) << "1,2,0,0.5,0,1.5\n";
    EXPECT_THROW(read_particle_csv(bad), pd::InputError);
    EXPECT_THROW(read_particle_csv((dir / "missing.csv").string()), pd::InputError);
    std::filesystem::remove_all(dir);
}

} // namespace
