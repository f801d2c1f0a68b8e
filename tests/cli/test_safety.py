# SPDX-License-Identifier: MIT
"""Nothing a user types can destroy results or crash a tool (issue 13).

Each case runs one tool on a mistaken command line or a damaged file and asserts the exit code
(2: bad input), that stderr names the culprit (option, scene key or dataset path), and that the
files that existed before are untouched: byte-identical, or (pd-post, which records its run in
/provenance) identical in every dataset and attribute outside /provenance.
PD_BIN_DIR = build bin directory (skipped when unset); PD_SOURCE_DIR = source tree."""

import hashlib
import json
import math
import os
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

h5py = pytest.importorskip("h5py")

HERE = pathlib.Path(__file__).resolve().parent
SRC = pathlib.Path(os.environ.get("PD_SOURCE_DIR", HERE.parent.parent))
SCENE = json.loads(
    "\n".join(
        line
        for line in (SRC / "examples/two_discs/scene.json").read_text().splitlines()
        if not line.lstrip().startswith("//")
    )
)


@pytest.fixture(scope="module")
def bin_dir():
    d = os.environ.get("PD_BIN_DIR")
    if not d:
        pytest.skip("PD_BIN_DIR is not set (build bin directory)")
    return pathlib.Path(d)


def run(exe, *args, timeout=120, user=None):
    cmd = [str(exe), *map(str, args)]
    if user is not None:
        cmd = ["setpriv", f"--reuid={user}", f"--regid={user}", "--clear-groups", *cmd]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)


def sha(path):
    return hashlib.sha256(pathlib.Path(path).read_bytes()).hexdigest()


def h5_digest(path, skip=("/provenance",)):
    """Hash of every dataset and attribute outside `skip` (the content, not the bytes)."""
    h = hashlib.sha256()

    def attrs(obj):
        for k in sorted(obj.attrs):
            h.update(k.encode())
            h.update(repr(obj.attrs[k]).encode())

    with h5py.File(path, "r") as f:
        attrs(f)

        def visit(name, obj):
            if any(("/" + name).startswith(s) for s in skip):
                return
            h.update(name.encode())
            attrs(obj)
            if isinstance(obj, h5py.Dataset):
                h.update(np.ascontiguousarray(obj[()]).tobytes())

        f.visititems(visit)
    return h.hexdigest()


def write_scene(path, **changes):
    s = json.loads(json.dumps(SCENE))
    for key, value in changes.items():
        node = s
        parts = key.split("/")
        for p in parts[:-1]:
            node = node[int(p)] if isinstance(node, list) else node[p]
        last = parts[-1]
        if isinstance(node, list):
            node[int(last)] = value
        else:
            node[last] = value
    pathlib.Path(path).write_text(json.dumps(s))
    return pathlib.Path(path)


def assert_refused(r, *culprits, code=2):
    assert r.returncode == code, f"exit {r.returncode}\n{r.stderr}"
    low = r.stderr.lower()
    for c in culprits:
        assert c.lower() in low, f"{c!r} not named in: {r.stderr}"
    assert "terminate called" not in r.stderr and "what():" not in r.stderr


# ---------------------------------------------------------------------------------------------
# Files made once per module: a packed scene, the same with a wall, and a solved run.


@pytest.fixture(scope="module")
def made(bin_dir, tmp_path_factory):
    d = tmp_path_factory.mktemp("safety")
    base = d / "base.h5"
    r = run(bin_dir / "pd-pack", write_scene(d / "scene.json"), "-o", base, "-q")
    assert r.returncode == 0, r.stderr
    walls = d / "walls.h5"
    s = write_scene(
        d / "walls.json", walls=[{"type": "plane", "point": [0, -1.2e-3], "normal": [0, 1]}]
    )
    r = run(bin_dir / "pd-pack", s, "-o", walls, "-q")
    assert r.returncode == 0, r.stderr
    solved = d / "solved.h5"
    shutil.copy(base, solved)
    r = run(bin_dir / "pd-solve", solved, "--steps", 30, "-q")
    assert r.returncode == 0, r.stderr
    return {"base": base, "walls": walls, "solved": solved}


@pytest.fixture
def copy(made, tmp_path):
    def get(which):
        p = tmp_path / f"{which}.h5"
        shutil.copy(made[which], p)
        return p

    return get


# ---------------------------------------------------------------------------------------------
# 1. Results destroyed by ordinary mistakes


def test_pack_output_is_the_scene(bin_dir, tmp_path):
    scene = write_scene(tmp_path / "scene.json")
    before = sha(scene)
    r = run(bin_dir / "pd-pack", scene, "-o", scene)
    assert_refused(r, "-o", "scene.json")
    assert sha(scene) == before


def test_pack_output_is_the_scene_by_another_name(bin_dir, tmp_path):
    scene = write_scene(tmp_path / "scene.json")
    before = sha(scene)
    r = run(bin_dir / "pd-pack", scene, "-o", tmp_path / "." / "x" / ".." / "scene.json")
    assert_refused(r, "-o")
    assert sha(scene) == before


def test_pack_write_scene_is_the_output(bin_dir, tmp_path):
    scene = write_scene(tmp_path / "scene.json")
    out = tmp_path / "out.h5"
    r = run(bin_dir / "pd-pack", scene, "-o", out, "--write-scene", out)
    assert_refused(r, "--write-scene")
    assert not out.exists()


def test_pack_preview_is_the_scene(bin_dir, tmp_path):
    scene = write_scene(tmp_path / "scene.json")
    before = sha(scene)
    r = run(bin_dir / "pd-pack", scene, "-o", tmp_path / "out.h5", "--preview", scene)
    assert_refused(r, "--preview")
    assert sha(scene) == before
    assert not (tmp_path / "out.h5").exists()


def test_pack_output_is_a_directory(bin_dir, tmp_path):
    scene = write_scene(tmp_path / "scene.json")
    d = tmp_path / "results"
    d.mkdir()
    (d / "keep.txt").write_text("keep")
    r = run(bin_dir / "pd-pack", scene, "-o", d)
    assert_refused(r, "-o", "directory")
    assert sorted(p.name for p in d.iterdir()) == ["keep.txt"]


def test_solve_fresh_on_solved_file(bin_dir, copy):
    f = copy("solved")
    before = sha(f)
    r = run(bin_dir / "pd-solve", f)
    assert_refused(r, "--restart", "--overwrite")
    assert sha(f) == before


@pytest.mark.parametrize("steps", [0, -3])
def test_solve_steps_not_positive(bin_dir, copy, steps):
    for which in ("solved", "base"):
        f = copy(which)
        before = sha(f)
        r = run(bin_dir / "pd-solve", f, "--steps", steps, "--overwrite")
        assert_refused(r, "--steps")
        assert sha(f) == before


@pytest.mark.parametrize("value", ["inf", "nan", "-1", "0", "1e300", "-inf"])
def test_solve_final_time_bad(bin_dir, copy, value):
    f = copy("base")
    before = sha(f)
    r = run(bin_dir / "pd-solve", f, f"--final-time={value}")
    assert_refused(r, "--final-time")
    assert sha(f) == before


@pytest.mark.parametrize("value", ["1e300", "nan", "1e-9"])
def test_restart_final_time_bad(bin_dir, copy, value):
    f = copy("solved")
    before = sha(f)
    r = run(bin_dir / "pd-solve", f, "--restart", f"--final-time={value}")
    assert_refused(r, "final time" if value == "1e-9" else "--final-time")
    assert sha(f) == before


def test_solve_final_time_earlier_without_restart(bin_dir, copy):
    f = copy("solved")
    before = sha(f)
    r = run(bin_dir / "pd-solve", f, "--final-time", "1e-9")
    assert_refused(r, "--overwrite")
    assert sha(f) == before


def test_solve_compress_out_of_range(bin_dir, copy):
    f = copy("solved")
    before = sha(f)
    r = run(bin_dir / "pd-solve", f, "--restart", "--compress", 12)
    assert r.returncode not in (0, 3, 4) and "--compress" in r.stderr + r.stdout
    assert sha(f) == before


@pytest.mark.parametrize("value", ["nan", "-1"])
def test_solve_energy_tolerance_bad(bin_dir, copy, value):
    f = copy("solved")
    before = sha(f)
    r = run(bin_dir / "pd-solve", f, "--restart", f"--energy-tolerance={value}")
    assert r.returncode not in (0, 3, 4), r.stderr
    assert "--energy-tolerance" in r.stderr + r.stdout
    assert sha(f) == before


@pytest.mark.parametrize(
    "attr, value, culprit",
    [
        ("step", -5, "step"),
        ("dt", float("nan"), "dt"),
        ("dt", -1e-9, "dt"),
        ("time", float("inf"), "time"),
        ("time", 1.0e3, "time"),
        ("step", 2**62, "step"),
    ],
)
def test_restart_bad_checkpoint(bin_dir, copy, attr, value, culprit):
    f = copy("solved")
    with h5py.File(f, "r+") as h:
        g = h["checkpoints"][h["checkpoints"].attrs["latest"]]
        g.attrs[attr] = np.int64(value) if attr == "step" else np.float64(value)
    before = sha(f)
    r = run(bin_dir / "pd-solve", f, "--restart")
    assert_refused(r, "/checkpoints/step_", culprit)
    assert sha(f) == before


def test_solve_overwrite_replaces_frames(bin_dir, copy):
    f = copy("solved")
    r = run(bin_dir / "pd-solve", f, "--overwrite", "--steps", 20, "-q")
    assert r.returncode == 0, r.stderr
    with h5py.File(f, "r") as h:
        assert h["checkpoints"].attrs["latest"] == "step_000000000020"


def test_restart_continues(bin_dir, copy):
    f = copy("solved")
    r = run(bin_dir / "pd-solve", f, "--restart", "--steps", 10, "-q")
    assert r.returncode == 0, r.stderr
    with h5py.File(f, "r") as h:
        assert h["checkpoints"].attrs["latest"] == "step_000000000040"


def as_user(path):
    """(uid, path) to run a tool as `nobody` on a read-only copy (root ignores file modes)."""
    if os.geteuid() != 0:
        return None
    if shutil.which("setpriv") is None:
        pytest.skip("setpriv is missing")
    d = path.parent
    for p in [d, *d.parents]:
        if p == pathlib.Path("/"):
            break
        os.chmod(p, os.stat(p).st_mode | 0o711)
    return 65534


@pytest.mark.parametrize("which", ["base", "solved"])
def test_solve_read_only_file(bin_dir, copy, which):
    f = copy(which)
    os.chmod(f, 0o444)
    user = as_user(f)
    before = sha(f)
    args = ["--restart"] if which == "solved" else []
    r = run(bin_dir / "pd-solve", f, *args, user=user)
    assert_refused(r, str(f), "writ")
    assert sha(f) == before


def test_partition_read_only_file(bin_dir, copy):
    f = copy("base")
    os.chmod(f, 0o444)
    user = as_user(f)
    before = sha(f)
    r = run(bin_dir / "pd-partition", f, "-n", 2, user=user)
    assert_refused(r, str(f), "writ")
    assert sha(f) == before


@pytest.mark.parametrize("parts", [0, -2])
def test_partition_parts_not_positive(bin_dir, copy, parts):
    f = copy("base")
    before = h5_digest(f)
    r = run(bin_dir / "pd-partition", f, "-n", parts)
    assert_refused(r, "-n")
    assert h5_digest(f) == before


# ---------------------------------------------------------------------------------------------
# 2. Crashes instead of messages (scenes)


@pytest.mark.parametrize(
    "changes, culprit",
    [
        ({"particles/0/radius": 1e30}, "particles[0].radius"),
        ({"particles/0/radius": -1e-3}, "particles[0].radius"),
        ({"discretization/mesh_size": 1e-7}, "--max-nodes"),
        ({"discretization/mesh_size": 0}, "mesh_size"),
        ({"particles/1/center": [1e300, 0]}, "center"),
    ],
    ids=["radius_1e30", "radius_negative", "mesh_size_1e-7", "mesh_size_0", "center_1e300"],
)
def test_pack_bad_scene(bin_dir, tmp_path, changes, culprit):
    scene = write_scene(tmp_path / "scene.json", **changes)
    before = sha(scene)
    out = tmp_path / "out.h5"
    out.write_bytes(b"previous result")
    r = run(bin_dir / "pd-pack", scene, "-o", out, timeout=60)
    assert_refused(r, culprit)
    assert sha(scene) == before and out.read_bytes() == b"previous result"


def test_pack_number_overflow(bin_dir, tmp_path):
    scene = write_scene(tmp_path / "scene.json")
    scene.write_text(scene.read_text().replace('"radius": 0.001', '"radius": 1e999', 1))
    assert "1e999" in scene.read_text()
    r = run(bin_dir / "pd-pack", scene, "-o", tmp_path / "out.h5")
    assert_refused(r, str(scene), "1e999")
    assert not (tmp_path / "out.h5").exists()


def test_pack_regular_polygon_many_sides(bin_dir, tmp_path):
    scene = write_scene(
        tmp_path / "scene.json",
        shapes={"p": {"type": "regular_polygon", "sides": 1000000000, "radius": 1e-3}},
        **{"particles/0/shape": "p"},
    )
    r = run(bin_dir / "pd-pack", scene, "-o", tmp_path / "out.h5", timeout=60)
    assert_refused(r, "sides")
    assert not (tmp_path / "out.h5").exists()


def test_pack_count_1e9(bin_dir, tmp_path):
    gen = {
        "generate": "random_pack",
        "container": {"type": "rectangle", "size": [0.05, 0.03]},
        "count": 1000000000,
        "radius": [0.9e-3, 1.1e-3],
        "seed": 7,
        "material": "m1",
    }
    scene = write_scene(tmp_path / "scene.json", particles=[gen])
    r = run(bin_dir / "pd-pack", scene, "-o", tmp_path / "out.h5", timeout=60)
    assert_refused(r, "count", "--max-nodes")
    assert not (tmp_path / "out.h5").exists()


@pytest.mark.parametrize("counts, culprit", [(["a", 2], "counts[0]"), ([-1, 2], "counts")])
def test_pack_lattice_counts_bad(bin_dir, tmp_path, counts, culprit):
    gen = {
        "generate": "lattice",
        "origin": [0, 0],
        "counts": counts,
        "spacing": [3e-3, 3e-3],
        "radius": [1e-3, 1e-3],
        "material": "m1",
    }
    scene = write_scene(tmp_path / "scene.json", particles=[gen])
    r = run(bin_dir / "pd-pack", scene, "-o", tmp_path / "out.h5", timeout=60)
    assert_refused(r, culprit)
    assert not (tmp_path / "out.h5").exists()


def test_pack_max_nodes_limit_and_raise(bin_dir, tmp_path):
    scene = write_scene(tmp_path / "scene.json")
    r = run(bin_dir / "pd-pack", scene, "-o", tmp_path / "out.h5", "--max-nodes", 100)
    assert_refused(r, "--max-nodes")
    assert not (tmp_path / "out.h5").exists()
    r = run(bin_dir / "pd-pack", scene, "-o", tmp_path / "out.h5", "--max-nodes", 10000, "-q")
    assert r.returncode == 0, r.stderr


@pytest.mark.parametrize("value", ["0", "-5", "nan"])
def test_pack_max_nodes_bad(bin_dir, tmp_path, value):
    scene = write_scene(tmp_path / "scene.json")
    r = run(bin_dir / "pd-pack", scene, "-o", tmp_path / "out.h5", f"--max-nodes={value}")
    assert r.returncode not in (0, 3, 4) and "--max-nodes" in r.stderr + r.stdout
    assert not (tmp_path / "out.h5").exists()


def test_pack_youngs_modulus_huge(bin_dir, tmp_path):
    scene = write_scene(tmp_path / "scene.json", **{"materials/m1/youngs_modulus": 1e300})
    r = run(bin_dir / "pd-pack", scene, "-o", tmp_path / "out.h5")
    assert_refused(r, "youngs_modulus")


def test_pack_negative_contact_stiffness(bin_dir, tmp_path):
    scene = write_scene(tmp_path / "scene.json", **{"contact/stiffness": -1e12})
    r = run(bin_dir / "pd-pack", scene, "-o", tmp_path / "out.h5")
    assert_refused(r, "stiffness")


# ---------------------------------------------------------------------------------------------
# 3. Damaged files: every tool that reads the model refuses them naming the dataset


def set_entry(path, dataset, index, value):
    with h5py.File(path, "r+") as h:
        d = h[dataset]
        a = d[()]
        if a.ndim == 0:
            d[()] = value
        else:
            a[index] = value
            d[...] = a


DAMAGE = [
    ("base", "/bodies/group", 0, 1_000_000_000),
    ("base", "/bodies/group", 1, -1),
    ("base", "/contact/group_a", 0, -1),
    ("base", "/contact/group_b", 0, 2_000_000_000),
    ("walls", "/walls/group", 0, -7),
    ("base", "/bodies/node_offsets", 1, 400),
    ("base", "/nodes/body", 3, 1),
    ("base", "/contact/stiffness", 0, -1e12),
    ("base", "/contact/radius", 0, -1e-4),
    ("base", "/contact/friction", 0, float("nan")),
    ("base", "/materials/m1/youngs_modulus", None, 1e300),
    ("base", "/materials/m1/density", None, float("inf")),
    ("base", "/materials/m1/poisson_ratio", None, float("nan")),
    ("base", "/solver/final_time", None, float("inf")),
    ("base", "/solver/dt", None, -1.0),
    ("base", "/solver/output_interval", None, float("nan")),
    ("base", "/solver/observe_every", None, -4),
]


SOLVE_ONLY = ("/solver/dt", "/solver/observe_every")  # read by pd-solve alone
DAMAGE_CASES = [
    (tool, *d)
    for d in DAMAGE
    for tool in ("pd-solve", "pd-partition", "pd-post-check")
    if tool == "pd-solve" or d[1] not in SOLVE_ONLY
]


@pytest.mark.parametrize(
    "tool, which, dataset, index, value",
    DAMAGE_CASES,
    ids=[f"{c[0]}:{c[2]}={c[4]}" for c in DAMAGE_CASES],
)
def test_damaged_model(bin_dir, copy, tool, which, dataset, index, value):
    f = copy(which)
    set_entry(f, dataset, index, value)
    before = sha(f)
    args = {
        "pd-solve": ["pd-solve", f],
        "pd-partition": ["pd-partition", f, "-n", 2],
        "pd-post-check": ["pd-post", "--check", f],
    }[tool]
    r = run(bin_dir / args[0], *args[1:], timeout=60)
    assert_refused(r, dataset)
    if tool != "pd-post-check":
        assert sha(f) == before


# ---------------------------------------------------------------------------------------------
# pd-post


@pytest.mark.parametrize("field", ["position", "velocity"])
def test_post_nan_in_frames(bin_dir, copy, tmp_path, field):
    f = copy("solved")
    with h5py.File(f, "r+") as h:
        v = h[f"particles/nodes/{field}/value"]
        a = v[()]
        a[0, 5, 1] = np.nan
        v[...] = a
    before = h5_digest(f)
    r = run(bin_dir / "pd-post", f, "-o", tmp_path / "out")
    assert_refused(r, f"/particles/nodes/{field}/value")
    assert h5_digest(f) == before


def test_post_output_is_the_file(bin_dir, copy):
    f = copy("solved")
    before = sha(f)
    r = run(bin_dir / "pd-post", f, "-o", f)
    assert_refused(r, "-o")
    assert sha(f) == before


def test_post_output_is_a_file(bin_dir, copy, tmp_path):
    f = copy("solved")
    other = tmp_path / "notes.txt"
    other.write_text("keep")
    before = sha(f)
    r = run(bin_dir / "pd-post", f, "-o", other)
    assert_refused(r, "-o", "notes.txt")
    assert other.read_text() == "keep" and sha(f) == before


def test_post_read_only_file(bin_dir, copy, tmp_path):
    """Documented choice: the outputs are written, a warning says provenance was not recorded."""
    f = copy("solved")
    os.chmod(f, 0o444)
    user = as_user(f)
    out = tmp_path / "out"
    out.mkdir()
    os.chmod(out, 0o777)
    before = sha(f)
    r = run(bin_dir / "pd-post", f, "-o", out, user=user)
    assert r.returncode == 0, r.stderr
    assert "provenance" in r.stderr.lower() and "warning" in r.stderr.lower()
    assert (out / "observables.csv").is_file() and list(out.glob("*.vtu"))
    assert sha(f) == before
