# SPDX-License-Identifier: MIT
"""The bad-input matrix (issue 13, item 7), with tests/cli/test_safety.py: scene keys and values,
geometry, STL and CSV files (pd-pack), HDF5 files with datasets deleted, reshaped, truncated,
overwritten with random bytes or not HDF5 at all (pd-solve, pd-partition, pd-post), and
command-line values. Each case asserts exit 2, the culprit (key, dataset, file or option) in the
message, and that every file that existed before is byte-identical afterwards. The number of
cases per tool is printed at the end of the run (tests/cli/conftest.py)."""

import json
import os
import pathlib
import shutil

import numpy as np
import pytest

from test_safety import SCENE, assert_refused, bin_dir, copy, made, run, sha, write_scene  # noqa: F401

h5py = pytest.importorskip("h5py")

SCENE_CASES = [
    # (id, changes {json-path: value}, culprit)
    ("density_negative", {"materials/m1/density": -1200}, "materials.m1.density"),
    ("density_zero", {"materials/m1/density": 0}, "materials.m1.density"),
    ("density_huge", {"materials/m1/density": 1e300}, "materials.m1.density"),
    ("density_string", {"materials/m1/density": "heavy"}, "density"),
    ("youngs_zero", {"materials/m1/youngs_modulus": 0}, "youngs_modulus"),
    ("youngs_negative", {"materials/m1/youngs_modulus": -3e7}, "youngs_modulus"),
    ("fracture_energy_negative", {"materials/m1/fracture_energy": -50}, "fracture_energy"),
    ("law_unknown", {"materials/m1/law": "rubber"}, "law"),
    ("material_unknown_key", {"materials/m1/colour": "red"}, "colour"),
    ("dimension_4", {"dimension": 4}, "dimension"),
    ("dimension_1", {"dimension": 1}, "dimension"),
    ("dimension_string", {"dimension": "2"}, "dimension"),
    ("horizon_factor_negative", {"discretization/horizon_factor": -3}, "horizon_factor"),
    ("horizon_factor_zero", {"discretization/horizon_factor": 0}, "horizon_factor"),
    ("mesh_size_negative", {"discretization/mesh_size": -1e-4}, "mesh_size"),
    ("mesh_size_huge", {"discretization/mesh_size": 1.0}, "h = 1 m"),
    ("center_short", {"particles/0/center": [0]}, "center"),
    ("center_string", {"particles/0/center": "origin"}, "center"),
    ("velocity_short", {"particles/0/velocity": [1]}, "velocity"),
    ("shape_unknown", {"particles/0/shape": "blob"}, "blob"),
    ("group_negative", {"particles/0/group": -1}, "group"),
    ("group_huge", {"particles/0/group": 1e9}, "group"),
    ("orientation_string", {"particles/0/orientation": "up"}, "orientation"),
    ("particle_unknown_key", {"particles/0/colour": "red"}, "colour"),
    ("particles_empty", {"particles": []}, "particles"),
    ("particles_object", {"particles": {}}, "particles"),
    ("radius_factor_negative", {"contact/radius_factor": -1}, "radius_factor"),
    ("radius_factor_zero", {"contact/radius_factor": 0}, "radius_factor"),
    ("contact_stiffness_word", {"contact/stiffness": "stiff"}, "stiffness"),
    ("contact_stiffness_negative", {"contact/stiffness": -1.0}, "stiffness"),
    ("restitution_above_1", {"contact/restitution": 1.5}, "restitution"),
    ("friction_negative", {"contact/friction": -0.1}, "friction"),
    ("gravity_short", {"loading/gravity": [0]}, "gravity"),
    ("gravity_huge", {"loading/gravity": [0, -1e300]}, "gravity"),
    ("damping_negative", {"loading/viscous_damping": -1}, "viscous_damping"),
    ("final_time_negative", {"solver/final_time": -1}, "final_time"),
    ("final_time_huge", {"solver/final_time": 1e300}, "final_time"),
    ("dt_negative", {"solver/dt": -1e-8}, "dt"),
    ("dt_word", {"solver/dt": "fast"}, "dt"),
    ("output_interval_negative", {"solver/output_interval": -1}, "output_interval"),
    ("checkpoint_interval_negative", {"solver/checkpoint_interval": -1}, "checkpoint_interval"),
    ("fields_unknown", {"solver/fields": ["temperature"]}, "temperature"),
    ("top_level_typo", {"partciles": []}, "partciles"),
    ("wall_zero_normal", {"walls": [{"type": "plane", "point": [0, -2e-3], "normal": [0, 0]}]}, "normal"),
    ("wall_type_unknown", {"walls": [{"type": "cylinder", "point": [0, -2e-3]}]}, "type"),
    ("shape_radius_negative", {"shapes": {"disc": {"type": "hexagon", "radius": -1e-3}}}, "radius"),
    ("shape_type_unknown", {"shapes": {"disc": {"type": "blob", "radius": 1e-3}}}, "type"),
    ("ellipse_one_axis", {"shapes": {"disc": {"type": "ellipse", "semi_axes": [1e-3]}}}, "semi_axes"),
    ("polygon_two_vertices", {"shapes": {"disc": {"type": "polygon", "vertices": [[0, 0], [1e-3, 0]]}}}, "3 vertices"),
    ("polygon_sides_2", {"shapes": {"disc": {"type": "regular_polygon", "sides": 2, "radius": 1e-3}}}, "sides"),
    ("polygon_sides_fraction", {"shapes": {"disc": {"type": "regular_polygon", "sides": 5.5, "radius": 1e-3}}}, "sides"),
    ("stl_missing", {"dimension": 3, "shapes": {"disc": {"type": "surface_mesh", "file": "nowhere.stl"}}}, "nowhere.stl"),
    ("stl_garbled", {"dimension": 3, "shapes": {"disc": {"type": "surface_mesh", "file": "garbled.stl"}}}, "garbled.stl"),
    ("stl_empty", {"dimension": 3, "shapes": {"disc": {"type": "surface_mesh", "file": "empty.stl"}}}, "empty.stl"),
    ("csv_missing_column", {"particles": [{"generate": "csv", "file": "short.csv", "shapes": ["disc"], "material": "m1"}]}, "short.csv"),
    ("csv_negative_radius", {"particles": [{"generate": "csv", "file": "negr.csv", "shapes": ["disc"], "material": "m1"}]}, "negr.csv"),
    ("csv_shape_index", {"particles": [{"generate": "csv", "file": "shape9.csv", "shapes": ["disc"], "material": "m1"}]}, "shapes"),
    ("pack_count_fraction", {"particles": [{"generate": "random_pack", "container": {"type": "rectangle", "size": [0.02, 0.02]}, "count": 2.5, "radius": [1e-3, 1e-3], "material": "m1"}]}, "count"),
    ("pack_radius_reversed", {"particles": [{"generate": "random_pack", "container": {"type": "rectangle", "size": [0.02, 0.02]}, "count": 3, "radius": [2e-3, 1e-3], "material": "m1"}]}, "radius"),
    ("pack_no_container", {"particles": [{"generate": "random_pack", "count": 3, "radius": [1e-3, 1e-3], "material": "m1"}]}, "container"),
    ("generator_unknown", {"particles": [{"generate": "scatter", "material": "m1"}]}, "generate"),
]
FILES = {
    "garbled.stl": b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 zero\n",
    "empty.stl": b"",
    "short.csv": b"x,y,z,r,orientation,shape\n0,0,0\n",
    "negr.csv": b"x,y,z,r,orientation,shape\n0,0,0,-1e-3,0,0\n",
    "shape9.csv": b"x,y,z,r,orientation,shape\n0,0,0,1e-3,0,9\n",
}


# A random_pack that cannot fit fails at once with the fraction it needed (168 s before).
SCENE_CASES.append(
    ("pack_cannot_fit",
     {"particles": [{"generate": "random_pack",
                     "container": {"type": "rectangle", "size": [0.05, 0.03]}, "count": 600,
                     "radius": [0.9e-3, 1.1e-3], "seed": 7, "material": "m1"}]},
     "packing fraction of 1.25"))


@pytest.mark.parametrize("cid, changes, culprit", SCENE_CASES, ids=[f"pd-pack:{c[0]}" for c in SCENE_CASES])
def test_pack_scene_matrix(bin_dir, tmp_path, cid, changes, culprit):
    for name, data in FILES.items():
        (tmp_path / name).write_bytes(data)
    scene = write_scene(tmp_path / "scene.json", **changes)
    out = tmp_path / "out.h5"
    out.write_bytes(b"previous result")
    before = {p.name: sha(p) for p in tmp_path.iterdir()}
    r = run(bin_dir / "pd-pack", scene, "-o", out, timeout=60)
    assert_refused(r, culprit)
    assert {p.name: sha(p) for p in tmp_path.iterdir()} == before  # nothing new, nothing changed


# ---------------------------------------------------------------------------------------------
# Damaged files

TOOLS = {
    "pd-solve": lambda f: ["pd-solve", f],
    "pd-partition": lambda f: ["pd-partition", f, "-n", 2],
    "pd-post-check": lambda f: ["pd-post", "--check", f],
}
DELETED = ["/nodes/reference_position", "/nodes/volume", "/nodes/body", "/bodies/node_offsets",
           "/bonds/neighbor", "/bonds/offsets", "/bodies/material", "/bodies/horizon",
           "/materials/m1/density", "/contact/stiffness", "/solver/final_time", "/bodies/group",
           "/bodies/fixed", "/loading/gravity"]
DELETE_CASES = [(t, d) for d in DELETED for t in TOOLS]


@pytest.mark.parametrize("tool, dataset", DELETE_CASES, ids=[f"{t}:deleted:{d}" for t, d in DELETE_CASES])
def test_deleted_dataset(bin_dir, copy, tool, dataset):
    f = copy("base")
    with h5py.File(f, "r+") as h:
        del h[dataset]
    before = sha(f)
    args = TOOLS[tool](f)
    r = run(bin_dir / args[0], *args[1:], timeout=60)
    assert_refused(r, dataset)
    if tool != "pd-post-check":
        assert sha(f) == before


# A dataset one row short (an array) or turned into two entries (a scalar): the message names it,
# or the dataset it disagrees with.
RESHAPED = {
    "/nodes/reference_position": ["/nodes/reference_position"],
    "/nodes/volume": ["/nodes/volume", "/nodes/reference_position"],
    "/nodes/body": ["/nodes/body"],
    "/bodies/node_offsets": ["/bodies/node_offsets"],
    "/bonds/offsets": ["/bonds/offsets"],
    "/bodies/material": ["/bodies/material", "/bodies/node_offsets"],
    "/materials/m1/density": ["/materials/m1/density"],
    "/solver/dt": ["/solver/dt"],
}
RESHAPE_CASES = [(t, d) for d in RESHAPED for t in ("pd-solve", "pd-partition")]


@pytest.mark.parametrize("tool, dataset", RESHAPE_CASES, ids=[f"{t}:reshaped:{d}" for t, d in RESHAPE_CASES])
def test_reshaped_dataset(bin_dir, copy, tool, dataset):
    f = copy("base")
    with h5py.File(f, "r+") as h:
        a = np.asarray(h[dataset][()])
        del h[dataset]
        h[dataset] = a[:-1] if a.ndim > 0 else np.array([a, a])
    before = sha(f)
    args = TOOLS[tool](f)
    r = run(bin_dir / args[0], *args[1:], timeout=60)
    assert r.returncode == 2 and any(d in r.stderr for d in RESHAPED[dataset]), r.stderr
    assert sha(f) == before


READERS = {
    "pd-solve": lambda f, o: ["pd-solve", f, "--restart"],
    "pd-partition": lambda f, o: ["pd-partition", f, "-n", 2],
    "pd-post": lambda f, o: ["pd-post", f, "-o", o],
    "pd-post-check": lambda f, o: ["pd-post", "--check", f],
}
TRUNC_CASES = [(t, frac) for frac in (0.3, 0.9) for t in READERS]


@pytest.mark.parametrize("tool, frac", TRUNC_CASES, ids=[f"{t}:truncated_{x}" for t, x in TRUNC_CASES])
def test_truncated_file(bin_dir, copy, tmp_path, tool, frac):
    f = copy("solved")
    os.truncate(f, int(f.stat().st_size * frac))
    before = sha(f)
    args = READERS[tool](f, tmp_path / "out")
    r = run(bin_dir / args[0], *args[1:], timeout=60)
    assert_refused(r, str(f), "truncated")
    assert sha(f) == before and not (tmp_path / "out").exists()


@pytest.mark.parametrize("tool", list(READERS), ids=[f"{t}:not_hdf5" for t in READERS])
def test_not_hdf5(bin_dir, tmp_path, tool):
    f = tmp_path / "results.h5"
    f.write_text("these are my notes, not an HDF5 file\n" * 20)
    before = sha(f)
    args = READERS[tool](f, tmp_path / "out")
    r = run(bin_dir / args[0], *args[1:], timeout=60)
    assert_refused(r, str(f))
    assert sha(f) == before


@pytest.mark.parametrize("tool", list(READERS), ids=[f"{t}:missing_file" for t in READERS])
def test_missing_file(bin_dir, tmp_path, tool):
    f = tmp_path / "nowhere.h5"
    args = READERS[tool](f, tmp_path / "out")
    r = run(bin_dir / args[0], *args[1:], timeout=60)
    # pd-solve and pd-partition check the path while parsing (CLI11's ExistingFile), pd-post
    # when it opens the file: exit 2 either way
    assert r.returncode == 2, r.stderr
    assert "nowhere.h5" in r.stderr + r.stdout, r.stderr
    assert not f.exists()


RANDOM_CASES = [(t, fld) for fld in ("position", "velocity", "force") for t in ("pd-post", "pd-post-check")]


@pytest.mark.parametrize("tool, field", RANDOM_CASES, ids=[f"{t}:random_bytes_in_{x}" for t, x in RANDOM_CASES])
def test_random_bytes_in_a_frame(bin_dir, copy, tmp_path, tool, field):
    """4 KiB of random bytes written over a frame's data (uncompressed chunks): refused naming
    the dataset (exit 0 before)."""
    f = copy("solved")
    ds = f"/particles/nodes/{field}/value"
    with h5py.File(f, "r") as h:
        info = h[ds].id.get_chunk_info(0)
    assert info.size >= 8192
    with open(f, "r+b") as out:
        out.seek(info.byte_offset + 2048)
        out.write(np.random.default_rng(13).bytes(4096))
    args = READERS[tool](f, tmp_path / "out")
    r = run(bin_dir / args[0], *args[1:], timeout=60)
    assert_refused(r, ds if tool == "pd-post" else "/particles/nodes/")


# ---------------------------------------------------------------------------------------------
# Command-line values

OPTION_CASES = [
    ("pd-solve", "solved", ["--restart", "--steps", "abc"], "--steps"),
    ("pd-solve", "solved", ["--restart", "--compress", "-1"], "--compress"),
    ("pd-solve", "base", ["--final-time", "1e301"], "--final-time"),
    ("pd-solve", "base", ["--bogus-option"], "--bogus-option"),
    ("pd-partition", "base", ["-n", "abc"], "--parts"),
    ("pd-partition", "base", ["-n", "2", "--by", "colour"], "--by"),
    ("pd-post", "solved", ["--crack-origin", "1"], "--crack-origin"),
    ("pd-post", "solved", ["--crack-direction", "1,2,3,4"], "--crack-direction"),
    ("pd-post", "solved", ["--bogus-option"], "--bogus-option"),
]


@pytest.mark.parametrize("tool, which, args, culprit", OPTION_CASES,
                         ids=[f"{c[0]}:{' '.join(c[2])}" for c in OPTION_CASES])
def test_bad_option(bin_dir, copy, tmp_path, tool, which, args, culprit):
    f = copy(which)
    before = sha(f)
    extra = ["-o", tmp_path / "out"] if tool == "pd-post" else []
    r = run(bin_dir / tool, f, *args, *extra, timeout=60)
    assert r.returncode == 2, r.stderr
    assert culprit in r.stderr + r.stdout, r.stderr + r.stdout
    assert sha(f) == before


# Command-line usage errors found by CLI11 while parsing (a required argument missing, a value
# that does not convert, an unknown option): exit 2 like any bad input (CLI11's own codes
# 105-109 before), CLI11's message naming the culprit on stderr, nothing written.
USAGE_CASES = [
    # (tool, which file (None: no file argument), args, culprit)
    ("pd-pack", None, [], "SCENE"),
    ("pd-pack", "scene", ["--max-nodes", "lots"], "--max-nodes"),
    ("pd-pack", "scene", ["--bogus-option"], "--bogus-option"),
    ("pd-pack", "scene", ["--parity", "peridem"], "--parity"),
    ("pd-partition", None, ["-n", "2"], "file"),
    ("pd-partition", "base", [], "--parts"),
    ("pd-partition", "base", ["-n", "2.5"], "--parts"),
    ("pd-partition", "base", ["-n", "2", "--bogus-option"], "--bogus-option"),
    ("pd-solve", None, [], "file"),
    ("pd-solve", "solved", ["--restart", "--steps", "1e3x"], "--steps"),
    ("pd-solve", "solved", ["--restart", "--bogus-option"], "--bogus-option"),
    ("pd-post", None, [], "file"),
    ("pd-post", "solved", ["--progress-seconds", "soon"], "--progress-seconds"),
    ("pd-post", "solved", ["--bogus-option"], "--bogus-option"),
]


@pytest.mark.parametrize("tool, which, args, culprit", USAGE_CASES,
                         ids=[f"{c[0]}:usage:{' '.join(c[2]) or 'no_file'}" for c in USAGE_CASES])
def test_usage_error(bin_dir, copy, tmp_path, tool, which, args, culprit):
    files = []
    if which == "scene":
        files = [write_scene(tmp_path / "scene.json")]
    elif which is not None:
        files = [copy(which)]
    before = [sha(f) for f in files]
    out = tmp_path / "out"
    extra = ["-o", out] if tool in ("pd-pack", "pd-post") and which is not None else []
    r = run(bin_dir / tool, *files, *args, *extra, timeout=60)
    assert_refused(r, culprit)
    assert "Run with --help for more information." in r.stderr, r.stderr
    assert [sha(f) for f in files] == before
    assert not out.exists()


@pytest.mark.parametrize("tool", ["pd-pack", "pd-partition", "pd-solve", "pd-post"])
def test_help_and_version_exit_0(bin_dir, tool):
    """The other side of usage_exit(): CLI11's --help and --version are not errors."""
    r = run(bin_dir / tool, "--help", timeout=60)
    assert r.returncode == 0 and "Usage:" in r.stdout and tool in r.stdout, r.stderr
    r = run(bin_dir / tool, "--version", timeout=60)
    assert r.returncode == 0 and "(pdgrain)" in r.stdout, r.stderr
