#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Writes hopper.stl (ASCII): an open conical hopper of `--sides` flat panels from the outlet,
radius 0.6 mm at z = 0, to radius 10.6 mm at z = 10 mm (45 degrees), with a flat rim ring out to
12 mm. The triangles' normals (right-hand rule) point into the hopper, the grains' side.

    make_hopper.py [-o hopper.stl] [--sides 24]"""

import argparse
import math


def rings():
    """(radius, z) of the rings, bottom to top, m."""
    return [(0.6e-3, 0.0), (10.6e-3, 10e-3), (12e-3, 10e-3)]


def triangles(sides):
    pts = [[(r * math.cos(2 * math.pi * k / sides), r * math.sin(2 * math.pi * k / sides), z)
            for k in range(sides)] for r, z in rings()]
    tris = []
    for lo, hi in zip(pts[:-1], pts[1:]):
        for k in range(sides):
            a, b = lo[k], lo[(k + 1) % sides]
            A, B = hi[k], hi[(k + 1) % sides]
            tris += [(a, A, b), (b, A, B)]  # (A - a) x (b - a) points to the axis and up
    return tris


def normal(t):
    u = [t[1][i] - t[0][i] for i in range(3)]
    v = [t[2][i] - t[0][i] for i in range(3)]
    n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    s = math.sqrt(sum(c * c for c in n))
    return [c / s for c in n]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--out", default="hopper.stl")
    ap.add_argument("--sides", type=int, default=24)
    a = ap.parse_args()
    lines = ["solid hopper"]
    for t in triangles(a.sides):
        lines.append(" facet normal %.6g %.6g %.6g" % tuple(normal(t)))
        lines.append("  outer loop")
        lines += ["   vertex %.9g %.9g %.9g" % p for p in t]
        lines += ["  endloop", " endfacet"]
    lines.append("endsolid hopper")
    with open(a.out, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
