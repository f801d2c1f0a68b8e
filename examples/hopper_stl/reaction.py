#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The hopper's reaction against the grains' weight, from a pd-file (h5py + matplotlib).

Weight W = g sum rho_i V_i over the grains' nodes; the reaction R = -z component of the force
the hopper (rigid wall 0) receives, /observables/wall_force (each row the mean over the steps
since the previous one). At rest, the mean of R over the last quarter of the run must equal W
within --tolerance (relative); exit 1 otherwise. Writes --json {"reaction_over_weight",
"weight", "reaction", "kinetic_energy_end"}, --png (R and W against time), --frame-png (the last
frame seen from the side: the nodes, and the hopper's triangles cut by the plane y = 0).

    reaction.py FILE.h5 [--tolerance 0.03] [--json out.json] [--png reaction.png]
                [--frame-png frame.png]"""

import argparse
import json
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def weight(f):
    """The grains' weight, N (gravity along -z)."""
    dens = {int(g.attrs["index"]): float(g["density"][()]) for g in f["materials"].values()}
    mat = f["bodies/material"][()]
    rho = np.array([dens[int(mat[b])] for b in f["nodes/body"][()]])
    g = -float(f["loading/gravity"][()][2]) if "loading/gravity" in f else 10.0
    return g * float(np.sum(rho * f["nodes/volume"][()]))


def side_view(f, ax):
    """The last frame's nodes (x, z) and the hopper's outline in the plane y = 0."""
    pos = f["particles/nodes/position/value"][-1]
    t = f["particles/nodes/position/time"][-1]
    body = f["nodes/body"][()]
    ax.scatter(pos[:, 0] * 1e3, pos[:, 2] * 1e3, c=body, s=6, cmap="tab10")
    p = f["walls/mesh/0/points"][()]
    for tri in f["walls/mesh/0/cells"][()]:
        q = p[tri]
        cut = []  # where the triangle's edges cross y = 0
        for a, b in ((0, 1), (1, 2), (2, 0)):
            ya, yb = q[a, 1], q[b, 1]
            if (ya <= 0 < yb) or (yb <= 0 < ya):
                s = ya / (ya - yb)
                cut.append(q[a] + s * (q[b] - q[a]))
        if len(cut) == 2:
            c = np.array(cut) * 1e3
            ax.plot(c[:, 0], c[:, 2], "k-", lw=1.5)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("z (mm)")
    ax.set_title("t = %.3g s: nodes by grain, hopper cut at y = 0" % t)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("--tolerance", type=float, default=0.03)
    ap.add_argument("--json")
    ap.add_argument("--png")
    ap.add_argument("--frame-png")
    a = ap.parse_args()
    with h5py.File(a.file, "r") as f:
        W = weight(f)
        t = f["observables/wall_force/time"][()]
        R = -f["observables/wall_force/value"][:, 0, 2]
        ke = float(f["observables/kinetic_energy/value"][-1])
        last = t >= t[0] + 0.75 * (t[-1] - t[0])
        mean = float(np.mean(R[last]))
        out = {"reaction_over_weight": mean / W, "weight": W, "reaction": mean,
               "kinetic_energy_end": ke}
        print("hopper: weight %.6g N, reaction at rest %.6g N, ratio %.4f, KE(end) %.3g J"
              % (W, mean, mean / W, ke))
        if a.json:
            with open(a.json, "w") as j:
                json.dump(out, j, indent=1)
        if a.png:
            fig, ax = plt.subplots(figsize=(6, 3.5))
            ax.plot(t * 1e3, R * 1e3, label="hopper reaction (-F_z)")
            ax.axhline(W * 1e3, color="k", ls="--", label="grains' weight")
            ax.axvspan(t[last][0] * 1e3, t[-1] * 1e3, color="0.9", label="averaged")
            ax.set_xlabel("t (ms)")
            ax.set_ylabel("force (mN)")
            ax.legend(loc="upper left", fontsize=8)
            fig.tight_layout()
            fig.savefig(a.png, dpi=120)
        if a.frame_png:
            fig, ax = plt.subplots(figsize=(5, 4))
            side_view(f, ax)
            fig.tight_layout()
            fig.savefig(a.frame_png, dpi=120)
    if abs(mean / W - 1) > a.tolerance:
        print("reaction.py: the reaction at rest is %.4f x the weight, not within %g"
              % (mean / W, a.tolerance), file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
