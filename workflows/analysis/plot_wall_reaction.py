#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Reaction of a wall against its displacement (and against time) from a pd-file, with h5py +
matplotlib. Copy and edit.

A rigid wall (--wall K): the force it receives (/observables/wall_force), projected on the wall
normal for a plane; the displacement is /walls/velocity * time along the normal.
A meshed wall (--body B: a fixed body, or one driven by displacement conditions, such as the
plate of examples/compressive_small): the force it receives from contact
(/observables/body_force); the displacement is its centroid's, from the frames (interpolated to
the observable times), along its direction of travel (or --axis for a body that does not move).

    plot_wall_reaction.py FILE.h5 [-o reaction.png] [--wall K | --body B] [--axis x|y|z]
                          [--length L]
Without --wall or --body: rigid wall 0 if the file has rigid walls, else the meshed wall that
travels farthest. With --length (m in 2D, m2 in 3D) the reaction is plotted as a stress (Pa)."""

import argparse
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

AXES = {"x": 0, "y": 1, "z": 2}


def fail(msg):
    print("plot_wall_reaction.py: error: " + msg, file=sys.stderr)
    sys.exit(2)


def rigid_wall(f, k):
    """(time, reaction along -normal, penetration, label) of rigid wall k."""
    if "walls" not in f:
        fail("%s: no rigid walls (/walls); a meshed wall is --body B" % f.filename)
    if "observables/wall_force" not in f:
        fail("%s: no /observables/wall_force (run pd-solve first)" % f.filename)
    force_all = f["observables/wall_force/value"]
    if not 0 <= k < force_all.shape[1]:
        fail("--wall %d: the file has %d rigid wall(s)" % (k, force_all.shape[1]))
    t = f["observables/wall_force/time"][()]
    force = force_all[:, k, :]  # (rows, 3), N
    names = [s.decode() if isinstance(s, bytes) else s for s in f["walls"].attrs["names"]]
    normal = f["walls/normal"][k]
    vel = f["walls/velocity"][k]
    n = normal / np.linalg.norm(normal) if np.linalg.norm(normal) > 0 else np.array([0, 1, 0])
    reaction = -(force @ n)  # the push of the grains into the wall, > 0 in compression
    # penetration: the wall's travel against its normal (a wall with a start_time, pd-file
    # 1.3, enters at that time and moves from then on; linear motion assumed)
    t1 = f["walls/start_time"][k] if "walls/start_time" in f else 0.0
    disp = -(vel @ n) * np.maximum(t - t1, 0.0)
    return t, reaction, disp, "wall %d (%s)" % (k, names[k]), "against its normal"


def centroid_displacement(f, b, t):
    """Volume-weighted centroid displacement (rows, 3) of body b at times t, from the frames."""
    off = f["bodies/node_offsets"][()]
    lo, hi = int(off[b]), int(off[b + 1])
    vol = f["nodes/volume"][lo:hi]
    x0 = f["nodes/reference_position"][lo:hi, :]
    c0 = vol @ x0 / vol.sum()
    if "particles/nodes/position" not in f:
        return np.zeros((len(t), 3))
    tf = f["particles/nodes/position/time"][()]
    pos = f["particles/nodes/position/value"]
    c = np.array([vol @ pos[k, lo:hi, :] / vol.sum() - c0 for k in range(len(tf))])
    return np.stack([np.interp(t, tf, c[:, d]) for d in range(3)], axis=1)


def meshed_wall(f, b, axis):
    """(time, reaction along the travel, travel, label) of the fixed or driven body b."""
    if "observables/body_force" not in f:
        fail("%s: no /observables/body_force: the file has no fixed or driven body, was not "
             "solved yet, or was written before pd-file 1.2.0" % f.filename)
    bodies = list(f["observables/body_force/body"][()])
    if b not in bodies:
        fail("--body %d: reactions are recorded for bodies %s only (fixed or driven)"
             % (b, ", ".join(map(str, bodies))))
    t = f["observables/body_force/time"][()]
    force = f["observables/body_force/value"][:, bodies.index(b), :]  # (rows, 3), N
    u = centroid_displacement(f, b, t)
    if axis is not None:
        d = np.eye(3)[AXES[axis]]
    elif np.linalg.norm(u[-1]) > 0:
        d = u[-1] / np.linalg.norm(u[-1])  # direction of travel
    else:
        fail("body %d does not move: give --axis for the direction of the reaction" % b)
    reaction = -(force @ d)  # the push of the grains against the travel, > 0 in compression
    return t, reaction, u @ d, "meshed wall: body %d" % b, "along its travel"


def pick_body(f):
    if "observables/body_force" not in f:
        fail("%s: no rigid wall and no /observables/body_force (no fixed or driven body, not "
             "solved yet, or written before pd-file 1.2.0)" % f.filename)
    bodies = list(f["observables/body_force/body"][()])
    t = f["observables/body_force/time"][()]
    travel = [np.linalg.norm(centroid_displacement(f, b, t[-1:])[-1]) for b in bodies]
    return int(bodies[int(np.argmax(travel))])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("-o", "--out", default="reaction.png")
    who = ap.add_mutually_exclusive_group()
    who.add_argument("--wall", type=int, help="rigid wall index (order of /walls)")
    who.add_argument("--body", type=int, help="body id of a fixed or driven meshed wall")
    ap.add_argument("--axis", choices=sorted(AXES), help="reaction direction (meshed wall)")
    ap.add_argument("--length", type=float, help="length (2D) or area (3D) for a stress")
    a = ap.parse_args()
    try:
        f = h5py.File(a.file, "r")
    except OSError as e:
        fail("%s: cannot open (%s)" % (a.file, e))
    with f:
        if a.wall is not None:
            series = rigid_wall(f, a.wall)
        elif a.body is not None:
            series = meshed_wall(f, a.body, a.axis)
        elif "walls" in f and "observables/wall_force" in f:
            series = rigid_wall(f, 0)
        else:
            series = meshed_wall(f, pick_body(f), a.axis)
    t, reaction, disp, label, along = series
    unit = "N"
    if a.length:
        reaction, unit = reaction / a.length, "Pa"
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].plot(t * 1e3, reaction, lw=0.8)
    ax[0].set_xlabel("time (ms)")
    ax[0].set_ylabel("reaction (%s)" % unit)
    ax[1].plot(disp * 1e3, reaction, lw=0.8)
    ax[1].set_xlabel("wall displacement %s (mm)" % along)
    ax[1].set_ylabel("reaction (%s)" % unit)
    fig.suptitle("%s: %s" % (a.file, label))
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    print("wrote", a.out)


if __name__ == "__main__":
    main()
