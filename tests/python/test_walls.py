# SPDX-License-Identifier: MIT
"""walls.csv: the reaction columns equal /observables/wall_force and wall_moment exactly, the
displacement is /walls/velocity * time, stress = force / --wall-length; and a disc resting on a
floor (made with pd-pack and pd-solve) pushes on it with its weight. The same for meshed walls
(fixed or driven bodies): body columns equal /observables/body_force and body_moment, the driven
plate's displacement is its condition's, a disc on a fixed meshed floor loads it with its weight."""

import json
from pathlib import Path

import h5py
import numpy as np
import pytest

from post_helpers import DENSITY, GRAVITY, meshed_floor, read_csv, resting_disc, run

SCHEMA = Path(__file__).resolve().parents[2] / "data-schema" / "pd-file.schema.json"
SCHEMA_VERSION = json.loads(SCHEMA.read_text())["version"]


@pytest.fixture(scope="module")
def disc(tmp_path_factory, bin_dir):
    return resting_disc(tmp_path_factory, bin_dir)


def check_against_file(h5, csv, length=None):
    d = read_csv(csv)
    with h5py.File(h5, "r") as f:
        force = f["observables/wall_force/value"][()]
        moment = f["observables/wall_moment/value"][()]
        time = f["observables/wall_force/time"][()]
        vel = f["walls/velocity"][()]
        normal = f["walls/normal"][()]
    np.testing.assert_array_equal(d["time"], time)
    for k in range(force.shape[1]):
        for c, a in enumerate("xyz"):
            np.testing.assert_array_equal(d["wall_%d_force_%s" % (k, a)], force[:, k, c])
            np.testing.assert_array_equal(d["wall_%d_moment_%s" % (k, a)], moment[:, k, c])
            np.testing.assert_allclose(d["wall_%d_disp_%s" % (k, a)], vel[k, c] * time)
            if length:
                np.testing.assert_allclose(d["wall_%d_stress_%s" % (k, a)], force[:, k, c] / length)
        np.testing.assert_allclose(d["wall_%d_normal_force" % k], force[:, k] @ normal[k],
                                   rtol=1e-12, atol=1e-300)
    return d


def test_synthetic_reaction_equals_observable(synthetic_file, pd_post, tmp_path):
    with h5py.File(synthetic_file, "a") as f:
        f["walls/velocity"][0] = [0.0, -0.5, 0.0]  # a moving wall: displacement = v t
    r = run(pd_post, synthetic_file, "-o", tmp_path / "out", "--wall-length", "0.01")
    assert r.returncode == 0, r.stderr
    check_against_file(synthetic_file, tmp_path / "out" / "walls.csv", 0.01)


def test_resting_disc_reaction_is_its_weight(disc):
    h5, post = disc
    d = check_against_file(h5, post / "walls.csv", 2e-3)
    with h5py.File(h5, "r") as f:
        weight = f["nodes/volume"][()].sum() * DENSITY * GRAVITY  # N per m of thickness
    fn = d["wall_0_normal_force"]
    late = fn[int(0.7 * len(fn)):]  # settled: the last 30 % of the run
    # The floor receives the weight, pointing into it (against its normal).
    # Step to step the contact nodes chatter; averaged over windows of 1/10 of the run it is
    # steady.
    for w in np.array_split(late, 3):
        np.testing.assert_allclose(-w.mean(), weight, rtol=0.01)


def test_no_walls_no_csv(synthetic_file, pd_post, tmp_path):
    with h5py.File(synthetic_file, "a") as f:
        del f["walls"], f["observables/wall_force"], f["observables/wall_moment"]
    r = run(pd_post, synthetic_file, "-o", tmp_path / "out", "--no-vtu")
    assert r.returncode == 0, r.stderr
    assert not (tmp_path / "out" / "walls.csv").exists()


def test_meshed_walls_columns_and_weight(tmp_path_factory, bin_dir):
    h5, post = meshed_floor(tmp_path_factory, bin_dir)
    d = read_csv(post / "walls.csv")
    with h5py.File(h5, "r") as f:
        bodies = list(f["observables/body_force/body"][()])
        force = f["observables/body_force/value"][()]
        moment = f["observables/body_moment/value"][()]
        time = f["observables/body_force/time"][()]
        off = f["bodies/node_offsets"][()]
        weight = f["nodes/volume"][off[1]:off[2]].sum() * DENSITY * GRAVITY  # the disc's
    assert bodies == [0, 2]  # the fixed floor and the driven plate, not the free disc
    np.testing.assert_array_equal(d["time"], time)
    for k, b in enumerate(bodies):
        for c, a in enumerate("xyz"):
            np.testing.assert_array_equal(d["body_%d_force_%s" % (b, a)], force[:, k, c])
            np.testing.assert_array_equal(d["body_%d_moment_%s" % (b, a)], moment[:, k, c])
            np.testing.assert_allclose(d["body_%d_stress_%s" % (b, a)], force[:, k, c] / 2e-3)
    np.testing.assert_allclose(d["body_2_disp_y"], 0.1 * time, rtol=1e-12, atol=1e-15)
    np.testing.assert_array_equal(d["body_2_disp_x"], 0 * time)
    np.testing.assert_array_equal(d["body_0_disp_y"], 0 * time)
    assert np.abs(force[:, 1, :]).max() == 0  # the plate never touches
    # The disc rests from 25 ms on (it lands on its lowest node and rocks onto a facet by 23 ms:
    # tests/unit/solver/test_body_reactions.cpp); over the last 20 ms of 50 the floor carries
    # its weight on average, and the disc keeps < 1e-3 of the 7e-6 J it lands with.
    with h5py.File(h5, "r") as f:
        ke = f["observables/kinetic_energy/value"][()]
    late = time > time[-1] - 0.02
    assert (ke[late] - ke[0]).max() < 7e-9, "the disc does not come to rest"
    # rtol 2 %: the node-level chatter of the floor force has a standard deviation of 20 % of the
    # weight with the surface correction (default; the disc's surface layer is as stiff as its
    # bulk), 14 % without it; the window averages it out.
    np.testing.assert_allclose(-force[late, 0, 1].mean(), weight, rtol=0.02)


def test_meshed_wall_missing_observable_is_a_clear_error(tmp_path_factory, bin_dir, tmp_path):
    h5, _ = meshed_floor(tmp_path_factory, bin_dir)
    bad = tmp_path / "old.h5"
    bad.write_bytes(h5.read_bytes())
    with h5py.File(bad, "a") as f:
        del f["observables/body_moment"]
    r = run(bin_dir / "pd-post", bad, "-o", tmp_path / "out", "--no-vtu")
    assert r.returncode == 2 and "body_moment" in r.stderr and "missing" in r.stderr, r.stderr


def test_solving_an_older_file_raises_its_version(bin_dir, tmp_path):
    """pd-solve adds pd-file 1.2.0 objects (body_force) to a 1.1.0 file: it raises the version."""
    from post_helpers import MESHED_FLOOR
    (tmp_path / "scene.json").write_text(MESHED_FLOOR)
    h5 = tmp_path / "old.h5"
    assert run(bin_dir / "pd-pack", tmp_path / "scene.json", "-o", h5, "-q").returncode == 0
    with h5py.File(h5, "a") as f:
        f.attrs["schema_version"] = "1.1.0"
    r = run(bin_dir / "pd-solve", h5, "-q", "--final-time", "1e-5")
    assert r.returncode == 0, r.stderr
    with h5py.File(h5, "r") as f:
        v = f.attrs["schema_version"]
        assert (v.decode() if isinstance(v, bytes) else v) == SCHEMA_VERSION
        assert list(f["observables/body_force/body"][()]) == [0, 2]
