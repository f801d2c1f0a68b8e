// SPDX-License-Identifier: MIT
// pdgrain as a library: pack a scene, then run it through pipeline::Simulation, reading the
// solver's state between steps. Usage: consumer SCENE.json OUT.h5
#include "core/tool.hpp"
#include "pipeline/pack.hpp"
#include "pipeline/simulation.hpp"
#include "solver/solver.hpp"

#include <cstdio>

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: consumer SCENE.json OUT.h5\n");
        return 2;
    }
    pd::CommonOptions common;
    common.quiet = true;
    return pd::run_tool("consumer", argc, argv, common, [&](pd::Context& ctx) {
        pd::pipeline::PackOptions pack;
        pack.scene = argv[1];
        pack.output = argv[2];
        pack.sets = {"solver.final_time=2e-5"};
        pd::pipeline::pack(pack, ctx);

        pd::pipeline::SolveOptions solve;
        solve.file = argv[2];
        pd::pipeline::Simulation sim(solve, ctx);
        const auto& st = sim.solver().state();
        double vx0 = st.v[0];
        while (!sim.finished())
            sim.advance(10);
        std::printf("nodes %zu steps %lld t %.6e vx0 %.6e -> %.6e\n", st.n,
                    static_cast<long long>(sim.step()), st.time, vx0, st.v[0]);
        sim.close();
    });
}
