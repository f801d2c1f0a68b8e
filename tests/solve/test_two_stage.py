#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Two-stage runs with a wall's start_time (pd-file 1.3): a disc settles on a floor; a plate that
enters at t1 = 2 ms, 0.2 mm above the disc's top (where no grain may be at t = 0), touches
nothing before t1, then moves down at 0.5 m/s and meets the disc when its travel closes the gap:
its reaction is exactly zero before contact and positive after; pd-post's walls.csv gives its
displacement as velocity * (t - t1); the same plate without start_time is refused by pd-pack
(the disc starts behind it)."""
import csv
import json
import os
import subprocess

import h5py
import numpy as np
import pytest

BIN = os.environ.get("PD_BIN_DIR", "build/bin")
R, RC, GAP, T1, V = 1e-3, 0.95 * 2e-4, 4e-4, 2e-3, 0.5
PLATE_Y = 2 * R + RC + GAP  # the disc rests on the floor (the node law: about RC above it)


def scene(start_time=T1):
    plate = {"name": "plate", "type": "plane", "point": [0, PLATE_Y], "normal": [0, -1],
             "velocity": [0, -V]}
    if start_time is not None:
        plate["start_time"] = start_time
    return {
        "dimension": 2,
        "materials": {"m1": {"law": "pmb", "density": 1200, "youngs_modulus": 3.24e7,
                             "fracture_energy": 50}},
        "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
        # the disc starts 0.8 mm up, across the plate's entry point: it must fall first
        "particles": [{"radius": R, "center": [0, R + 8e-4], "material": "m1"}],
        "walls": [{"name": "floor", "type": "plane", "point": [0, 0], "normal": [0, 1]}, plate],
        "contact": {"restitution": 0.5},
        "loading": {"gravity": [0, -1000], "viscous_damping": 2000},  # at rest by t1
        "solver": {"final_time": 3.4e-3, "output_interval": 2e-4, "observe_every": 5},
    }


def run(*args):
    return subprocess.run([str(a) for a in args], capture_output=True, text=True, timeout=300)


@pytest.fixture(scope="module")
def solved(tmp_path_factory):
    if not os.path.isfile(os.path.join(BIN, "pd-solve")):
        pytest.skip("PD_BIN_DIR has no pd-solve")
    d = tmp_path_factory.mktemp("two_stage")
    (d / "s.json").write_text(json.dumps(scene()))
    h5 = d / "s.h5"
    for args in (["pd-pack", d / "s.json", "-o", h5, "-q"], ["pd-solve", h5, "-q"],
                 ["pd-post", h5, "-o", d / "post", "-q"]):
        r = run(os.path.join(BIN, args[0]), *args[1:])
        assert r.returncode == 0, r.stderr
    return d, h5


def test_plate_enters_at_start_time_and_then_pushes(solved):
    d, h5 = solved
    with h5py.File(h5, "r") as f:
        assert f["walls/start_time"][()].tolist() == [0.0, T1]
        t = f["observables/wall_force/time"][()]
        fy = f["observables/wall_force/value"][:, 1, 1]  # plate, y
        top = f["particles/nodes/position/value"][:, :, 1].max(axis=1)
        tf = f["particles/nodes/position/time"][()]
    # before t1 the disc lies above the plate's entry point (it starts there), yet no force
    assert top[0] > PLATE_Y
    assert np.all(fy[t < T1] == 0.0)
    # the disc has settled on the floor by t1, its top GAP + RC - reach below the plate (the
    # contact's reach: R_c of the node law, 0 of the surface law, the default)
    with h5py.File(h5, "r") as f:
        law = f["contact/law"][()] if "contact/law" in f else np.zeros(1)
        reach = f["contact/radius"][()][law == 0].max(initial=0.0)
    k1 = np.argmin(abs(tf - T1))
    gap = PLATE_Y - top[k1]
    assert 0.5 * (GAP + RC) < gap < 1.2 * (GAP + RC), gap
    # contact once the plate's travel has closed the gap to within the reach, less than 0.05 mm
    # of travel later (the observation's interval, the disc's vibration)
    t_touch = t[np.argmax(fy > 0)]
    assert fy.max() > 0
    t0 = T1 + (gap - reach) / V
    assert t0 - 1e-5 < t_touch < t0 + 1e-4, (t_touch, t0, gap, reach)


def test_walls_csv_displacement_counts_from_start_time(solved):
    d, h5 = solved
    rows = list(csv.DictReader(open(d / "post" / "walls.csv")))
    t = np.array([float(r["time"]) for r in rows])
    uy = np.array([float(r["wall_1_disp_y"]) for r in rows])
    np.testing.assert_allclose(uy, -V * np.maximum(t - T1, 0), rtol=1e-12, atol=1e-15)


def test_without_start_time_the_plate_is_refused(tmp_path):
    if not os.path.isfile(os.path.join(BIN, "pd-pack")):
        pytest.skip("PD_BIN_DIR has no pd-pack")
    (tmp_path / "s.json").write_text(json.dumps(scene(None)))
    r = run(os.path.join(BIN, "pd-pack"), tmp_path / "s.json", "-o", tmp_path / "s.h5")
    assert r.returncode == 2 and "crosses the wall" in r.stderr, r.stderr
    (tmp_path / "b.json").write_text(json.dumps(scene(-1.0)))
    r = run(os.path.join(BIN, "pd-pack"), tmp_path / "b.json", "-o", tmp_path / "b.h5")
    assert r.returncode == 2 and "start_time" in r.stderr, r.stderr


@pytest.mark.parametrize("t1", [1e-9, 1e-4])
def test_plate_entering_inside_a_grain_is_refused_naming_the_wall(tmp_path, t1):
    # At t1 the disc (top 0.2 mm above the plate's entry point at t = 0; it falls 5 um by
    # 0.1 ms) still crosses the plate's surface: the run stops before the plate's first step
    # with exit 2 naming the wall, not with a blow-up that blames dt (the n500 run did that).
    # t1 = 1e-9 s enters within the run's first step (checked at set-up).
    if not os.path.isfile(os.path.join(BIN, "pd-solve")):
        pytest.skip("PD_BIN_DIR has no pd-solve")
    (tmp_path / "s.json").write_text(json.dumps(scene(start_time=t1)))
    h5 = tmp_path / "s.h5"
    r = run(os.path.join(BIN, "pd-pack"), tmp_path / "s.json", "-o", h5, "-q")
    assert r.returncode == 0, r.stderr
    r = run(os.path.join(BIN, "pd-solve"), h5, "-q")
    assert r.returncode == 2, r.stderr
    assert "wall 'plate' (walls[1]) enters at t = " in r.stderr, r.stderr
    assert "behind its surface" in r.stderr and "Lower dt" not in r.stderr
    depth = float(r.stderr.split("the deepest ")[1].split(" m")[0])
    assert 1.5e-4 < depth < 2.2e-4, r.stderr  # the disc's top, 0.21 mm above the plate
    with h5py.File(h5, "r") as f:  # the frames before the entry stay readable
        t = f["particles/nodes/position/time"][:]
        assert t[0] == 0 and np.all(t < t1 + 1e-12)
