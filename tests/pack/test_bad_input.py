# SPDX-License-Identifier: MIT
"""Bad scenes are refused before anything is written: exit 2, the key or the grain ids in the
message, no output file (nor a *.tmp.* left-over), and an existing output file untouched."""

import copy
import json

import pytest

from conftest import run

BASE = {
    "dimension": 2,
    "materials": {"m1": {"law": "pmb", "density": 1200, "youngs_modulus": 3.24e7,
                         "fracture_energy": 50}},
    "discretization": {"mesh_size": 2.5e-4, "horizon_factor": 3},
    "particles": [
        {"shape": "disc", "radius": 1e-3, "center": [0, 1.2e-3], "material": "m1"},
        {"shape": "disc", "radius": 1e-3, "center": [0, 3.5e-3], "material": "m1"},
    ],
    "walls": [{"type": "plane", "point": [0, 0], "normal": [0, 1]}],
    "solver": {"final_time": 1e-4},
}


def edit(fn):
    s = copy.deepcopy(BASE)
    fn(s)
    return s


def setp(path, value):
    def fn(s):
        obj = s
        for p in path[:-1]:
            obj = obj[p]
        obj[path[-1]] = value
    return fn


CASES = {
    "overlapping grains": (setp(["particles", 1, "center"], [0, 2.5e-3]),
                           ["particles[0], particles[1]", "overlap"]),
    "grain crossing a wall": (setp(["particles", 0, "center"], [0, 0.5e-3]),
                              ["particles[0], walls[0]", "crosses the wall"]),
    # horizon_factor x mesh_size against 2 x the grain's smallest node spacing (~0.7 mesh_size
    # for a disc): 1.0 is too small, 1.5 is not.
    "horizon below 2 h": (setp(["discretization", "horizon_factor"], 1.0),
                          ["discretization.horizon_factor", "less than 2 x"]),
    "horizon ratio below 2 h": (
        lambda s: s["discretization"].update({"horizon_mesh_ratio": 1.9}) or
        s["discretization"].pop("horizon_factor"),
        ["discretization.horizon_mesh_ratio", "less than 2 x"]),
    "absolute horizon below 2 h": (
        lambda s: s["discretization"].update({"horizon": 3e-4}) or
        s["discretization"].pop("horizon_factor"), ["discretization.horizon"]),
    "negative density": (setp(["materials", "m1", "density"], -1200),
                         ["materials.m1.density", "positive"]),
    "zero radius": (setp(["particles", 1, "radius"], 0), ["particles[1].radius", "positive"]),
    "zero final time": (setp(["solver", "final_time"], 0), ["solver.final_time", "positive"]),
    "zero mesh size": (setp(["discretization", "mesh_size"], 0),
                       ["discretization.mesh_size"]),
    "negative restitution": (lambda s: s.update({"contact": {"restitution": -0.5}}),
                             ["contact.restitution"]),
    "missing material": (setp(["particles", 1, "material"], "m2"),
                         ["particles[1].material", "no material named 'm2'"]),
    "material key absent": (lambda s: s["particles"][0].pop("material"),
                            ["particles[0].material", "missing"]),
    "no materials": (lambda s: s.pop("materials"), ["materials", "missing"]),
}


def check_refused(pd_pack, tmp_path, scene_text, words, existing=False):
    path = tmp_path / "scene.json"
    path.write_text(scene_text)
    out = tmp_path / "out.h5"
    if existing:
        out.write_bytes(b"previous content")
    r = run(pd_pack, path, "-o", out)
    assert r.returncode == 2, (r.returncode, r.stderr)
    for w in words:
        assert w in r.stderr, (w, r.stderr)
    left = sorted(p.name for p in tmp_path.iterdir() if p.name.startswith("out.h5"))
    if existing:
        assert left == ["out.h5"] and out.read_bytes() == b"previous content"
    else:
        assert left == [], left
    return r


def test_base_scene_packs(pd_pack, tmp_path):
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(BASE))
    r = run(pd_pack, path, "-o", tmp_path / "out.h5")
    assert r.returncode == 0, r.stderr


@pytest.mark.parametrize("case", sorted(CASES))
def test_refused(pd_pack, tmp_path, case):
    fn, words = CASES[case]
    check_refused(pd_pack, tmp_path, json.dumps(edit(fn)), words)


@pytest.mark.parametrize("case", ["overlapping grains", "missing material"])
def test_existing_output_untouched(pd_pack, tmp_path, case):
    fn, words = CASES[case]
    check_refused(pd_pack, tmp_path, json.dumps(edit(fn)), words, existing=True)


def test_bad_json(pd_pack, tmp_path):
    check_refused(pd_pack, tmp_path, json.dumps(BASE)[:-10], ["not valid JSON"])


def test_unreadable_csv(pd_pack, tmp_path):
    s = edit(lambda s: s.update({"particles": [
        {"generate": "csv", "file": "missing_grains.csv", "shapes": ["disc"], "material": "m1"}]}))
    check_refused(pd_pack, tmp_path, json.dumps(s), ["missing_grains.csv"])


def test_garbled_csv(pd_pack, tmp_path):
    (tmp_path / "grains.csv").write_text("x,y,z,r,orientation,shape\n0,1e-3,zero,1e-3,0,0\n")
    s = edit(lambda s: s.update({
        "shapes": {"disc": {"type": "circle", "radius": 1e-3}},
        "particles": [{"generate": "csv", "file": "grains.csv", "shapes": ["disc"],
                       "material": "m1"}]}))
    check_refused(pd_pack, tmp_path, json.dumps(s), ["grains.csv"])


def test_unreadable_msh(pd_pack, tmp_path):
    s = edit(lambda s: s.update({"shapes": {"disc": {"type": "circle", "radius": 1e-3,
                                                     "mesh": "file", "file": "nowhere.msh"}}}))
    check_refused(pd_pack, tmp_path, json.dumps(s), ["nowhere.msh"])


def test_garbled_msh(pd_pack, tmp_path):
    (tmp_path / "bad.msh").write_text("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0\n")
    s = edit(lambda s: s.update({"shapes": {"disc": {"type": "circle", "radius": 1e-3,
                                                     "mesh": "file", "file": "bad.msh"}}}))
    check_refused(pd_pack, tmp_path, json.dumps(s), ["bad.msh"])


def test_bad_peridem_deck(pd_pack, tmp_path, shared_dir):
    src = shared_dir / "data/peridem/single_particle_circle"
    deck = (src / "input_0.yaml").read_text()
    (tmp_path / "mesh_cir_1_0.msh").write_bytes((src / "mesh_cir_1_0.msh").read_bytes())
    bad = tmp_path / "input.yaml"
    bad.write_text(deck.replace("Density: 1.200000e+03", "Density: -1"))
    out = tmp_path / "out.h5"
    r = run(pd_pack, "--from-peridem", bad, "-o", out)
    assert r.returncode == 2 and "Material.Zone_1.Density" in r.stderr, r.stderr
    bad.write_text(deck.replace("File: mesh_cir_1_0.msh", "File: ./gone.msh"))
    r = run(pd_pack, "--from-peridem", bad, "-o", out)
    assert r.returncode == 2 and "Mesh.Zone_1.File" in r.stderr and "gone.msh" in r.stderr
    # rotation is imported now (a rigid rotation condition), but needs [omega, x0, y0(, z0)]
    bad.write_text(deck.replace("Type: linear", "Type: rotation"))
    r = run(pd_pack, "--from-peridem", bad, "-o", out)
    assert r.returncode == 2 and "Displacement_BC.Set_2.Time_Function.Parameters" in r.stderr
    bad.write_text(deck.replace("Type: linear", "Type: spline"))
    r = run(pd_pack, "--from-peridem", bad, "-o", out)
    assert r.returncode == 2 and "Displacement_BC.Set_2.Time_Function.Type" in r.stderr
    bad.write_text("Model: [unclosed\n")
    r = run(pd_pack, "--from-peridem", bad, "-o", out)
    assert r.returncode == 2 and "YAML" in r.stderr, r.stderr
    assert not out.exists()
