# SPDX-License-Identifier: MIT
"""grains.csv: centre of mass, its velocity, rigid rotation (2D Procrustes), damage, and the bond
state (broken bonds, fragments) at the latest checkpoint, on hand-made files with known motion;
and a resting disc (real tools) ends still and unrotated."""

import numpy as np
import pytest

from post_helpers import add_checkpoint, read_csv, resting_disc, run, with_nodes


def rot(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def test_translation_rotation_damage(tmp_path, pd_post):
    # body 0: a 4x3 grid spinning at 40 rad/s about its centre while translating; body 1: a bar
    # at rest, half damaged.
    g = np.array([[i * 1e-3, j * 1e-3, 0] for i in range(4) for j in range(3)])
    b1 = np.array([[10e-3 + i * 1e-3, 0, 0] for i in range(4)])
    x0 = np.vstack([g, b1])
    body = [0] * len(g) + [1] * len(b1)
    times = np.linspace(0, 0.2, 9)  # up to 8 rad: the angle must unwrap past pi
    c0 = g.mean(axis=0)
    vel = np.array([0.3, -0.1, 0])
    pos = np.stack([np.vstack([(g - c0) @ rot(40 * t).T + c0 + vel * t, b1]) for t in times])
    dmg = np.zeros((len(times), len(x0)))
    dmg[:, len(g):len(g) + 2] = 0.5
    path, offsets, neighbor = with_nodes(str(tmp_path / "g.h5"), x0, body, times, pos, dmg)
    # Checkpoint at the last frame: the bar's middle bond (nodes 13-14) broken both ways.
    alive = np.ones(len(neighbor), np.uint8)
    for i, j in [(13, 14), (14, 13)]:
        alive[offsets[i] + list(neighbor[offsets[i]:offsets[i + 1]]).index(j)] = 0
    add_checkpoint(path, 800, alive)
    r = run(pd_post, path, "-o", tmp_path / "out", "--no-vtu")
    assert r.returncode == 0, r.stderr
    d = read_csv(tmp_path / "out" / "grains.csv")
    assert len(d) == 2 * len(times)
    b0, bb = d[d["body"] == 0], d[d["body"] == 1]
    np.testing.assert_allclose(b0["com_x"], c0[0] + vel[0] * times, rtol=1e-12)
    np.testing.assert_allclose(b0["com_y"], c0[1] + vel[1] * times, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(b0["rotation"], 40 * times, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(bb["rotation"], 0, atol=1e-12)
    np.testing.assert_allclose(b0["damage"], 0)
    np.testing.assert_allclose(bb["damage"], 0.25)  # half the nodes at phi = 0.5
    # Bond state: exact at the checkpoint's frame only, empty (nan) elsewhere.
    assert np.isnan(bb["fragments"][:-1]).all() and np.isnan(bb["broken_bonds"][:-1]).all()
    assert bb["broken_bonds"][-1] == 1 and bb["fragments"][-1] == 2
    assert b0["broken_bonds"][-1] == 0 and b0["fragments"][-1] == 1


def test_resting_disc(tmp_path_factory, bin_dir):
    h5, post = resting_disc(tmp_path_factory, bin_dir)
    d = read_csv(post / "grains.csv")
    assert (d["body"] == 0).all()
    assert abs(d["vcom_y"][-1]) < 1e-4 and abs(d["rotation"][-1]) < 1e-3
    assert d["fragments"][-1] == 1 and d["broken_bonds"][-1] == 0  # end-of-run checkpoint
    assert d["com_y"][-1] < d["com_y"][0]  # it fell
