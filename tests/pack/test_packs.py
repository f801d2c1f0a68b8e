# SPDX-License-Identifier: MIT
"""Random packs checked independently of pd-pack's own checks, from the written file only (h5py):
no two grains overlap (bounding circles from /bodies/center + bounding_radius apart, and no node of
a grain inside another grain's convex hull), every node inside the container, the same seed gives
the same /nodes/reference_position, a different seed a different one."""

import json

import h5py
import numpy as np
import pytest

from conftest import run

W, H = 12e-3, 9e-3  # container, m


def scene(seed, count=30):
    return {
        "dimension": 2,
        "materials": {"m1": {"law": "lps", "density": 1200, "youngs_modulus": 3.24e7,
                             "poisson_ratio": 0.25, "fracture_energy": 50}},
        "discretization": {"mesh_size": 2.5e-4, "horizon_factor": 3},
        "shapes": {"circle": {"type": "circle", "radius": 1e-3},
                   "hexagon": {"type": "hexagon", "radius": 1e-3}},
        "particles": [{"generate": "random_pack",
                       "container": {"type": "rectangle", "corners": [[0, 0], [W, H]]},
                       "count": count, "radius": [0.6e-3, 0.9e-3],
                       "shapes": {"circle": 0.5, "hexagon": 0.5},
                       "gap": 5e-5, "seed": seed, "material": "m1"}],
        "solver": {"final_time": 1e-4},
    }


def pack(pd_pack, tmp_path, seed, name):
    path = tmp_path / f"{name}.json"
    path.write_text(json.dumps(scene(seed)))
    out = tmp_path / f"{name}.h5"
    r = run(pd_pack, path, "-o", out, "-q")
    assert r.returncode == 0, r.stderr
    return out


def hull(p):
    """Convex hull (Andrew's monotone chain), counter-clockwise."""
    p = sorted(map(tuple, p))
    cross = lambda o, a, b: (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    lo, up = [], []
    for q in p:
        while len(lo) >= 2 and cross(lo[-2], lo[-1], q) <= 0:
            lo.pop()
        lo.append(q)
    for q in reversed(p):
        while len(up) >= 2 and cross(up[-2], up[-1], q) <= 0:
            up.pop()
        up.append(q)
    return np.array(lo[:-1] + up[:-1])


def strictly_inside(points, h):
    """Boolean per point: strictly inside the CCW convex polygon h (beyond 1e-12 m)."""
    a, b = h, np.roll(h, -1, axis=0)
    e = b - a
    n = np.hypot(e[:, 0], e[:, 1])
    # signed distance to every edge line, positive inside
    d = (e[None, :, 0] * (points[:, None, 1] - a[None, :, 1]) -
         e[None, :, 1] * (points[:, None, 0] - a[None, :, 0])) / n[None, :]
    return (d > 1e-12).all(axis=1)


@pytest.fixture(scope="module")
def packed(pd_pack, tmp_path_factory):
    d = tmp_path_factory.mktemp("packs")
    return {name: pack(pd_pack, d, seed, name) for name, seed in
            [("a", 11), ("a_again", 11), ("b", 12)]}


def test_no_overlap_and_inside(packed):
    with h5py.File(packed["a"], "r") as f:
        x = f["nodes/reference_position"][:, :2]
        off = f["bodies/node_offsets"][:]
        c = f["bodies/center"][:, :2]
        rb = f["bodies/bounding_radius"][:]
    nb = len(off) - 1
    assert nb == 30
    # every node inside the container
    assert x[:, 0].min() >= 0 and x[:, 1].min() >= 0
    assert x[:, 0].max() <= W and x[:, 1].max() <= H
    grains = [x[off[b]:off[b + 1]] for b in range(nb)]
    hulls = [hull(g) for g in grains]
    # the bounding circle holds every node of its grain
    for b in range(nb):
        assert np.hypot(*(grains[b] - c[b]).T).max() <= rb[b] * (1 + 1e-9)
    for a in range(nb):
        for b in range(a + 1, nb):
            d = np.hypot(*(c[a] - c[b]))
            if d >= rb[a] + rb[b]:
                continue  # bounding circles apart
            # closer: node-level checks
            dist = np.hypot(*(grains[a][:, None, :] - grains[b][None, :, :]).transpose(2, 0, 1))
            assert dist.min() > 0, (a, b)
            assert not strictly_inside(grains[a], hulls[b]).any(), (a, b)
            assert not strictly_inside(grains[b], hulls[a]).any(), (a, b)


def test_same_seed_same_file(packed):
    with h5py.File(packed["a"], "r") as f, h5py.File(packed["a_again"], "r") as g:
        assert np.array_equal(f["nodes/reference_position"][:], g["nodes/reference_position"][:])
        assert np.array_equal(f["bodies/orientation"][:], g["bodies/orientation"][:])


def test_different_seed_different_pack(packed):
    with h5py.File(packed["a"], "r") as f, h5py.File(packed["b"], "r") as g:
        xa, xb = f["nodes/reference_position"][:], g["nodes/reference_position"][:]
        assert xa.shape != xb.shape or not np.array_equal(xa, xb)
