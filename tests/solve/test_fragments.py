#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Fragments: a disc cut through by a pre-crack is two fragments in every frame (the fragment
frame field from pd-solve), and pd-post's grains.csv counts them."""
import json
import os
import subprocess

import h5py
import numpy as np

BIN = os.environ.get("PD_BIN_DIR", "build/bin")


def solved_cut_disc(tmp_path):
    """A disc cut through by a pre-crack (two pieces) beside a whole one, solved 2 frames."""
    scene = {
        "dimension": 2,
        "materials": {"m": {"density": 1000, "youngs_modulus": 1e8, "fracture_energy": 10}},
        "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
        "particles": [{"radius": 1e-3, "center": [0, 0], "material": "m"},
                      {"radius": 1e-3, "center": [3e-3, 0], "material": "m"}],
        "cracks": [{"from": [-2e-3, 1e-5], "to": [2e-3, 1e-5]}],
        "solver": {"final_time": 2e-5, "output_interval": 1e-5},
    }
    sp = tmp_path / "cut.json"
    sp.write_text(json.dumps(scene))
    f = tmp_path / "cut.h5"
    subprocess.run([f"{BIN}/pd-pack", str(sp), "-o", str(f), "-q"], check=True)
    subprocess.run([f"{BIN}/pd-solve", str(f), "-q"], check=True)
    return f


def test_a_cut_disc_is_two_fragments(tmp_path):
    f = solved_cut_disc(tmp_path)
    with h5py.File(f, "r") as h:
        off = h["bodies/node_offsets"][:]
        frag = h["particles/nodes/fragment/value"]
        for k in range(frag.shape[0]):
            ids = frag[k]
            assert len(np.unique(ids[off[0]:off[1]])) == 2  # cut disc
            assert len(np.unique(ids[off[1]:off[2]])) == 1  # intact disc
            x0 = h["nodes/reference_position"][off[0]:off[1]]
            upper = ids[off[0]:off[1]][x0[:, 1] > 1e-5]
            assert len(np.unique(upper)) == 1  # the upper half is one fragment
    out = tmp_path / "post"
    subprocess.run([f"{BIN}/pd-post", str(f), "-o", str(out), "-q", "--no-vtu"], check=True)
    rows = [l for l in (out / "grains.csv").read_text().splitlines()
            if l and not l.startswith("#")]
    head = rows[0].split(",")
    body, frags, broken = head.index("body"), head.index("fragments"), head.index("broken_bonds")
    with h5py.File(f, "r") as h:
        cut = int(h["observables/broken_bonds/value"][-1])  # all in disc 0 (the pre-crack)
    assert cut > 0
    for r in rows[1:]:
        c = r.split(",")
        assert int(c[frags]) == (2 if c[body] == "0" else 1)
        assert int(c[broken]) == (cut if c[body] == "0" else 0)


def read_csv(path):
    """Header names and rows (lists of strings) of a pd-post CSV, comment lines dropped."""
    lines = [l for l in path.read_text().splitlines() if l and not l.startswith("#")]
    return lines[0].split(","), [l.split(",") for l in lines[1:]]


def test_fragments_csv_masses_ids_and_h5py_agree(tmp_path):
    """Issue 31: pd-post --fragments. The cut disc is two fragments of ids = the smallest node
    index of each half, the intact disc one; per frame and body the masses sum to the grain's
    mass (fines row included), with no fragment and with every piece a fine; psd.csv has one row
    per frame and B_r = 0 when nothing breaks after the first frame; workflows/analysis/
    fragments.py (h5py) gives the same rows."""
    import sys
    sys.path.insert(0, os.path.join(os.environ.get("PD_SOURCE_DIR", "."), "workflows",
                                    "analysis"))
    import fragments
    f = solved_cut_disc(tmp_path)
    with h5py.File(f, "r") as h:
        off = h["bodies/node_offsets"][:]
        vol = h["nodes/volume"][:]
        x0 = h["nodes/reference_position"][:]
        frames = h["particles/nodes/fragment/value"].shape[0]
        grain = [1000 * vol[off[b]:off[b + 1]].sum() for b in range(2)]
        lower = int(np.flatnonzero(x0[off[0]:off[1], 1] < 1e-5)[0])
        upper = int(np.flatnonzero(x0[off[0]:off[1], 1] > 1e-5)[0])
        py = [rows for _, _, rows, _ in fragments.frames(h, fines_nodes=10)]
    for fines, expect in ((10, {0: {lower, upper}, 1: {int(off[1])}}),
                          (10**6, {0: {-1}, 1: {-1}})):
        out = tmp_path / f"post{fines}"
        subprocess.run([f"{BIN}/pd-post", str(f), "-o", str(out), "-q", "--no-vtu", "--no-xdmf",
                        "--fragments", "--fines-nodes", str(fines)], check=True)
        head, rows = read_csv(out / "fragments.csv")
        col = {c: head.index(c) for c in head}
        steps = sorted({int(r[col["step"]]) for r in rows})
        assert len(steps) == frames
        for s in steps:
            for b in range(2):
                mine = [r for r in rows if int(r[col["step"]]) == s and int(r[col["body"]]) == b]
                assert {int(r[col["fragment"]]) for r in mine} == expect[b]
                mass = sum(float(r[col["mass"]]) for r in mine)
                assert abs(mass - grain[b]) <= 1e-12 * grain[b]
        if fines == 10:  # the h5py computation: the same rows in the same order
            flat = [r for fr in py for r in fr]
            assert len(flat) == len(rows)
            for p, r in zip(flat, rows):
                assert p["fragment"] == int(r[col["fragment"]])
                for k in ("mass", "diameter"):
                    assert abs(p[k] - float(r[col[k]])) <= 1e-12 * p[k]
                assert np.allclose(p["x"], [float(r[col[c]]) for c in "xyz"], rtol=1e-12)
        phead, prow = read_csv(out / "psd.csv")
        assert len(prow) == frames
        for r in prow:
            assert float(r[phead.index("B_r")]) == 0.0
