# SPDX-License-Identifier: MIT
"""Rigid walls in pd-post's ParaView output (issue 12, item 6): `<stem>_walls_<k>.vtu` per frame
with `<stem>_walls.pvd`, and a "walls" temporal collection in the .xmf, hold each rigid wall at
its position at the frame's time. Scene: a disc inside a drum (circle_inside, R = 4 mm) that
turns at 200 rad/s about its centre while the centre moves at (0.5, 0) m/s, under a plate
(plane, normal -y) moving down at 2 m/s from y = 1.5 mm; 2D, 40 us."""

import json
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest

from post_helpers import run

R_DRUM, OMEGA, V_DRUM = 4e-3, 200.0, 0.5
Y_PLATE, V_PLATE = 1.5e-3, 2.0

SCENE = {
    "dimension": 2,
    "materials": {"m": {"law": "pmb", "density": 1200, "youngs_modulus": 3.24e7,
                        "fracture_energy": 50}},
    "discretization": {"mesh_size": 2.5e-4, "horizon_factor": 3},
    "particles": [{"radius": 1e-3, "center": [0, 0], "material": "m"}],
    "walls": [
        {"type": "circle_inside", "center": [0, 0], "radius": R_DRUM,
         "angular_velocity": OMEGA, "velocity": [V_DRUM, 0]},
        {"type": "plane", "point": [0, Y_PLATE], "normal": [0, -1], "velocity": [0, -V_PLATE]},
    ],
    "loading": {"gravity": [0, 0]},
    "solver": {"final_time": 4e-5, "dt": "auto", "output_interval": 1e-5},
}


@pytest.fixture(scope="module")
def posted(tmp_path_factory, bin_dir):
    d = tmp_path_factory.mktemp("wall_export")
    (d / "scene.json").write_text(json.dumps(SCENE))
    h5 = d / "drum.h5"
    for tool, args in (("pd-pack", [d / "scene.json", "-o", h5, "-q"]), ("pd-solve", [h5, "-q"]),
                       ("pd-post", [h5, "-o", d / "post", "-q"])):
        r = run(bin_dir / tool, *args)
        assert r.returncode == 0, r.stderr
    return d / "post"


def pvd_items(path):
    return [(float(e.get("timestep")), path.parent / e.get("file"))
            for e in ET.parse(path).getroot().iter("DataSet")]


def expected(t, points):
    """Per point: (wall index, expected position) from the analytic motion."""
    cx = V_DRUM * t
    ang = OMEGA * t
    drum = [(cx + R_DRUM * np.cos(2 * np.pi * i / 128 + ang), R_DRUM * np.sin(2 * np.pi * i / 128 + ang))
            for i in range(128)]
    return np.array(drum), Y_PLATE - V_PLATE * t


def check(points, cells, wall, velocity, t):
    drum, y_plate = expected(t, points)
    assert cells.shape == (129, 2)
    np.testing.assert_array_equal(wall, [0] * 128 + [1])
    # The drum: 128 points on the circle about its moved centre, point 0 turned by omega t.
    np.testing.assert_allclose(points[:128, :2], drum, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(points[:, 2], 0)
    # Surface velocity of the drum: v + omega x r.
    r = points[:128, :2] - [V_DRUM * t, 0]
    np.testing.assert_allclose(velocity[:128, 0], V_DRUM - OMEGA * r[:, 1], rtol=1e-12)
    np.testing.assert_allclose(velocity[:128, 1], OMEGA * r[:, 0], rtol=1e-12)
    # The plate: a horizontal segment at y = y0 - v t, wider than the disc.
    np.testing.assert_allclose(points[128:, 1], y_plate, rtol=0, atol=1e-15)
    assert points[128:, 0].min() < -1e-3 and points[128:, 0].max() > 1e-3
    np.testing.assert_allclose(velocity[128:], [[0, -V_PLATE, 0]] * 2)


def test_vtu_has_the_walls_where_they_are(posted):
    items = pvd_items(posted / "drum_walls.pvd")
    node_items = pvd_items(posted / "drum.pvd")
    assert [t for t, _ in items] == [t for t, _ in node_items]
    assert len(items) == 5 and items[-1][0] == pytest.approx(4e-5)
    for t, path in items:
        m = meshio.read(path)
        assert [c.type for c in m.cells] == ["line"]
        check(m.points, m.cells[0].data, m.cell_data["wall"][0], m.point_data["velocity"], t)
    # The plate has moved 80 um down by the last frame, the drum turned by 0.008 rad.
    assert meshio.read(items[-1][1]).points[128, 1] == pytest.approx(Y_PLATE - 8e-5, abs=1e-15)


def values(item):
    return np.array(item.text.split(), dtype=float)


def test_xdmf_has_the_walls_where_they_are(posted):
    root = ET.parse(posted / "drum.xmf").getroot()
    grids = root.find("Domain").findall("Grid")
    assert [g.get("Name") for g in grids] == ["nodes", "walls"]
    frames = grids[1].findall("Grid")
    assert len(frames) == 5
    for g in frames:
        t = float(g.find("Time").get("Value"))
        assert g.find("Topology").get("TopologyType") == "Polyline"
        cells = values(g.find("Topology/DataItem")).astype(int).reshape(-1, 2)
        points = values(g.find("Geometry/DataItem")).reshape(-1, 3)
        attrs = {a.get("Name"): values(a.find("DataItem")) for a in g.findall("Attribute")}
        check(points, cells, attrs["wall"], attrs["velocity"].reshape(-1, 3), t)


def test_no_walls_no_wall_files(pipeline_dir):
    """The demo (two discs, no rigid wall) gets no wall series and an unchanged .xmf."""
    post = pipeline_dir / "post"
    assert not list(post.glob("*_walls*"))
    root = ET.parse(post / "two_discs.xmf").getroot()
    assert [g.get("Name") for g in root.find("Domain").findall("Grid")] == ["nodes"]
