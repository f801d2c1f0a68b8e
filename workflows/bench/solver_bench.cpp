// SPDX-License-Identifier: MIT
// Benchmark of pd-solve's hot paths, in CPU time so that it holds on a shared machine: a figure
// is the best (min time) and the median of several runs, and the side-by-side ratios come from
// runs interleaved in one process.
//   1. bond kernels: bond-updates per second per core (thread CPU time, 1 thread), PMB and LPS,
//      2D plate and 3D box, energies summed (as on observation steps) and not (the other
//      steps), and the naive PMB loop of before issue 15 built in this binary;
//   2. whole steps: node-steps per second (per process CPU second, and per wall second) at 1 and
//      2 threads, and the share of a step spent outside the bond and contact loops;
//   3. scaling: CPU time per node-step of a 2D PMB plate from 1e4 nodes up.
// Usage: solver_bench [--quick] [--runs N] [--kernels]
//   (quick: smaller sizes, for a smoke run; kernels: section 1 only)
#include "core/log.hpp"
#include "pipeline/scene.hpp"
#include "solver/solver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace {

using namespace pd;
const Log quiet("bench", 0, Verbosity::quiet);

double clock_of(clockid_t id) {
    timespec t{};
    clock_gettime(id, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
double thread_cpu() {
    return clock_of(CLOCK_THREAD_CPUTIME_ID);
}
double process_cpu() {
    return clock_of(CLOCK_PROCESS_CPUTIME_ID);
}
double wall() {
    return clock_of(CLOCK_MONOTONIC);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const auto n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
double least(const std::vector<double>& v) {
    return *std::min_element(v.begin(), v.end());
}

void set_threads(int t) {
#ifdef _OPENMP
    omp_set_num_threads(t);
#else
    (void)t;
#endif
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

std::string read(const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

/// A solver a few steps into the motion (bonds stretched), energies as pd-solve computes them.
struct Warm {
    explicit Warm(const model::Model& m)
        : s(m) {
        s.set_dt(0.7 * s.stable_dt().limit);
        s.initialize();
        for (int k = 0; k < 3; ++k)
            s.advance();
    }
    solver::Solver s;
};

/// Whole steps: seconds of process CPU and wall for `steps` steps (energies every 10th step,
/// as pd-solve's default observation interval), and the step's share outside the bond and
/// contact loops (timers of the same run).
struct Steps {
    double cpu = 0, wall = 0, other = 0;
};
Steps run_steps(solver::Solver& s, int steps) {
    auto& T = s.timers();
    auto loops = [&] {
        double t = 0;
        for (const char* name : {"pd::solver::bond_forces", "pd::solver::contact_search",
                                 "pd::solver::contact_forces", "pd::solver::wall_contact"})
            t += T.total(T.id(name));
        return t;
    };
    const double l0 = loops(), c0 = process_cpu(), w0 = wall();
    for (int k = 0; k < steps; ++k) {
        s.set_energies(k % 10 == 0);
        s.advance();
    }
    Steps r;
    r.cpu = process_cpu() - c0;
    r.wall = wall() - w0;
    r.other = 1.0 - (loops() - l0) / r.wall;
    return r;
}

} // namespace

int main(int argc, char** argv) {
    bool quick = false, kernels_only = false;
    int runs = 5;
    for (int a = 1; a < argc; ++a) {
        if (std::strcmp(argv[a], "--quick") == 0)
            quick = true;
        else if (std::strcmp(argv[a], "--kernels") == 0)
            kernels_only = true;
        else if (std::strcmp(argv[a], "--runs") == 0 && a + 1 < argc)
            runs = std::max(1, std::atoi(argv[++a]));
    }
    fmt::print("solver_bench{}: {} runs per figure, best (min CPU time) / median\n\n",
               quick ? " (quick)" : "", runs);

    fmt::print("## 1. Bond kernels (1 thread, thread CPU time)\n\n");
    fmt::print("| law | dim | nodes | bonds | bonds/node | bond-updates/s per core | naive loop "
               "(before issue 15) | ratio (best) | without energies |\n");
    fmt::print("|---|---|---|---|---|---|---|---|---|\n");
    set_threads(1);
    for (const char* law : {"pmb", "lps"})
        for (int dim : {2, 3}) {
            const double h = dim == 2 ? (quick ? 2e-4 : 1e-4) : (quick ? 8e-4 : 5e-4);
            const auto m = pipeline::build_scene(plate(3e-2, 1e-2, h, law, dim), "bench", quiet);
            Warm w(m);
            const double bonds = static_cast<double>(m.bonds.num());
            const int calls = std::max(2, static_cast<int>((quick ? 2e7 : 2e8) / bonds));
            const bool naive = std::strcmp(law, "pmb") == 0;
            std::vector<double> rate, rate_ref, rate_noe;
            for (int r = 0; r < runs; ++r) { // interleaved
                double t0 = thread_cpu();
                for (int c = 0; c < calls; ++c)
                    w.s.bond_forces_only();
                rate.push_back(bonds * calls / (thread_cpu() - t0));
                if (naive) {
                    t0 = thread_cpu();
                    for (int c = 0; c < calls; ++c)
                        w.s.bond_forces_only(true);
                    rate_ref.push_back(bonds * calls / (thread_cpu() - t0));
                }
                // The kernels of the steps that sum no energy (9 of 10 by default).
                w.s.set_energies(false);
                t0 = thread_cpu();
                for (int c = 0; c < calls; ++c)
                    w.s.bond_forces_only();
                rate_noe.push_back(bonds * calls / (thread_cpu() - t0));
                w.s.set_energies(true);
            }
            const double best = *std::max_element(rate.begin(), rate.end());
            std::string ref = "-", ratio = "-";
            if (naive) {
                const double best_ref = *std::max_element(rate_ref.begin(), rate_ref.end());
                ref = fmt::format("{:.3g} / {:.3g}", best_ref, median(rate_ref));
                ratio = fmt::format("{:.2f}", best / best_ref);
            }
            fmt::print("| {} | {}D | {} | {:.0f} | {:.1f} | {:.3g} / {:.3g} | {} | {} | {:.3g} / "
                       "{:.3g} |\n",
                       law, dim, m.nodes.num(), bonds, bonds / static_cast<double>(m.nodes.num()),
                       best, median(rate), ref, ratio,
                       *std::max_element(rate_noe.begin(), rate_noe.end()), median(rate_noe));
        }

    if (kernels_only)
        return 0;
    fmt::print("\n## 2. Whole steps (process CPU time; wall for reference)\n\n");
    fmt::print("| scene | nodes | threads | steps | node-steps per CPU s | node-steps per wall s "
               "| share of the step outside bond and contact loops |\n");
    fmt::print("|---|---|---|---|---|---|---|\n");
    const std::string src = PD_SOURCE_DIR;
    for (const auto& [name, file, steps] : std::vector<std::tuple<std::string, std::string, int>>{
             {"two discs (demo)", src + "/examples/two_discs/scene.json", 2000},
             {"compressive_small", src + "/examples/compressive_small/scene.json", 1000},
             {"pack500", src + "/examples/pack500/scene.json", 100}}) {
        const auto m = pipeline::build_scene(read(file), file, quiet);
        const int n = quick ? std::max(10, steps / 10) : steps;
        for (int threads : {1, 2}) {
            set_threads(threads);
            std::vector<double> cpu, wl, other;
            for (int r = 0; r < runs; ++r) {
                Warm w(m); // every run the same steps (continuing one solver, the later runs
                           // were another phase of the motion: 3x between min and median)
                const auto st = run_steps(w.s, n);
                cpu.push_back(st.cpu);
                wl.push_back(st.wall);
                other.push_back(st.other);
            }
            const double ns = static_cast<double>(m.nodes.num()) * n;
            fmt::print("| {} | {} | {} | {} | {:.3g} / {:.3g} | {:.3g} / {:.3g} | {:.1f}% |\n",
                       name, m.nodes.num(), threads, n, ns / least(cpu), ns / median(cpu),
                       ns / least(wl), ns / median(wl), 100 * median(other));
        }
    }

    fmt::print("\n## 3. Scaling: 2D PMB plate (1 thread, process CPU time)\n\n");
    fmt::print("| nodes | steps | CPU s per step | ns per node-step | ratio to the first |\n");
    fmt::print("|---|---|---|---|---|\n");
    set_threads(1);
    double base = 0;
    for (double n : quick ? std::vector<double>{1e4, 1e5} : std::vector<double>{1e4, 1e5, 1e6}) {
        const double h = std::sqrt(3e-2 * 1e-2 / n);
        const auto m = pipeline::build_scene(plate(3e-2, 1e-2, h, "pmb", 2), "bench", quiet);
        Warm w(m);
        const int steps = static_cast<int>(std::max(5.0, 2e6 / n));
        std::vector<double> cpu;
        for (int r = 0; r < std::min(runs, 3); ++r)
            cpu.push_back(run_steps(w.s, steps).cpu);
        const double ns = 1e9 * least(cpu) / (static_cast<double>(m.nodes.num()) * steps);
        if (base == 0)
            base = ns;
        fmt::print("| {} | {} | {:.4g} | {:.1f} | {:.2f} |\n", m.nodes.num(), steps,
                   least(cpu) / steps, ns, ns / base);
    }
    return 0;
}
