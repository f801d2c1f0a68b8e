#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Reaction of a rigid wall against its displacement (and against time) from a pd-file, with
h5py + matplotlib. Copy and edit. The reaction is the force the wall receives
(/observables/wall_force), projected on the wall normal for a plane; the displacement is
/walls/velocity * time along the normal (the wall translates rigidly).

    plot_wall_reaction.py FILE.h5 [-o reaction.png] [--wall K] [--length L]
With --length (m in 2D, m2 in 3D) the reaction is plotted as a stress (Pa)."""

import argparse

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("-o", "--out", default="reaction.png")
    ap.add_argument("--wall", type=int, default=0, help="wall index (order of /walls)")
    ap.add_argument("--length", type=float, help="length (2D) or area (3D) for a stress")
    a = ap.parse_args()
    with h5py.File(a.file, "r") as f:
        t = f["observables/wall_force/time"][()]
        force = f["observables/wall_force/value"][:, a.wall, :]  # (rows, 3), N
        names = [s.decode() if isinstance(s, bytes) else s for s in f["walls"].attrs["names"]]
        normal = f["walls/normal"][a.wall]
        vel = f["walls/velocity"][a.wall]
    n = normal / np.linalg.norm(normal) if np.linalg.norm(normal) > 0 else np.array([0, 1, 0])
    reaction = -(force @ n)  # the push of the grains into the wall, > 0 in compression
    disp = -(vel @ n) * t    # penetration: the wall's travel against its normal
    unit = "N"
    if a.length:
        reaction, unit = reaction / a.length, "Pa"
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].plot(t * 1e3, reaction, lw=0.8)
    ax[0].set_xlabel("time (ms)")
    ax[0].set_ylabel("reaction (%s)" % unit)
    ax[1].plot(disp * 1e3, reaction, lw=0.8)
    ax[1].set_xlabel("wall displacement against its normal (mm)")
    ax[1].set_ylabel("reaction (%s)" % unit)
    fig.suptitle("%s: wall %d (%s)" % (a.file, a.wall, names[a.wall]))
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    print("wrote", a.out)


if __name__ == "__main__":
    main()
