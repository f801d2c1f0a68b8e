#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""ellipse_on_tip from Python, in process (issue 30): both scenes (the ring as an LPS and as a
PMB solid) packed and run step by step, recording from the state between steps the peak of the
tip's reaction force and its time, the time of the first broken bond and the time the ring's
mean vertical velocity turns upward (its rebound), then pd-post on the files. (The ring starts
within the contact radius of the tip: contact pairs exist from t = 0.)

    PYTHONPATH=build/python /usr/bin/python3 examples/ellipse_on_tip/problem.py [--quick] \\
        [--steps N] [--scene lps|pmb] [--out DIR] [--json FILE]

--quick: the Makefile's quick runs (the first 1 ms: the impact and the first cracking are at
0.1-0.3 ms); --steps N stops each run after N steps.
"""
import argparse
import json
import os
import pathlib
import shutil
import subprocess
import sys

import pdgrain

HERE = pathlib.Path(__file__).resolve().parent


def run(scene, out, sets, steps, every):
    f = pdgrain.pack(HERE / ("scene_%s.json" % scene), out / ("%s.h5" % scene), sets=sets,
                     overwrite=True)
    rec = {"peak_force": 0.0, "peak_time": None, "first_break": None, "rebound": None}
    with pdgrain.Simulation(f, threads=1, overwrite=True, max_steps=steps) as sim:
        ring = sim.body == 0
        v = sim.velocities
        while not sim.finished:
            sim.step(every)
            o = sim.observe()
            fy = -o["body_force"][1]  # N per unit thickness, on the tip (body 1), downward
            if fy > rec["peak_force"]:
                rec["peak_force"], rec["peak_time"] = fy, sim.time
            if rec["rebound"] is None and v[ring, 1].mean() > 0:
                rec["rebound"] = sim.time
            if rec["first_break"] is None and o["broken_bonds"] > 0:
                rec["first_break"] = sim.time
        rec.update(time=sim.time, steps=sim.step_index, dt=sim.dt,
                   ring_vy=float(v[ring, 1].mean()), broken_bonds=int(o["broken_bonds"]),
                   max_damage=float(sim.damage[ring].max()), file=str(f))
        rec["exit_code"] = sim.close()
    fmt = lambda t: "-" if t is None else "%.4e s" % t  # noqa: E731
    print("%s ring: tip force peak %.1f N/m at %s, first broken bond %s, rebound %s; at t = "
          "%.4e s (%d steps) %d broken bonds, max damage %.3f, mean vy %+.4f m/s" % (
              scene.upper(), rec["peak_force"], fmt(rec["peak_time"]), fmt(rec["first_break"]),
              fmt(rec["rebound"]), rec["time"], rec["steps"], rec["broken_bonds"],
              rec["max_damage"], rec["ring_vy"]))
    return rec


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the first 1 ms (make quick)")
    ap.add_argument("--steps", type=int, help="stop each run after this many steps")
    ap.add_argument("--scene", choices=["lps", "pmb"], action="append")
    ap.add_argument("--every", type=int, default=5, help="steps between records")
    ap.add_argument("--out", default="out_ellipse_on_tip")
    ap.add_argument("--json", help="write the records here")
    a = ap.parse_args()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    sets = ["solver.final_time=1e-3"] if a.quick else []
    recs = {s: run(s, out, sets, a.steps, a.every) for s in a.scene or ["lps", "pmb"]}
    if a.json:
        pathlib.Path(a.json).write_text(json.dumps(recs, indent=1))
    bin_dir = os.environ.get("PD_BIN_DIR")
    post = str(pathlib.Path(bin_dir) / "pd-post") if bin_dir else shutil.which("pd-post")
    for s, r in recs.items():
        if post:
            subprocess.run([post, r["file"], "-o", str(out / ("post_" + s)), "-q"], check=True)
    return max(r["exit_code"] for r in recs.values())


if __name__ == "__main__":
    sys.exit(main())
