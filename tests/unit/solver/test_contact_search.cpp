// SPDX-License-Identifier: MIT
// The contact search misses no pair: grains pressed deep into each other (far past the surface
// layer of width R_c + h that alone searched for contact before) and into a rigid wall give
// exactly the node pairs a brute-force O(n^2) check finds, at the build and after moves that stay
// inside the skin.
#include "body_means.hpp"
#include "core/log.hpp"
#include "pipeline/scene.hpp"
#include "solver/contact.hpp"
#include "solver/domain.hpp"
#include "solver/solver.hpp"
#include "solver/walls.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace {

using namespace pd;

const Log quiet("test", 0, Verbosity::quiet);

/// Moves body b rigidly: rotation by `angle` about its centre of nodes, then shift (dx, dy).
void move_body(const model::Model& m, solver::State& s, std::size_t b, double angle, double dx,
               double dy) {
    double c[2] = {0, 0};
    const auto n = static_cast<double>(m.bodies.end(b) - m.bodies.begin(b));
    for (auto i = m.bodies.begin(b); i < m.bodies.end(b); ++i)
        for (int d = 0; d < 2; ++d)
            c[d] += s.x[3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(d)] / n;
    const double cs = std::cos(angle), sn = std::sin(angle);
    for (auto i = m.bodies.begin(b); i < m.bodies.end(b); ++i) {
        double* x = &s.x[3 * static_cast<std::size_t>(i)];
        const double rx = x[0] - c[0], ry = x[1] - c[1];
        x[0] = c[0] + cs * rx - sn * ry + dx;
        x[1] = c[1] + sn * rx + cs * ry + dy;
    }
}

/// Node pairs of different bodies closer than R_c, and their spring energy, by brute force.
std::pair<std::int64_t, double> brute_force(const model::Model& m, const solver::State& s) {
    const auto& law = m.contact.front();
    std::int64_t pairs = 0;
    double e = 0;
    for (std::size_t i = 0; i < s.n; ++i)
        for (std::size_t j = i + 1; j < s.n; ++j) {
            if (s.body[i] == s.body[j])
                continue;
            const double r = std::hypot(s.x[3 * j] - s.x[3 * i], s.x[3 * j + 1] - s.x[3 * i + 1]);
            if (r < law.radius) {
                ++pairs;
                e +=
                    0.5 * law.stiffness * (law.radius - r) * (law.radius - r) * s.vol[i] * s.vol[j];
            }
        }
    return {pairs, e};
}

model::Model two_discs() {
    return pipeline::build_scene(R"({"dimension": 2,
      "materials": {"m1": {"density": 1200, "youngs_modulus": 3.24e7}},
      "discretization": {"mesh_size": 1e-4, "horizon_factor": 3},
      "particles": [{"radius": 1e-3, "center": [0, 0], "material": "m1"},
                    {"radius": 0.8e-3, "center": [3e-3, 0.3e-3], "material": "m1",
                     "orientation": 0.37}],
      "contact": {"law": "node"}, "solver": {"final_time": 1}})",
                                 "t", quiet);
}

TEST(ContactSearch, DeepOverlapMissesNoPair) {
    const auto m = two_discs();
    const double rc = m.contact.front().radius;
    auto s = test::state_of(m);
    // Disc 1 pushed 0.9 mm deep into disc 0 (its centre 0.9 mm from disc 0's, far past the
    // surface layer of width R_c + h = 0.195 mm), and turned.
    move_body(m, s, 1, 0.21, -2.1e-3, -0.3e-3);
    solver::Domain dom(s.n);
    solver::ContactList cl(m, rc);
    ASSERT_TRUE(cl.active());
    ASSERT_TRUE(cl.update(s, dom));
    double e = 0;
    auto [pairs, e_ref] = brute_force(m, s);
    // Pairs of two nodes that lie deeper than R_c + h in their own grains (m.nodes.surface = 0):
    // the old rule, which searched the surface layers only, missed every one of them.
    std::int64_t deep = 0;
    for (std::size_t i = 0; i < s.n; ++i)
        for (std::size_t j = i + 1; j < s.n; ++j)
            deep += s.body[i] != s.body[j] && !m.nodes.surface[i] && !m.nodes.surface[j] &&
                    std::hypot(s.x[3 * j] - s.x[3 * i], s.x[3 * j + 1] - s.x[3 * i + 1]) < rc;
    ASSERT_GT(deep, 100);
    EXPECT_EQ(cl.add_forces(s, e, nullptr), pairs);
    EXPECT_NEAR(e, e_ref, 1e-12 * e_ref);
    // Moves of less than half the skin per build keep the list exact without a rebuild; larger
    // ones rebuild. Disc 1 slides through disc 0 in steps of 0.2 R_c.
    std::int64_t rebuilds = cl.rebuilds();
    for (int k = 0; k < 40; ++k) {
        move_body(m, s, 1, 0.003, 0.2 * rc, 0.05 * rc);
        cl.update(s, dom);
        std::fill(s.f.begin(), s.f.end(), 0.0);
        const auto ref = brute_force(m, s);
        ASSERT_EQ(cl.add_forces(s, e, nullptr), ref.first) << "step " << k;
        ASSERT_NEAR(e, ref.second, 1e-12 * ref.second) << "step " << k;
    }
    EXPECT_GT(cl.rebuilds(), rebuilds);      // the skin ran out several times
    EXPECT_LT(cl.rebuilds(), rebuilds + 40); // but not at every step
}

TEST(ContactSearch, GrainsApartCostNoCandidates) {
    // Far apart: the broad phase keeps both discs out; within reach but not touching: only nodes
    // near the gap have candidates (the inside of each disc is skipped cell by cell).
    const auto m = two_discs();
    const double rc = m.contact.front().radius;
    auto s = test::state_of(m);
    solver::Domain dom(s.n);
    solver::ContactList cl(m, rc);
    cl.update(s, dom);
    EXPECT_EQ(cl.num_candidates(), 0u);
    move_body(m, s, 1, 0, -1.2e-3 + 1.5 * rc, -0.3e-3); // gap 1.5 R_c < R_c + skin
    cl.invalidate();
    cl.update(s, dom);
    double e = 0;
    EXPECT_EQ(cl.add_forces(s, e, nullptr), 0);
    EXPECT_GT(cl.num_candidates(), 0u);
    EXPECT_LT(cl.num_candidates(), s.n);
}

TEST(WallSearch, GrainPressedDeepIntoAWallMissesNoNode) {
    const auto m = pipeline::build_scene(R"({"dimension": 2,
      "materials": {"m1": {"density": 1200, "youngs_modulus": 3.24e7}},
      "discretization": {"mesh_size": 1e-4, "horizon_factor": 3},
      "particles": [{"radius": 1e-3, "center": [0, 1.5e-3], "material": "m1"}],
      "walls": [{"type": "plane", "point": [0, 0], "normal": [0, 1]}],
      "contact": {"law": "node"}, "solver": {"final_time": 1}})",
                                         "t", quiet);
    const double rc = m.contact.front().radius;
    auto s = test::state_of(m);
    solver::WallContact wc(m, rc);
    ASSERT_TRUE(wc.active());
    for (int k = 0; k < 60; ++k) {
        move_body(m, s, 0, 0.002, 0.1 * rc, -0.3 * rc); // sinks 1.3 mm into the wall in all
        wc.update(s);
        solver::WallLoad load;
        wc.add_forces(s, load, nullptr);
        std::int64_t below = 0;
        for (std::size_t i = 0; i < s.n; ++i)
            below += s.x[3 * i + 1] < rc;
        ASSERT_EQ(load.touching, below) << "step " << k;
    }
}

TEST(ContactSearch, DiscPressedByAPlateStaysOutOfPlateAndBlock) {
    // A soft disc (E = 1e5 Pa, R = 1 mm, h = 0.2 mm) between a fixed block and a plate driven
    // down by 1.2 mm (60 % of the diameter): nodes deep inside the disc reach the plate. On the
    // surface contact law, with no stiffness factor, no disc node may end beyond the plate's or
    // the block's outer row of nodes. (The node-to-node law needed 300 x its auto
    // stiffness here: at 1 x the squeezed disc went into the block, at 100 x with the surface
    // correction through both.)
    auto m = pipeline::build_scene(R"({"dimension": 2,
      "materials": {"m": {"density": 1000, "youngs_modulus": 1e5}},
      "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
      "shapes": {"block": {"type": "rectangle", "corners": [[-2e-3, -1e-3], [2e-3, 0]]},
                 "plate": {"type": "rectangle", "corners": [[-2e-3, 2.4e-3], [2e-3, 3.4e-3]]},
                 "disc": {"type": "circle", "radius": 1e-3}},
      "particles": [{"shape": "block", "center": [0, 0], "material": "m", "fixed": true},
                    {"shape": "disc", "center": [0, 1.2e-3], "material": "m"},
                    {"shape": "plate", "center": [0, 0], "material": "m"}],
      "contact": {"restitution": 0.5, "law": "surface"},
      "loading": {"conditions": [
        {"kind": "displacement", "particles": [2], "components": ["y"], "value": -0.5,
         "time_function": "linear"},
        {"kind": "displacement", "particles": [2], "components": ["x"], "value": 0}]},
      "solver": {"final_time": 1}})",
                                   "t", quiet);
    solver::Solver s(m);
    s.set_dt(0.7 * s.stable_dt().limit);
    s.initialize();
    const int steps = static_cast<int>(std::ceil(2.4e-3 / s.dt())); // plate moves 1.2 mm
    for (int k = 0; k < steps; ++k)
        s.advance();
    const auto& x = s.state().x;
    auto y_range = [&](std::size_t b) {
        std::pair<double, double> r{1, -1};
        for (auto i = m.bodies.begin(b); i < m.bodies.end(b); ++i) {
            r.first = std::min(r.first, x[3 * static_cast<std::size_t>(i) + 1]);
            r.second = std::max(r.second, x[3 * static_cast<std::size_t>(i) + 1]);
        }
        return r;
    };
    const auto block = y_range(0), disc = y_range(1), plate = y_range(2);
    std::printf("[ pressed ] block top row %.3f mm, disc %.3f to %.3f mm, plate bottom row %.3f "
                "mm\n",
                block.second * 1e3, disc.first * 1e3, disc.second * 1e3, plate.first * 1e3);
    // The penalty lets the boundaries overlap in proportion to the pressure: at this squeeze
    // (60 %, far past the elastic range of the disc) by 0.042 mm into the block and 0.055 mm into
    // the plate (measured; 0.28 h and 0.36 h of their smallest node spacing h = 0.15 mm); the node
    // law at 300 x its auto stiffness kept 0.07 and 0.08 mm apart, at 1 x it went through. Bound:
    // the guard's h / 2 (contact holds).
    const double hb = m.bodies.mesh_size[0], hp = m.bodies.mesh_size[2];
    EXPECT_LT(plate.first, 1.21e-3); // the plate did press the disc (from 2.4 mm)
    EXPECT_GT(disc.first, block.second - hb / 2);
    EXPECT_LT(disc.second, plate.first + hp / 2);
}

TEST(WallSearch, RotatingWallMeetsAGrainFarFromItsCentre) {
    // A plane through the origin turning at 1 rad/s sweeps up into a disc at rest 10 mm from the
    // rotation centre. The list is rebuilt when the wall may have moved half the skin near any
    // node: the bound must use the farthest node, not only the current candidates (there are
    // none at the start, so a bound over candidates is 0 and the list is never rebuilt).
    const auto m = pipeline::build_scene(R"({"dimension": 2,
      "materials": {"m1": {"density": 1200, "youngs_modulus": 3.24e7}},
      "discretization": {"mesh_size": 1e-4, "horizon_factor": 3},
      "particles": [{"radius": 1e-3, "center": [10e-3, 1.5e-3], "material": "m1"}],
      "walls": [{"type": "plane", "point": [0, 0], "normal": [0, 1], "angular_velocity": 1}],
      "contact": {"law": "node"}, "solver": {"final_time": 1}})",
                                         "t", quiet);
    const double rc = m.contact.front().radius;
    const auto r = test::rotating_wall_sweep(m, [&](const solver::State& s, std::size_t i) {
        const auto pose = solver::wall_pose(m.walls.front(), s.time);
        double d = 0;
        for (std::size_t q = 0; q < 3; ++q)
            d += (s.x[3 * i + q] - pose.point[q]) * pose.normal[q];
        return d < rc;
    });
    EXPECT_EQ(r.bad_step, -1) << r.got << " touching, " << r.want << " within R_c";
    EXPECT_GT(r.touched, 10); // the wall did reach into the disc
}

/// Is (x, y) inside the closed polygon of body b's boundary facets (ray casting)?
bool inside_boundary(const solver::Facets& F, const solver::State& s, std::int32_t b, double x,
                     double y) {
    bool in = false;
    for (std::size_t f = 0; f < F.num(); ++f) {
        if (F.body[f] != b)
            continue;
        const double* p = &s.x[3 * static_cast<std::size_t>(F.v[2 * f])];
        const double* q = &s.x[3 * static_cast<std::size_t>(F.v[2 * f + 1])];
        if ((p[1] > y) != (q[1] > y) && x < p[0] + (y - p[1]) / (q[1] - p[1]) * (q[0] - p[0]))
            in = !in;
    }
    return in;
}

/// Whether x lies within delta / 4 of body b's boundary and within a quarter of the facet of a
/// convex vertex whose smoothing band is delta (surface_blend.cpp, vertex_blend: the vertex
/// is rounded off, at most delta / 4 deep, over its band).
bool in_fillet(const solver::Facets& F, const solver::State& s, std::int32_t b, const double* x) {
    for (std::size_t f = 0; f < F.num(); ++f)
        for (std::size_t e = 0; e < 2; ++e) {
            const double c = F.blend[2 * f + e];
            if (F.body[f] != b || !(c > 0))
                continue;
            const auto normal = [&](std::size_t k, double* n) {
                const double* A = &s.x[3 * static_cast<std::size_t>(F.v[2 * k])];
                const double* B = &s.x[3 * static_cast<std::size_t>(F.v[2 * k + 1])];
                const double l = std::hypot(B[0] - A[0], B[1] - A[1]);
                n[0] = (B[1] - A[1]) / l;
                n[1] = -(B[0] - A[0]) / l;
            };
            double nf[2], ng[2];
            normal(f, nf);
            normal(static_cast<std::size_t>(F.across[2 * f + e]), ng);
            const double delta = c * 0.5 * std::hypot(nf[0] - ng[0], nf[1] - ng[1]);
            const double* v = &s.x[3 * static_cast<std::size_t>(F.v[2 * f + e])];
            const double* o = &s.x[3 * static_cast<std::size_t>(F.v[2 * f + 1 - e])];
            const double L = std::hypot(o[0] - v[0], o[1] - v[1]);
            const double n[2] = {(o[1] - v[1]) / L, -(o[0] - v[0]) / L}; // +-normal
            const double along =
                ((x[0] - v[0]) * (o[0] - v[0]) + (x[1] - v[1]) * (o[1] - v[1])) / L;
            const double depth = std::abs((x[0] - v[0]) * n[0] + (x[1] - v[1]) * n[1]);
            if (along < 0.26 * L && depth <= 0.25 * delta * (1 + 1e-9))
                return true;
        }
    return false;
}

TEST(SurfaceContact, TouchingNodesAreTheNodesInsideTheOtherBoundary) {
    // The surface law: disc 1 slides along disc 0 overlapping it by up to 0.4 h
    // and turning; at every step the nodes in contact are the nodes of either disc that lie
    // inside the other's boundary polygon (ray casting over its facets) but for those in the
    // rounding of a convex vertex (vertex_blend: at most delta / 4 deep, a quarter of the facet
    // along it), which may be out of contact, and the contact forces sum to zero (the facets'
    // nodes take the reactions).
    const auto m = pipeline::build_scene(R"({"dimension": 2,
      "materials": {"m1": {"density": 1200, "youngs_modulus": 3.24e7}},
      "discretization": {"mesh_size": 1e-4, "horizon_factor": 3},
      "particles": [{"radius": 1e-3, "center": [0, 0], "material": "m1"},
                    {"radius": 0.8e-3, "center": [3e-3, 0.3e-3], "material": "m1",
                     "orientation": 0.37}],
      "contact": {"law": "surface"}, "solver": {"final_time": 1}})",
                                         "t", quiet);
    ASSERT_EQ(m.contact.front().law, model::ContactLaw::surface);
    const double h = m.bodies.mesh_size[0];
    auto s = test::state_of(m);
    const auto F = solver::boundary_facets(m, {1, 1});
    ASSERT_GT(F.num(), 50u);
    solver::Domain dom(s.n);
    solver::ContactList cl(m, h);
    // Centre distance 1.8 mm - overlap; the overlap grows to 0.4 h and back while disc 1 turns
    // about disc 0 by 0.6 rad (and about itself).
    std::int64_t most = 0, filleted = 0;
    for (int k = 0; k <= 60; ++k) {
        const double overlap = 0.4 * h * std::sin(M_PI * k / 60.0);
        const double angle = 0.01 * k;
        auto t = test::state_of(m);
        move_body(m, t, 1, angle, 0, 0); // spin in place, then place its centre
        double c[2] = {0, 0};
        const auto n1 = static_cast<double>(m.bodies.end(1) - m.bodies.begin(1));
        for (auto i = m.bodies.begin(1); i < m.bodies.end(1); ++i)
            for (int d = 0; d < 2; ++d)
                c[d] += t.x[3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(d)] / n1;
        const double r = 1.8e-3 - overlap;
        move_body(m, t, 1, 0, r * std::cos(angle) - c[0], r * std::sin(angle) - c[1]);
        s.x = t.x;
        // Each k is a configuration of its own, not a step: no depth history (the law's rule
        // that a depth grows only with the nodes' motion, surface_contact.cpp).
        cl.invalidate();
        cl.update(s, dom);
        std::fill(s.f.begin(), s.f.end(), 0.0);
        double e = 0;
        const auto touching = cl.add_forces(s, e, nullptr);
        std::int64_t inside = 0;
        std::int64_t fillet = 0;
        for (std::size_t i = 0; i < s.n; ++i)
            if (inside_boundary(F, s, 1 - s.body[i], s.x[3 * i], s.x[3 * i + 1])) {
                ++inside;
                fillet += in_fillet(F, s, 1 - s.body[i], &s.x[3 * i]);
            }
        // Every node inside, but those the rounding of a convex vertex may leave out.
        ASSERT_LE(touching, inside) << "step " << k;
        ASSERT_GE(touching, inside - fillet) << "step " << k;
        filleted += fillet;
        double sum[2] = {0, 0}, mag = 0;
        for (std::size_t i = 0; i < s.n; ++i)
            for (int d = 0; d < 2; ++d) {
                sum[d] += s.f[3 * i + static_cast<std::size_t>(d)] * s.vol[i];
                mag += std::abs(s.f[3 * i + static_cast<std::size_t>(d)] * s.vol[i]);
            }
        EXPECT_LE(std::abs(sum[0]) + std::abs(sum[1]), 1e-12 * mag + 1e-300) << "step " << k;
        EXPECT_EQ(touching > 0, e > 0);
        most = std::max(most, touching);
    }
    EXPECT_GT(most, 5); // the discs did overlap
    std::printf("[ touching ] at most %lld nodes in contact; %lld node-steps in a fillet\n",
                static_cast<long long>(most), static_cast<long long>(filleted));
}

} // namespace
