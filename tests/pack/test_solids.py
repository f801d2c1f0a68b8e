# SPDX-License-Identifier: MIT
"""3D shapes beyond the primitives through pd-pack, checked from the written file (h5py): closed
surface meshes from STL files (ASCII and binary, path relative to the scene file) meshed by gmsh
and by the lattice, scaled and rotated per instance; 3D CSG (box minus a cylinder, union of two
spheres). Per grain, the sum of nodal volumes must match the exact volume (times scale^3) within
1% and the volume-weighted node centroid the placed centroid. Bad surface meshes and keys are
refused with exit 2, naming the key and the file, and no output file."""

import json
import math
import os
import shutil
import struct

import h5py
import numpy as np
import pytest

from conftest import run

MAT = {"m1": {"law": "lps", "density": 1200, "youngs_modulus": 3.24e7, "poisson_ratio": 0.25,
              "fracture_energy": 50}}


def icosphere(r, levels):
    g = (1 + 5 ** 0.5) / 2
    v = [(-1, g, 0), (1, g, 0), (-1, -g, 0), (1, -g, 0), (0, -1, g), (0, 1, g), (0, -1, -g),
         (0, 1, -g), (g, 0, -1), (g, 0, 1), (-g, 0, -1), (-g, 0, 1)]
    v = [np.array(p) / np.linalg.norm(p) for p in v]
    t = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        mid = {}

        def m(a, b):
            k = (min(a, b), max(a, b))
            if k not in mid:
                p = v[a] + v[b]
                v.append(p / np.linalg.norm(p))
                mid[k] = len(v) - 1
            return mid[k]
        t = [tri for a, b, c in t for tri in
             ((a, m(a, b), m(c, a)), (b, m(b, c), m(a, b)), (c, m(c, a), m(b, c)),
              (m(a, b), m(b, c), m(c, a)))]
    return np.array(v) * r, np.array(t)


def cube(a):
    v = np.array([[(k & 1) * a, (k >> 1 & 1) * a, (k >> 2 & 1) * a] for k in range(8)], float)
    t = np.array([(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4), (2, 6, 3),
                  (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)])
    return v, t


def polyhedron(v, t):
    """Exact volume and centroid (tetrahedra from the origin)."""
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    det = np.einsum("ij,ij->i", a, np.cross(b, c))
    vol = det.sum() / 6
    return vol, (det[:, None] * (a + b + c)).sum(axis=0) / 4 / det.sum()


def write_stl(path, v, t, binary=False):
    if binary:
        with open(path, "wb") as f:
            f.write(b"binary STL of the pdgrain pack tests".ljust(80, b" "))
            f.write(struct.pack("<I", len(t)))
            for tri in t:
                p = v[tri]
                n = np.cross(p[1] - p[0], p[2] - p[0])
                f.write(struct.pack("<12fH", *(n / np.linalg.norm(n)), *p.ravel(), 0))
        return
    with open(path, "w") as f:
        f.write("solid test\n")
        for tri in t:
            p = v[tri]
            n = np.cross(p[1] - p[0], p[2] - p[0])
            n /= np.linalg.norm(n)
            f.write(f"facet normal {n[0]:.17g} {n[1]:.17g} {n[2]:.17g}\n outer loop\n")
            for q in p:
                f.write(f"  vertex {q[0]:.17g} {q[1]:.17g} {q[2]:.17g}\n")
            f.write(" endloop\nendfacet\n")
        f.write("endsolid test\n")


def scene(shapes, particles, h):
    return {"dimension": 3, "materials": MAT,
            "discretization": {"mesh_size": h, "horizon_factor": 3},
            "shapes": shapes, "particles": particles, "solver": {"final_time": 1e-4}}


def pack(pd_pack, folder, sc):
    """Writes the scene into `folder` (STL paths are relative to it), runs pd-pack, returns
    per body (nodal volume sum, weighted centroid, scale, centre, orientation)."""
    path = folder / "scene.json"
    path.write_text(json.dumps(sc))
    out = folder / "out.h5"
    r = run(pd_pack, path, "-o", out)  # cwd is not folder: the relative path must resolve
    assert r.returncode == 0, r.stderr
    with h5py.File(out, "r") as f:
        x = f["nodes/reference_position"][:]
        vol = f["nodes/volume"][:]
        off = f["bodies/node_offsets"][:]
        res = []
        for b in range(len(off) - 1):
            s = slice(off[b], off[b + 1])
            res.append((vol[s].sum(), (vol[s, None] * x[s]).sum(axis=0) / vol[s].sum(),
                        f["bodies/scale"][b], f["bodies/center"][b], f["bodies/orientation"][b]))
    return res, r.stdout


def test_stl_grains(pd_pack, tmp_path):
    r = 1e-3
    v_ico, t_ico = icosphere(r, 3)
    v_ico = v_ico + [0.2e-3, 0.1e-3, 0]  # off the origin: "centered" moves it back
    write_stl(tmp_path / "ball.stl", v_ico, t_ico)
    v_cube, t_cube = cube(1e-3)
    write_stl(tmp_path / "cube.stl", v_cube, t_cube, binary=True)
    vol_ico, c_ico = polyhedron(v_ico, t_ico)
    shapes = {"ball": {"type": "surface_mesh", "file": "ball.stl", "centered": True},
              "cube": {"type": "surface_mesh", "file": "cube.stl", "centered": True},
              "cube_grid": {"type": "surface_mesh", "file": "cube.stl", "centered": True,
                            "mesh": "grid"},
              "ball_grid": {"type": "surface_mesh", "file": "ball.stl", "centered": True,
                            "mesh": "grid", "mesh_size": 0.05e-3}}
    parts = [{"shape": "ball", "center": [0, 0, 0], "material": "m1"},
             {"shape": "ball", "center": [4e-3, 0, 0], "radius": 1.5e-3, "orientation": 0.7,
              "material": "m1"},
             {"shape": "cube", "center": [8e-3, 0, 0], "orientation": 0.4, "material": "m1"},
             {"shape": "cube_grid", "center": [12e-3, 0, 0], "radius": 1.2e-3,
              "material": "m1"},
             {"shape": "ball_grid", "center": [16e-3, 0, 0], "material": "m1"}]
    res, log = pack(pd_pack, tmp_path, scene(shapes, parts, 0.12e-3))
    rb_ico = np.linalg.norm(v_ico - c_ico, axis=1).max()
    rb_cube = math.sqrt(3) / 2 * 1e-3
    exact = [vol_ico, vol_ico * (1.5e-3 / rb_ico) ** 3, 1e-9, 1e-9 * (1.2e-3 / rb_cube) ** 3,
             vol_ico]
    for b, (vsum, cen, s, centre, theta) in enumerate(res):
        print(f"body {b}: scale {s:.4f}, volume error {vsum / exact[b] - 1:+.2e}, centroid "
              f"offset {np.linalg.norm(cen - centre):.2e} m")
        assert vsum == pytest.approx(exact[b], rel=0.01), b
        assert np.linalg.norm(cen - centre) < 0.01 * 1e-3, b
    assert res[1][2] == pytest.approx(1.5e-3 / rb_ico, rel=1e-12)
    assert res[1][4] == 0.7
    # The cube's lattice tiles it exactly.
    assert res[3][0] == pytest.approx(exact[3], rel=1e-9)
    assert "surface_mesh(cube.stl)" in log


def test_csg_3d_grains(pd_pack, tmp_path):
    lx, ly, lz, rc, e = 4e-3, 3e-3, 2e-3, 0.8e-3, 0.6e-3
    R, d = 1e-3, 1.2e-3
    holed = {"type": "difference", "base": {"type": "box", "size": [lx, ly, lz]},
             "minus": [{"type": "cylinder", "radius": rc, "length": 3 * lz,
                        "offset": [e, 0, 0]}]}
    peanut = {"type": "union", "parts": [{"type": "sphere", "radius": R},
                                         {"type": "sphere", "radius": R, "offset": [d, 0, 0]}]}
    shapes = {"holed": holed, "peanut": peanut}
    parts = [{"shape": "holed", "center": [0, 0, 0], "material": "m1", "orientation": 0.3},
             {"shape": "peanut", "center": [6e-3, 0, 0], "material": "m1"}]
    res, log = pack(pd_pack, tmp_path, scene(shapes, parts, 0.15e-3))
    hole = math.pi * rc * rc * lz
    v_holed = lx * ly * lz - hole
    v_peanut = 2 * 4 / 3 * math.pi * R ** 3 - math.pi * (4 * R + d) * (2 * R - d) ** 2 / 12
    c_holed = np.array([-hole * e / v_holed * math.cos(0.3), -hole * e / v_holed * math.sin(0.3),
                        0])
    for (vsum, cen, _, centre, _), exact, g in ((res[0], v_holed, c_holed),
                                                (res[1], v_peanut, np.array([d / 2, 0, 0]))):
        err = np.linalg.norm(cen - centre - g)  # g: the centroid relative to the centre
        print(f"volume error {vsum / exact - 1:+.2e}, centroid error {err:.2e} m")
        assert vsum == pytest.approx(exact, rel=0.01)
        assert err < 2e-5


def refused(pd_pack, folder, sc, words):
    path = folder / "scene.json"
    path.write_text(json.dumps(sc))
    out = folder / "out.h5"
    r = run(pd_pack, path, "-o", out)
    assert r.returncode == 2, (r.returncode, r.stderr)
    for w in words:
        assert w in r.stderr, (w, r.stderr)
    assert not [p for p in folder.iterdir() if p.name.startswith("out.h5")]


def one(shape, mesh=None):
    s = dict(shape)
    if mesh:
        s["mesh"] = mesh
    return scene({"g": s}, [{"shape": "g", "center": [0, 0, 0], "material": "m1"}], 0.25e-3)


def test_open_stl_refused(pd_pack, tmp_path):
    v, t = cube(1e-3)
    write_stl(tmp_path / "open.stl", v, t[:-1])
    refused(pd_pack, tmp_path, one({"type": "surface_mesh", "file": "open.stl"}),
            ["shapes.g.file", "open.stl", "open (3 border edges)"])


def test_missing_stl_refused(pd_pack, tmp_path):
    refused(pd_pack, tmp_path, one({"type": "surface_mesh", "file": "nowhere.stl"}),
            ["shapes.g.file", "nowhere.stl"])


def test_self_intersecting_stl_refused(pd_pack, tmp_path):
    v, t = cube(1e-3)
    v2 = np.vstack([v, v + 0.5e-3])
    t2 = np.vstack([t, t + 8])
    write_stl(tmp_path / "two.stl", v2, t2)
    refused(pd_pack, tmp_path, one({"type": "surface_mesh", "file": "two.stl"}),
            ["two.stl", "intersects itself"])


def test_unknown_key_refused(pd_pack, tmp_path):
    write_stl(tmp_path / "cube.stl", *cube(1e-3))
    refused(pd_pack, tmp_path, one({"type": "surface_mesh", "fiel": "cube.stl"}),
            ["shapes.g.fiel", "did you mean 'file'"])
    refused(pd_pack, tmp_path, one({"type": "sphere", "radius": 1e-3, "centred": True}),
            ["shapes.g.centred", "did you mean 'centered'"])


def test_surface_mesh_needs_gmsh_or_grid(pd_pack, tmp_path):
    write_stl(tmp_path / "cube.stl", *cube(1e-3))
    refused(pd_pack, tmp_path, one({"type": "surface_mesh", "file": "cube.stl"}, "file"),
            ["shapes.g.mesh", "gmsh", "grid"])
    csg = {"type": "difference", "base": {"type": "surface_mesh", "file": "cube.stl"},
           "minus": [{"type": "sphere", "radius": 0.3e-3}]}
    refused(pd_pack, tmp_path, one(csg), ["\"grid\""])


def test_sparse_bond_families_are_warned_about(pd_pack, tmp_path):
    """The example's gem (sharp STL tips: smallest spacing 0.087 mm at h = 0.25 mm) with
    horizon = 3 x smallest spacing (horizon_mesh_ratio) has a median of 8 bonds per node: pd-pack
    warns; with the absolute horizon of the example, or horizon_factor 3 (3 x mesh_size, the
    same 0.75 mm), it does not."""
    src = os.path.join(os.environ.get("PD_SOURCE_DIR", "."), "examples", "three_d_csg")
    shutil.copy(os.path.join(src, "gem.stl"), tmp_path / "gem.stl")
    sc = {"dimension": 3, "materials": MAT,
          "discretization": {"mesh_size": 2.5e-4, "horizon_mesh_ratio": 3},
          "shapes": {"gem": {"type": "surface_mesh", "file": "gem.stl", "centered": True}},
          "particles": [{"shape": "gem", "center": [0, 0, 0], "material": "m1"}],
          "solver": {"final_time": 1e-4}}
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(sc))
    r = run(pd_pack, path, "-o", tmp_path / "a.h5")
    assert r.returncode == 0 and "median of 8 bonds per node" in r.stderr, r.stderr
    for disc in ({"horizon": 7.5e-4}, {"horizon_factor": 3}):
        sc["discretization"] = dict({"mesh_size": 2.5e-4}, **disc)
        path.write_text(json.dumps(sc))
        r = run(pd_pack, path, "-o", tmp_path / "b.h5")
        assert r.returncode == 0 and "bonds per node" not in r.stderr, r.stderr
