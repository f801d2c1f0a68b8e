#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Issue 31, material flaws: a pulled plate with Weibull flaws starts to break at a load that
differs between seeds (and earlier than without flaws: its weakest bonds break first); the file
records the law and seed; flaws "none" is bitwise the run without the key; a bad modulus is
refused at pack (exit 2)."""
import copy
import json
import os
import subprocess

import h5py
import numpy as np

BIN = os.environ.get("PD_BIN_DIR", "build/bin")

PLATE = {
    "dimension": 2,
    "materials": {"m": {"law": "pmb", "density": 1200, "youngs_modulus": 3.24e7,
                        "fracture_energy": 5}},
    "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
    "shapes": {"plate": {"type": "rectangle", "corners": [[0, 0], [0.006, 0.003]],
                         "mesh": "grid"}},
    "particles": [{"shape": "plate", "center": [0, 0], "material": "m"}],
    "loading": {"conditions": [
        {"name": "top", "kind": "displacement", "region": {"min": [-1, 0.0026], "max": [1, 1]},
         "components": ["y"], "time_function": "linear", "value": 0.5},
        {"name": "bottom", "kind": "displacement", "region": {"min": [-1, -1],
                                                              "max": [1, 0.0004]},
         "components": ["y"], "time_function": "linear", "value": -0.5}]},
    "solver": {"final_time": 5e-5, "output_interval": 2.5e-5, "observe_every": 1,
               "fields": ["velocity", "damage", "fragment"]},
}


def solve(tmp_path, name, flaws):
    scene = copy.deepcopy(PLATE)
    if flaws is not None:
        scene["materials"]["m"]["flaws"] = flaws
    sp = tmp_path / f"{name}.json"
    sp.write_text(json.dumps(scene))
    f = tmp_path / f"{name}.h5"
    subprocess.run([f"{BIN}/pd-pack", str(sp), "-o", str(f), "-q"], check=True)
    # The ramp starts the loaded rows at 0.5 m/s in one step, which the energy balance sees as a
    # 5.8 % jump of the little energy in play at step 1: its guard is off here.
    subprocess.run([f"{BIN}/pd-solve", str(f), "-q", "--energy-tolerance", "0"], check=True)
    return f


def first_break(f):
    """Time (s) of the first broken bond and the broken count at the end."""
    with h5py.File(f, "r") as h:
        t = h["observables/broken_bonds/time"][:]
        b = h["observables/broken_bonds/value"][:]
    assert b[-1] > 0
    return float(t[np.argmax(b > 0)]), int(b[-1])


def frames(f):
    with h5py.File(f, "r") as h:
        g = h["particles/nodes"]
        return {k: g[k]["value"][:] for k in g
                if isinstance(g[k], h5py.Group) and "value" in g[k]}


def test_flaws_change_the_breaking_load_by_seed(tmp_path):
    plain = solve(tmp_path, "plain", None)
    none = solve(tmp_path, "none", {"law": "none"})
    a = solve(tmp_path, "seed1", {"law": "weibull", "modulus": 6, "seed": 1})
    b = solve(tmp_path, "seed2", {"law": "weibull", "modulus": 6, "seed": 2})
    fp, fn = frames(plain), frames(none)
    assert fp.keys() == fn.keys() and all(np.array_equal(fp[k], fn[k]) for k in fp)
    t0, n0 = first_break(plain)
    t1, n1 = first_break(a)
    t2, n2 = first_break(b)
    print(f"first break: no flaws {t0:.4g} s ({n0} broken at the end), seed 1 {t1:.4g} s "
          f"({n1}), seed 2 {t2:.4g} s ({n2})")
    assert t1 < t0 and t2 < t0  # the weakest of ~10^4 bonds is well below the median
    assert t1 != t2
    with h5py.File(a, "r") as h:
        assert float(h["materials/m/flaw_modulus"][()]) == 6
        assert int(h["materials/m/flaw_seed"][()]) == 1
    with h5py.File(plain, "r") as h:
        assert "flaw_modulus" not in h["materials/m"]
    r = subprocess.run([f"{BIN}/pd-post", str(a), "--check"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_bad_flaws_are_refused(tmp_path):
    for flaws, words in (({"modulus": 0.1}, "modulus"), ({"modulus": 6, "seed": -1}, "seed"),
                         ({"modulus": 6, "sead": 1}, "sead")):
        scene = copy.deepcopy(PLATE)
        scene["materials"]["m"]["flaws"] = flaws
        sp = tmp_path / "bad.json"
        sp.write_text(json.dumps(scene))
        r = subprocess.run([f"{BIN}/pd-pack", str(sp), "-o", str(tmp_path / "bad.h5"), "-q"],
                           capture_output=True, text=True)
        assert r.returncode == 2 and words in r.stderr, r.stderr


def test_flaws_are_validated_on_read(tmp_path):
    scene = copy.deepcopy(PLATE)
    scene["materials"]["m"]["flaws"] = {"modulus": 6, "seed": 1}
    sp = tmp_path / "f.json"
    sp.write_text(json.dumps(scene))
    f = tmp_path / "f.h5"
    subprocess.run([f"{BIN}/pd-pack", str(sp), "-o", str(f), "-q"], check=True)
    for path, value, words in (("materials/m/flaw_modulus", 0.1, "flaw_modulus"),
                               ("materials/m/flaw_seed", None, "flaw_seed")):
        bad = tmp_path / "bad.h5"
        bad.write_bytes(f.read_bytes())
        with h5py.File(bad, "r+") as h:
            if value is None:
                del h[path]
            else:
                h[path][()] = value
        r = subprocess.run([f"{BIN}/pd-solve", str(bad), "-q"], capture_output=True, text=True)
        assert r.returncode == 2 and words in r.stderr, r.stderr
