#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Writes a scene of examples/pack3d_1000 (README.md): COUNT grains of two sizes, spheres and
cuboids, on a lattice above the floor of a rigid box, and its grain list (pd-pack's csv
generator: x, y, z, r, orientation, shape), seeded: same arguments, same files.

    make_scene.py --count 100 --width 4 --seed 1 --times 0.025,0.035,0.045 -o OUT/scene.json

Two interleaved simple-cubic lattices of spacing s = 2 R + GAP (the CsCl arrangement): large
grains (bounding radius R = 1 mm) at the sites (i + 1/2, j + 1/2, k + 1/2) s of a WIDTH x WIDTH
grid, small ones (0.7 R, just below the (sqrt 3 - 1) R that fits the body-centred hole) at the
(WIDTH - 1)^2 body centres (i + 1, j + 1, k + 1) s between them. The sites are taken from the
floor up until COUNT grains are placed (the top layer may be partial). Each grain is a sphere or
a cuboid (a 1.4 x 1.2 x 1.0 box scaled to the grain's bounding radius) with probability 1/2,
turned by a uniform angle about z; centres are jittered by up to JITTER in x and y so that the
columns do not stand exactly on top of each other. The box's inner cross-section is
(WIDTH s)^2.

The run has three stages at the times T_POUR, T_SETTLE, T_END (--times): the grains fall with a
light viscous damping (DAMPING_POUR, whose terminal speed g / c is above the speeds of the
collapsing lattice) to T_POUR, the Makefile restarts with a strong one (its SETTLE_DAMPING) to
T_SETTLE, and restarts without damping: the plate enters PLATE_GAP above the settled grains at
T_SETTLE (pd-solve places it) and moves down at PLATE_SPEED to T_END."""
import argparse
import json
import os

import numpy as np

R_LARGE, R_SMALL, GAP, JITTER = 1.0e-3, 0.7e-3, 0.1e-3, 0.03e-3
SHAPES = ("sphere", "cuboid", "sphere_small", "cuboid_small")  # the csv's shape index


def sites(width, count, seed):
    """Rows (x, y, z, r, orientation, shape) of the first COUNT lattice sites from the floor."""
    rng = np.random.default_rng(seed)
    s = 2 * R_LARGE + GAP
    rows = []
    k = 0
    while len(rows) < count:
        for r, m, off in ((R_LARGE, width, 0.5), (R_SMALL, width - 1, 1.0)):
            for j in range(m):
                for i in range(m):
                    if len(rows) == count:
                        return rows
                    dx, dy = rng.uniform(-JITTER, JITTER, 2)
                    kind = int(rng.random() < 0.5) + (2 if r == R_SMALL else 0)
                    rows.append((s * (i + off) + dx, s * (j + off) + dy, s * (k + off), r,
                                 rng.uniform(0, 2 * np.pi), kind))
        k += 1
    return rows


def walls(lx, t_settle):
    """The box (floor and four sides, analytic planes) and the plate, which enters above the
    settled grains at t_settle and moves down at PLATE_SPEED."""
    c = 0.5 * lx
    return [
        {"name": "floor", "type": "plane", "point": [0, 0, 0], "normal": [0, 0, 1]},
        {"name": "x0", "type": "plane", "point": [0, 0, 0], "normal": [1, 0, 0]},
        {"name": "x1", "type": "plane", "point": [lx, 0, 0], "normal": [-1, 0, 0]},
        {"name": "y0", "type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]},
        {"name": "y1", "type": "plane", "point": [0, lx, 0], "normal": [0, -1, 0]},
        {"name": "plate", "type": "plane", "point": [c, c, 1.0], "normal": [0, 0, -1],
         "velocity": [0, 0, -PLATE_SPEED], "start_time": t_settle, "enter": "above_grains",
         "gap": PLATE_GAP}]


# s^-1: viscous damping while the grains fall; m/s, m: the plate's speed and its gap above the
# highest node as it enters
DAMPING_POUR, PLATE_SPEED, PLATE_GAP = 30.0, 0.1, 5e-5
MESH_SIZE = 4.0e-4
CUBOID = [1.4e-3, 1.2e-3, 1.0e-3]  # m: the box, scaled to each grain's bounding radius
# soft grains (1/100 of PeriDEM's 32.4 MPa): the step grows as 1 / sqrt(E), the weight's strain
# stays below 1e-3
YOUNGS = 3.24e5


def scene(title, csv_name, lx, times):
    t_pour, t_settle, t_end = times
    box = CUBOID
    scale = R_SMALL / R_LARGE
    return {
        "title": title,
        "dimension": 3,
        # unbreakable (fracture_energy 0): a scale example, grains do not break
        "materials": {"grain": {"law": "pmb", "density": 1200, "youngs_modulus": YOUNGS,
                                "fracture_energy": 0}},
        "discretization": {"mesh_size": MESH_SIZE, "horizon": 3 * MESH_SIZE},
        "shapes": {
            "sphere": {"type": "sphere", "radius": R_LARGE},
            "cuboid": {"type": "box", "size": box, "mesh": "grid"},
            # gmsh meshes a sphere with at least ~190 nodes at MESH_SIZE whatever its radius:
            # the small one is meshed coarser (115 nodes); the horizon stays HORIZON
            "sphere_small": {"type": "sphere", "radius": R_SMALL, "mesh_size": 1.5 * MESH_SIZE},
            "cuboid_small": {"type": "box", "size": [scale * b for b in box], "mesh": "grid"}},
        "particles": [{"generate": "csv", "file": csv_name, "shapes": list(SHAPES),
                       "material": "grain"}],
        "walls": walls(lx, t_settle),
        "contact": {"law": "surface", "restitution": 1.0, "friction": 0.3},
        "loading": {"gravity": [0, 0, -9.81], "viscous_damping": DAMPING_POUR},
        # a skin of h/2 instead of the automatic R_c: 2x cheaper contact forces, more rebuilds
        "solver": {"final_time": t_end, "dt": "auto", "output_interval": 1.25e-3,
                   "observe_every": 20, "checkpoint_interval": t_pour,
                   "contact_skin": 0.5 * MESH_SIZE, "fields": ["velocity"]}}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, required=True)
    ap.add_argument("--width", type=int, required=True, help="large grains per row")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--times", required=True, help="T_POUR,T_SETTLE,T_END (s)")
    ap.add_argument("-o", "--out", required=True, help="scene JSON; the csv beside it")
    a = ap.parse_args()
    rows = sites(a.width, a.count, a.seed)
    base = os.path.splitext(a.out)[0]
    csv_path = base + "_grains.csv"
    with open(csv_path, "w") as out:
        out.write("# pack3d_1000: %d grains, width %d, seed %d (make_scene.py)\n"
                  "x,y,z,r,orientation,shape\n" % (a.count, a.width, a.seed))
        for r in rows:
            out.write("%.9g,%.9g,%.9g,%.9g,%.9g,%d\n" % r)
    lx = a.width * (2 * R_LARGE + GAP)
    title = "pack3d_1000: %d grains poured, settled and compressed" % a.count
    with open(a.out, "w") as out:
        times = [float(v) for v in a.times.split(",")]
        json.dump(scene(title, os.path.basename(csv_path), lx, times), out, indent=1)
    kinds = np.bincount([r[5] for r in rows], minlength=4)
    print("%s: %d grains (%s), box %.4g mm wide, top site %.4g mm" % (
        a.out, len(rows), ", ".join("%d %s" % (n, s) for n, s in zip(kinds, SHAPES)), lx * 1e3,
        max(r[2] for r in rows) * 1e3))


if __name__ == "__main__":
    main()
