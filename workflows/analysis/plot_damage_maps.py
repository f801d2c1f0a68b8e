#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Damage map snapshots: nodes at their current positions coloured by damage phi, for a few
frames of a pd-file, with h5py + matplotlib. Copy and edit (frames, colour map, marker size).

    plot_damage_maps.py FILE.h5 [--frames 0,5,-1] [-o damage_maps.png]
Default: 4 frames evenly spaced from the first to the last. 3D runs are shown projected on x-y."""

import argparse

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("--frames", help="comma-separated frame indices (negative from the end)")
    ap.add_argument("-o", "--out", default="damage_maps.png")
    a = ap.parse_args()
    with h5py.File(a.file, "r") as f:
        pn = f["particles/nodes"]
        nt = pn["position/value"].shape[0]
        ks = ([int(k) % nt for k in a.frames.split(",")] if a.frames
              else sorted(set(np.linspace(0, nt - 1, min(4, nt)).round().astype(int))))
        fig, axes = plt.subplots(1, len(ks), figsize=(3.6 * len(ks), 3.6), squeeze=False)
        for ax, k in zip(axes[0], ks):
            x = pn["position/value"][k]  # one frame at a time
            phi = pn["damage/value"][k] if "damage" in pn else np.zeros(len(x))
            sc = ax.scatter(x[:, 0] * 1e3, x[:, 1] * 1e3, c=phi, s=4, cmap="inferno_r",
                            vmin=0, vmax=1, linewidths=0)
            ax.set_aspect("equal")
            ax.set_title("t = %.4g s" % pn["position/time"][k], fontsize=9)
            ax.set_xlabel("x (mm)")
        axes[0][0].set_ylabel("y (mm)")
        fig.colorbar(sc, ax=axes[0].tolist(), label="damage phi", shrink=0.8)
    fig.savefig(a.out, dpi=120)
    print("wrote", a.out)


if __name__ == "__main__":
    main()
