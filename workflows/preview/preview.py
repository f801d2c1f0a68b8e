#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Draws a packed pd-file (written by pd-pack) to a PNG: every grain's mesh (cells of its
/reference_meshes entry on its /nodes/reference_position), coloured by body (fixed bodies grey),
and the rigid walls of /walls (planes as lines across the view, circles as circles; a wall
that enters after t = 0, /walls/start_time > 0, dashed and labelled with its start time).
3D scenes are drawn as the xy projection of the nodes.

    /usr/bin/python3 workflows/preview/preview.py FILE.h5 -o scene.png [--dpi 150] [--no-mesh]
"""

import argparse
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402


def draw(path, out, dpi=150, mesh_lines=True):
    with h5py.File(path, "r") as f:
        dim = int(f.attrs.get("dimension", 2))
        x = f["nodes/reference_position"][:]
        off = f["bodies/node_offsets"][:]
        ref = f["bodies/ref_mesh"][:]
        fixed = f["bodies/fixed"][:] if "bodies/fixed" in f else np.zeros(len(off) - 1)
        cells = {int(k.split("_")[1]): f["reference_meshes"][k]["cells"][:]
                 for k in f["reference_meshes"]}
        walls = {k: f["walls"][k][:] for k in f["walls"]} if "walls" in f else {}
    nb = len(off) - 1
    cmap = plt.get_cmap("tab20")
    fig, ax = plt.subplots(figsize=(8, 6))
    polys, colors = [], []
    for b in range(nb):
        xb = x[off[b]:off[b + 1], :2]
        color = (0.6, 0.6, 0.6, 1.0) if fixed[b] else cmap(b % 20)
        if dim == 2:
            for c in cells[int(ref[b])]:
                polys.append(xb[c])
                colors.append(color)
        else:
            ax.scatter(xb[:, 0], xb[:, 1], s=1, color=color, linewidths=0)
    if polys:
        ax.add_collection(PolyCollection(polys, facecolors=colors,
                                         edgecolors="k" if mesh_lines else "none",
                                         linewidths=0.1 if mesh_lines else 0))
    lo, hi = x[:, :2].min(axis=0), x[:, :2].max(axis=0)
    pad = 0.05 * max(hi - lo) if len(x) else 1.0
    lo, hi = lo - pad, hi + pad
    start = walls.get("start_time", np.zeros(len(walls.get("shape", []))))
    enter = walls.get("enter", np.zeros(len(walls.get("shape", []))))
    for k in range(len(walls.get("shape", []))):
        p = walls["point"][k][:2]
        # A wall that enters later (start_time > 0) is not there at t = 0: dashed, labelled.
        later = start[k] > 0
        style = dict(linestyles="dashed" if later else "solid")
        # enter = 1 (above_grains): drawn at the scene's point, placed by pd-solve at its entry.
        where = " above the grains" if enter[k] == 1 else ""
        if later:
            ax.annotate(f"enters{where} at t = {start[k]:.4g} s", p, fontsize=7, color="tab:red")
        if walls["shape"][k] == 0:
            n = walls["normal"][k][:2]
            t = np.array([-n[1], n[0]])
            L = 2 * max(hi - lo)
            ax.add_collection(LineCollection([[p - L * t, p + L * t]], colors="tab:red",
                                             linewidths=2, **style))
            lo, hi = np.minimum(lo, p - pad), np.maximum(hi, p + pad)
        else:
            r = walls["radius"][k]
            ax.add_patch(Circle(p, r, fill=False, color="tab:red", linewidth=2,
                                linestyle="--" if later else "-"))
            lo, hi = np.minimum(lo, p - r - pad), np.maximum(hi, p + r + pad)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"{path}: {nb} bodies, {len(x)} nodes, {len(walls.get('shape', []))} rigid walls",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=dpi)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("file", help="pd-file written by pd-pack")
    ap.add_argument("-o", "--output", required=True, help="PNG to write")
    ap.add_argument("--dpi", type=int, default=150)
    ap.add_argument("--no-mesh", action="store_true", help="fill cells without edges")
    a = ap.parse_args(argv)
    try:
        draw(a.file, a.output, a.dpi, not a.no_mesh)
    except (OSError, KeyError) as e:
        print(f"preview: {a.file}: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
