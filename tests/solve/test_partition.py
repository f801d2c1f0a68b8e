#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""pd-partition: METIS by grain or by node, auto choice, quality figures written to /partition,
refusal of more parts than work."""
import os
import subprocess

import h5py
import numpy as np

BIN = os.environ.get("PD_BIN_DIR", "build/bin")
SRC = os.environ.get("PD_SOURCE_DIR", ".")


def packed(tmp_path, scene="pack500"):
    f = tmp_path / "p.h5"
    subprocess.run([f"{BIN}/pd-pack", os.path.join(SRC, "examples", scene, "scene.json"), "-o",
                    str(f), "-q"], check=True)
    return f


def part(f, *args):
    return subprocess.run([f"{BIN}/pd-partition", str(f), "-q", *map(str, args)],
                          capture_output=True, text=True)


def test_by_grain_and_by_node(tmp_path):
    f = packed(tmp_path)
    assert part(f, "-n", 4).returncode == 0  # auto: 500 grains / 4 parts -> by body
    with h5py.File(f, "r") as h:
        p = h["partition"]
        owner = p["owner"][:]
        assert p.attrs["by"] == "body" and owner.shape == (500,)
        assert set(owner) == {0, 1, 2, 3}
        assert p.attrs["imbalance"] < 1.1
        # Edge cut recomputed independently: pairs of grains within reach in different parts.
        c = h["bodies/center"][:]
        r = h["bodies/bounding_radius"][:]
        reach = 2 * h["contact/radius"][:].max()
        d = np.linalg.norm(c[:, None, :] - c[None, :, :], axis=2)
        near = (d < r[:, None] + r[None, :] + reach) & ~np.eye(len(r), dtype=bool)
        # Weight of each edge: the grains' surface-node pairs closer than reach, at least 1.
        x = h["nodes/reference_position"][:]
        body = h["nodes/body"][:]
        surf = h["nodes/surface"][:].astype(bool)
        cut = 0
        for a, b in zip(*np.nonzero(np.triu(near & (owner[:, None] != owner[None, :])))):
            xa = x[(body == a) & surf]
            xb = x[(body == b) & surf]
            pairs = (np.linalg.norm(xa[:, None, :] - xb[None, :, :], axis=2) < reach).sum()
            cut += max(1, pairs)
        assert cut == p.attrs["edge_cut"]
    assert part(f, "-n", 4, "--by", "node").returncode == 0
    with h5py.File(f, "r") as h:
        p = h["partition"]
        assert p.attrs["by"] == "node"
        assert p["owner"].shape == (h["nodes/volume"].shape[0],)
        assert p.attrs["imbalance"] < 1.1


def test_more_parts_than_work_is_refused(tmp_path):
    f = packed(tmp_path, "two_discs")
    r = part(f, "-n", 3, "--by", "body")
    assert r.returncode == 2 and "more parts than the 2 grains" in r.stderr
    assert part(f, "-n", 3).returncode == 0  # auto -> by node
    with h5py.File(f, "r") as h:
        assert h["partition"].attrs["by"] == "node"
