#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Gaps of a settled pack, from a solved pd-file's last frame (issue 26, "Why" item 1).

    gaps.py FILE.h5 [--frame -1] [--json]

For every pair of grains that come within h of each other, the signed gap between their deformed
boundaries: min over both directions of (minus) the depth of a boundary node of one behind the
other's boundary facets (2D: the boundary segments of its reference mesh, on the current
positions; 3D: the boundary triangles, oriented outwards, signed by angle-weighted
pseudo-normals). Negative = overlap. For every grain, its lowest node's signed distance to each
plane wall it comes within h of. Printed: the pairs' gaps (min / median / max, in m and in h),
the grain-wall gaps, each grain's nearest support (its smallest gap to a grain or wall: a
floating grain shows a large one), the pile height (the highest node above the floor wall) and
the kinetic energy of the frame.
"""
import argparse
import json
import os
import sys

import h5py
import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "analysis"))
import check_run  # noqa: E402


def boundary_tris(model, b):
    """3D: boundary triangles of body b (global node ids), oriented outwards."""
    sl = model.body_nodes(b)
    nmesh, cells, ctype = model.meshes[int(model.ref_mesh[b])]
    assert ctype == "tetra" and nmesh == sl.stop - sl.start
    faces, opp = [], []
    for f, o in (([0, 1, 2], 3), ([0, 1, 3], 2), ([0, 2, 3], 1), ([1, 2, 3], 0)):
        faces.append(cells[:, f])
        opp.append(cells[:, o])
    faces, opp = np.concatenate(faces), np.concatenate(opp)
    _, idx, cnt = np.unique(np.sort(faces, axis=1), axis=0, return_index=True,
                            return_counts=True)
    faces, opp = faces[idx[cnt == 1]], opp[idx[cnt == 1]]
    x = model.x0[sl]
    n = np.cross(x[faces[:, 1]] - x[faces[:, 0]], x[faces[:, 2]] - x[faces[:, 0]])
    flip = np.sum(n * (x[opp] - x[faces[:, 0]]), 1) > 0
    faces[flip] = faces[flip][:, [0, 2, 1]]
    return faces + sl.start


def depth_into(model, y, b, pts):
    """Signed depth (> 0 inside) of points pts behind body b's deformed boundary."""
    if model.dim == 2:
        return check_run.polygon_depth(model.boundary_edges(b), y, pts)
    tris = boundary_tris(model, b)
    nodes = np.unique(tris)
    remap = np.full(tris.max() + 1, -1)
    remap[nodes] = np.arange(len(nodes))
    surf = check_run.MeshSurface(y[nodes], remap[tris])
    return -surf.signed_distance(pts)


def analyse(path, frame=-1):
    with h5py.File(path, "r") as f:
        model = check_run.Model(f)
        y = f["particles/nodes/position/value"][frame]
        t = float(f["particles/nodes/position/time"][frame])
        vel = f["particles/nodes/velocity/value"][frame] if "velocity" in f["particles/nodes"] \
            else None
        mass = f["particles/nodes/mass"][()]
        ke_t = f["observables/kinetic_energy/time"][()]
        ke = f["observables/kinetic_energy/value"][()]
        try:  # the scene's nominal mesh size (the h); else the largest node spacing
            h = float(json.loads(f["parameters/scene"][()])["discretization"]["mesh_size"])
        except (KeyError, TypeError, ValueError):
            h = float(model.h.max())
    moving = np.flatnonzero((model.fixed == 0) & (model.kind == 0))
    bnd = model.bmask
    lo = np.array([y[model.body_nodes(b)].min(0) for b in range(model.nb)])
    hi = np.array([y[model.body_nodes(b)].max(0) for b in range(model.nb)])
    pairs = []
    deepest = (-np.inf, -1, -1, -1)  # depth, node, its body, the body it is in
    for ia, a in enumerate(moving):
        for b in moving[ia + 1:]:
            if np.any(lo[a] - hi[b] > h) or np.any(lo[b] - hi[a] > h):
                continue
            g = np.inf
            for p, q in ((a, b), (b, a)):
                sl = model.body_nodes(p)
                pts_idx = np.arange(sl.start, sl.stop)  # every node, not only the boundary's
                pts = y[pts_idx]
                near = np.all((pts >= lo[q] - h) & (pts <= hi[q] + h), axis=1)
                if not near.any():
                    continue
                d = depth_into(model, y, q, pts[near])
                k = int(np.argmax(d))
                if -d[k] < g:
                    g = float(-d[k])
                    if d[k] > deepest[0]:
                        deepest = (float(d[k]), int(pts_idx[near][k]), int(p), int(q))
            if g < h:
                pairs.append((int(a), int(b), g))
    walls, floor = [], []
    if model.walls is not None:
        for w in range(len(model.walls["shape"])):
            if int(model.walls["shape"][w]) != 0:
                continue
            for b in moving:
                sl = model.body_nodes(b)
                d = check_run.wall_distance(model, w, y[sl], t)
                if d.min() < h:
                    walls.append((int(b), w, float(d.min())))
                    if model.walls["normal"][w][model.dim - 1] > 0.99:
                        floor.append((int(b), w, float(d.min())))
    support = {}
    for a, b, g in pairs:
        support[a] = min(support.get(a, np.inf), g)
        support[b] = min(support.get(b, np.inf), g)
    for b, w, g in walls:
        support[b] = min(support.get(b, np.inf), g)
    floating = [int(b) for b in moving if b not in support]
    # the floor: the plane wall whose normal is +y (2D) / +z (3D)
    up = model.dim - 1
    height = None
    if model.walls is not None:
        for w in range(len(model.walls["shape"])):
            nrm = model.walls["normal"][w]
            if int(model.walls["shape"][w]) == 0 and nrm[up] > 0.99:
                height = float((y[:, up] - model.walls["point"][w][up]).max())
    centres = np.array([np.average(y[model.body_nodes(b)], axis=0,
                                   weights=mass[model.body_nodes(b)]) for b in moving])
    out = {"file": path, "t": t, "h": h, "pairs": len(pairs), "ke": float(ke[-1]),
           "ke_t": float(ke_t[-1]),
           "pair_gap": [min(p[2] for p in pairs), float(np.median([p[2] for p in pairs])),
                        max(p[2] for p in pairs)] if pairs else None,
           "wall_gap": [min(w[2] for w in walls), float(np.median([w[2] for w in walls])),
                        max(w[2] for w in walls)] if walls else None,
           "nearest_support_max": max(support.values()) if support else None,
           "nearest_support_worst_grain": max(support, key=support.get) if support else None,
           "floating": floating, "pile_height": height,
           "mean_centre_height": float(centres[:, up].mean()),
           "max_speed": float(np.linalg.norm(vel, axis=1).max()) if vel is not None else None,
           "wall_contacts": len(walls), "pair_list": pairs,
           "floor_gap": [min(w[2] for w in floor), float(np.median([w[2] for w in floor])),
                         max(w[2] for w in floor)] if floor else None,
           "floor_contacts": len(floor),
           "deepest": deepest,
           # pairs by gap: touching (< 0.01 h: a facet's sagitta on a 1 mm circle at h = 0.25
           # mm is 0.008 h), within h/4, h/4 to h (near but not touching, or held apart)
           "pair_bins": [sum(p[2] < 0.01 * h for p in pairs),
                         sum(0.01 * h <= p[2] < 0.25 * h for p in pairs),
                         sum(p[2] >= 0.25 * h for p in pairs)]}
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("--frame", type=int, default=-1)
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    r = analyse(a.file, a.frame)
    if a.json:
        print(json.dumps(r))
        return
    h = r["h"]
    print(f"{r['file']}: t = {r['t']:.4g} s, h = {h:.3g} m, KE {r['ke']:.3g} J, "
          f"max node speed {r['max_speed']}")
    if r["pair_gap"]:
        g = r["pair_gap"]
        print(f"grain pairs within h: {r['pairs']}; gap min / median / max "
              f"{g[0]:.3g} / {g[1]:.3g} / {g[2]:.3g} m = {g[0] / h:+.3f} / {g[1] / h:+.3f} / "
              f"{g[2] / h:+.3f} h; < 0.01 h: {r['pair_bins'][0]}, 0.01-0.25 h: "
              f"{r['pair_bins'][1]}, 0.25-1 h: {r['pair_bins'][2]}")
    if r["wall_gap"]:
        g = r["wall_gap"]
        print(f"grain-wall contacts within h: {r['wall_contacts']}; lowest node's distance min / "
              f"median / max {g[0]:.3g} / {g[1]:.3g} / {g[2]:.3g} m = {g[0] / h:+.3f} / "
              f"{g[1] / h:+.3f} / {g[2] / h:+.3f} h")
    if r["floor_gap"]:
        g = r["floor_gap"]
        print(f"grains within h of the floor: {r['floor_contacts']}; lowest node's distance min "
              f"/ median / max {g[0] / h:+.4f} / {g[1] / h:+.4f} / {g[2] / h:+.4f} h")
    d = r["deepest"]
    print(f"deepest node inside another grain (behind its deformed boundary): {d[0]:.3g} m "
          f"({d[0] / h:+.4f} h), node {d[1]} of body {d[2]} in body {d[3]}")
    print(f"largest nearest-support gap {r['nearest_support_max']:.3g} m "
          f"({r['nearest_support_max'] / h:+.3f} h, grain {r['nearest_support_worst_grain']}); "
          f"grains with nothing within h: {r['floating']}")
    print(f"pile height (highest node above the floor) {r['pile_height']:.4g} m; mean grain "
          f"centre height {r['mean_centre_height']:.4g} m")


if __name__ == "__main__":
    main()
