#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Crack tip and crack speed over time for a plate, from a pd-file's damage frames, with h5py +
matplotlib. Copy and edit. The same method as `pd-post --crack-origin ... --crack-direction ...`
(crack.csv): damaged nodes are phi > threshold within `band` of the path (a ray from the origin
along the direction, current positions); the tip is the farthest one along the path; the speed is
the least-squares slope of the tip's path length over the 2w+1 frames centred on each frame.
Frames are read one at a time.

    plot_crack_speed.py FILE.h5 --origin X,Y --direction DX,DY [--threshold 0.3] [--band B]
                        [--window W] [-o crack_speed.png]"""

import argparse

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def vec(s):
    v = [float(x) for x in s.split(",")]
    return np.array(v + [0.0] * (3 - len(v)))


def tips(f, origin, d, threshold, band):
    pos, phi = f["particles/nodes/position/value"], f["particles/nodes/damage/value"]
    out = np.full(pos.shape[0], np.nan)
    for k in range(pos.shape[0]):  # one frame in memory at a time
        r = pos[k] - origin
        s = r @ d
        off = np.sqrt(np.maximum((r * r).sum(axis=1) - s * s, 0))
        sel = (phi[k] > threshold) & (off <= band)
        if sel.any():
            out[k] = s[sel].max()
    return out


def speed(t, length, w):
    v = np.full(len(t), np.nan)
    for k in range(len(t)):
        j = np.arange(max(0, k - w), min(len(t), k + w + 1))
        j = j[~np.isnan(length[j])]
        if np.isnan(length[k]) or len(j) < 2:
            continue
        v[k] = np.polyfit(t[j] - t[k], length[j], 1)[0]
    return v


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("--origin", type=vec, required=True, help="x,y[,z] (m)")
    ap.add_argument("--direction", type=vec, required=True, help="dx,dy[,dz]")
    ap.add_argument("--threshold", type=float, default=0.3)
    ap.add_argument("--band", type=float, default=np.inf, help="max distance from the path (m)")
    ap.add_argument("--window", type=int, default=2, help="half-width in frames")
    ap.add_argument("-o", "--out", default="crack_speed.png")
    a = ap.parse_args()
    d = a.direction / np.linalg.norm(a.direction)
    with h5py.File(a.file, "r") as f:
        t = f["particles/nodes/position/time"][()]
        length = tips(f, a.origin, d, a.threshold, a.band)
    v = speed(t, length, a.window)
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].plot(t * 1e6, length * 1e3, "o-", ms=3)
    ax[0].set_xlabel("time (us)")
    ax[0].set_ylabel("crack tip along the path (mm)")
    ax[1].plot(t * 1e6, v, "o-", ms=3)
    ax[1].set_xlabel("time (us)")
    ax[1].set_ylabel("crack speed (m/s), LSQ slope over %d frames" % (2 * a.window + 1))
    fig.suptitle("%s: phi > %g" % (a.file, a.threshold))
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    print("wrote", a.out)


if __name__ == "__main__":
    main()
