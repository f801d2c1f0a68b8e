# SPDX-License-Identifier: MIT
"""Bounded work (issue 27, item 6): every input whose cost is not bounded by the node limit is
refused early with exit 2 and a message naming the key, within seconds, the scene and any
existing output untouched. Classes: JSON nesting (scene and --set), grain counts whose nodes are
not known before meshing (lattice of a shape meshed from a file or not defined), numbers that do
not convert to counts, thin shapes (few nodes per area, a long boundary; the grid method's
bounding-box lattice), bonds (a large horizon multiplies bonds, not nodes), random placement
(tries and relaxation steps), unions/differences and polygons (parts, vertices and the work of
their Boolean operations, counted from the scene before any shape is built), and pd-file
datasets and attributes declared larger than the file can hold (allocation before the read)."""

import json
import math
import pathlib
import time

import pytest

from test_safety import SCENE, assert_refused, bin_dir, run, sha  # noqa: F401 (fixture)

h5py = pytest.importorskip("h5py")
np = pytest.importorskip("numpy")


def scene_file(path, mutate=None, text=None):
    s = json.loads(json.dumps(SCENE))
    if mutate:
        mutate(s)
    pathlib.Path(path).write_text(text if text is not None else json.dumps(s))
    return pathlib.Path(path)


def pack_refused(bin_dir, tmp_path, scene, *culprits, extra=(), limit_s=30):
    """pd-pack refuses `scene` (exit 2, culprits named) fast; scene and output untouched."""
    before = sha(scene)
    out = tmp_path / "out.h5"
    out.write_bytes(b"previous result")
    t0 = time.monotonic()
    r = run(bin_dir / "pd-pack", scene, "-o", out, *extra, timeout=120)
    took = time.monotonic() - t0
    assert_refused(r, *culprits)
    assert took < limit_s, f"refused after {took:.1f} s"
    assert sha(scene) == before and out.read_bytes() == b"previous result"
    return r


# ---------------------------------------------------------------------------------------------
# JSON nesting: the parser stops at 64 levels (a deep scene dumped with its indentation grew
# quadratically: a 100 kB scene ran out of memory, a 60 kB --set value took 47 s).


def nested(kind, depth):
    return ("[" * depth + "]" * depth) if kind == "array" else ('{"a":' * depth + "1" + "}" * depth)


@pytest.mark.parametrize("kind", ["array", "object"])
@pytest.mark.parametrize("depth", [65, 50000])
def test_scene_nesting_refused(bin_dir, tmp_path, kind, depth):
    text = json.dumps(SCENE)[:-1] + ', "title": ' + nested(kind, depth) + "}"
    scene = scene_file(tmp_path / "scene.json", text=text)
    pack_refused(bin_dir, tmp_path, scene, "nested more than 64 levels")


@pytest.mark.parametrize("key", ["particles", "contact", "solver"])
def test_scene_nesting_refused_anywhere(bin_dir, tmp_path, key):
    s = json.loads(json.dumps(SCENE))
    marker = "@@DEEP@@"
    s.setdefault(key, {})
    if isinstance(s[key], list):
        s[key][0]["velocity"] = marker
    else:
        s[key]["x"] = marker
    text = json.dumps(s).replace(json.dumps(marker), nested("array", 20000))
    scene = scene_file(tmp_path / "scene.json", text=text)
    pack_refused(bin_dir, tmp_path, scene, "nested more than 64 levels")


@pytest.mark.parametrize("kind", ["array", "object"])
def test_set_value_nesting_refused(bin_dir, tmp_path, kind):
    scene = scene_file(tmp_path / "scene.json")
    value = nested(kind, 20000)  # 40 to 100 kB (one argument: at most 128 kB)
    pack_refused(bin_dir, tmp_path, scene, "--set solver.final_time", "nested more than 64",
                 extra=("--set", f"solver.final_time={value}"), limit_s=10)


def test_shallow_nesting_still_reads(bin_dir, tmp_path):
    """Depth 60 inside a key is read (and then refused as the wrong type, not as too deep)."""
    text = json.dumps(SCENE)[:-1] + ', "title": ' + nested("array", 60) + "}"
    scene = scene_file(tmp_path / "scene.json", text=text)
    r = run(bin_dir / "pd-pack", scene, "-o", tmp_path / "out.h5")
    assert r.returncode == 2 and "nested more than" not in r.stderr, r.stderr
    assert "title" in r.stderr


# ---------------------------------------------------------------------------------------------
# Grain counts: each grain has a node at least, whatever its shape.


def lattice(counts, shapes=None, **kw):
    g = {"generate": "lattice", "origin": [0, 0], "counts": counts, "spacing": [3e-3, 3e-3],
         "radius": [1e-3, 1e-3], "material": "m1", **kw}
    if shapes is not None:
        g["shapes"] = shapes
    return g


@pytest.mark.parametrize("shapes, named", [
    ({"nowhere": 1}, None),  # not defined: its nodes were counted 0, the lattice generated
    ({"m": 1}, {"m": {"type": "circle", "radius": 1e-3, "mesh": "file", "file": "m.msh"}}),
], ids=["undefined_shape", "shape_from_file"])
@pytest.mark.parametrize("counts", [[100000, 100000], [1e7, 1e7]], ids=["1e10", "1e14"])
def test_lattice_count_bounded(bin_dir, tmp_path, shapes, named, counts):
    def mutate(s):
        s["particles"] = [lattice(counts, shapes)]
        if named:
            s["shapes"] = named
    scene = scene_file(tmp_path / "scene.json", mutate)
    pack_refused(bin_dir, tmp_path, scene, "particles[0].counts", "--max-nodes",
                 extra=("--max-nodes", 4000), limit_s=10)


@pytest.mark.parametrize("value", [1e300, -1, 2.5, "3", True, None],
                         ids=["1e300", "negative", "fraction", "string", "bool", "null"])
def test_lattice_count_not_a_count(bin_dir, tmp_path, value):
    scene = scene_file(tmp_path / "scene.json",
                       lambda s: s.update(particles=[lattice([value, 2])]))
    pack_refused(bin_dir, tmp_path, scene, "particles[0].counts[0]", "whole number")


# ---------------------------------------------------------------------------------------------
# Thin shapes: few nodes for their area, but gmsh puts nodes along the whole boundary and the
# grid method visits the bounding box's lattice.


@pytest.mark.parametrize("shape", [
    {"type": "rectangle", "size": [1e3, 1e-6]},
    {"type": "rectangle", "size": [1e-6, 1e3]},
    {"type": "ellipse", "semi_axes": [1e3, 1e-6]},
    {"type": "polygon", "vertices": [[0, 0], [1e3, 0], [1e3, 1e-6]]},
    {"type": "rectangle", "size": [1e3, 1e-6], "mesh": "grid"},
    {"type": "rectangle", "size": [50, 1e-6], "rotation": 0.785, "mesh": "grid"},
], ids=["rect_x", "rect_y", "ellipse", "sliver", "grid", "grid_rotated"])
def test_thin_shape_bounded(bin_dir, tmp_path, shape):
    def mutate(s):
        s["shapes"] = {"thin": shape}
        for p in s["particles"]:
            p["shape"] = "thin"
            p.pop("radius", None)
        s["particles"] = s["particles"][:1]
        s.pop("walls", None)
    scene = scene_file(tmp_path / "scene.json", mutate)
    pack_refused(bin_dir, tmp_path, scene, "shapes.thin", "--max-nodes",
                 extra=("--max-nodes", 100000), limit_s=10)


# ---------------------------------------------------------------------------------------------
# Bonds: horizon_factor 300 packed 81 s and ended in bad_alloc; refused by the bond estimate.


@pytest.mark.parametrize("disc", [
    {"horizon_factor": 300},
    {"horizon_factor": 40},
    {"horizon": 1.0},
    {"horizon_mesh_ratio": 300},
], ids=["factor_300", "factor_40", "absolute_1m", "ratio_300"])
def test_bond_estimate_bounded(bin_dir, tmp_path, disc):
    def mutate(s):
        d = s["discretization"]
        for k in ("horizon", "horizon_factor", "horizon_mesh_ratio"):
            d.pop(k, None)
        d.update(disc)
        d["mesh_size"] = d["mesh_size"] / 4  # about 5000 nodes per grain
    scene = scene_file(tmp_path / "scene.json", mutate)
    key = "discretization." + next(iter(disc))
    r = pack_refused(bin_dir, tmp_path, scene, key, "bonds", "--max-nodes",
                     extra=("--max-nodes", 20000), limit_s=10)
    assert "nodes and" in r.stderr


def test_bond_estimate_counts_grain_size(bin_dir, tmp_path):
    """A large horizon on small grains: each node has at most the grain's nodes as bonds, so the
    scene (2 grains of about 300 nodes: 2e5 bonds, not 300 x 2.8e5) packs."""
    def mutate(s):
        d = s["discretization"]
        d.pop("horizon", None)
        d.pop("horizon_mesh_ratio", None)
        d["horizon_factor"] = 300
    scene = scene_file(tmp_path / "scene.json", mutate)
    r = run(bin_dir / "pd-pack", scene, "-o", tmp_path / "out.h5", "--max-nodes", 10000, "-q")
    assert r.returncode == 0, r.stderr


# ---------------------------------------------------------------------------------------------
# Random placement: the tries and relaxation steps are bounded by the node limit.


def test_random_pack_work_bounded(bin_dir, tmp_path):
    """A ring 1.5 grain diameters wide holds one file of about 628 grains: 625 jam random
    placement (a try lands in the ring 1 time in 70) and leave the relaxation nearly no room
    (it ran up to 100000 sweeps)."""
    ring = {"type": "difference", "base": {"type": "circle", "radius": 0.1},
            "minus": [{"type": "circle", "radius": 0.1 - 1.5e-3}]}
    gen = {"generate": "random_pack", "container": ring, "count": 625,
           "radius": [0.5e-3, 0.5e-3], "seed": 3, "material": "m1"}

    def mutate(s):
        s["particles"] = [gen]
        s["discretization"]["mesh_size"] = 0.5e-3
        s.pop("walls", None)
    scene = scene_file(tmp_path / "scene.json", mutate)
    pack_refused(bin_dir, tmp_path, scene, "particles[0]", "gave up after",
                 extra=("--max-nodes", 4000), limit_s=20)


# ---------------------------------------------------------------------------------------------
# pd-file datasets and attributes declared larger than the file holds: refused before the
# allocation, by every tool that reads them.


@pytest.fixture(scope="module")
def packed(bin_dir, tmp_path_factory):
    d = tmp_path_factory.mktemp("bounded")
    scene = scene_file(d / "scene.json")
    r = run(bin_dir / "pd-pack", scene, "-o", d / "base.h5", "-q")
    assert r.returncode == 0, r.stderr
    return d / "base.h5"


def forge_dataset(src, dst, path, rows):
    dst.write_bytes(src.read_bytes())
    with h5py.File(dst, "r+") as f:
        old = f[path]
        inner, dtype = old.shape[1:], old.dtype
        del f[path]
        f.create_dataset(path, shape=(rows, *inner), maxshape=(None, *inner), dtype=dtype,
                         chunks=(1024, *inner))  # never written: no chunk stored


@pytest.mark.parametrize("path", ["/nodes/reference_position", "/nodes/volume",
                                  "/bonds/offsets", "/bonds/neighbor"])
@pytest.mark.parametrize("tool", ["pd-solve", "pd-partition", "pd-post --check"])
def test_huge_declared_dataset_refused(bin_dir, tmp_path, packed, path, tool):
    with h5py.File(packed, "r") as f:
        if path not in f:
            pytest.skip(f"{path} not in this pd-file version")
    f = tmp_path / "forged.h5"
    forge_dataset(packed, f, path, 10**11)
    before = sha(f)
    exe, *args = tool.split()
    if exe == "pd-partition":
        args = ["-n", "2"]
    t0 = time.monotonic()
    r = run(bin_dir / exe, *args, f, timeout=120)
    # the first dataset of its group read: too large for the file; the others: the wrong shape,
    # checked before the read
    assert_refused(r, path.rsplit("/", 1)[0] + "/")  # neighbor: refused as offsets disagree
    assert any(w in r.stderr for w in ("refused before allocating", "expected", "must rise")), \
        r.stderr
    assert time.monotonic() - t0 < 20
    assert sha(f) == before


# ---------------------------------------------------------------------------------------------
# Unions, differences and polygons: a shape's geometry is built as the scene is read (2D: CGAL's
# exact Boolean operations, each CSG node rebuilding its subtree; 3D: octree quadrature), before
# any node estimate. Counted from the JSON first (geometry/shapes.hpp limits). Before: 30
# disjoint circles in a union packed in 12 s, 100 in 209 s (310 MB).


def circles(k, sep=3e-3, r=1e-3):
    return [{"type": "circle", "radius": r, "offset": [i * sep, 0]} for i in range(k)]


def ngon(n, x=0.0, r=1e-3):
    return [[x + r * math.cos(2 * math.pi * j / n), r * math.sin(2 * math.pi * j / n)]
            for j in range(n)]


def chain(depth, r=1e-3):
    """union(union(... union(circle, circle), ...), circle): each level rebuilds those below."""
    sh = {"type": "circle", "radius": r}
    for i in range(depth):
        sh = {"type": "union", "parts": [sh, {"type": "circle", "radius": r,
                                              "offset": [(i + 1) * r, 0]}]}
    return sh


def shapes_scene(tmp_path, shapes, dim=2, container=None):
    def mutate(s):
        s["shapes"] = shapes
        if dim == 3:
            s["dimension"] = 3
            s["shapes"]["ball"] = {"type": "sphere", "radius": 1e-3}
            for p in s["particles"]:
                p.update(shape="ball", center=p["center"] + [0], velocity=p["velocity"] + [0])
                p.pop("radius", None)
            s["loading"]["gravity"] = [0, 0, 0]
            s["discretization"]["mesh_size"] = 4e-4
        if container is not None:
            s["particles"] = [{"generate": "random_pack", "container": container, "count": 2,
                               "radius": [1e-3, 1e-3], "seed": 1, "material": "m1"}]
            s.pop("walls", None)
    return scene_file(tmp_path / "scene.json", mutate)


def shape_refused(bin_dir, tmp_path, scene, *culprits):
    """pack_refused, and a fresh output name is not created."""
    r = pack_refused(bin_dir, tmp_path, scene, *culprits, limit_s=5)
    fresh = tmp_path / "fresh.h5"
    r2 = run(bin_dir / "pd-pack", scene, "-o", fresh)
    assert r2.returncode == 2 and not fresh.exists(), r2.stderr
    return r


@pytest.mark.parametrize("shape, dim, culprits", [
    ({"type": "union", "parts": circles(300)}, 2, ["shapes.blob", "300 parts", "limit of 256"]),
    ({"type": "union", "parts": [{"type": "sphere", "radius": 1e-3, "offset": [i * 3e-3, 0, 0]}
                                 for i in range(257)]}, 3, ["shapes.blob", "257 parts"]),
    ({"type": "difference", "base": {"type": "circle", "radius": 1.0},
      "minus": circles(400, r=1e-4)}, 2, ["shapes.blob", "401 parts"]),
], ids=["union_2d", "union_3d", "difference_holes"])
def test_csg_parts_bounded(bin_dir, tmp_path, shape, dim, culprits):
    scene = shapes_scene(tmp_path, {"blob": shape}, dim)
    shape_refused(bin_dir, tmp_path, scene, *culprits)


@pytest.mark.parametrize("shape", [
    {"type": "union", "parts": circles(30)},                          # 9.2e5: 12 s before
    {"type": "union", "parts": circles(100)},                         # 1e7: 209 s before
    {"type": "difference", "base": {"type": "circle", "radius": 1.0},
     "minus": circles(30, r=1e-3)},                                   # 9.8e5: 13.5 s before
    chain(20),                                                        # 4.7e5: 16.6 s before
    {"type": "union", "parts": [{"type": "polygon", "vertices": ngon(9000, 3e-3 * i)}
                                for i in range(8)]},                  # 8 x 9000 vertices
], ids=["circles_30", "circles_100", "difference_30", "nested_20", "polygons_8x9000"])
def test_csg_work_bounded(bin_dir, tmp_path, shape):
    scene = shapes_scene(tmp_path, {"blob": shape})
    shape_refused(bin_dir, tmp_path, scene, "shapes.blob", "vertex operations", "limit of 3e+05")


def test_csg_work_bounded_in_a_container(bin_dir, tmp_path):
    scene = shapes_scene(tmp_path, {}, container={"type": "union", "parts": circles(30)})
    shape_refused(bin_dir, tmp_path, scene, "particles[0].container", "vertex operations")


def test_csg_work_summed_over_the_scene(bin_dir, tmp_path):
    """Each shape under the limit (1e5 vertex operations), the scene's shapes together above it:
    refused at the shape that crosses it."""
    shapes = {f"s{k}": {"type": "union", "parts": circles(10)} for k in range(4)}
    scene = shapes_scene(tmp_path, shapes)
    shape_refused(bin_dir, tmp_path, scene, "shapes.s2", "up to this one need 3.07e+05")


@pytest.mark.parametrize("where", ["alone", "in_union"])
def test_polygon_vertices_bounded(bin_dir, tmp_path, where):
    poly = {"type": "polygon", "vertices": ngon(10001)}
    shape = poly if where == "alone" else {"type": "union", "parts": [
        {"type": "circle", "radius": 1e-3}, poly]}
    key = "shapes.blob.vertices" if where == "alone" else "shapes.blob.parts[1].vertices"
    scene = shapes_scene(tmp_path, {"blob": shape})
    shape_refused(bin_dir, tmp_path, scene, key, "10001 vertices", "limit of 10000")


def test_csg_under_the_limits_still_packs(bin_dir, tmp_path):
    """Ten disjoint circles (1e5 vertex operations) and a 2D chain of 5 unions pack; so does a
    3D union of 64 spheres."""
    shapes = {"ten": {"type": "union", "parts": circles(10)},
              "chain": chain(5),
              "poly": {"type": "polygon", "vertices": ngon(10000)}}
    r = run(bin_dir / "pd-pack", shapes_scene(tmp_path, shapes), "-o", tmp_path / "a.h5", "-q")
    assert r.returncode == 0, r.stderr
    balls = {"type": "union", "parts": [
        {"type": "sphere", "radius": 1e-3, "offset": [1.5e-3 * i, 1.5e-3 * j, 1.5e-3 * k]}
        for i in range(4) for j in range(4) for k in range(4)]}
    (tmp_path / "3d").mkdir()
    r = run(bin_dir / "pd-pack", shapes_scene(tmp_path / "3d", {"blob": balls}, 3), "-o",
            tmp_path / "b.h5", "-q")
    assert r.returncode == 0, r.stderr


@pytest.mark.parametrize("where", ["alone", "in_union"])
def test_surface_mesh_file_bounded(bin_dir, tmp_path, where):
    """A surface_mesh's STL is bounded like a mesh wall's (200 000 triangles): a 100 MB file
    (sparse) is refused by its size before CGAL reads it."""
    with open(tmp_path / "big.stl", "wb") as fh:
        fh.truncate(100 << 20)
    mesh = {"type": "surface_mesh", "file": "big.stl"}
    shape = mesh if where == "alone" else {"type": "union", "parts": [
        {"type": "sphere", "radius": 1e-3}, mesh]}
    key = "shapes.blob.file" if where == "alone" else "shapes.blob.parts[1].file"
    scene = shapes_scene(tmp_path, {"blob": shape}, 3)
    shape_refused(bin_dir, tmp_path, scene, key, "too large", "200000 triangles")
