#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The cost of driving a run from Python (issue 30): per step() call, against pd-solve's loop.

On a small scene (two_discs at mesh size 0.2 mm, 242 nodes), in one process: steps N+1..2N as N
calls step(1) against one call step(N) (same steps, same scheduled actions): the difference per call
is what a Python-driven step adds. Then pd-solve on the same file, its loop's time per step as
the difference of a 2N-step and an N-step run, for scale. CPU time throughout (the machine is
shared), best of --repeat.

    PYTHONPATH=build/python /usr/bin/python3 workflows/bench/python_step_overhead.py [--bin build/bin]
"""
import argparse
import os
import pathlib
import resource
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
        with pdgrain.Simulation(f, threads=1, overwrite=True, max_steps=2 * N) as sim:
            sim.step(N)  # steps 1..N untimed: the timed ones are N+1..2N, as pd-solve's below
            t0 = time.process_time()
            if chunk == 1:
                for _ in range(N):
                    sim.step(1)
            else:
                sim.step(N)
            best = min(best, time.process_time() - t0)
            n = sim.num_nodes
    return best / N, n


def empty_call():
    """A step(0) call: the binding, the GIL release and advance(0), no step (CPU s per call)."""
    with pdgrain.Simulation(f, threads=1, overwrite=True, max_steps=1) as sim:
        t0 = time.process_time()
        for _ in range(100000):
            sim.step(0)
        return (time.process_time() - t0) / 100000


one, n = timed(1)
many, _ = timed(N)


def cli_wall(steps):
    """pd-solve's CPU time (s, user + system of the child) for `steps` steps, set-up included."""
    best = float("inf")
    for _ in range(args.repeat):
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run([os.path.join(args.bin, "pd-solve"), str(f), "--overwrite", "--steps",
                        str(steps), "-q"], check=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        best = min(best, r1.ru_utime + r1.ru_stime - r0.ru_utime - r0.ru_stime)
    return best


# Per step of pd-solve's loop: the difference of a 2N-step and an N-step run (set-up cancels).
cli = (cli_wall(2 * N) - cli_wall(N)) / N
print("scene: two_discs at h = 0.2 mm, %d nodes, %d steps, 1 thread, best of %d" % (
    n, N, args.repeat))
print("pd-solve loop ((2N - N steps) / N):     %8.2f us/step" % (cli * 1e6))
print("Python step(N) once (/ N):              %8.2f us/step" % (many * 1e6))
print("Python step(1) N times:                 %8.2f us/step" % (one * 1e6))
print("a step(0) call (no step):               %8.2f us" % (empty_call() * 1e6))
print("overhead per step() call:               %8.2f us (%.1f %% of a step)" % (
    (one - many) * 1e6, 100 * (one - many) / many))
