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


def test_a_cut_disc_is_two_fragments(tmp_path):
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
