# SPDX-License-Identifier: MIT
"""(c) pd-post's observables.csv, read with numpy, equals the /observables series of the file
(17 significant digits: an exact round trip). Columns follow the schema's observable order, which
must be store::observable_list()'s (pd-post takes its header from there)."""

import json
import re
import subprocess

import h5py
import numpy as np

from conftest import SCHEMA_DIR


def observables(h5):
    """(name, components) per CSV block: the standard series in schema order (=
    store::observable_list()), then the other series present in the file, in name order."""
    std, extra = [], []
    for e in json.loads((SCHEMA_DIR / "pd-file.schema.json").read_text())["entries"]:
        m = re.fullmatch(r"/observables/(\w+)/value", e["path"])
        # the standard series: required, or optional ones of one value or 3-vector per row
        # (since pd-file 1.2) when present; per-item series (walls) follow in name order
        if m and (e["path"].rsplit("/", 1)[0] in REQUIRED or
                  (m.group(1) in h5["observables"] and e["rank"] == 1)):
            std.append(m.group(1))
    for name in sorted(h5["observables"]):
        if name not in std:
            extra.append(name)
    out = []
    for name in std + extra:
        shape = h5["observables"][name]["value"].shape
        out.append((name, int(np.prod(shape[1:])), name in extra))
    return out


REQUIRED = {e["path"]
            for e in json.loads((SCHEMA_DIR / "pd-file.schema.json").read_text())["entries"]
            if e["path"].startswith("/observables/") and e["kind"] == "group" and e["required"]}


def expected_header(obs):
    cols = ["step", "time"]
    for name, c, per_item in obs:
        if c == 1:
            cols.append(name)
        elif c % 3 == 0:
            for k in range(c):
                cols.append(name + ("_%d" % (k // 3) if per_item else "") + "_" + "xyz"[k % 3])
        else:
            cols += ["%s_%d" % (name, k) for k in range(c)]
    return cols


def check_csv(path, h5file):
    header = path.read_text().splitlines()[0].split(",")
    table = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    with h5py.File(h5file, "r") as f:
        obs = observables(f)
        assert header == expected_header(obs)
        step = f["observables/kinetic_energy/step"][()]
        assert table.shape == (len(step), len(header))
        np.testing.assert_array_equal(table[:, 0].astype(np.int64), step)
        np.testing.assert_array_equal(table[:, 1], f["observables/kinetic_energy/time"][()])
        col = 2
        for name, c, _ in obs:
            value = f["observables"][name]["value"][()].reshape(len(step), c)
            np.testing.assert_array_equal(table[:, col:col + c], value, err_msg=name)
            col += c
    return header


def test_observables_csv_equals_file(post_dir, h5file):
    check_csv(post_dir / "observables.csv", h5file)


def test_observables_csv_with_walls(pd_post, synthetic_file, tmp_path):
    """The wall reactions (walls, 3) follow the standard columns: wall_force_0_x, ..."""
    r = subprocess.run([str(pd_post), synthetic_file, "-o", str(tmp_path / "out"), "--no-vtu"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    header = check_csv(tmp_path / "out" / "observables.csv", synthetic_file)
    assert header[-6:] == ["wall_force_0_x", "wall_force_0_y", "wall_force_0_z",
                           "wall_moment_0_x", "wall_moment_0_y", "wall_moment_0_z"]
