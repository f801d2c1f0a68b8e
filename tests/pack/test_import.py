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


def decks(shared):
    return sorted(p.parent.name for p in (shared / "data" / "peridem").glob("*/input_0.yaml"))


def test_every_shared_deck_imports(pd_pack, shared_dir, tmp_path):
    """Every deck PeriDEM 0.2.x runs imports (compression_small_set: horizon 0.4 mm below 2 x
    its grains' smallest node spacing, 0.215 mm: a warning, not a refusal)."""
    names = decks(shared_dir)
    assert {"compression_small_set", "twop_circ", "compressive_n500"} <= set(names)
    for case in names:
        deck = shared_dir / "data" / "peridem" / case / "input_0.yaml"
        out = tmp_path / f"{case}.h5"
        r = run(pd_pack, "--from-peridem", deck, "-o", out)
        assert r.returncode == 0, f"{case}: {r.stderr}"
        with h5py.File(out, "r") as f:
            assert f["nodes/volume"].shape[0] > 0
        if case == "compression_small_set":
            assert "horizon below 2 x" in r.stderr and "small_horizon" in r.stderr
            with h5py.File(out, "r") as f:
                # 15 grains + fixed container + moving lid; every grain's horizon 0.4 mm
                assert len(f["bodies/horizon"]) == 17
                assert np.allclose(f["bodies/horizon"][()], 4e-4)


def test_parity_maps_the_2d_pdstate_material(pd_pack, shared_dir, tmp_path):
    """--parity peridem: mu' = 15 G / 8, kappa' = 9 K / 4 (plane strain K3' = kappa' - mu'/3),
    Gc' keeping PeriDEM's 3D s0; the default mode keeps K and G and says how they differ."""
    deck = shared_dir / "data" / "peridem" / "single_particle_circle" / "input_0.yaml"
    K, G, Gc, delta = 2.16e5, 1.296e5, 500.0, 6e-4
    scene = tmp_path / "p.json"
    r = run(pd_pack, "--from-peridem", deck, "--parity", "peridem", "-o", tmp_path / "p.h5",
            "--write-scene", scene)
    assert r.returncode == 0, r.stderr
    s = json.loads(scene.read_text())
    m = s["materials"]["zone_1"]
    mu, kappa = 15 * G / 8, 9 * K / 4
    assert s["planar"] == "plane_strain"
    assert m["shear_modulus"] == pytest.approx(mu, rel=1e-12)
    assert m["bulk_modulus"] == pytest.approx(kappa - mu / 3, rel=1e-12)
    s0_peridem = math.sqrt(Gc / ((3 * G + 0.75 ** 4 * (K - 5 * G / 3)) * delta))
    d2 = 6 * mu / math.pi + 16 / (9 * math.pi ** 2) * (kappa - 2 * mu)
    assert math.sqrt(m["fracture_energy"] / (d2 * delta)) == pytest.approx(s0_peridem, rel=1e-12)
    r = run(pd_pack, "--from-peridem", deck, "-o", tmp_path / "d.h5", "--write-scene",
            tmp_path / "d.json")
    assert r.returncode == 0 and "--parity peridem" in r.stdout + r.stderr
    assert json.loads((tmp_path / "d.json").read_text())["materials"]["zone_1"][
        "youngs_modulus"] == pytest.approx(9 * K * G / (3 * K + G))


def test_parity_single_particle_circle_against_peridem(pd_pack, shared_dir, tmp_path):
    """PeriDEM 0.2.1's own run of single_particle_circle (shared README), t = 0.01 s: max |u|
    over free nodes 5.682177e-5 m, centre node (2.544201e-5, 2.545276e-5) m. --parity peridem
    gives 5.68238e-5 (+3.7e-5 relative) and (2.54397e-5, 2.54524e-5) (-9e-5); the default mode
    (consistent 2D LPS) 5.6550e-5 (-0.48 %)."""
    solve = pd_pack.parent / "pd-solve"
    deck = shared_dir / "data" / "peridem" / "single_particle_circle" / "input_0.yaml"
    got = {}
    for mode, extra in (("parity", ["--parity", "peridem"]), ("default", [])):
        h5 = tmp_path / f"{mode}.h5"
        assert run(pd_pack, "--from-peridem", deck, *extra, "-o", h5, "-q").returncode == 0
        r = run(solve, h5, "-q", "--final-time", "0.0101")
        assert r.returncode == 0, r.stderr
        with h5py.File(h5, "r") as f:
            t = f["particles/nodes/position/time"][()]
            k = int(np.argmin(abs(t - 0.01)))
            assert t[k] == pytest.approx(0.01, abs=1e-9)
            u = f["particles/nodes/displacement/value"][k]
            x0 = f["nodes/reference_position"][()]
            held = np.zeros(len(x0), bool)
            for c in f["loading/conditions"]:
                held[f["loading/conditions"][c]["nodes"][()]] = True
        centre = int(np.argmin(np.linalg.norm(x0, axis=1)))
        got[mode] = (np.linalg.norm(u[~held], axis=1).max(), u[centre][:2])
    umax, c = got["parity"]
    assert umax == pytest.approx(5.682177e-5, rel=1e-4)
    assert c[0] == pytest.approx(2.544201e-5, rel=2e-4)
    assert c[1] == pytest.approx(2.545276e-5, rel=2e-4)
    # the mapping matters: without it the grain is softer and moves 0.5 % less
    assert got["default"][0] == pytest.approx(5.682177e-5 * (1 - 4.8e-3), rel=5e-4)


def test_parity_undamped_twop_circ_against_peridem(pd_pack, shared_dir, tmp_path):
    """PeriDEM 0.2.1's run of twop_circ with Damping_On: false (shared README): node contact from
    step 14058 to 14213, impact speed of the upper disc 0.1316167 m/s, rebound 0.1309946 m/s.
    --parity peridem (its material, symplectic Euler, its Kn and dt with --force-dt) gives the
    same steps and 0.1316137 / 0.1309946 m/s (the speeds one step before and after contact)."""
    solve = pd_pack.parent / "pd-solve"
    src = shared_dir / "data" / "peridem" / "twop_circ"
    for p in src.iterdir():
        (tmp_path / p.name).write_bytes(p.read_bytes())
    deck = tmp_path / "input_0.yaml"
    text = deck.read_text()
    deck.write_text(text.replace("Epsilon: 9.000000e-01",
                                 "Epsilon: 9.000000e-01\n    Damping_On: false"))
    h5 = tmp_path / "t.h5"
    r = run(pd_pack, "--from-peridem", deck, "--parity", "peridem", "-o", h5, "-q",
            "--set", "solver.observe_every=1")
    assert r.returncode == 0, r.stderr
    r = run(solve, h5, "-q", "--force-dt")
    assert r.returncode == 0, r.stderr
    with h5py.File(h5, "r") as f:
        p = f["observables/momentum/value"][()]
        step = f["observables/momentum/step"][()]
        touching = f["observables/contact_count/value"][()] > 0
        off = f["bodies/node_offsets"][()]
        assert list(f["bodies/fixed"][()]) == [1, 0]
        mass = f["materials"][next(iter(f["materials"]))]["density"][()] * \
            f["nodes/volume"][off[1]:off[2]].sum()
    vy = p[:, 1] / mass  # the lower disc is fixed: the momentum is the upper disc's
    on = np.nonzero(touching)[0]
    assert (step[on[0]], step[on[-1]]) == (14058, 14213)
    assert -vy[on[0] - 1] == pytest.approx(0.1316167, rel=5e-5)
    assert vy[on[-1] + 1] == pytest.approx(0.1309946, rel=2e-6)


def test_peridem_03_json_deck(pd_pack, shared_dir, tmp_path):
    """PeriDEM 0.3 reads JSON decks with the 0.2 blocks plus Model.MPI_Strategy and
    Output.PVD_Collection: twop_circ written as such a JSON deck imports to the same model."""
    yaml = pytest.importorskip("yaml")
    src = shared_dir / "data" / "peridem" / "twop_circ"
    for p in src.iterdir():
        (tmp_path / p.name).write_bytes(p.read_bytes())
    deck = yaml.safe_load((tmp_path / "input_0.yaml").read_text())
    deck["Model"]["MPI_Strategy"] = "particle"
    deck["Output"]["PVD_Collection"] = True
    (tmp_path / "input.json").write_text(json.dumps(deck, indent=1))
    for name in ("input_0.yaml", "input.json"):
        r = run(pd_pack, "--from-peridem", tmp_path / name, "-o", tmp_path / (name + ".h5"), "-q")
        assert r.returncode == 0, r.stderr
    with h5py.File(tmp_path / "input_0.yaml.h5", "r") as a, \
            h5py.File(tmp_path / "input.json.h5", "r") as b:
        for path in ("nodes/reference_position", "nodes/volume", "bonds/neighbor",
                     "contact/stiffness", "bodies/fixed"):
            assert np.array_equal(a[path][()], b[path][()]), path
        assert len(a["nodes/volume"]) == 246


def test_rotating_meshed_wall_imports_as_rotation(pd_pack, shared_dir, tmp_path):
    """A PeriDEM rotation BC (attrition drums, spec 5.6/5.9: [omega, x0, y0, z0]) on a meshed
    wall becomes a rigid-body rotation condition of its nodes (compression_small_set with its
    container rotating at -40 pi rad/s about (1, 2) mm); after pd-solve the container's nodes
    sit at R(omega t)(X - c) + c to round-off."""
    src = shared_dir / "data" / "peridem" / "compression_small_set"
    for p in src.iterdir():
        (tmp_path / p.name).write_bytes(p.read_bytes())
    deck = tmp_path / "input_0.yaml"
    omega, cx, cy = -40 * math.pi, 1e-3, 2e-3
    text = deck.read_text().replace(
        "    Particle_List: [15]\n    Direction: [1,2]\n    Zero_Displacement: true\n",
        "    Particle_List: [15]\n    Direction: [1,2]\n    Time_Function:\n      Type: rotation\n"
        f"      Parameters: [{omega!r}, {cx}, {cy}, 0.0]\n")
    assert "Type: rotation" in text
    deck.write_text(text)
    h5, scene = tmp_path / "rot.h5", tmp_path / "rot.json"
    r = run(pd_pack, "--from-peridem", deck, "-o", h5, "--write-scene", scene,
            "--set", "solver.final_time=2e-4", "--set", "solver.output_interval=1e-4")
    assert r.returncode == 0, r.stderr
    c = [c for c in json.loads(scene.read_text())["loading"]["conditions"]
         if c.get("time_function") == "rotation"]
    assert len(c) == 1 and c[0]["particles"] == [15]
    assert c[0]["value"] == pytest.approx(omega) and c[0]["rotation_center"] == [cx, cy]
    r = run(pd_pack.parent / "pd-solve", h5, "-q", "--force-dt")
    assert r.returncode == 0, r.stderr
    with h5py.File(h5, "r") as f:
        off = f["bodies/node_offsets"][()]
        X = f["nodes/reference_position"][off[15]:off[16]]
        t = f["particles/nodes/position/time"][-1]
        x = f["particles/nodes/position/value"][-1, off[15]:off[16]]
    th = omega * t
    rx, ry = X[:, 0] - cx, X[:, 1] - cy
    np.testing.assert_allclose(x[:, 0], cx + np.cos(th) * rx - np.sin(th) * ry, atol=1e-15)
    np.testing.assert_allclose(x[:, 1], cy + np.sin(th) * rx + np.cos(th) * ry, atol=1e-15)
    assert abs(th) > 0.02  # it did turn


def test_parity_breaks_bonds_in_compression(pd_pack, shared_dir, tmp_path):
    """PeriDEM breaks bonds at |s| > s0 (spec 1.3): --parity peridem sets the material's
    break_in_compression (scene key and /materials/<name>/break_in_compression = 1); the default
    mode keeps pdgrain's tension-only breaking (0) and says so."""
    deck = shared_dir / "data" / "peridem" / "single_particle_circle" / "input_0.yaml"
    r = run(pd_pack, "--from-peridem", deck, "--parity", "peridem", "-o", tmp_path / "p.h5",
            "--write-scene", tmp_path / "p.json")
    assert r.returncode == 0, r.stderr
    assert json.loads((tmp_path / "p.json").read_text())["materials"]["zone_1"][
        "break_in_compression"] is True
    with h5py.File(tmp_path / "p.h5", "r") as f:
        assert f["materials/zone_1/break_in_compression"][()] == 1
    r = run(pd_pack, "--from-peridem", deck, "-o", tmp_path / "d.h5", "--write-scene",
            tmp_path / "d.json")
    assert r.returncode == 0, r.stderr
    assert "tension only" in r.stdout + r.stderr
    assert "break_in_compression" not in json.loads((tmp_path / "d.json").read_text())[
        "materials"]["zone_1"]
    with h5py.File(tmp_path / "d.h5", "r") as f:
        assert f["materials/zone_1/break_in_compression"][()] == 0


def test_kn_zero_and_wall_pairs_mean_no_contact(pd_pack, shared_dir, tmp_path):
    """Issue 28: a deck's Kn 0 is no contact (PeriDEM applies no force), not "auto", and two wall
    zones never interact (PeriDEM skips wall-wall pairs): compression_small_set's container
    (zone 9) and plate (zone 10) had pushed on each other from step 0 (Zone_99 Kn 0, Zone_910 a
    copy of it)."""
    f, scene = imported(pd_pack, shared_dir, tmp_path, "compression_small_set")
    pairs = {tuple(p["groups"]): p for p in scene["contact"]["pairs"]}
    for g in [(8, 8), (8, 9), (9, 9)]:
        assert pairs[g]["stiffness"] == 0, g
    assert all(p["stiffness"] == "auto" or p["stiffness"] > 0
               for g, p in pairs.items() if max(g) < 8)
    f.close()


def test_spatial_rotation_is_constant_as_peridem_computes_it(pd_pack, shared_dir, tmp_path):
    """Issue 28: the drum deck attrition_mix_particles_small_set pairs a rotation Time_Function
    with Spatial_Function 'rotation', which PeriDEM 0.2.1 evaluates as S = 1 (its displacements
    evaluate sin_x/y and linear_x/y only): imported as constant with a note, not refused. A type
    PeriDEM does evaluate but pdgrain cannot express (sin_y) is still refused."""
    src = shared_dir / "data" / "peridem" / "compression_small_set"
    for p in src.iterdir():
        (tmp_path / p.name).write_bytes(p.read_bytes())
    deck = tmp_path / "input_0.yaml"
    base = deck.read_text()
    old = "    Particle_List: [15]\n    Direction: [1,2]\n    Zero_Displacement: true\n"
    assert old in base

    def with_spatial(kind):
        deck.write_text(base.replace(old, (
            "    Particle_List: [15]\n    Direction: [1,2]\n    Time_Function:\n"
            "      Type: rotation\n      Parameters: [-10.0, 1.0e-3, 2.0e-3, 0.0]\n"
            f"    Spatial_Function:\n      Type: {kind}\n      Parameters: [0.0, 1.0e-3, 2.0e-3]\n")))
        scene = tmp_path / f"{kind}.json"
        return run(pd_pack, "--from-peridem", deck, "-o", tmp_path / f"{kind}.h5",
                   "--write-scene", scene), scene

    r, scene = with_spatial("rotation")
    assert r.returncode == 0, r.stderr
    assert "Spatial_Function.Type 'rotation': constant, as PeriDEM computes it" in r.stdout
    c = [c for c in json.loads(scene.read_text())["loading"]["conditions"]
         if c.get("time_function") == "rotation"]
    assert len(c) == 1 and c[0].get("space_function", "constant") == "constant"
    assert c[0]["value"] == pytest.approx(-10.0)
    r, _ = with_spatial("sin_y")
    assert r.returncode == 2 and "'sin_y' cannot be expressed" in r.stderr, r.stderr


def test_deck_dt_above_the_estimate_runs_with_a_warning(pd_pack, shared_dir, tmp_path):
    """Issue 28: PeriDEM runs its decks at their dt; compression_small_set's 2.5e-6 s (or what the
    shipped deck gives) exceeds pdgrain's estimate. Imported decks write
    solver.dt_above_estimate "warn" (/solver/dt_above_estimate = 1): pd-solve warns with the
    estimate and runs; the same file without it is refused (exit 2) as a native scene is."""
    deck = shared_dir / "data" / "peridem" / "compression_small_set" / "input_0.yaml"
    h5, scene = tmp_path / "c.h5", tmp_path / "c.json"
    r = run(pd_pack, "--from-peridem", deck, "-o", h5, "--write-scene", scene, "-q")
    assert r.returncode == 0, r.stderr
    assert json.loads(scene.read_text())["solver"]["dt_above_estimate"] == "warn"
    # Nor does PeriDEM stop where a node tunnels (its drum deck does at 5.7 ms): a warning.
    assert json.loads(scene.read_text())["solver"]["penetration"] == "warn"
    with h5py.File(h5, "r") as f:
        assert f["solver/dt_above_estimate"][()] == 1
        assert f["solver/penetration_warns"][()] == 1
    r = run(pd_pack.parent / "pd-solve", h5, "--steps", 20)
    assert r.returncode == 0, r.stderr
    assert "exceeds the stability estimate" in r.stderr, r.stderr
    assert "(solver.dt_above_estimate: warn)" in r.stderr, r.stderr
    with h5py.File(h5, "r+") as f:
        del f["solver/dt_above_estimate"]
    r = run(pd_pack.parent / "pd-solve", h5, "--overwrite", "--steps", 20)
    assert r.returncode == 2 and "--force-dt" in r.stderr, r.stderr
