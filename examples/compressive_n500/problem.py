#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""compressive_n500 quick from Python, in process (issue 30): scene_quick.json (29 grains settle,
then the plate enters at 14 ms and presses at 0.3 m/s) packed and run step by step as `make quick`
runs it (pd-solve --no-penetration-check), the plate's reaction stress read from the run between
steps, then the curve of the file checked against bounds_quick.json with reaction.py, as
`make quick` does.

    PYTHONPATH=build/python /usr/bin/python3 examples/compressive_n500/problem.py \\
        [--final-time T] [--out DIR] [--no-check]

--final-time T stops early (the check is then skipped: the curve is incomplete).
"""
import argparse
import json
import pathlib
import sys
import time

import numpy as np

import pdgrain

HERE = pathlib.Path(__file__).resolve().parent
LENGTH = 0.01462  # m: the loaded plate length (the quick box's inner width), as the Makefile


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true",
                    help="accepted (make quick-python): scene_quick.json is what this runs")
    ap.add_argument("--final-time", type=float, help="s (default: the scene's 27.5 ms)")
    ap.add_argument("--out", default="out_n500", help="output folder")
    ap.add_argument("--every", type=float, default=2.5e-4, help="s between printed rows")
    ap.add_argument("--no-check", action="store_true", help="skip the bounds_quick.json check")
    a = ap.parse_args()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    sets = ["solver.final_time=%r" % a.final_time] if a.final_time else []
    f = pdgrain.pack(HERE / "scene_quick.json", out / "quick.h5", sets=sets, overwrite=True)
    with f.h5() as h:
        names = [s.decode() if isinstance(s, bytes) else s for s in h["walls"].attrs["names"]]
        k = names.index("plate")
        t1, v = float(h["walls/start_time"][k]), float(-h["walls/velocity"][k][1])
    rows = []
    cpu = time.process_time()
    with pdgrain.Simulation(f, threads=1, overwrite=True, penetration_check=False) as sim:
        print("%d nodes, dt = %.3e s, %d steps; the plate enters at %.1f ms" % (
            sim.num_nodes, sim.dt, sim.last_step, t1 * 1e3))
        while not sim.finished:
            sim.run(until=min(sim.time + a.every, sim.last_step * sim.dt))
            o = sim.observe()
            fy = o["wall_force"][3 * k + 1]  # N per unit thickness, received by the plate
            pen = max(0.0, (sim.time - t1) * v)
            rows.append((sim.time, pen, fy / LENGTH, o["broken_bonds"], o["kinetic_energy"]))
            if sim.time >= t1:
                print("t = %6.2f ms  plate %5.3f mm  stress %7.2f kPa  broken bonds %6d" % (
                    sim.time * 1e3, pen * 1e3, fy / LENGTH / 1e3, o["broken_bonds"]))
        steps = sim.step_index
        code = sim.close()
    cpu = time.process_time() - cpu
    rows = np.array(rows)
    print("%d steps in %.1f s of CPU, exit code %d" % (steps, cpu, code))
    (out / "curve.json").write_text(json.dumps({
        "columns": ["t", "penetration", "stress", "broken_bonds", "kinetic_energy"],
        "rows": rows.tolist(), "cpu_seconds": cpu, "steps": steps}))
    if a.no_check or a.final_time:
        return 0
    # The file's curve (the observables pd-post and reaction.py read), checked as make quick.
    sys.path.insert(0, str(HERE))
    import reaction
    sys.argv = ["reaction.py", str(f), "-o", str(out / "quick_reaction.csv"), "--length",
                str(LENGTH), "--window", "1e-4", "--check", str(HERE / "bounds_quick.json")]
    return reaction.main()


if __name__ == "__main__":
    sys.exit(main())
