#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""two_discs from Python, in process (issue 30): the scene built with pdgrain.scene, packed, run
step by step with the discs' mean velocities read from the numpy view as the run advances, a
cut through the left disc, then pd-post on the same file.

    PYTHONPATH=build/python /usr/bin/python3 examples/two_discs/problem.py [--quick] [--out DIR]
"""
import argparse
import os
import pathlib
import shutil
import subprocess

import pdgrain

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("--quick", action="store_true", help="the first 0.4 ms only (CI)")
ap.add_argument("--out", default="out_two_discs", help="output folder")
args = ap.parse_args()
out = pathlib.Path(args.out)
out.mkdir(parents=True, exist_ok=True)

scene = pdgrain.scene.two_discs()  # = examples/two_discs/scene.json
if args.quick:
    scene.solver(final_time=4.0e-4)
f = pdgrain.pack(scene, out / "two_discs.h5", overwrite=True)

with pdgrain.Simulation(f, threads=1, overwrite=True) as sim:
    v, body = sim.velocities, sim.body  # views: they follow the run
    print("%d nodes, dt = %.3e s, %d steps" % (sim.num_nodes, sim.dt, sim.last_step))
    while sim.step_index < sim.last_step and sim.time < 3.5e-4:  # into the impact (0.3 ms)
        sim.step(100)
        print("step %4d  t = %.3e s  mean vx: left %+.4f  right %+.4f m/s" % (
            sim.step_index, sim.time, v[body == 0, 0].mean(), v[body == 1, 0].mean()))
    c = -1.15e-3  # the left disc's centre line
    print("cut through the left disc: %d bonds" % sim.break_bonds(segment=([c, -2e-3], [c, 2e-3])))
    sim.run()  # to the final time
    o = sim.observe()
    print("t = %.3e s: KE = %.4e J, broken bonds %d, max damage %.3f" % (
        sim.time, o["kinetic_energy"], o["broken_bonds"], sim.damage.max()))

# The same file through pd-post (the tools from PD_BIN_DIR, else PATH).
bin_dir = os.environ.get("PD_BIN_DIR")
post = str(pathlib.Path(bin_dir) / "pd-post") if bin_dir else shutil.which("pd-post")
if post:
    subprocess.run([post, os.fspath(f), "-o", str(out / "post"), "-q"], check=True)
    print("pd-post:", sorted(p.name for p in (out / "post").iterdir())[:4], "...")
