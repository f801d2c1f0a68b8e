// SPDX-License-Identifier: MIT
// Triangulated (STL) and polyline walls (issue 26 item 5): the grid-accelerated closest-cell
// query answers what the brute-force search answers; signed distances of a closed cube against
// the analytic box distance; a disc resting on a two-segment floor carries its weight as on an
// analytic plane (node and surface laws); a disc dropped on a tilted polyline follows the same path
// as on the analytic plane of the same tilt; a rotating polyline wall keeps its candidate list
// complete and the momentum and energy balances close; STL files (ASCII and binary) are read, and
// bad surfaces refused with a message naming the key.
#include "body_means.hpp"
#include "core/errors.hpp"
#include "core/log.hpp"
#include "model/wall_mesh.hpp"
#include "pipeline/scene.hpp"
#include "solver/solver.hpp"
#include "solver/walls.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <unistd.h>

namespace {

using namespace pd;

const Log quiet("test", 0, Verbosity::quiet);

/// An open funnel of `seg` sides (radius 0.3 at z = -1 to 1 at z = 0) with a flat rim ring out to
/// radius 1.6, consistently oriented, its vertices jittered at random.
model::WallMesh funnel(int seg, std::mt19937& rng) {
    std::uniform_real_distribution<double> jit(-0.05, 0.05);
    std::vector<double> p;
    std::vector<std::int32_t> c;
    const double r[3] = {0.3, 1.0, 1.6}, z[3] = {-1.0, 0.0, 0.05};
    for (int ring = 0; ring < 3; ++ring)
        for (int k = 0; k < seg; ++k) {
            const double a = 2 * std::numbers::pi * k / seg;
            p.insert(p.end(), {r[ring] * std::cos(a) + jit(rng), r[ring] * std::sin(a) + jit(rng),
                               z[ring] + jit(rng)});
        }
    for (int ring = 0; ring < 2; ++ring)
        for (int k = 0; k < seg; ++k) {
            const int a = ring * seg + k, b = ring * seg + (k + 1) % seg;
            const int A = a + seg, B = b + seg;
            c.insert(c.end(), {a, b, A, b, B, A});
        }
    EXPECT_EQ(model::check_wall_mesh(3, p, c), "");
    return model::WallMesh(3, std::move(p), std::move(c));
}

TEST(WallMesh, GridQueryEqualsBruteForce) {
    std::mt19937 rng(7);
    for (int seg : {5, 24, 96}) {
        const auto mesh = funnel(seg, rng);
        std::uniform_real_distribution<double> u(-2.0, 2.0), ur(0.0, 1.0);
        int found = 0;
        for (int q = 0; q < 20000; ++q) {
            const double X[3] = {u(rng), u(rng), u(rng) * 0.8};
            const double rmax = q % 10 == 0 ? HUGE_VAL : 0.5 * ur(rng) * ur(rng);
            double d1 = 7, d2 = 7, n1[3] = {0, 0, 0}, n2[3] = {0, 0, 0};
            const bool a = mesh.closest(X, rmax, d1, n1), b = mesh.closest_brute(X, rmax, d2, n2);
            ASSERT_EQ(a, b) << "query " << q;
            if (a) {
                ++found;
                ASSERT_EQ(d1, d2) << "query " << q;
                for (int k = 0; k < 3; ++k)
                    ASSERT_EQ(n1[k], n2[k]);
                ASSERT_LE(std::abs(d1), rmax);
            }
        }
        EXPECT_GT(found, 2000) << seg; // the queries did find cells, not only misses
    }
}

TEST(WallMesh, ClosedCubeSignedDistanceIsTheBoxDistance) {
    // A unit cube of 12 outward triangles: outside positive, inside negative, exact.
    std::vector<double> p;
    for (int i = 0; i < 8; ++i)
        p.insert(p.end(), {double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
    const std::vector<std::int32_t> c{0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                      2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
    ASSERT_EQ(model::check_wall_mesh(3, p, c), "");
    const model::WallMesh mesh(3, p, c);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-0.7, 1.7);
    for (int q = 0; q < 5000; ++q) {
        const double X[3] = {u(rng), u(rng), u(rng)};
        double out2 = 0, in = HUGE_VAL;
        for (int k = 0; k < 3; ++k) {
            const double e = std::max({-X[k], X[k] - 1, 0.0});
            out2 += e * e;
            in = std::min({in, X[k], 1 - X[k]});
        }
        const double exact = out2 > 0 ? std::sqrt(out2) : -in;
        double d = 0, n[3];
        ASSERT_TRUE(mesh.closest(X, 3.0, d, n));
        ASSERT_NEAR(d, exact, 1e-12) << X[0] << " " << X[1] << " " << X[2];
        ASSERT_NEAR(std::hypot(n[0], n[1], n[2]), 1.0, 1e-12);
    }
    // Flipped orientation: the sign turns.
    auto f = c;
    for (std::size_t k = 0; k < f.size(); k += 3)
        std::swap(f[k], f[k + 1]);
    const model::WallMesh inner(3, p, f);
    const double X[3] = {0.5, 0.5, 0.2};
    double d = 0, n[3];
    ASSERT_TRUE(inner.closest(X, 1.0, d, n));
    EXPECT_NEAR(d, 0.2, 1e-15);
    EXPECT_NEAR(n[2], 1.0, 1e-15);
}

TEST(WallMesh, BadSurfacesAreRefused) {
    const std::vector<double> p{0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0};
    EXPECT_NE(model::check_wall_mesh(3, p, {0, 1, 3}).find("degenerate"), std::string::npos);
    EXPECT_NE(model::check_wall_mesh(3, p, {0, 1, 4}).find("refers to point 4"), std::string::npos);
    EXPECT_NE(model::check_wall_mesh(3, p, {}).find("no triangle"), std::string::npos);
    auto q = p;
    q[4] = NAN;
    EXPECT_NE(model::check_wall_mesh(3, q, {0, 1, 2}).find("coordinate"), std::string::npos);
    const std::vector<double> sq{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    EXPECT_EQ(model::check_wall_mesh(3, sq, {0, 1, 2, 0, 2, 3}), "");
    EXPECT_NE(model::check_wall_mesh(3, sq, {0, 1, 2, 0, 3, 2}).find("opposite orientations"),
              std::string::npos);
    EXPECT_NE(model::check_wall_mesh(2, sq, {0, 1, 2, 1}).find("opposite orientations"),
              std::string::npos);
}

std::string scene2d(const std::string& particles, const std::string& rest) {
    return R"({"dimension": 2,
      "materials": {"m1": {"density": 1200, "youngs_modulus": 3.24e7, "fracture_energy": 50}},
      "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
      "particles": [)" +
           particles + "], " + rest + R"(, "solver": {"final_time": 1}})";
}

/// Mean of the wall's y reaction over the last 20 ms of 40, over the disc's weight (`law`:
/// the contact law, node or surface).
double resting_load(const std::string& wall, const std::string& law = "node") {
    auto m = pipeline::build_scene(
        scene2d(R"({"radius": 1e-3, "center": [0, 1.2e-3], "material": "m1"})",
                R"("walls": [)" + wall + R"(], "contact": {"restitution": 0.5, "law": ")" + law +
                    R"("},
                   "loading": {"gravity": [0, -10]})"),
        "t", quiet);
    solver::Solver s(m);
    return test::resting_reaction(s, 1);
}

TEST(MeshWall, RestingDiscCarriesItsWeightOnATwoSegmentFloor) {
    const double mesh = resting_load(R"({"type": "mesh", "polyline": [[-3e-3, 0], [0, 0],
                                         [3e-3, 0]]})");
    const double plane = resting_load(R"({"type": "plane", "point": [0, 0], "normal": [0, 1]})");
    std::printf("[ floor ] reaction / weight: mesh %.6f plane %.6f\n", mesh, plane);
    EXPECT_NEAR(mesh, 1.0, 0.01);
    EXPECT_NEAR(mesh, plane, 1e-6);
}

TEST(MeshWall, SurfaceLawOnATwoSegmentFloorEqualsThePlane) {
    const std::string floor = R"({"type": "mesh", "polyline": [[-3e-3, 0], [0, 0], [3e-3, 0]]})";
    const double mesh = resting_load(floor, "surface");
    const double plane =
        resting_load(R"({"type": "plane", "point": [0, 0], "normal": [0, 1]})", "surface");
    std::printf("[ floor, surface law ] reaction / weight: mesh %.6f plane %.6f\n", mesh, plane);
    // Over 15-30 ms the disc still bounced on this law (1.0440 x its weight on the plane too);
    // over 20-40 ms it rests: 0.99995. The mesh floor gives the plane's answer.
    EXPECT_NEAR(mesh, 1.0, 0.01);
    EXPECT_NEAR(mesh, plane, 1e-4);
}

/// Centre of mass of the disc after each millisecond of a drop on the wall (x, y per sample).
std::vector<double> drop_path(const std::string& wall) {
    auto m = pipeline::build_scene(
        scene2d(R"({"radius": 1e-3, "center": [0, 1.6e-3], "material": "m1"})",
                R"("walls": [)" + wall + R"(], "contact": {"restitution": 0.8, "friction": 0.3},
                   "loading": {"gravity": [0, -10]})"),
        "t", quiet);
    solver::Solver s(m);
    s.set_dt(0.7 * s.stable_dt().limit);
    s.initialize();
    std::vector<double> path;
    const int every = static_cast<int>(1e-3 / s.dt());
    for (int k = 1; k <= 20 * every; ++k) {
        s.advance();
        if (k % every == 0) {
            double c[2] = {0, 0}, mass = 0;
            const auto& st = s.state();
            for (std::size_t i = 0; i < st.n; ++i) {
                const double mi = st.rho[i] * st.vol[i];
                c[0] += mi * st.x[3 * i];
                c[1] += mi * st.x[3 * i + 1];
                mass += mi;
            }
            path.insert(path.end(), {c[0] / mass, c[1] / mass});
        }
    }
    return path;
}

TEST(MeshWall, DiscOnATiltedPolylineFollowsTheAnalyticPlane) {
    // 20 degrees: the plane through the origin, and a polyline along it whose middle vertex lies
    // right under the disc (the vertex pseudo-normal must give the face's answer).
    const double a = 20 * std::numbers::pi / 180, c = std::cos(a), s = std::sin(a);
    const auto mesh =
        drop_path(fmt::format(R"({{"type": "mesh", "polyline": [[{}, {}], [0, 0], [{}, {}]]}})",
                              -8e-3 * c, -8e-3 * s, 8e-3 * c, 8e-3 * s));
    const auto plane = drop_path(
        fmt::format(R"({{"type": "plane", "point": [0, 0], "normal": [{}, {}]}})", -s, c));
    ASSERT_EQ(mesh.size(), plane.size());
    double worst = 0;
    for (std::size_t k = 0; k < mesh.size(); ++k)
        worst = std::max(worst, std::abs(mesh[k] - plane[k]));
    const double travel = std::hypot(plane[plane.size() - 2], plane.back() - 1.6e-3);
    std::printf("[ tilted ] travel %.4g m, largest difference %.3g m\n", travel, worst);
    EXPECT_GT(travel, 3e-4);       // it did slide down
    EXPECT_LT(worst, 1e-6 * 1e-3); // within 1e-6 of the radius
}

TEST(MeshWall, RotatingPolylineMeetsAGrainFarFromItsCentre) {
    // As WallSearch.RotatingWallMeetsAGrainFarFromItsCentre, with the plane as a polyline: the
    // candidate list stays complete while the wall turns into the disc.
    const auto m = pipeline::build_scene(R"({"dimension": 2,
      "materials": {"m1": {"density": 1200, "youngs_modulus": 3.24e7}},
      "discretization": {"mesh_size": 1e-4, "horizon_factor": 3},
      "particles": [{"radius": 1e-3, "center": [10e-3, 1.5e-3], "material": "m1"}],
      "walls": [{"type": "mesh", "polyline": [[-20e-3, 0], [5e-3, 0], [20e-3, 0]],
                 "rotation_center": [0, 0], "angular_velocity": 1}],
      "contact": {"law": "node"}, "solver": {"final_time": 1}})",
                                         "t", quiet);
    const double rc = m.contact.front().radius;
    // A mesh wall is searched within R_c + skin (the skin is R_c here): nodes deeper behind it
    // are not pushed.
    const auto r = test::rotating_wall_sweep(m, [&](const solver::State& s, std::size_t i) {
        const double th = s.time; // 1 rad/s
        const double d = -std::sin(th) * s.x[3 * i] + std::cos(th) * s.x[3 * i + 1];
        return d < rc && d >= -2 * rc;
    });
    EXPECT_EQ(r.bad_step, -1) << r.got << " touching, " << r.want << " within R_c";
    EXPECT_GT(r.touched, 10);
}

/// A temporary folder holding a 3D scene and the two-triangle floor [-4, 4] mm^2 at z = 0 (normal
/// +z) as floor_ascii.stl and floor_binary.stl.
struct Floor3D {
    std::filesystem::path dir;
    Floor3D() {
        dir = std::filesystem::temp_directory_path() /
              fmt::format("pd_mesh_wall_{}", static_cast<long>(::getpid()));
        std::filesystem::create_directories(dir / "sub");
        const float t[2][9] = {{-4e-3f, -4e-3f, 0, 4e-3f, -4e-3f, 0, 4e-3f, 4e-3f, 0},
                               {-4e-3f, -4e-3f, 0, 4e-3f, 4e-3f, 0, -4e-3f, 4e-3f, 0}};
        std::ofstream a(dir / "floor_ascii.stl");
        a << "solid floor\n";
        for (const auto& f : t) {
            a << " facet normal 0 0 1\n  outer loop\n";
            for (int k = 0; k < 3; ++k)
                a << fmt::format("   vertex {} {} {}\n", f[3 * k], f[3 * k + 1], f[3 * k + 2]);
            a << "  endloop\n endfacet\n";
        }
        a << "endsolid floor\n";
        std::ofstream b(dir / "floor_binary.stl", std::ios::binary);
        char header[80] = "solid but binary";
        b.write(header, 80);
        const std::uint32_t n = 2;
        b.write(reinterpret_cast<const char*>(&n), 4);
        for (const auto& f : t) {
            const float normal[3] = {0, 0, 1};
            const std::uint16_t attr = 0;
            b.write(reinterpret_cast<const char*>(normal), 12);
            b.write(reinterpret_cast<const char*>(f), 36);
            b.write(reinterpret_cast<const char*>(&attr), 2);
        }
    }
    ~Floor3D() {
        std::error_code ec;
        std::filesystem::remove_all(dir, ec);
    }
    /// The scene with `wall`, as if read from <dir>/<sub>/scene.json.
    model::Model build(const std::string& wall, bool allow_outside = false,
                       const std::string& sub = "") const {
        return pipeline::build_scene(R"({"dimension": 3,
          "materials": {"m": {"density": 1200, "youngs_modulus": 3.24e7}},
          "discretization": {"mesh_size": 3e-4, "horizon_factor": 3},
          "shapes": {"ball": {"type": "sphere", "radius": 1e-3}},
          "particles": [{"shape": "ball", "center": [0, 0, 1.2e-3], "material": "m"}],
          "walls": [)" + wall + R"(], "contact": {"restitution": 0.5},
          "loading": {"gravity": [0, 0, -10]}, "solver": {"final_time": 1}})",
                                     (dir / sub / "scene.json").string(), quiet, 0, allow_outside);
    }
};

TEST(MeshWall, StlFilesAsciiAndBinaryGiveTheSameSurface) {
    const Floor3D f;
    const auto a = f.build(R"({"type": "mesh", "file": "floor_ascii.stl"})");
    const auto b = f.build(R"({"type": "mesh", "file": "floor_binary.stl"})");
    ASSERT_EQ(a.walls.size(), 1u);
    ASSERT_EQ(a.walls[0].shape, model::WallShape::mesh);
    EXPECT_EQ(a.walls[0].mesh->num_cells(), 2u);
    EXPECT_EQ(a.walls[0].mesh->points().size(), 12u); // 4 welded vertices
    ASSERT_EQ(a.walls[0].mesh->points().size(), b.walls[0].mesh->points().size());
    for (std::size_t k = 0; k < a.walls[0].mesh->points().size(); ++k) // binary: floats
        EXPECT_NEAR(a.walls[0].mesh->points()[k], b.walls[0].mesh->points()[k], 1e-9);
    EXPECT_EQ(a.walls[0].mesh->cells(), b.walls[0].mesh->cells());
    // Outside the scene's folder: refused unless allowed.
    const std::string outside = R"({"type": "mesh", "file": "../floor_ascii.stl"})";
    EXPECT_EQ(f.build(outside, true, "sub").walls[0].mesh->cells(), a.walls[0].mesh->cells());
    try {
        f.build(outside, false, "sub");
        ADD_FAILURE() << "a file outside the scene's folder was read";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("walls[0].file"), std::string::npos) << e.what();
    }
    std::ofstream(f.dir / "bad.stl") << "solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 "
                                        "0\n vertex 1 0 0\n vertex 2 0 0\n endloop\n endfacet\n"
                                        "endsolid x\n";
    try {
        f.build(R"({"type": "mesh", "file": "bad.stl"})");
        ADD_FAILURE() << "a degenerate triangle was accepted";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("degenerate"), std::string::npos) << e.what();
    }
}

TEST(MeshWall, RestingSphereCarriesItsWeightOnATwoTriangleFloor) {
    const Floor3D f;
    auto m = f.build(R"({"type": "mesh", "file": "floor_binary.stl"})");
    solver::Solver s(m);
    const double load = test::resting_reaction(s, 2);
    std::printf("[ sphere on STL floor ] reaction / weight %.6f (%zu nodes)\n", load, s.state().n);
    EXPECT_NEAR(load, 1.0, 0.01);
}

struct Balance {
    double energy = 0;   ///< largest |balance drift| / energy in play
    double momentum = 0; ///< largest |p - p0 - impulse| / (m g t)
    double push = 0;     ///< largest |wall force| / weight
};

/// A disc tumbling for 40 ms in a drum turning at 20 rad/s about its centre (gravity -10):
/// `wall` holds the disc. The energy balance (with the walls' work) and the momentum balance
/// p(t) - p(0) = sum dt (m g - F_wall) (trapezoidal, as velocity Verlet) must close.
Balance drum(const std::string& wall) {
    auto m = pipeline::build_scene(
        scene2d(R"({"radius": 1e-3, "center": [0, -2.5e-3], "material": "m1"})",
                R"("walls": [)" + wall + R"(], "contact": {},
                   "loading": {"gravity": [0, -10]})"),
        "t", quiet);
    solver::Solver s(m);
    s.set_dt(0.5 * s.stable_dt().limit);
    s.initialize();
    double mass = 0;
    for (std::size_t i = 0; i < s.state().n; ++i)
        mass += s.state().rho[i] * s.state().vol[i];
    const auto o0 = s.observe();
    s.end_interval();
    const double b0 = solver::energy_balance(o0);
    double scale = solver::energy_in_play(o0), worst_e = 0, worst_p = 0, push = 0;
    double impulse[2] = {0, 0}, prev[2] = {o0.wall_force[0], o0.wall_force[1]};
    const int steps = static_cast<int>(0.04 / s.dt());
    for (int k = 1; k <= steps; ++k) {
        s.advance();
        const auto o = s.observe();
        s.end_interval();
        const double g[2] = {0, -10 * mass};
        for (int d = 0; d < 2; ++d) {
            impulse[d] += s.dt() * (g[d] - 0.5 * (prev[d] + o.wall_force[d]));
            prev[d] = o.wall_force[d];
            worst_p = std::max(worst_p, std::abs(o.momentum[d] - o0.momentum[d] - impulse[d]) /
                                            (10 * mass * k * s.dt()));
        }
        scale = std::max(scale, solver::energy_in_play(o));
        push = std::max(push, std::hypot(o.wall_force[0], o.wall_force[1]) / (10 * mass));
        worst_e = std::max(worst_e, std::abs(solver::energy_balance(o) - b0));
    }
    return {worst_e / scale, worst_p, push};
}

TEST(MeshWall, RotatingDrumClosesTheEnergyAndMomentumBalances) {
    // The drum as a closed counter-clockwise 12-gon of radius 5 mm (grains inside), and the
    // analytic circle of the same radius.
    std::string poly;
    for (int k = 0; k < 12; ++k) {
        const double a = 2 * std::numbers::pi * k / 12;
        poly += fmt::format("{}[{}, {}]", k ? ", " : "", 5e-3 * std::cos(a), 5e-3 * std::sin(a));
    }
    const auto mesh = drum(R"({"type": "mesh", "closed": true, "angular_velocity": 20,
                               "rotation_center": [0, 0], "polyline": [)" +
                           poly + "]}");
    const auto circle = drum(R"({"type": "circle_inside", "center": [0, 0], "radius": 5e-3,
                                 "angular_velocity": 20})");
    std::printf("[ drum ] energy drift: mesh %.3g circle %.3g; momentum: mesh %.3g circle "
                "%.3g; largest wall force / weight: mesh %.3g circle %.3g\n",
                mesh.energy, circle.energy, mesh.momentum, circle.momentum, mesh.push, circle.push);
    EXPECT_GT(mesh.push, 1.0); // the drum did carry and throw the disc
    EXPECT_GT(circle.push, 1.0);
    EXPECT_LT(mesh.energy, 5e-3);
    EXPECT_LT(mesh.momentum, 1e-3);
    EXPECT_LT(circle.energy, 5e-3);
}

} // namespace
