# SPDX-License-Identifier: MIT
"""PeriDEM importer: `pd-pack --from-peridem DECK` on the shipped decks gives the node counts and
nodal volumes of spec 11 (123-node circle, sum of volumes 3.121445e-6 m2; 91-node hexagon
2.598076e-6 m2), zone-by-zone particle ids, the spec 2.5 transform and the deck's parameters."""

import json
import math

import h5py
import numpy as np
import pytest

from conftest import run

CIRCLE_VOLUME = 3.121445e-6  # m2, 123-node 1 mm circle (spec 11.1)
HEXAGON_VOLUME = 2.598076e-6  # m2, 91-node 1 mm hexagon


def imported(pd_pack, shared_dir, tmp_path, case):
    deck = shared_dir / "data" / "peridem" / case / "input_0.yaml"
    out = tmp_path / f"{case}.h5"
    scene = tmp_path / f"{case}.json"
    r = run(pd_pack, "--from-peridem", deck, "-o", out, "--write-scene", scene, "-q")
    assert r.returncode == 0, r.stderr
    return h5py.File(out, "r"), json.loads(scene.read_text())


def body_volumes(f):
    off = f["bodies/node_offsets"][:]
    vol = f["nodes/volume"][:]
    return [vol[off[b]:off[b + 1]] for b in range(len(off) - 1)]


def test_single_particle_circle(pd_pack, shared_dir, tmp_path):
    f, scene = imported(pd_pack, shared_dir, tmp_path, "single_particle_circle")
    (v,) = body_volumes(f)
    assert len(v) == 123
    assert v.sum() == pytest.approx(CIRCLE_VOLUME, rel=1e-6)
    assert v.min() == pytest.approx(1.194e-8, rel=2e-3)
    assert f["bodies/horizon"][0] == pytest.approx(6e-4)
    assert f["bodies/mesh_size"][0] == pytest.approx(1.40912e-4, rel=1e-5)
    m = scene["materials"]["zone_1"]
    assert m["law"] == "lps" and m["influence"] == "linear"
    assert m["youngs_modulus"] == pytest.approx(3.24e5) and m["poisson_ratio"] == pytest.approx(0.25)
    assert scene["solver"]["integrator"] == "symplectic_euler"
    assert scene["solver"]["dt"] == pytest.approx(0.05 / 40000)
    conds = scene["loading"]["conditions"]
    assert conds[0]["region"] == {"min": [-0.001, -0.001], "max": [-0.0005, -0.0005]}
    assert conds[1]["time_function"] == "linear" and conds[1]["value"] == 0.005


def test_single_particle_rectangle_grid(pd_pack, shared_dir, tmp_path):
    f, scene = imported(pd_pack, shared_dir, tmp_path, "single_particle_rectangle")
    (v,) = body_volumes(f)
    assert len(v) == 21 * 21
    assert v.sum() == pytest.approx(1e-4, rel=1e-12)
    assert v.min() == pytest.approx(0.0005**2 / 4)  # corners a quarter (spec 2.1)
    # The 5-parameter region [Lx, Ly, xc, yc, zc] = 8 mm centred at (10, 10) mm (spec 8.6).
    assert scene["loading"]["conditions"][1]["region"] == {"min": [0.006, 0.006],
                                                           "max": [0.014, 0.014]}


def test_twoparticle_demo(pd_pack, shared_dir, tmp_path):
    f, scene = imported(pd_pack, shared_dir, tmp_path, "twoparticle_demo")
    vols = body_volumes(f)
    assert [len(v) for v in vols] == [916, 123]
    assert vols[1].sum() == pytest.approx(CIRCLE_VOLUME, rel=1e-6)
    assert list(f["bodies/fixed"][:]) == [1, 0]  # particle 0 held at zero displacement
    assert f["bodies/initial_velocity"][1] == pytest.approx([0, -8.944272e-02, 0])
    assert f["bodies/center"][1] == pytest.approx([0.003, 0.0076, 0])
    # Spec 2.5: rotation about the origin, then scale r / Parameters[0], then translation.
    ref = f["reference_meshes/mesh_1/nodes"][:]
    o = f["bodies/orientation"][1]
    assert o == pytest.approx(1.570796)
    c, s = math.cos(o), math.sin(o)
    expect = np.c_[c * ref[:, 0] - s * ref[:, 1], s * ref[:, 0] + c * ref[:, 1]] * 1.0 + [0.003, 0.0076]
    x = f["nodes/reference_position"][916:, :2]
    assert np.abs(x - expect).max() < 1e-15
    # Contact table: Kn per zone pair, damping eps.
    k = {(a, b): kn for a, b, kn in zip(f["contact/group_a"], f["contact/group_b"],
                                        f["contact/stiffness"])}
    assert k[(0, 0)] == pytest.approx(1.473657e26) and k[(0, 1)] == pytest.approx(3.149089e24)
    assert k[(1, 1)] == pytest.approx(1.591549e24)
    assert set(f["contact/restitution"][:]) == {0.95}
    # Contact radius 0.95 h_min over all particles (spec 4.1).
    assert f["contact/radius"][0] == pytest.approx(0.95 * f["bodies/mesh_size"][:].min())


def test_compressive_n500(pd_pack, shared_dir, tmp_path):
    f, scene = imported(pd_pack, shared_dir, tmp_path, "compressive_n500")
    vols = body_volumes(f)
    assert len(vols) == 504  # 366 circles + 136 hexagons + 2 walls (ids 502, 503)
    groups = f["bodies/group"][:]
    assert (groups == 0).sum() == 366 and (groups == 1).sum() == 136
    assert list(groups[502:]) == [2, 3]
    assert [len(v) for v in vols[502:]] == [3870, 1730]
    scale = f["bodies/scale"][:]
    for b in range(502):
        n, ref = (123, CIRCLE_VOLUME) if groups[b] == 0 else (91, HEXAGON_VOLUME)
        assert len(vols[b]) == n
        assert vols[b].sum() == pytest.approx(ref * scale[b] ** 2, rel=1e-9)
    # Scale = r_csv / Parameters[0] = r_csv / 1 mm.
    csv = np.loadtxt(shared_dir / "data/peridem/compressive_n500/particle_locations_0.csv",
                     delimiter=",", skiprows=1)
    order = np.r_[np.where(csv[:, 0] == 0)[0], np.where(csv[:, 0] == 1)[0]]
    assert scale[:502] == pytest.approx(csv[order, 4] / 1e-3, rel=1e-12)
    assert f["bodies/mesh_size"][502] == pytest.approx(1.4621e-4, rel=1e-4)
    assert f["bodies/mesh_size"][503] == pytest.approx(1.5588e-4, rel=1e-4)
    assert list(f["bodies/fixed"][502:]) == [1, 0]
    conds = scene["loading"]["conditions"]
    moving = [c for c in conds if c.get("time_function") == "linear"]
    assert moving == [{"name": "displacement_set_2", "kind": "displacement", "particles": [503],
                       "components": ["y"], "time_function": "linear", "value": -0.06}]
    assert scene["discretization"]["bond_cutoff"] == "strict"
    assert scene["solver"]["surface_correction"] is False
