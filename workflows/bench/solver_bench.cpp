// SPDX-License-Identifier: MIT
// Benchmark of pd-solve's hot paths, measured side by side in one run (ratios hold on a noisy
// machine, absolute times do not):
//   1. bond kernels: bond-updates per second per core, PMB and LPS, 2D plate and 3D box;
//   2. whole steps: node-steps per second and the share of contact in the step, on the two-disc
//      demo scene and on a dense 500-grain pack resting on walls;
//   3. scaling: time per node-step of a 2D PMB plate at 1e4, 1e5 and 1e6 nodes.
// Usage: solver_bench [--quick]   (quick: smaller sizes, for a smoke run)
#include "core/log.hpp"
#include "pipeline/scene.hpp"
#include "solver/solver.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace {

using namespace pd;
using Clock = std::chrono::steady_clock;
const Log quiet("bench", 0, Verbosity::quiet);

double since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string plate(double lx, double ly, double h, const std::string& law, int dim) {
    const std::string mat = law == "lps" ? R"("law": "lps", "poisson_ratio": 0.25, )" : "";
    const std::string size =
        dim == 2 ? fmt::format("[{}, {}]", lx, ly) : fmt::format("[{}, {}, {}]", lx, ly, ly);
    return fmt::format(R"({{"dimension": {},
      "materials": {{"m": {{{} "density": 1000, "youngs_modulus": 1e9, "fracture_energy": 1e3}}}},
      "discretization": {{"mesh_size": {}, "horizon_factor": 3}},
      "shapes": {{"p": {{"type": "{}", "size": {}, "mesh": "grid"}}}},
      "particles": [{{"shape": "p", "center": [0, 0{}], "material": "m",
                      "velocity": [1e-3, 0{}]}}],
      "solver": {{"final_time": 1}}}})",
                       dim, mat, h, dim == 2 ? "rectangle" : "box", size, dim == 3 ? ", 0" : "",
                       dim == 3 ? ", 0" : "");
}

/// Runs `steps` steps; returns wall seconds and fills the timer shares.
struct Run {
    double wall = 0, bonds_s = 0, contact_s = 0, nodes = 0, bonds = 0;
    int steps = 0;
};

Run run(const model::Model& m, int steps) {
    solver::Solver s(m);
    s.set_dt(0.7 * s.stable_dt().limit);
    s.initialize();
    s.advance(); // warm-up
    auto& T = s.timers();
    const double b0 = T.total(T.id("pd::solver::bond_forces"));
    const double c0 =
        T.total(T.id("pd::solver::contact_search")) + T.total(T.id("pd::solver::contact_forces")) +
        T.total(T.id("pd::solver::wall_contact")) + T.total(T.id("pd::solver::damping_friction"));
    const auto t0 = Clock::now();
    for (int k = 0; k < steps; ++k)
        s.advance();
    Run r;
    r.wall = since(t0);
    r.bonds_s = T.total(T.id("pd::solver::bond_forces")) - b0;
    r.contact_s = T.total(T.id("pd::solver::contact_search")) +
                  T.total(T.id("pd::solver::contact_forces")) +
                  T.total(T.id("pd::solver::wall_contact")) +
                  T.total(T.id("pd::solver::damping_friction")) - c0;
    r.nodes = static_cast<double>(m.nodes.num());
    r.bonds = static_cast<double>(m.bonds.num());
    r.steps = steps;
    return r;
}

std::string read(const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

} // namespace

int main(int argc, char** argv) {
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
    int threads = 1;
#ifdef _OPENMP
    threads = omp_get_max_threads();
#endif
    fmt::print("solver_bench: {} thread(s){}\n\n", threads, quick ? " (quick)" : "");

    fmt::print("## 1. Bond kernels (1 thread)\n\n");
    fmt::print("| law | dim | nodes | bonds | bonds/node | bond-updates/s per core |\n");
    fmt::print("|---|---|---|---|---|---|\n");
#ifdef _OPENMP
    omp_set_num_threads(1);
#endif
    for (const char* law : {"pmb", "lps"})
        for (int dim : {2, 3}) {
            const double h = dim == 2 ? (quick ? 2e-4 : 1e-4) : (quick ? 4e-4 : 2.5e-4);
            auto m = pipeline::build_scene(plate(3e-2, 1e-2, h, law, dim), "bench", quiet);
            const auto r = run(m, quick ? 20 : 50);
            fmt::print("| {} | {}D | {:.0f} | {:.0f} | {:.1f} | {:.3g} |\n", law, dim, r.nodes,
                       r.bonds, r.bonds / r.nodes, r.bonds * r.steps / r.bonds_s);
        }
#ifdef _OPENMP
    omp_set_num_threads(threads);
#endif

    fmt::print("\n## 2. Whole steps ({} threads)\n\n", threads);
    fmt::print("| scene | nodes | steps | node-steps/s | contact share of step |\n");
    fmt::print("|---|---|---|---|---|\n");
    const std::string src = PD_SOURCE_DIR;
    for (const auto& [name, file] : std::vector<std::pair<std::string, std::string>>{
             {"two discs (demo)", src + "/examples/two_discs/scene.json"},
             {"500-grain pack on walls", src + "/examples/pack500/scene.json"}}) {
        auto m = pipeline::build_scene(read(file), file, quiet);
        const auto r = run(m, quick ? 50 : 400);
        fmt::print("| {} | {:.0f} | {} | {:.3g} | {:.1f}% |\n", name, r.nodes, r.steps,
                   r.nodes * r.steps / r.wall, 100 * r.contact_s / r.wall);
    }

    fmt::print("\n## 3. Scaling: 2D PMB plate ({} threads)\n\n", threads);
    fmt::print("| nodes | steps | s per step | ns per node-step | ratio to 1e4 |\n");
    fmt::print("|---|---|---|---|---|\n");
    double base = 0;
    for (double n : quick ? std::vector<double>{1e4, 1e5} : std::vector<double>{1e4, 1e5, 1e6}) {
        const double h = std::sqrt(3e-2 * 1e-2 / n);
        auto m = pipeline::build_scene(plate(3e-2, 1e-2, h, "pmb", 2), "bench", quiet);
        const int steps = static_cast<int>(std::max(10.0, 2e7 / n));
        const auto r = run(m, steps);
        const double ns = 1e9 * r.wall / (r.nodes * r.steps);
        if (base == 0)
            base = ns;
        fmt::print("| {:.0f} | {} | {:.4g} | {:.1f} | {:.2f} |\n", r.nodes, r.steps,
                   r.wall / r.steps, ns, ns / base);
    }
    return 0;
}
