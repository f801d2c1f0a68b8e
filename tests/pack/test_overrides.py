# SPDX-License-Identifier: MIT
"""pd-pack --set PATH=VALUE (dotted paths, indices, JSON pointers; values parsed as JSON) and
--print-scene (the resolved scene as plain JSON); the overrides land in /parameters/overrides,
/parameters/scene and the pd-pack /provenance entry; a path that does not exist is exit 2
naming the closest key."""
import json
import subprocess

import h5py
import pytest
from conftest import REPO, run

SCENE = REPO / "examples" / "two_discs" / "scene.json"  # has // comments


def test_print_scene_is_plain_json_with_the_overrides(pd_pack):
    r = run(pd_pack, SCENE, "--print-scene", "--set", "contact.restitution=0.5",
            "--set", "/discretization/mesh_size=2e-4", "--set", "particles[1].velocity=[-1, 0]",
            "--set", "particles.0.material=m1", "--set", "materials.m1.law=lps",
            "--set", "materials.m1.poisson_ratio=0.25")
    assert r.returncode == 0, r.stderr
    s = json.loads(r.stdout)  # nothing but the JSON on stdout
    assert s["contact"]["restitution"] == 0.5
    assert s["discretization"]["mesh_size"] == 2e-4
    assert s["particles"][1]["velocity"] == [-1, 0]
    assert s["materials"]["m1"]["law"] == "lps"  # a bare word is a string
    plain = run(pd_pack, SCENE, "--print-scene")
    assert json.loads(plain.stdout)["title"] == "two discs, head-on elastic collision"


@pytest.mark.parametrize("path, closest", [
    ("contact.stiffnes", "contact.stiffness"),
    ("contcat.restitution", "contact"),
    ("/materials/m2/density", "m1"),
])
def test_unknown_path_is_exit_2_with_the_closest_key(pd_pack, path, closest):
    r = run(pd_pack, SCENE, "--print-scene", "--set", f"{path}=1")
    assert r.returncode == 2, r.stderr
    assert closest in r.stderr and "did you mean" in r.stderr


def test_new_key_is_checked_when_the_scene_is_built(pd_pack, tmp_path):
    """A key absent from the scene may be added (contact.restitution here); a misspelt one is
    refused by the scene's key check, naming the closest valid key."""
    r = run(pd_pack, SCENE, "-q", "-o", tmp_path / "x.h5", "--set", "contact.restitutoin=0.5")
    assert r.returncode == 2 and "did you mean 'restitution'" in r.stderr, r.stderr
    r = run(pd_pack, SCENE, "-q", "-o", tmp_path / "y.h5", "--set", "contact.restitution=0.5")
    assert r.returncode == 0, r.stderr


def test_index_out_of_range_and_bad_form_are_exit_2(pd_pack):
    r = run(pd_pack, SCENE, "--print-scene", "--set", "particles.2.radius=1")
    assert r.returncode == 2 and "2 entries" in r.stderr
    r = run(pd_pack, SCENE, "--print-scene", "--set", "contact.restitution")
    assert r.returncode == 2 and "PATH=VALUE" in r.stderr


def test_overrides_recorded_in_the_file(pd_pack, tmp_path):
    out = tmp_path / "o.h5"
    r = run(pd_pack, SCENE, "-q", "-o", out, "--set", "contact.restitution=0.5",
            "--set", "materials.m1.youngs_modulus=2e9")
    assert r.returncode == 0, r.stderr
    with h5py.File(out, "r") as h:
        over = json.loads(h["parameters/overrides"][()])
        assert over == {"contact.restitution": 0.5, "materials.m1.youngs_modulus": 2e9}
        scene = json.loads(h["parameters/scene"][()])
        assert scene["contact"]["restitution"] == 0.5
        assert scene["materials"]["m1"]["youngs_modulus"] == 2e9
        entry = h["provenance"][sorted(h["provenance"])[-1]]
        assert json.loads(entry.attrs["overrides"]) == over
        assert float(h["contact/restitution"][()].max()) == 0.5 if "contact/restitution" in h \
            else True
    chk = subprocess.run(["/usr/bin/python3", str(REPO / "data-schema" / "check_pd_file.py"),
                          str(out)], capture_output=True, text=True)
    assert chk.returncode == 0, chk.stdout + chk.stderr
    plain = tmp_path / "p.h5"
    assert run(pd_pack, SCENE, "-q", "-o", plain).returncode == 0
    with h5py.File(plain, "r") as h:
        assert "overrides" not in h["parameters"]
        assert "overrides" not in h["provenance"][sorted(h["provenance"])[-1]].attrs


@pytest.mark.parametrize("example", ["two_discs/scene.json", "attrition_sim1/scene.json",
                                     "ellipse_on_tip/scene_pmb.json"])
def test_print_scene_defaults_fills_every_default_and_packs_the_same(pd_pack, tmp_path,
                                                                     example):
    """--print-scene --defaults (issue 28): the schema's defaults the scene leaves out appear
    (solver.dt_safety, contact.friction, materials' law, ...), what the scene gives is kept, and
    the printed scene packs to the same file as the scene (nodes, bonds, contact table, solver
    settings)."""
    scene = REPO / "examples" / example
    plain = json.loads(run(pd_pack, scene, "--print-scene").stdout)
    r = run(pd_pack, scene, "--print-scene", "--defaults")
    assert r.returncode == 0, r.stderr
    full = json.loads(r.stdout)
    assert full["solver"]["dt_safety"] == plain["solver"].get("dt_safety", 0.85)
    assert full["solver"]["integrator"] == plain["solver"].get("integrator", "velocity_verlet")
    assert full["solver"]["observe_every"] == plain["solver"].get("observe_every", 10)
    assert "friction" in full["contact"] and "restitution" in full["contact"]
    assert all("law" in m for m in full["materials"].values())
    for k, v in plain["solver"].items():
        assert full["solver"][k] == v  # the scene's own values are kept
    filled = tmp_path / "filled.json"
    filled.write_text(r.stdout)
    a, b = tmp_path / "a.h5", tmp_path / "b.h5"
    assert run(pd_pack, scene, "-q", "-o", a).returncode == 0
    rb = run(pd_pack, filled, "-q", "-o", b)
    assert rb.returncode == 0, rb.stderr
    with h5py.File(a, "r") as fa, h5py.File(b, "r") as fb:
        for p in ["nodes/position", "bonds/offsets", "bonds/neighbor"]:
            if p in fa:
                assert (fa[p][...] == fb[p][...]).all(), p
        for g in ["contact", "solver"]:
            for k in fa[g]:
                if isinstance(fa[g][k], h5py.Dataset):
                    assert (fa[g][k][...] == fb[g][k][...]).all(), f"{g}/{k}"


def test_defaults_needs_print_scene(pd_pack, tmp_path):
    r = run(pd_pack, SCENE, "--defaults", "-o", tmp_path / "x.h5")
    assert r.returncode == 2
