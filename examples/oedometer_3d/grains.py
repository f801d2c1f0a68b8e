#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Writes the grain lists of examples/oedometer_3d (grains_quick.csv, grains.csv: x, y, z, r,
orientation, shape for pd-pack's csv generator). Run once; the outputs are committed (same
seeds, same files).

    grains.py [--quick grains_quick.csv] [--full grains.csv]

Two interleaved simple-cubic lattices (the CsCl arrangement): large grains (bounding radius
R = 1 mm) at the n x n x layers sites of spacing s = 2 R + gap (gap 0.1 mm) in the box
[0, n s]^2 x [0, layers s], and small grains (R = 0.7 mm, 0.7 R: just below the (sqrt 3 - 1) R
that fits the body-centred hole) at the (n - 1)^2 (layers - 1) body centres between them. Each
grain a sphere or a cuboid (shape 0 sphere, 1 cuboid: the scene's convex polyhedron, scaled to
its bounding radius) with probability 1/2 (seeded), centres jittered by up to +-0.03 mm in x
and y, orientation about z uniform in [0, 2 pi)."""
import argparse

import numpy as np

R_LARGE, R_SMALL, GAP, JITTER = 1.0e-3, 0.7e-3, 0.1e-3, 0.03e-3


def lattice(n, layers, seed):
    """Rows (x, y, z, r, orientation, shape): the large grains, then the small ones."""
    rng = np.random.default_rng(seed)
    s = 2 * R_LARGE + GAP
    rows = []
    for r, m, off in ((R_LARGE, n, 0.5), (R_SMALL, n - 1, 1.0)):
        for k in range(layers if r == R_LARGE else layers - 1):
            for j in range(m):
                for i in range(m):
                    dx, dy = rng.uniform(-JITTER, JITTER, 2)
                    rows.append((s * (i + off) + dx, s * (j + off) + dy, s * (k + off), r,
                                 rng.uniform(0, 2 * np.pi), int(rng.random() < 0.5)))
    return rows


def write_csv(path, rows, comment):
    with open(path, "w") as out:
        out.write("# %s\nx,y,z,r,orientation,shape\n" % comment)
        for r in rows:
            out.write("%.9g,%.9g,%.9g,%.9g,%.9g,%d\n" % r)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", default="grains_quick.csv")
    ap.add_argument("--full", default="grains.csv")
    a = ap.parse_args()
    for path, n, layers, seed in ((a.quick, 3, 3, 1), (a.full, 5, 5, 2)):
        rows = lattice(n, layers, seed)
        write_csv(path, rows, "oedometer_3d: %d x %d x %d large grains and the small ones at "
                  "the body centres, seed %d (grains.py)"
                  % (n, n, layers, seed))
        big = sum(r[3] == R_LARGE for r in rows)
        cub = sum(r[5] == 1 for r in rows)
        print("%s: %d grains (%d large, %d cuboids)" % (path, len(rows), big, cub))


if __name__ == "__main__":
    main()
