#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Walls placed by the state (pd-file 1.6, issue 28): no scene here knows where the settled grains
are. A disc falls onto a floor and settles; then a plate with "enter": "above_grains" enters at
t1, placed by pd-solve GAP beyond the contact reach (R_c) of the disc's top node, and moves down
onto it. A second run settles with no plate in play (its start_time past the end), then
pd-solve --restart --set moves the plate to a point the test reads from the file's last frame
and makes it enter now: recorded in /provenance, the plate pushes; a point inside the disc is
refused with the file unchanged. The same placement under mpirun -np 2."""
import hashlib
import json
import os
import shutil
import subprocess

import h5py
import numpy as np
import pytest

BIN = os.environ.get("PD_BIN_DIR", "build/bin")
R, H, GAP, T1, V = 1e-3, 2e-4, 1e-4, 2e-3, 0.5


def reach(f):
    """The contact's reach: R_c of the node law (0.95 x the smallest node spacing), 0 of the
    surface law (the default)."""
    law = f["contact/law"][()] if "contact/law" in f else np.zeros(1)
    return f["contact/radius"][()][law == 0].max(initial=0.0)


def scene(plate):
    return {
        "dimension": 2,
        "materials": {"m1": {"law": "pmb", "density": 1200, "youngs_modulus": 3.24e7,
                             "fracture_energy": 50}},
        "discretization": {"mesh_size": H, "horizon_factor": 3},
        "particles": [{"radius": R, "center": [0, R + 3e-4], "material": "m1"}],
        "walls": [{"name": "floor", "type": "plane", "point": [0, 0], "normal": [0, 1]}, plate],
        "contact": {"restitution": 0.5},
        "loading": {"gravity": [0, -1000], "viscous_damping": 2000},  # at rest by 1.2 ms
        "solver": {"final_time": 3e-3, "output_interval": 2e-4, "observe_every": 5,
                   "checkpoint_interval": 1e-3},
    }


# The plate's scene point is on the floor (inside the disc's path): only its normal and motion
# matter; where it enters is the grains' business.
PLATE = {"name": "plate", "type": "plane", "point": [0, 0], "normal": [0, -1],
         "velocity": [0, -V], "start_time": T1, "enter": "above_grains", "gap": GAP}


def run(*args, **kw):
    return subprocess.run([str(a) for a in args], capture_output=True, text=True, timeout=600,
                          **kw)


def tool(name):
    path = os.path.join(BIN, name)
    if not os.path.isfile(path):
        pytest.skip(f"PD_BIN_DIR has no {name}")
    return path


def pack(d, name, plate, restitution=0.5):
    sc = scene(plate)
    sc["contact"]["restitution"] = restitution
    (d / f"{name}.json").write_text(json.dumps(sc))
    h5 = d / f"{name}.h5"
    r = run(tool("pd-pack"), d / f"{name}.json", "-o", h5, "-q")
    assert r.returncode == 0, r.stderr
    return h5


def top_at(f, t):
    """The disc's top (largest y) in the frame nearest time t, and that frame's time."""
    tf = f["particles/nodes/position/time"][()]
    k = int(np.argmin(abs(tf - t)))
    return f["particles/nodes/position/value"][k, :, 1].max(), tf[k]


@pytest.fixture(scope="module")
def placed(tmp_path_factory):
    d = tmp_path_factory.mktemp("placed")
    h5 = pack(d, "s", PLATE)
    r = run(tool("pd-solve"), h5)
    assert r.returncode == 0, r.stderr
    return h5, r.stdout


def test_plate_enters_above_the_settled_grains(placed):
    h5, out = placed
    assert "wall 'plate' enters above the grains at t = " in out, out
    with h5py.File(h5, "r") as f:
        assert f.attrs["schema_version"] == "1.9.1"
        assert f["walls/enter"][()].tolist() == [0, 1]
        assert f["walls/gap"][1] == GAP
        y = f["walls/point"][1, 1]
        top, _ = top_at(f, T1)
        rc = reach(f)
        t = f["observables/wall_force/time"][()]
        fy = f["observables/wall_force/value"][:, 1, 1]
    # placed at the settled disc's top + R_c + GAP (the disc moves < 1 um in the frame's step)
    assert abs(y - (top + rc + GAP)) < 1e-6, (y, top + rc + GAP)
    assert top < 2 * R + rc + 0.05 * H  # settled on the floor, 0.2 mm below where it started
    # no force before t1; contact once the travel closes GAP (about one observation late)
    assert np.all(fy[t < T1] == 0.0)
    t_touch = t[np.argmax(fy > 0)]
    assert fy.max() > 0
    assert T1 + 0.9 * GAP / V < t_touch < T1 + GAP / V + 2e-5, t_touch


def test_pd_post_draws_the_placed_plate(placed, tmp_path):
    h5, _ = placed
    r = run(tool("pd-post"), h5, "-o", tmp_path / "post", "-q")
    assert r.returncode == 0, r.stderr
    import csv
    rows = list(csv.DictReader(open(tmp_path / "post" / "walls.csv")))
    t = np.array([float(r["time"]) for r in rows])
    uy = np.array([float(r["wall_1_disp_y"]) for r in rows])
    np.testing.assert_allclose(uy, -V * np.maximum(t - T1, 0), rtol=1e-12, atol=1e-15)


def test_placed_at_pack_time_when_present_from_the_start(tmp_path):
    plate = dict(PLATE, start_time=0, velocity=[0, 0])
    h5 = pack(tmp_path, "p", plate)
    with h5py.File(h5, "r") as f:
        top = f["nodes/reference_position"][:, 1].max()
        y = f["walls/point"][1, 1]
        rc = reach(f)
    assert abs(y - (top + rc + GAP)) < 1e-12, (y, top)


def test_restart_changes_the_plate_and_records_it(tmp_path):
    # Stage 1: the plate is in the scene but enters only after the end (start_time 1 s).
    h5 = pack(tmp_path, "r", dict(PLATE, enter="at_point", start_time=1.0, point=[0, 0.01]))
    r = run(tool("pd-solve"), h5, "-q", "--final-time", T1)
    assert r.returncode == 0, r.stderr
    with h5py.File(h5, "r") as f:
        top, t_end = top_at(f, T1)
        rc = reach(f)
        ck = f["checkpoints"][f["checkpoints"].attrs["latest"]].attrs["time"]
    assert abs(t_end - T1) < 1e-9 and abs(ck - T1) < 1e-9
    t1 = float(ck)  # the plate enters at the checkpoint's time (time is a running sum of dt)
    # A point inside the disc is refused, the file byte for byte as it was.
    before = hashlib.sha256(h5.read_bytes()).hexdigest()
    r = run(tool("pd-solve"), h5, "--restart", "--final-time", 3e-3,
            "--set", f"walls.plate.point=[0, {top - 1e-4}]", "--set", f"walls.plate.start_time={t1!r}")
    assert r.returncode == 2, r.stderr
    assert "wall 'plate' as changed would have" in r.stderr and "behind its surface" in r.stderr
    assert hashlib.sha256(h5.read_bytes()).hexdigest() == before
    r = run(tool("pd-solve"), h5, "--restart", "--set", "walls.plat.point=[0, 1]")
    assert r.returncode == 2 and "did you mean 'plate'" in r.stderr, r.stderr
    # Stage 2: the plate 0.1 mm + R_c above the settled top, entering now, moving down.
    y = top + rc + GAP
    sets = [f"walls.plate.point=[0, {y!r}]", f"walls.plate.start_time={t1!r}"]
    r = run(tool("pd-solve"), h5, "-q", "--restart", "--final-time", 3e-3,
            *sum((["--set", s] for s in sets), []))
    assert r.returncode == 0, r.stderr
    with h5py.File(h5, "r") as f:
        assert f["walls/point"][1, 1] == y
        assert f["walls/start_time"][1] == t1
        prov = [f["provenance"][k] for k in sorted(f["provenance"])]
        last = prov[-1]
        assert last.attrs["tool"] == "pd-solve" and last.attrs["exit_status"] == 0
        assert json.loads(last.attrs["overrides"]) == {"walls.plate.point": [0, y],
                                                       "walls.plate.start_time": t1}
        t = f["observables/wall_force/time"][()]
        fy = f["observables/wall_force/value"][:, 1, 1]
    assert np.all(fy[t < T1] == 0.0) and fy.max() > 0
    t_touch = t[np.argmax(fy > 0)]
    assert T1 + 0.9 * GAP / V < t_touch < T1 + GAP / V + 2e-5, t_touch


def test_placement_is_the_same_under_mpi(tmp_path):
    # Undamped contact (grain-level damping needs whole grains per rank; the one disc is split):
    # the ranks' minimum places the plate where one rank does, bit for bit.
    if shutil.which("mpirun") is None:
        pytest.skip("no mpirun")
    h1, h2 = pack(tmp_path, "one", PLATE, 1.0), pack(tmp_path, "two", PLATE, 1.0)
    r = run(tool("pd-solve"), h1, "-q")
    assert r.returncode == 0, r.stderr
    r = run("mpirun", "--allow-run-as-root", "--oversubscribe", "-np", "2", tool("pd-solve"),
            h2, "-q")
    assert r.returncode == 0, r.stderr
    with h5py.File(h1, "r") as f, h5py.File(h2, "r") as g:
        assert f["walls/point"][1].tolist() == g["walls/point"][1].tolist()
        assert f["walls/point"][1, 1] != 0  # placed
        # the reactions are sums over the ranks: equal to round-off
        np.testing.assert_allclose(f["observables/wall_force/value"][()],
                                   g["observables/wall_force/value"][()], rtol=1e-12, atol=1e-9)
