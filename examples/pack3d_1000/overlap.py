#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""How deep the nodes of one grain get inside another, measured against the grains' exact
shapes (spheres and boxes) moved with each grain: a check of examples/pack3d_1000 that does not
depend on the mesh's boundary nodes.

    overlap.py FILE.h5 GRAINS.csv [--json OUT.json]

For every frame each grain's rigid motion is fitted to its nodes (Kabsch: the rotation and
translation that carry the reference positions closest to the current ones; the grains are
unbreakable and strain little). A node y of grain A is inside grain B when, in B's frame,
|y| < R (sphere of bounding radius R) or |y_k| < a_k for k = 1..3 (box of half-sizes a); its
depth is R - |y| or min_k (a_k - |y_k|). The meshes' facets lie up to a fraction of h inside
the exact surface between their nodes (a gmsh sphere's facets are chords under its surface; a
grid box's outer nodes lie on its faces), and the surface law stops a node at the other
grain's facets, so a node resting on B can be a fraction of h deep; the reported figure is the
deepest node over all frames, against the scene's mesh size h (make quick checks it against
quick.json's overlap_max_h)."""
import argparse
import json

import h5py
import numpy as np
from scipy.spatial import cKDTree

import make_scene  # the scene's mesh size and cuboid

BOX = np.array(make_scene.CUBOID)  # scaled to each grain's bounding radius


def grain_shapes(csv):
    """Per grain (row of the csv, the order of the bodies): True for a box, and its bounding
    radius."""
    d = np.loadtxt(csv, delimiter=",", skiprows=2, ndmin=2)
    return d[:, 5].astype(int) % 2 == 1, d[:, 3]


def fit(x0, y):
    """Rotation Q and centroids (c0, c) with y - c ~ Q (x0 - c0) (Kabsch)."""
    c0, c = x0.mean(0), y.mean(0)
    u, _, vt = np.linalg.svd((y - c).T @ (x0 - c0))
    d = np.sign(np.linalg.det(u @ vt))
    return u @ np.diag([1.0, 1.0, d]) @ vt, c0, c


def depth_in(is_box, radius, local):
    """Depth of the points `local` (in the grain's frame, about its centre) inside it (< 0:
    outside)."""
    if not is_box:
        return radius - np.linalg.norm(local, axis=1)
    half = 0.5 * BOX * radius / (0.5 * np.linalg.norm(BOX))
    return np.min(half - np.abs(local), axis=1)


def frame_depth(x0, y, off, boxes, radii, centres, orient):
    """Deepest node of any grain inside another in one frame: (depth, node, grain entered)."""
    nb = len(off) - 1
    body = np.repeat(np.arange(nb), np.diff(off))
    tree = cKDTree(y)
    best = (-np.inf, -1, -1)
    for b in range(nb):
        s = slice(off[b], off[b + 1])
        q, c0, c = fit(x0[s], y[s])
        # the grain's frame: the csv centre and its turn about z map the shape onto x0
        ct, st = np.cos(orient[b]), np.sin(orient[b])
        rz = np.array([[ct, -st, 0.0], [st, ct, 0.0], [0.0, 0.0, 1.0]])
        centre = c + q @ (centres[b] - c0)
        near = np.array(tree.query_ball_point(centre, radii[b]), dtype=int)
        near = near[body[near] != b] if len(near) else near
        if len(near) == 0:
            continue
        local = (y[near] - centre) @ (q @ rz)  # rows: rz^T q^T (y - centre)
        d = depth_in(boxes[b], radii[b], local)
        k = int(np.argmax(d))
        if d[k] > best[0]:
            best = (float(d[k]), int(near[k]), b)
    return best


def run(path, csv):
    boxes, radii = grain_shapes(csv)
    with h5py.File(path, "r") as f:
        x0 = f["nodes/reference_position"][()]
        off = f["bodies/node_offsets"][()]
        centres = f["bodies/center"][()]
        orient = f["bodies/orientation"][()]
        g = f["particles/nodes/position"]
        worst = {"depth": -np.inf}
        for k in range(g["value"].shape[0]):
            d, node, grain = frame_depth(x0, g["value"][k], off, boxes, radii, centres, orient)
            if d > worst["depth"]:
                worst = {"depth": d, "node": node, "grain": grain,
                         "time": float(g["time"][k]), "frame": k}
    worst["h"] = h = make_scene.MESH_SIZE
    worst["depth_over_h"] = worst["depth"] / h
    return worst


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("grains", help="the grain list of the scene (make_scene.py)")
    ap.add_argument("--json")
    a = ap.parse_args()
    w = run(a.file, a.grains)
    print("deepest node inside another grain: %.3g mm = %.3f h (h = %.3g mm), node %d in grain "
          "%d at t = %.4g ms" % (w["depth"] * 1e3, w["depth_over_h"], w["h"] * 1e3, w["node"],
                                 w["grain"], w["time"] * 1e3))
    if a.json:
        with open(a.json, "w") as out:
            json.dump(w, out, indent=1)


if __name__ == "__main__":
    main()
