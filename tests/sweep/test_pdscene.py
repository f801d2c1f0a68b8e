#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""workflows/sweep/pdscene.py: examples/two_discs rebuilt from Python resolves to the same scene
(pd-pack --print-scene) and packs to the same model (nodes, bonds, bodies, contact: every
dataset equal); a scene breaking the schema is refused naming the key; run() gives a solved
file."""
import os
import pathlib
import subprocess
import sys

import h5py
import numpy as np
import pytest

SRC = pathlib.Path(os.environ.get("PD_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BIN = pathlib.Path(os.environ.get("PD_BIN_DIR", SRC / "build" / "bin"))
sys.path.insert(0, str(SRC / "workflows" / "sweep"))
import pdscene  # noqa: E402


def resolved(scene_path):
    r = subprocess.run([str(BIN / "pd-pack"), str(scene_path), "--print-scene"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return r.stdout


def datasets(h5, group):
    out = {}
    def visit(name, obj):
        if isinstance(obj, h5py.Dataset):
            out[name] = obj[()]
    h5[group].visititems(visit)
    return out


def test_two_discs_from_python_equals_the_json_scene(tmp_path):
    py = pdscene.two_discs().write(tmp_path / "py.json")
    js = SRC / "examples" / "two_discs" / "scene.json"
    assert resolved(py) == resolved(js)
    for name, src in (("py", py), ("js", js)):
        r = subprocess.run([str(BIN / "pd-pack"), str(src), "-o", str(tmp_path / (name + ".h5")),
                            "-q"], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
    with h5py.File(tmp_path / "py.h5") as a, h5py.File(tmp_path / "js.h5") as b:
        for group in ("nodes", "bonds", "bodies", "contact", "materials"):
            da, db = datasets(a, group), datasets(b, group)
            assert da.keys() == db.keys(), group
            for k in da:
                assert np.array_equal(da[k], db[k]), "%s/%s" % (group, k)


def test_schema_violation_names_the_key():
    s = pdscene.two_discs().discretization(mesh_size="fine")
    with pytest.raises(pdscene.SceneError, match="discretization.mesh_size"):
        s.validate()


def test_run_gives_a_solved_file(tmp_path):
    s = pdscene.two_discs().solver(final_time=1e-4, output_interval=5e-5)
    h5 = s.run(tmp_path / "run", bin_dir=BIN)
    with h5py.File(h5) as f:
        t = f["observables/kinetic_energy/time"][()]
        assert abs(t[-1] - 1e-4) < 1e-9
        ke = f["observables/kinetic_energy/value"][()]
        assert abs(ke[-1] / ke[0] - 1) < 1e-6  # free flight before the discs meet
