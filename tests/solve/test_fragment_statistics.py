#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Fragment statistics checked (issue 31 item 5) on a grain that really breaks: the crushing
example's quick run (a flawed disc between platens, split in two halves and fines by 42 us).
At every frame the fragments' masses sum to the grain's mass, and fragments.csv / psd.csv are
the same, fragment ids included, at 1 and 2 MPI ranks (the grain split between the ranks)."""
import csv
import os
import pathlib
import shutil
import subprocess

import h5py
import numpy as np

BIN = pathlib.Path(os.environ.get("PD_BIN_DIR", "build/bin"))
REPO = pathlib.Path(__file__).resolve().parents[2]
MPIRUN = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", "2"]


def rows(path):
    with open(path) as f:
        return [r for r in csv.reader(l for l in f if not l.startswith("#"))]


def solved(tmp_path, ranks):
    f = tmp_path / f"crush_{ranks}.h5"
    subprocess.run([BIN / "pd-pack", REPO / "examples" / "grain_crushing" / "scene.json", "-o", f,
                    "-q", "--set", "solver.final_time=4.2e-5"], check=True)
    cmd = [BIN / "pd-solve", f, "-q"]
    if ranks == 2:
        subprocess.run([BIN / "pd-partition", f, "-n", "2", "-q"], check=True)
        cmd = MPIRUN + cmd
    subprocess.run(cmd, check=True)
    out = tmp_path / f"post_{ranks}"
    subprocess.run([BIN / "pd-post", f, "-o", out, "-q", "--no-vtu", "--no-xdmf", "--fragments"],
                   check=True)
    return f, out


def test_fragment_masses_and_ids_at_one_and_two_ranks(tmp_path):
    if not shutil.which("mpirun"):
        raise RuntimeError("mpirun missing")
    f1, p1 = solved(tmp_path, 1)
    f2, p2 = solved(tmp_path, 2)
    for name in ("fragments.csv", "psd.csv"):
        assert rows(p1 / name) == rows(p2 / name), name
    with h5py.File(f1, "r") as h:
        off = h["bodies/node_offsets"][()]
        rho = h["materials"][next(iter(h["materials"]))]["density"][()]
        grain = rho * h["nodes/volume"][off[0]:off[1]].sum()
    table = rows(p1 / "fragments.csv")
    head, data = table[0], table[1:]
    step, mass = head.index("step"), head.index("mass")
    per_frame = {}
    for r in data:
        per_frame.setdefault(r[step], []).append(float(r[mass]))
    assert len(per_frame) >= 5
    for s, masses in per_frame.items():
        assert abs(sum(masses) - grain) <= 1e-12 * grain, s
    last = sorted(per_frame[max(per_frame, key=int)], reverse=True)
    assert len(last) >= 3 and last[1] > 0.4 * grain  # two halves and fines
    assert np.isclose(sum(last[2:]), grain - last[0] - last[1])
