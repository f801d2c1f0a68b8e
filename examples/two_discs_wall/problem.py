#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""two_discs_wall (rigid floor) from Python, in process (issue 30): the scene_rigid.json scene
packed, then run step by step recording each disc's first bounce, the step at which its mean
vertical velocity turns upward, read from the numpy view (the step-driven record PeriDEM's
problem.py scripts keep, e.g. crack arrival times).

    PYTHONPATH=build/python /usr/bin/python3 examples/two_discs_wall/problem.py [--quick]
"""
import argparse
import pathlib

import pdgrain

HERE = pathlib.Path(__file__).resolve().parent
ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("--quick", action="store_true", help="the first 1 ms only (CI)")
ap.add_argument("--out", default="out_two_discs_wall", help="output folder")
args = ap.parse_args()
out = pathlib.Path(args.out)
out.mkdir(parents=True, exist_ok=True)

sets = ["solver.final_time=1.0e-3"] if args.quick else []
f = pdgrain.pack(HERE / "scene_rigid.json", out / "two_discs_wall.h5", sets=sets,
                 overwrite=True)
bounce = {}
with pdgrain.Simulation(f, threads=1, overwrite=True) as sim:
    v, body = sim.velocities, sim.body
    while not sim.finished:
        sim.step(10)
        for b in (0, 1):
            if b not in bounce and v[body == b, 1].mean() > 0:
                bounce[b] = sim.time
    for b in (0, 1):
        print("disc %d: bounces at t = %s" % (b, "%.4e s" % bounce[b] if b in bounce else "-"))
    print("end: t = %.4e s, step %d, mean vy %+.4f / %+.4f m/s" % (
        sim.time, sim.step_index, v[body == 0, 1].mean(), v[body == 1, 1].mean()))
assert bounce, "no disc bounced"
