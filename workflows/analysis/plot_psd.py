#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Grading (particle size distribution) over time and Hardin's relative breakage B_r from a
pd-file, with h5py + matplotlib: the data of pd-post --fragments (psd.csv), computed here by
fragments.py. Copy and edit.

    plot_psd.py FILE.h5 [-o psd.png] [--fines-nodes 10] [--cutoff D] [--curves 5]
                [--wall K | --body B] [--length L] [--csv psd_table.csv]

Panels: the mass-weighted cumulative grading (fraction finer than d, log d) at --curves frames
spread over the run; B_r against time; and, when the file has a wall reaction (a rigid wall's
/observables/wall_force, else the meshed wall that travels farthest, as plot_wall_reaction.py),
B_r against that reaction (a stress with --length, m in 2D or m2 in 3D). Needs the fragment
frame field (scene solver.fields); definitions in fragments.py."""

import argparse
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fragments  # noqa: E402
import plot_wall_reaction  # noqa: E402


def fail(msg):
    print("plot_psd.py: error: " + msg, file=sys.stderr)
    sys.exit(2)


def wall_reaction(f, a):
    """(time, reaction, label) of the chosen or the file's wall, or None when it records none."""
    if a.wall is not None:
        t, r, _, label, _ = plot_wall_reaction.rigid_wall(f, a.wall)
        return t, r, label
    if a.body is not None:
        t, r, _, label, _ = plot_wall_reaction.meshed_wall(f, a.body, None)
        return t, r, label
    if "walls" in f and "observables/wall_force" in f:
        t, r, _, label, _ = plot_wall_reaction.rigid_wall(f, 0)
        return t, r, label
    if "observables/body_force" in f:
        t, r, _, label, _ = plot_wall_reaction.meshed_wall(f, plot_wall_reaction.pick_body(f),
                                                           None)
        return t, r, label
    return None


def grading_curves(f, a):
    """Per frame: time, the psd row and the sorted (d, cumulative fraction) of every piece."""
    out = []
    for step, t, rows, psd in fragments.frames(f, a.fines_nodes, a.cutoff):
        # every piece (fines by themselves) is in the grading: rebuild it from the rows'
        # fragments plus the fines' total at the bottom of the curve
        d = np.array([r["diameter"] for r in rows if r["fragment"] >= 0] + [0.0])
        w = np.array([r["mass"] for r in rows if r["fragment"] >= 0] + [psd["fines_mass"]])
        o = np.argsort(d)
        out.append((step, t, psd, d[o], np.cumsum(w[o]) / w.sum()))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("-o", "--out", default="psd.png")
    ap.add_argument("--fines-nodes", type=int, default=10)
    ap.add_argument("--cutoff", type=float, default=0.0, help="Hardin cut-off d (m)")
    ap.add_argument("--curves", type=int, default=5, help="grading curves drawn")
    who = ap.add_mutually_exclusive_group()
    who.add_argument("--wall", type=int, help="rigid wall index (default: 0)")
    who.add_argument("--body", type=int, help="body id of a fixed or driven meshed wall")
    ap.add_argument("--length", type=float, help="length (2D) or area (3D) for a stress")
    ap.add_argument("--csv", help="also write the per-frame table here")
    a = ap.parse_args()
    try:
        f = h5py.File(a.file, "r")
    except OSError as e:
        fail("%s: cannot open (%s)" % (a.file, e))
    with f:
        if "particles/nodes/fragment" not in f:
            fail("%s: no /particles/nodes/fragment (add \"fragment\" to solver.fields)" % a.file)
        frames = grading_curves(f, a)
        wall = wall_reaction(f, a)
    t = np.array([fr[1] for fr in frames])
    br = np.array([fr[2]["B_r"] for fr in frames])
    if a.csv:
        keys = list(frames[0][2])
        with open(a.csv, "w") as out:
            out.write("step,time," + ",".join(keys) + "\n")
            for step, tk, psd, _, _ in frames:
                out.write("%d,%.17g," % (step, tk) + ",".join("%.17g" % psd[k] for k in keys)
                          + "\n")
    fig, ax = plt.subplots(1, 3 if wall else 2, figsize=(14 if wall else 10, 4))
    picks = sorted(set(np.linspace(0, len(frames) - 1, a.curves).round().astype(int)))
    for k in picks:
        _, tk, psd, d, cum = frames[k]
        ax[0].step(np.maximum(d, psd["cutoff"] / 10) * 1e3, cum, where="post",
                   label="t = %.3g ms" % (tk * 1e3))
    ax[0].axvline(frames[0][2]["cutoff"] * 1e3, color="grey", ls=":", lw=0.8, label="d_cut")
    ax[0].set_xscale("log")
    ax[0].set_xlabel("equivalent diameter d (mm)")
    ax[0].set_ylabel("mass fraction finer")
    ax[0].legend(fontsize=7)
    ax[1].plot(t * 1e3, br, ".-", lw=0.8)
    ax[1].set_xlabel("time (ms)")
    ax[1].set_ylabel("relative breakage B_r")
    if wall:
        tw, r, label = wall
        unit = "N"
        if a.length:
            r, unit = r / a.length, "Pa"
        ax[2].plot(np.interp(t, tw, r), br, ".-", lw=0.8)
        ax[2].set_xlabel("%s reaction (%s)" % (label, unit))
        ax[2].set_ylabel("relative breakage B_r")
    fig.suptitle("%s: %d frames, last: %d fragments, %d fines, B_r = %.3g"
                 % (os.path.basename(a.file), len(frames), frames[-1][2]["fragments"],
                    frames[-1][2]["fines"], br[-1]), fontsize=9)
    fig.tight_layout()
    fig.savefig(a.out, dpi=90)
    print("wrote %s (%d frames)" % (a.out, len(frames)))


if __name__ == "__main__":
    main()
