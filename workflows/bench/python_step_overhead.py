#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The cost of driving a run from Python (issue 30): per step() call, against pd-solve's loop.

On a small scene (two_discs at mesh size 0.2 mm), in one process: N steps as N calls step(1)
against one call step(N) (same steps, same scheduled actions): the difference per call is what a
Python-driven step adds. Then pd-solve on the same file for the same N steps (--steps N), wall
time per step from its own node-steps/s, for scale. Prints one table.

    PYTHONPATH=build/python /usr/bin/python3 workflows/bench/python_step_overhead.py [--bin build/bin]
"""
import argparse
import os
import pathlib
import re
import subprocess
import tempfile
import time

import pdgrain

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("--bin", default=os.environ.get("PD_BIN_DIR", "build/bin"))
ap.add_argument("--steps", type=int, default=2000)
ap.add_argument("--repeat", type=int, default=3)
args = ap.parse_args()
N = args.steps

tmp = pathlib.Path(tempfile.mkdtemp(prefix="pd-overhead-"))
scene = pdgrain.scene.two_discs().discretization(mesh_size=2.0e-4)
# Frames only at the end, so the loops compare stepping, not output.
scene.solver(final_time=1.0, output_interval=1.0, observe_every=100000)
f = pdgrain.pack(scene, tmp / "small.h5")


def timed(chunk):
    best = float("inf")
    for _ in range(args.repeat):
        with pdgrain.Simulation(f, threads=1, overwrite=True, max_steps=N) as sim:
            t0 = time.perf_counter()
            if chunk == 1:
                for _ in range(N):
                    sim.step(1)
            else:
                sim.step(N)
            best = min(best, time.perf_counter() - t0)
            n = sim.num_nodes
    return best / N, n


one, n = timed(1)
many, _ = timed(N)
cli = float("inf")
for _ in range(args.repeat):
    r = subprocess.run([os.path.join(args.bin, "pd-solve"), str(f), "--overwrite", "--steps",
                        str(N)], capture_output=True, text=True, env=dict(os.environ,
                                                                         OMP_NUM_THREADS="1"))
    m = re.search(r"([0-9.e+]+) node-steps/s", r.stdout)
    cli = min(cli, n / float(m.group(1)))
print("scene: two_discs at h = 0.2 mm, %d nodes, %d steps, 1 thread, best of %d" % (
    n, N, args.repeat))
print("pd-solve (whole run incl. set-up / N):  %8.2f us/step" % (cli * 1e6))
print("Python step(N) once (/ N):              %8.2f us/step" % (many * 1e6))
print("Python step(1) N times:                 %8.2f us/step" % (one * 1e6))
print("overhead per step() call:               %8.2f us (%.1f %% of a step)" % (
    (one - many) * 1e6, 100 * (one - many) / many))
