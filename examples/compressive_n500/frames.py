#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Force chains and damage of a compressive run, frame by frame (h5py + matplotlib).

    frames.py RUN.h5 [--frames -3,-1] [-o frames.png]

Top row: each grain coloured by its compressive strain, the smaller principal value of the
affine fit x = F X + c of its nodes (least squares, E = (F^T F - I) / 2): the grains that carry
the load form the force chains. Bottom row: damage phi at each node, the damaged nodes drawn
larger on top. Default frames: the third-last and the last."""

import argparse
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PatchCollection  # noqa: E402
from matplotlib.patches import Polygon  # noqa: E402


def grain_strain(X, x, body, nb):
    """The smaller principal Green-Lagrange strain of each grain's affine fit (2D)."""
    e = np.zeros(nb)
    for b in range(nb):
        sel = body == b
        if sel.sum() < 3:
            continue
        Xb = X[sel, :2] - X[sel, :2].mean(0)
        xb = x[sel, :2] - x[sel, :2].mean(0)
        F = np.linalg.lstsq(Xb, xb, rcond=None)[0].T  # x = F X
        E = 0.5 * (F.T @ F - np.eye(2))
        e[b] = np.linalg.eigvalsh(E)[0]
    return e


def hull(p):
    """Convex hull of 2D points (monotone chain), for a grain's outline."""
    p = p[np.lexsort((p[:, 1], p[:, 0]))]

    def half(q):
        h = []
        for r in q:
            while len(h) >= 2 and np.cross(h[-1] - h[-2], r - h[-2]) <= 0:
                h.pop()
            h.append(r)
        return h

    lo, up = half(p), half(p[::-1])
    return np.array(lo[:-1] + up[:-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("--frames", default="-3,-1", help="comma-separated frame indices")
    ap.add_argument("-o", "--out", default="frames.png")
    ap.add_argument("--dpi", type=int, default=110)
    ap.add_argument("--strain-max", type=float, default=None,
                    help="colour scale of the compressive strain (default: 95th percentile of the frame)")
    a = ap.parse_args()
    try:
        f = h5py.File(a.file, "r")
    except OSError as e:
        sys.exit("frames.py: %s: %s" % (a.file, e))
    with f:
        X = f["nodes/reference_position"][:]
        body = f["nodes/body"][:]
        nb = int(body.max()) + 1
        pn = f["particles/nodes"]
        nt = pn["position/value"].shape[0]
        ks = [int(k) % nt for k in a.frames.split(",")]
        fig, axes = plt.subplots(2, len(ks), figsize=(6.4 * len(ks), 7.6), squeeze=False)
        for c, k in enumerate(ks):
            x = pn["position/value"][k]
            t = pn["position/time"][k]
            phi = pn["damage/value"][k] if "damage" in pn else np.zeros(len(x))
            e = -grain_strain(X, x, body, nb)
            vmax = a.strain_max or max(np.percentile(e, 95), 1e-12)
            polys = [Polygon(hull(x[body == b, :2] * 1e3)) for b in range(nb)]
            pc = PatchCollection(polys, cmap="magma_r", edgecolor="0.6", linewidth=0.2)
            pc.set_array(np.clip(e, 0, None))
            pc.set_clim(0, vmax)
            ax = axes[0][c]
            ax.add_collection(pc)
            ax.autoscale_view()
            ax.set_aspect("equal")
            ax.set_title("t = %.4g s: grain compressive strain (force chains)" % t, fontsize=9)
            fig.colorbar(pc, ax=ax, shrink=0.8, label="-min principal strain")
            ax = axes[1][c]
            ax.scatter(x[:, 0] * 1e3, x[:, 1] * 1e3, c="0.85", s=0.3, linewidths=0)
            d = phi > 0
            sc = ax.scatter(x[d, 0] * 1e3, x[d, 1] * 1e3, c=phi[d], s=6, cmap="inferno_r",
                            vmin=0, vmax=max(phi.max(), 1e-12), linewidths=0)
            ax.set_aspect("equal")
            ax.set_title("damage: %d nodes with phi > 0 (max %.2f)" % (d.sum(), phi.max()),
                         fontsize=9)
            ax.set_xlabel("x (mm)")
            fig.colorbar(sc, ax=ax, shrink=0.8, label="damage phi")
        axes[0][0].set_ylabel("y (mm)")
        axes[1][0].set_ylabel("y (mm)")
        fig.tight_layout()
        fig.savefig(a.out, dpi=a.dpi)
    print("wrote", a.out)


if __name__ == "__main__":
    main()
