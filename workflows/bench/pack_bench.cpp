// SPDX-License-Identifier: MIT
// Benchmark of scene building for 2D grains: random packing (circles and hexagons 50/50, bounding
// radius 0.9-1.1 mm), meshing each reference shape once with gmsh (h = 0.2 mm, PeriDEM's n500
// meshes), and instancing every grain with place_instance. Prints one table row per size.
// Usage: pack_bench [max_grains = 100000]
#include "geometry/packing.hpp"
#include "mesh/discretize.hpp"
#include "mesh/shape_mesher.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <numbers>

namespace {

using namespace pd;
using Clock = std::chrono::steady_clock;
constexpr double mm = 1e-3;

double since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct Row {
    std::size_t grains = 0;
    double lx = 0, ly = 0, phi = 0;
    geometry::PackStats stats;
    double t_pack = 0, t_mesh = 0, t_place = 0;
    std::size_t nodes = 0;
};

Row run(std::size_t n) {
    Row row;
    row.grains = n;
    if (n == 500) { // PeriDEM's compressive test box (spec 8.3)
        row.lx = 68.5 * mm;
        row.ly = 41 * mm;
    } else { // square box for a packing fraction of 0.5 (E[r^2] = 0.98333 mm^2)
        row.lx = row.ly = std::sqrt(static_cast<double>(n) * std::numbers::pi * 0.98333 / 0.5) * mm;
    }
    const auto box = geometry::Shape::rectangle_corners(0, 0, row.lx, row.ly);
    geometry::PackOptions opt;
    opt.count = n;
    opt.rmin = 0.9 * mm;
    opt.rmax = 1.1 * mm;
    opt.fractions = {0.5, 0.5};
    opt.seed = 1;

    auto t0 = Clock::now();
    const auto grains = geometry::random_pack(box, opt, &row.stats);
    row.t_pack = since(t0);
    row.phi = row.stats.packing_fraction;

    t0 = Clock::now();
    const geometry::Shape refs[2] = {geometry::Shape::circle(1 * mm),
                                     geometry::Shape::hexagon(1 * mm)};
    const model::RefMesh meshes[2] = {mesh::mesh_shape(refs[0], 0.2 * mm),
                                      mesh::mesh_shape(refs[1], 0.2 * mm)};
    row.t_mesh = since(t0);

    t0 = Clock::now();
    std::size_t total = 0;
    for (const auto& g : grains)
        total += meshes[g.shape].nodes.size();
    std::vector<double> x;
    x.reserve(total);
    for (const auto& g : grains) {
        const auto s = static_cast<std::size_t>(g.shape);
        mesh::place_instance(meshes[s], g.orientation, g.radius / refs[s].bounding_radius(),
                             g.center, x);
    }
    row.t_place = since(t0);
    row.nodes = x.size() / 3;
    return row;
}

} // namespace

int main(int argc, char** argv) {
    const std::size_t max_grains = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 100000;
    fmt::print("pack_bench: 2D grains, circles + hexagons 50/50, r in [0.9, 1.1] mm, h = 0.2 mm\n");
    fmt::print("{:>7} {:>15} {:>6} {:>9} {:>7} {:>8} {:>9} {:>10} {:>9} {:>8} {:>9}\n", "grains",
               "box mm", "phi", "pack s", "rsa", "relaxed", "mesh s", "place s", "nodes", "MB",
               "total s");
    for (std::size_t n : {std::size_t{500}, std::size_t{10000}, std::size_t{100000}}) {
        if (n > max_grains)
            break;
        const Row r = run(n);
        fmt::print("{:>7} {:>7.1f}x{:<7.1f} {:>6.3f} {:>9.3f} {:>7} {:>8} {:>9.3f} {:>10.3f} "
                   "{:>9} {:>8.1f} {:>9.3f}\n",
                   r.grains, r.lx / mm, r.ly / mm, r.phi, r.t_pack, r.stats.placed_by_rsa,
                   r.stats.relaxed, r.t_mesh, r.t_place, r.nodes,
                   static_cast<double>(r.nodes) * 3 * sizeof(double) / 1e6,
                   r.t_pack + r.t_mesh + r.t_place);
    }
    return 0;
}
