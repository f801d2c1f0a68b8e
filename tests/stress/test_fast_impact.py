#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Fast impacts on the surface law's defaults (issue 26 item 3): a PMB disc (R = 1 mm, E = 32.4
MPa, rho = 1200, unbreakable, Mach 0.03 / 0.12 / 0.30 of sqrt(K / rho) = 164 m/s) thrown at 5,
20 and 50 m/s onto a rigid wall and onto an equal disc at rest, at h = 0.1, 0.05 and 0.025 mm
(gmsh, delta = 3 h). The scene names no contact law and no factor: the stiffness follows the
scene's speed (lib/pipeline/scene/contact_speed.cpp). Each run must exit 0 (no guard: no node
more than h/2 behind a boundary or through the wall at any step), pass check_run.py (its
exact 2D depth behind the other disc's boundary within h/2, the energy balance within 2 %), and
this file measures the deepest node itself from the frames (behind the wall, or behind the other
disc's deformed boundary polygon) against h_min/2, h_min the disc's smallest node spacing (the
guard's h)."""
import json
import os
import pathlib
import subprocess

import h5py
import numpy as np
import pytest

import check_run

BIN = pathlib.Path(os.environ.get("PD_BIN_DIR", "build/bin"))
pytestmark = pytest.mark.skipif(not (BIN / "pd-solve").is_file(),
                                reason="PD_BIN_DIR has no pd-solve")

R = 1e-3
M1 = {"law": "pmb", "density": 1200, "youngs_modulus": 3.24e7, "fracture_energy": 0}
# Measured on s19-impact (deepest node / (h_min / 2), h_min = 0.71 h): the 50 m/s runs are not
# held yet. On the wall the stiffness (18.5 kappa / h^2) holds every node within 0.53-0.57 h_min/2
# but the contact, stiff at 0.85 x its stable step, leaves the balance 3.6-5.0 % off (the guard
# stops h at 5 %); two discs at 50 m/s (M = 0.3, 30 % strain in an unbreakable PMB disc) fold
# their contact edges, nodes there reach 50-75 m/s and one slips 0.16 mm behind the other's
# boundary at t = 14-21 us whatever the stiffness (tried up to 80 kappa / h^2).
XFAIL = {("wall", 50): "balance 3.6-5 % at 50 m/s (stiff contact at 0.85 x its step)",
         ("disc", 50): "two discs at 50 m/s: the folding contact edge lets a node through"}


def scene(kind, speed, h):
    gap = 0.2 * h
    T = gap / speed + 8e-5
    s = {"dimension": 2, "materials": {"m": M1},
         "discretization": {"mesh_size": h, "horizon_factor": 3},
         "solver": {"final_time": T, "output_interval": T / 200}}
    if kind == "wall":
        s["particles"] = [{"radius": R, "center": [0, R + gap], "material": "m",
                           "velocity": [0, -speed]}]
        s["walls"] = [{"name": "floor", "type": "plane", "point": [0, 0], "normal": [0, 1]}]
    else:
        s["particles"] = [{"radius": R, "center": [0, 0], "material": "m"},
                          {"radius": R, "center": [0, 2 * R + gap], "material": "m",
                           "velocity": [0, -speed]}]
    return s


def deepest(path, kind):
    """The deepest node over the frames (m) and the smallest node spacing h_min (m)."""
    with h5py.File(path, "r") as f:
        model = check_run.Model(f)
        pos = f["particles/nodes/position/value"]
        worst = 0.0
        for k in range(pos.shape[0]):
            y = pos[k]
            if kind == "wall":
                worst = max(worst, -float(y[:, 1].min()))
                continue
            for a, b in ((0, 1), (1, 0)):
                sl = model.body_nodes(a)
                d = check_run.polygon_depth(model.boundary_edges(b), y, y[sl])
                worst = max(worst, float(d.max()))
        return worst, float(model.h.min())


CASES = [(k, v, h) for k in ("wall", "disc") for v in (5, 20, 50) for h in (1e-4, 5e-5, 2.5e-5)]


@pytest.mark.parametrize("kind,speed,h", [
    pytest.param(k, v, h, id="%s_%dms_h%g" % (k, v, h * 1e3),
                 marks=[pytest.mark.xfail(strict=False, reason=XFAIL[(k, v)])]
                 if (k, v) in XFAIL else []) for k, v, h in CASES])
def test_fast_impact(kind, speed, h, tmp_path):
    src = tmp_path / "scene.json"
    src.write_text(json.dumps(scene(kind, speed, h)))
    out = tmp_path / "run.h5"
    r = subprocess.run([str(BIN / "pd-pack"), str(src), "-o", str(out), "-q"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    r = subprocess.run([str(BIN / "pd-solve"), str(out), "-q"], capture_output=True, text=True)
    assert r.returncode == 0, "pd-solve exit %d: %s" % (r.returncode, r.stderr[-1500:])
    bad = check_run.failed(check_run.check_file(out))
    assert not bad, "\n".join(c.line() for c in bad)
    depth, h_min = deepest(out, kind)
    assert depth <= 0.5 * h_min, "deepest node %.3g m, h_min/2 = %.3g m" % (depth, 0.5 * h_min)
    if kind == "wall":  # the disc came back up: it neither stuck nor passed
        with h5py.File(out, "r") as f:
            p = f["observables/momentum/value"][()]
        assert p[-1][1] > 0, "the disc did not rebound: momentum %s" % p[-1]
