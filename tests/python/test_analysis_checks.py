# SPDX-License-Identifier: MIT
"""The checking scripts of workflows/analysis that the example Makefiles rely on:
compare_frames.py passes identical files and fails on one changed bit; check_impact.py measures
the restitution and the energy drift of hand-made files and fails when they are off."""

import pathlib
import shutil
import subprocess
import sys

import h5py
import numpy as np

ANALYSIS = pathlib.Path(__file__).resolve().parents[2] / "workflows" / "analysis"


def script(name, *args):
    return subprocess.run([sys.executable, str(ANALYSIS / name), *map(str, args)],
                          capture_output=True, text=True, timeout=60)


def test_compare_frames_bitwise(synthetic_file, tmp_path):
    a = tmp_path / "a.h5"
    b = tmp_path / "b.h5"
    shutil.copy(synthetic_file, a)
    shutil.copy(synthetic_file, b)
    r = script("compare_frames.py", a, b)
    assert r.returncode == 0 and "0 values differ" in r.stdout, r.stdout + r.stderr
    with h5py.File(b, "r+") as f:
        x = f["particles/nodes/position/value"]
        v = x[-1]
        v[0, 0] = np.nextafter(v[0, 0], np.inf)  # one ulp on one value
        x[-1] = v
    r = script("compare_frames.py", a, b)
    assert r.returncode == 1 and "1 values differ" in r.stdout, r.stdout
    assert script("compare_frames.py", a, tmp_path / "missing.h5").returncode == 2


def impact_file(path, v1, work_drift=0.0):
    """Two nodes of body 0 falling at 1 m/s, leaving at v1; energies that balance (plus a drift)."""
    nf = 20
    vy = np.where(np.arange(nf) < 8, -1.0, v1)
    with h5py.File(path, "w") as f:
        f["nodes/body"] = np.zeros(2, np.int32)
        f["nodes/volume"] = np.array([1.0, 3.0])
        vel = np.zeros((nf, 2, 3))
        vel[:, :, 1] = vy[:, None]
        f["particles/nodes/velocity/value"] = vel
        ke = 0.5 * 4 * vy ** 2
        damp = ke[0] - ke
        for name, val in (("kinetic_energy", ke), ("elastic_energy", 0 * ke),
                          ("contact_energy", 0 * ke), ("damping_dissipation", damp),
                          ("external_work", -work_drift * np.linspace(0, 1, nf))):
            f[f"observables/{name}/value"] = val


def test_check_impact(tmp_path):
    good = tmp_path / "good.h5"
    impact_file(good, 0.8)
    r = script("check_impact.py", good, "--bodies", "0", "--restitution", "0.8", "--tolerance",
               "0.001")
    assert r.returncode == 0 and "e = 0.8000" in r.stdout, r.stdout + r.stderr
    r = script("check_impact.py", good, "--bodies", "0", "--restitution", "0.9")
    assert r.returncode == 1 and "FAIL" in r.stdout
    drift = tmp_path / "drift.h5"
    impact_file(drift, 0.8, work_drift=0.1)  # W falls by 0.1 J: 0.1 / (2 + 0.1) in play
    r = script("check_impact.py", drift, "--energy-tolerance", "0.01")
    assert r.returncode == 1 and "balance drift 0.0476" in r.stdout, r.stdout
