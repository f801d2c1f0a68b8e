#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Contact cost per step, node law against surface law, on the examples (issue 26 item 10).

    contact_cost.py BIN_DIR [--repeat 3] [--steps 400] [--work DIR] [--only NAME ...]
                    [--base OLD_BIN_DIR]

Each case is packed twice from its example folder (copied to WORK, so relative paths hold):
"node", the scene as shipped (PeriDEM's node-to-node law with the scene's factors), and
"surface", the same scene with `contact.law` "surface" and every contact radius and stiffness
factor removed (the surface law refuses them: its stiffness comes from the materials and the
mesh). Both solve the same number of steps at their own automatic dt, --repeat times,
interleaved, one thread; the process CPU time per step is that of a run of steps + 1 less that of
a run of 1 step (so start-up is not in it). Printed (Markdown): dt; per step, in ms of wall time (pd-solve's timers,
min and median over the runs): the contact search, the contact forces, the wall contact, the
damping and friction, the bonds and the whole step; the process CPU time (user + sys) per step;
and the cost per unit model time (CPU per step / dt), which is what a run pays. --base: also
the surface law solved by another build's pd-solve (rows "surface, base"; an A/B of a change).
"""
import argparse
import json
import os
import pathlib
import re
import resource
import shutil
import statistics
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[3]
# name: (folder, scene file in it, model time solved before the timed steps: 0 = from the start)
CASES = {
    "pack500": ("examples/pack500", "scene.json", 0),
    "compressive_small": ("examples/compressive_small", "scene.json", 0),
    "n500 quick": ("examples/compressive_n500", "scene_quick.json", 0),
    "box2d settled": ("workflows/bench/contact", "box2d.json", 0.03),
    "pour3d settled": ("workflows/bench/contact", "pour3d.json", 0.012),
}
TIMERS = {"search": "pd::solver::contact_search", "contact": "pd::solver::contact_forces",
          "walls": "pd::solver::wall_contact", "damping": "pd::solver::damping_friction",
          "bonds": "pd::solver::bond_forces"}
FACTOR_KEYS = ("stiffness_factor", "radius_factor", "radius_mesh_factor", "radius")


def strip_json_comments(text):
    return re.sub(r"^\s*//.*$", "", text, flags=re.M)


def surface_scene(scene):
    """The scene on the surface law: factors and radii removed, globally and per pair."""
    c = scene.setdefault("contact", {})
    c["law"] = "surface"
    for holder in [c, *c.get("pairs", [])]:
        for k in FACTOR_KEYS:
            holder.pop(k, None)
    return scene


def solve(bin_dir, packed, run, steps):
    shutil.copyfile(packed, run)
    restart = ["--restart"] if settled(packed) else []
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMP_", "GOMP_"))}
    env["OMP_NUM_THREADS"] = "1"
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    r = subprocess.run([str(bin_dir / "pd-solve"), str(run), *restart, "--steps", str(steps),
                        "--no-penetration-check", "--energy-tolerance", "0"],
                       env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        sys.exit(f"pd-solve {run}: exit {r.returncode}\n{r.stderr[-2000:]}")
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    out = {"cpu": cpu, "wall": wall}
    text = r.stdout + r.stderr
    for key, label in TIMERS.items():
        m = re.search(re.escape(label) + r"\s+(\d+)\s+([0-9.eE+-]+)", text)
        out[key] = float(m.group(2)) if m else 0.0
    m = re.search(r"dt = ([0-9.eE+-]+) s", text)
    out["dt"] = float(m.group(1)) if m else float("nan")
    return out


def settled(h5):
    return h5.with_suffix(".settled").exists()


def settle(bin_dir, h5, t):
    """Solves h5 to t (not timed); the timed runs restart from its last checkpoint."""
    subprocess.run([str(bin_dir / "pd-solve"), str(h5), "--final-time", str(t), "-q",
                    "--no-penetration-check", "--energy-tolerance", "0"], check=True)
    h5.with_suffix(".settled").touch()


def row(name, law, runs, steps):
    med = lambda k: statistics.median(r[k] for r in runs) / steps * 1e3
    lo = lambda k: min(r[k] for r in runs) / steps * 1e3
    cells = [f"{lo(k):.3f} / {med(k):.3f}" for k in ("search", "contact", "walls", "damping",
                                                     "bonds")]
    dt = runs[0]["dt"]
    cpu_step = statistics.median(r["cpu"] for r in runs) / steps
    return (f"| {name} | {law} | {dt:.4g} | " + " | ".join(cells) +
            f" | {lo('cpu'):.3f} / {med('cpu'):.3f} | {cpu_step / dt * 1e-3:.4g} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("bin", type=pathlib.Path)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--steps", type=int, default=400)
    ap.add_argument("--work", type=pathlib.Path, default=pathlib.Path("/tmp/pd_contact_bench"))
    ap.add_argument("--only", nargs="*")
    ap.add_argument("--base", type=pathlib.Path)
    a = ap.parse_args()
    a.bin = a.bin.resolve()
    bins = {"node": a.bin, "surface": a.bin}
    if a.base:
        bins["surface, base"] = a.base.resolve()
    print(f"nproc {os.cpu_count()}, load average {os.getloadavg()[0]:.2f}, {a.steps} steps, "
          f"{a.repeat} runs, 1 thread")
    print("\n| case | law | dt (s) | search | contact forces | walls | damping, friction "
          "| bonds | CPU per step | CPU s per model ms |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, (folder, scene_name, t_settle) in CASES.items():
        if a.only and not any(o in name for o in a.only):
            continue
        work = a.work / name.split()[0]
        shutil.rmtree(work, ignore_errors=True)
        shutil.copytree(ROOT / folder, work)
        scene = json.loads(strip_json_comments((work / scene_name).read_text()))
        (work / "scene_surface.json").write_text(json.dumps(surface_scene(scene), indent=1))
        packed = {}
        for law, file in (("node", scene_name), ("surface", "scene_surface.json")):
            packed[law] = work / f"{law}.h5"
            subprocess.run([str(a.bin / "pd-pack"), str(work / file), "-o", str(packed[law]),
                            "-q"], check=True)
            if t_settle > 0:
                settle(a.bin, packed[law], t_settle)
        runs = {label: [] for label in bins}
        for _ in range(a.repeat):
            for label, bin_dir in bins.items():
                h5 = packed[label.split(",")[0]]
                # CPU per step: a run of steps + 1 less a run of 1 step (start-up aside)
                one = solve(bin_dir, h5, work / "run.h5", 1)
                r = solve(bin_dir, h5, work / "run.h5", a.steps + 1)
                r["cpu"] -= one["cpu"]
                runs[label].append(r)
        for label in bins:
            print(row(name, label, runs[label], a.steps), flush=True)


if __name__ == "__main__":
    main()
