#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Frames of an oedometer run as one PNG (matplotlib, from the file's node positions): per frame
chosen, a 3D view of every node coloured by its grain, and the nodes of a central vertical slice
(|y - y_mid| < --slab) seen along y, coloured by damage, with the floor and the plate.

    frames.py FILE.h5 [--frames 0,-1] [--slab 5e-4] [--dpi 70] -o frames.png"""
import argparse

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def plate_height(f, t):
    names = [s.decode() if isinstance(s, bytes) else s for s in f["walls"].attrs["names"]]
    k = names.index("plate")
    t1 = float(f["walls/start_time"][k]) if "walls/start_time" in f else 0.0
    return float(f["walls/point"][k][2] + f["walls/velocity"][k][2] * max(t - t1, 0.0)), t >= t1


def draw(f, k, ax3, ax2, slab):
    g = f["particles/nodes"]
    x = g["position/value"][k]
    t = float(g["position/time"][k])
    body = f["nodes/body"][()] if "nodes/body" in f else np.zeros(len(x), int)
    dmg = g["damage/value"][k] if "damage" in g else np.zeros(len(x))
    rng = np.random.default_rng(0).permutation(int(body.max()) + 1)
    ax3.scatter(x[:, 0] * 1e3, x[:, 1] * 1e3, x[:, 2] * 1e3, c=rng[body] % 20, cmap="tab20",
                s=1.5, linewidths=0)
    ax3.set_title("t = %.2f ms" % (t * 1e3), fontsize=8)
    ax3.set_box_aspect(np.ptp(x, 0))
    ax3.tick_params(labelsize=6)
    ym = 0.5 * (x[:, 1].min() + x[:, 1].max())
    sel = np.abs(x[:, 1] - ym) < slab
    sc = ax2.scatter(x[sel, 0] * 1e3, x[sel, 2] * 1e3, c=dmg[sel], cmap="plasma", vmin=0,
                     vmax=1, s=5, linewidths=0)
    zp, inside = plate_height(f, t)
    ax2.axhline(0, color="k", lw=1)
    if inside:
        ax2.axhline(zp * 1e3, color="tab:blue", lw=1.5)
    ax2.set_aspect("equal")
    ax2.set_xlabel("x (mm)", fontsize=7)
    ax2.set_ylabel("z (mm)", fontsize=7)
    ax2.tick_params(labelsize=6)
    ax2.set_title("slice |y - %.1f mm| < %.2g mm, damage" % (ym * 1e3, slab * 1e3), fontsize=8)
    return sc


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("-o", "--out", default="frames.png")
    ap.add_argument("--frames", default="0,-1")
    ap.add_argument("--slab", type=float, default=5e-4, help="half-thickness of the slice (m)")
    ap.add_argument("--dpi", type=int, default=70)
    a = ap.parse_args()
    with h5py.File(a.file, "r") as f:
        n = f["particles/nodes/position/value"].shape[0]
        picks = [int(s) % n for s in a.frames.split(",")]
        fig = plt.figure(figsize=(4.2 * len(picks), 7))
        for j, k in enumerate(picks):
            ax3 = fig.add_subplot(2, len(picks), j + 1, projection="3d")
            ax2 = fig.add_subplot(2, len(picks), len(picks) + j + 1)
            sc = draw(f, k, ax3, ax2, a.slab)
        fig.colorbar(sc, ax=fig.axes[-1], shrink=0.7, label="damage")
        fig.tight_layout()
        fig.savefig(a.out, dpi=a.dpi)
    print("wrote %s (frames %s)" % (a.out, picks))


if __name__ == "__main__":
    main()
