# SPDX-License-Identifier: MIT
"""The command line the examples' problem.py share (examples/*/problem.py): pack the folder's
scene in process, drive the run step by step from Python with a report between chunks (each
body's centre and mean velocity read from the numpy views, the observables), then pd-post on
the same file when the tool is found (PD_BIN_DIR, else PATH).

    problem.py [--quick] [--steps N] [--set PATH=VALUE ...] [--out DIR] [--threads T] [--no-post]

--quick stops after the example's CI-sized number of steps (`quick_steps`, or its `quick`
overrides); --steps N after N steps (pd-solve --steps N: a checkpoint is written, so
`pd-solve FILE --restart` continues the run from the shell)."""

import argparse
import os
import pathlib
import shutil
import subprocess
import time

import numpy as np

from . import Simulation, pack


def report(sim, bodies):
    """One line: time, kinetic energy, contacts, broken bonds; and per body (at most 4) its
    centre of mass and mean velocity, from the views."""
    o = sim.observe()
    line = "step %6d  t = %.4e s  KE = %.4e J  contacts %5d  broken %6d" % (
        sim.step_index, sim.time, o["kinetic_energy"], o["contact_count"], o["broken_bonds"])
    x, v, body = sim.positions, sim.velocities, sim.body
    for b in bodies:
        sel = body == b
        line += "\n    body %d: centre (%+.4e, %+.4e) m  v (%+.3e, %+.3e) m/s" % (
            b, x[sel, 0].mean(), x[sel, 1].mean(), v[sel, 0].mean(), v[sel, 1].mean())
    print(line, flush=True)
    return o


def main(doc, scene, quick=(), quick_steps=200, name=None, chunks=8, force_dt=False,
         argv=None):
    """Runs the example `scene` (a JSON path or a scene dict); `quick`: pd-pack --set overrides
    of --quick, `quick_steps`: its step count (None: run to the quick final time); `force_dt`:
    pd-solve --force-dt (the PeriDEM-parity scenes' dt is above pdgrain's estimate: README).
    Returns the closed Simulation's exit code (0 ok)."""
    ap = argparse.ArgumentParser(description=doc.strip().splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a CI-sized run")
    ap.add_argument("--steps", type=int, help="stop after this many steps")
    ap.add_argument("--set", action="append", default=[], help="pd-pack --set PATH=VALUE")
    ap.add_argument("--out", help="output folder (default out_<example>)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--no-post", action="store_true", help="skip pd-post")
    a = ap.parse_args(argv)
    name = name or pathlib.Path(scene).parent.name
    out = pathlib.Path(a.out or "out_" + name)
    out.mkdir(parents=True, exist_ok=True)
    sets = (list(quick) if a.quick else []) + a.set
    steps = a.steps or (quick_steps if a.quick else None)
    f = pack(scene, out / (name + ".h5"), sets=sets, overwrite=True)
    cpu = time.process_time()
    with Simulation(f, threads=a.threads, overwrite=True, max_steps=steps,
                    force_dt=force_dt) as sim:
        bodies = sorted(set(sim.body.tolist()))[:4]
        print("%s: %d nodes, %d bodies, dt = %.3e s, steps %d to %d" % (
            name, sim.num_nodes, len(set(sim.body.tolist())), sim.dt, sim.step_index,
            sim.last_step))
        o = report(sim, bodies)
        chunk = max(1, (sim.last_step - sim.step_index) // chunks)
        while not sim.finished:
            sim.step(chunk)
            o = report(sim, bodies)
        steps = sim.step_index
        code = sim.close()
    cpu = time.process_time() - cpu
    print("%s: %d steps in %.2f s of CPU (%.1f us per step), exit code %d" % (
        name, steps, cpu, 1e6 * cpu / max(1, steps), code))
    if np.isfinite(o["kinetic_energy"]) and not a.no_post:
        bin_dir = os.environ.get("PD_BIN_DIR")
        post = str(pathlib.Path(bin_dir) / "pd-post") if bin_dir else shutil.which("pd-post")
        if post:
            subprocess.run([post, os.fspath(f), "-o", str(out / "post"), "-q"], check=True)
            print("pd-post: %d files in %s" % (len(list((out / "post").iterdir())), out / "post"))
    return code
