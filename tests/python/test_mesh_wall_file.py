# SPDX-License-Identifier: MIT
"""Triangulated walls in the pd-file (issue 26 item 5, pd-file 1.7.0): pd-pack stores a polyline
wall's points and cells under /walls/mesh/<k>, the validators accept the file, pd-solve runs it and
pd-post draws its cells; a file whose wall surface is broken (an index out of range, a degenerate
segment, two segments of opposite orientation, a non-finite point) is refused by pd-solve with
exit 2 and a message naming /walls/mesh/0."""

import json
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from post_helpers import run

REPO = Path(__file__).resolve().parents[2]

# A disc in a V of two segments (free side up: the polyline runs left to right), and a plane.
SCENE = {
    "dimension": 2,
    "materials": {"m": {"density": 1200, "youngs_modulus": 3.24e7}},
    "discretization": {"mesh_size": 2.5e-4, "horizon_factor": 3},
    "particles": [{"radius": 1e-3, "center": [0, 2.2e-3], "material": "m"}],
    "walls": [{"name": "plane", "type": "plane", "point": [0, -1e-3], "normal": [0, 1]},
              {"name": "vee", "type": "mesh", "polyline": [[-4e-3, 4e-3], [0, 0], [4e-3, 4e-3]]}],
    "loading": {"gravity": [0, -10]},
    "solver": {"final_time": 2e-4, "output_interval": 1e-4},
}


@pytest.fixture(scope="module")
def packed(tmp_path_factory, bin_dir):
    d = tmp_path_factory.mktemp("meshwall")
    (d / "scene.json").write_text(json.dumps(SCENE))
    h5 = d / "vee.h5"
    r = run(bin_dir / "pd-pack", d / "scene.json", "-o", h5, "-q")
    assert r.returncode == 0, r.stderr
    return h5


def test_polyline_is_stored_solved_and_drawn(packed, bin_dir, tmp_path):
    with h5py.File(packed, "r") as f:
        assert f.attrs["schema_version"] in ("1.9.1", b"1.9.1")
        assert list(f["walls/shape"][()]) == [0, 3]
        assert "0" not in f["walls/mesh"]  # the plane has no surface
        np.testing.assert_array_equal(f["walls/mesh/1/points"][()],
                                      [[-4e-3, 4e-3, 0], [0, 0, 0], [4e-3, 4e-3, 0]])
        np.testing.assert_array_equal(f["walls/mesh/1/cells"][()], [[0, 1], [1, 2]])
        np.testing.assert_allclose(f["walls/point"][1], [0, 2e-3, 0])  # bounding-box centre
    r = run(sys.executable, REPO / "data-schema" / "check_pd_file.py", packed)
    assert r.returncode == 0, r.stdout + r.stderr
    h5 = tmp_path / "run.h5"
    h5.write_bytes(packed.read_bytes())
    r = run(bin_dir / "pd-solve", h5, "-q")
    assert r.returncode == 0, r.stderr
    r = run(bin_dir / "pd-post", h5, "-o", tmp_path / "post", "-q")
    assert r.returncode == 0, r.stderr
    walls = sorted((tmp_path / "post").glob("run_walls_*.vtu"))
    assert walls, "no wall frames"
    import meshio
    w = meshio.read(walls[-1])
    owner = w.cell_data["wall"][0]
    assert (owner == 1).sum() == 2  # the V's two segments


def mutate_cells(f):
    f["walls/mesh/1/cells"][1, 1] = 7


def mutate_degenerate(f):
    f["walls/mesh/1/points"][2] = f["walls/mesh/1/points"][1]


def mutate_orientation(f):
    f["walls/mesh/1/cells"][1] = [2, 1]


def mutate_nan(f):
    f["walls/mesh/1/points"][0, 0] = np.nan


@pytest.mark.parametrize("mutate, says", [(mutate_cells, "refers to point 7"),
                                          (mutate_degenerate, "degenerate"),
                                          (mutate_orientation, "opposite orientations"),
                                          (mutate_nan, "not finite")])
def test_broken_surface_is_refused(packed, bin_dir, tmp_path, mutate, says):
    h5 = tmp_path / "bad.h5"
    h5.write_bytes(packed.read_bytes())
    with h5py.File(h5, "a") as f:
        mutate(f)
    r = run(bin_dir / "pd-solve", h5, "-q")
    assert r.returncode == 2, r.stderr
    assert "/walls/mesh/1" in r.stderr and says in r.stderr, r.stderr
