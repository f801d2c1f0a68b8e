# SPDX-License-Identifier: MIT
"""Helpers of the pd-post product tests (test_xdmf, test_grains, test_walls, test_crack,
test_plots): hand-made files with chosen node motions (built on synthetic.py), a resting disc
made with the real tools, and ParaView's pvbatch."""

import json
import os
import pathlib
import shutil
import subprocess

import h5py
import numpy as np
import pytest

import synthetic

HERE = pathlib.Path(__file__).resolve().parent
REPO = HERE.parents[1]
ANALYSIS = REPO / "workflows" / "analysis"


def run(exe, *args, timeout=120, **kw):
    return subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, **kw)


def with_nodes(path, x0, body, times, position, damage=None, velocity=None, bonds=None):
    """synthetic.make(path) with its nodes replaced: x0 (n, 3), body (n) with bodies 0 and 1 both
    non-empty and contiguous, frames at `times` with position (T, n, 3), damage (T, n), velocity
    (T, n, 3). bonds: list of (i, j) pairs (stored both ways); default, a chain within each body."""
    synthetic.make(path)
    x0 = np.asarray(x0, float)
    n, T = len(x0), len(times)
    body = np.asarray(body, np.int32)
    if bonds is None:
        bonds = [(i, i + 1) for i in range(n - 1) if body[i] == body[i + 1]]
    rows = [[] for _ in range(n)]
    for i, j in bonds:
        rows[i].append(j)
        rows[j].append(i)
    offsets = np.cumsum([0] + [len(r) for r in rows]).astype(np.int64)
    neighbor = np.array([j for r in rows for j in sorted(r)], np.int32)
    damage = np.zeros((T, n)) if damage is None else np.asarray(damage, float)
    velocity = np.zeros((T, n, 3)) if velocity is None else np.asarray(velocity, float)
    position = np.asarray(position, float)
    with h5py.File(path, "a") as f:
        def put(p, data, unit=None, extendible=False):
            if p in f:
                del f[p]
            kw = {}
            if extendible:
                kw = {"maxshape": (None,) + data.shape[1:], "chunks": (1,) + data.shape[1:]}
            d = f.create_dataset(p, data=data, **kw)
            if unit is not None:
                d.attrs["unit"] = unit
        put("bodies/node_offsets", np.array([0, np.count_nonzero(body == 0), n], np.int64), "1")
        put("nodes/reference_position", x0, "m")
        put("nodes/volume", np.full(n, 1e-8), "m3")
        put("nodes/body", body, "1")
        put("bonds/offsets", offsets, "1")
        put("bonds/neighbor", neighbor, "1")
        pn = "particles/nodes/"
        put(pn + "species", body, "1")
        put(pn + "mass", np.full(n, 1.2e-5), "kg")
        for name in ("step", "time"):
            for field in ("velocity", "displacement", "force", "damage"):
                del f[pn + field + "/" + name]
        put(pn + "position/step", np.arange(T, dtype=np.int64) * 100, None, True)
        put(pn + "position/time", np.asarray(times, float), "s", True)
        put(pn + "position/value", position, "m", True)
        put(pn + "velocity/value", velocity, "m s-1", True)
        put(pn + "displacement/value", position - x0[None], "m", True)
        put(pn + "force/value", np.zeros((T, n, 3)), "N", True)
        put(pn + "damage/value", damage, "1", True)
        for field in ("velocity", "displacement", "force", "damage"):
            for name in ("step", "time"):
                f[pn + field + "/" + name] = f[pn + "position/" + name]
    return path, offsets, neighbor


def add_checkpoint(path, step, alive):
    """A /checkpoints/step_<N> group holding `alive` (per CSR bond) as the latest checkpoint."""
    with h5py.File(path, "a") as f:
        n = f["nodes/volume"].shape[0]
        name = "step_%012d" % step
        g = f.create_group("checkpoints/" + name)
        for k, v in [("step", np.int64(step)), ("time", step * 1e-6), ("dt", 1e-6),
                     ("broken_total", np.int64(np.count_nonzero(np.asarray(alive) == 0))),
                     ("external_work", 0.0), ("external_power", 0.0), ("complete", np.int32(1))]:
            g.attrs[k] = v
        for k, unit in [("displacement", "m"), ("velocity", "m s-1"), ("force_density", "N m-3")]:
            g.create_dataset(k, data=np.zeros((n, 3))).attrs["unit"] = unit
        g.create_dataset("bond_alive", data=np.asarray(alive, np.uint8)).attrs["unit"] = "1"
        f["checkpoints"].attrs["latest"] = name


RESTING_DISC = """{
  "title": "resting disc on a floor",
  "dimension": 2,
  "materials": { "m1": { "law": "pmb", "density": 1200, "youngs_modulus": 3.24e7,
                         "fracture_energy": 50 } },
  "discretization": { "mesh_size": 2.0e-4, "horizon_factor": 3 },
  "particles": [ { "shape": "disc", "radius": 1.0e-3, "center": [0, 1.2e-3], "material": "m1" } ],
  "walls": [ { "type": "plane", "point": [0, 0], "normal": [0, 1] } ],
  "contact": { "restitution": 0.5 },
  "loading": { "gravity": [0, -10], "viscous_damping": 200 },
  "solver": { "final_time": 0.03, "dt": "auto", "output_interval": 1.0e-3 }
}
"""
DENSITY, GRAVITY = 1200.0, 10.0
_cache = {}

# The resting disc on a fixed meshed floor (body 0), with a meshed plate (body 2) driven up and
# away at 0.1 m/s (it never touches): meshed walls record reactions.
MESHED_FLOOR = """{
  "title": "resting disc on a meshed floor",
  "dimension": 2,
  "materials": { "m1": { "law": "pmb", "density": 1200, "youngs_modulus": 3.24e7,
                         "fracture_energy": 50 } },
  "discretization": { "mesh_size": 2.0e-4, "horizon_factor": 3 },
  "shapes": { "slab": { "type": "rectangle", "corners": [[-2e-3, -0.6e-3], [2e-3, 0]] } },
  "particles": [ { "shape": "slab", "center": [0, 0], "material": "m1", "fixed": true },
                 { "shape": "disc", "radius": 1.0e-3, "center": [0, 1.2e-3], "material": "m1" },
                 { "shape": "slab", "center": [0, 3.5e-3], "material": "m1" } ],
  "contact": { "restitution": 0.5 },
  "loading": { "gravity": [0, -10], "viscous_damping": 200, "conditions": [
    { "name": "up", "kind": "displacement", "particles": [2], "components": ["y"],
      "time_function": "linear", "value": 0.1 },
    { "name": "still", "kind": "displacement", "particles": [2], "components": ["x"],
      "value": 0 } ] },
  "solver": { "final_time": 0.05, "dt": "auto", "output_interval": 1.0e-3 }
}
"""


def meshed_floor(tmp_path_factory, bin_dir):
    """MESHED_FLOOR made with pd-pack and pd-solve and exported with pd-post (walls.csv with
    --wall-length 2e-3); built once per session."""
    if "floor" in _cache:
        return _cache["floor"]
    tools = {t: bin_dir / t for t in ("pd-pack", "pd-solve", "pd-post")}
    for t, exe in tools.items():
        if not exe.is_file():
            pytest.skip("%s missing in PD_BIN_DIR" % exe)
    d = tmp_path_factory.mktemp("meshed_floor")
    (d / "scene.json").write_text(MESHED_FLOOR)
    h5 = d / "floor.h5"
    for exe, args in [("pd-pack", [d / "scene.json", "-o", h5]), ("pd-solve", [h5]),
                      ("pd-post", [h5, "-o", d / "post", "--no-vtu", "--wall-length", "2e-3"])]:
        r = run(tools[exe], *args, timeout=600)
        assert r.returncode == 0, "%s failed: %s" % (exe, r.stderr)
    _cache["floor"] = (h5, d / "post")
    return _cache["floor"]


def resting_disc(tmp_path_factory, bin_dir):
    """A 1 mm disc dropped 0.2 mm onto a floor under gravity (damped, restitution 0.5), made with
    pd-pack and pd-solve (about 2 s) and exported with pd-post; built once per session."""
    if "disc" in _cache:
        return _cache["disc"]
    tools = {t: bin_dir / t for t in ("pd-pack", "pd-solve", "pd-post")}
    for t, exe in tools.items():
        if not exe.is_file():
            pytest.skip("%s missing in PD_BIN_DIR" % exe)
    d = tmp_path_factory.mktemp("resting_disc")
    (d / "scene.json").write_text(RESTING_DISC)
    h5 = d / "disc.h5"
    for exe, args in [("pd-pack", [d / "scene.json", "-o", h5]), ("pd-solve", [h5]),
                      ("pd-post", [h5, "-o", d / "post", "--wall-length", "2e-3"])]:
        r = run(tools[exe], *args)
        assert r.returncode == 0, "%s failed: %s" % (exe, r.stderr)
    _cache["disc"] = (h5, d / "post")
    return _cache["disc"]


def pvbatch_ranges(path):
    """Runs pv_ranges.py under ParaView's pvbatch on `path`; returns its JSON. Skips the test when
    pvbatch (Debian's paraview) or its Python modules (python3-paraview, or a directory named by
    PD_PARAVIEW_PYTHONPATH, e.g. the package unpacked with dpkg-deb -x) are missing."""
    exe = shutil.which("pvbatch")
    if not exe:
        pytest.skip("pvbatch not found (install Debian's paraview)")
    env = dict(os.environ)
    extra = os.environ.get("PD_PARAVIEW_PYTHONPATH")
    if extra:
        env["PYTHONPATH"] = extra + os.pathsep + env.get("PYTHONPATH", "")
    r = run(exe, HERE / "pv_ranges.py", path, env=env, timeout=300)
    if r.returncode != 0 and "No module named 'paraview'" in r.stderr:
        pytest.skip("pvbatch has no paraview Python modules (python3-paraview conflicts with "
                    "python3-vtk9; set PD_PARAVIEW_PYTHONPATH)")
    assert r.returncode == 0, r.stderr
    line = [l for l in r.stdout.splitlines() if l.startswith("PV_RANGES ")]
    assert line, r.stdout + r.stderr
    return json.loads(line[-1][len("PV_RANGES "):])


def read_csv(path):
    """A pd-post CSV as a numpy structured array (trailing '#' method lines are skipped)."""
    return np.genfromtxt(path, delimiter=",", names=True)
