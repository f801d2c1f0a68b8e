#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""examples/grain_crushing's strength sweep as a Slurm job array on the single-node Slurm of
test_slurm.py (its `slurm` fixture): sweep.py expand, sbatch --wait, then strength.py table on
the runs. By default the 0.4 mm grains with 4 seeds (a few seconds); PD_CRUSH_SWEEP=full runs
the example's whole sweep (3 sizes x 20 seeds, ~5 min of CPU) and, with PD_CRUSH_SWEEP_OUT=DIR,
keeps it there (the README's Slurm run)."""
import csv
import json
import os
import pathlib
import subprocess
import time

from test_slurm import BIN, SRC, SWEEP, slurm, tail  # noqa: F401 (the fixture)

EXAMPLE = pathlib.Path(SRC) / "examples" / "grain_crushing"


def sets(full):
    with open(EXAMPLE / "sweep_sets.csv", newline="") as fh:
        rows = [{k: json.loads(v) for k, v in r.items()} for r in csv.DictReader(fh)]
    return rows if full else [r for r in rows if r["particles[0].radius"] == 2e-4][:4]


def test_crushing_sweep_as_a_slurm_job_array(tmp_path, slurm):  # noqa: F811
    full = os.environ.get("PD_CRUSH_SWEEP") == "full"
    out = pathlib.Path(os.environ.get("PD_CRUSH_SWEEP_OUT", tmp_path / "sw")).resolve()
    env = dict(slurm, PD_BIN_DIR=os.path.abspath(BIN), OMP_NUM_THREADS="1")
    spec = tmp_path / "sweep.json"
    spec.write_text(json.dumps({"base": str(EXAMPLE / "scene.json"), "list": sets(full),
                                "solve_args": ["-q"], "slurm": {"time": "00:10:00"}}))
    r = subprocess.run(["/usr/bin/python3", SWEEP, "expand", str(spec), "-o", str(out)],
                       env=env, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    t0 = time.time()
    r = subprocess.run(["sbatch", "--wait", str(out / "slurm.sh")], env=env,
                       capture_output=True, text=True, timeout=3600 if full else 600)
    wall = time.time() - t0
    outs = "".join(tail(p, 5) for p in sorted((out / "runs").glob("slurm-*.out")))
    assert r.returncode == 0, r.stdout + r.stderr + outs
    n = len(list((out / "runs").glob("*/run.done")))
    print(f"sbatch --wait ({n}-task array on 2 CPUs): {wall:.1f} s; {r.stdout.strip()}")
    r = subprocess.run(["/usr/bin/python3", str(EXAMPLE / "strength.py"), "table", str(out),
                        "-o", str(out / "strength.csv"), "--md", str(out / "strength.md"),
                        "--png", str(out / "strength.png")], env=env, capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    print(r.stdout)
    rows = list(csv.DictReader(open(out / "strength.csv")))
    assert len(rows) == n == len(sets(full))
    assert all(row["crushed"] == "True" for row in rows), rows
    # every grain splits near the example's strength (seed 1 of 0.4 mm: 101 MPa, CoV 2 %)
    assert all(90e6 < float(row["sigma"]) < 125e6 for row in rows if float(row["d"]) < 5e-4)
