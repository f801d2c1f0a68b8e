#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Kalthoff-Winkler: check the crack angle and speed that pd-post measured, or plot them.

    kw.py check RUN.h5 RIGHT_DIR LEFT_DIR [--angle 68,72]
    kw.py plot  RUN.h5 RIGHT_DIR LEFT_DIR -o kw.png

RIGHT_DIR/LEFT_DIR hold pd-post's crack_summary.csv and crack_nodes.csv for the cracks from the
notch tips at x = +25 and -25 mm. `check` prints both and exits 1 unless each crack's angle to the
notch axis (angle_to_axis_deg: the path within --crack-fit-radius of the tip) lies in the range
and its mean and peak speeds lie below the Rayleigh speed of the material in RUN.h5 (PMB: plane
stress nu = 1/3 in 2D, nu = 1/4 in 3D)."""

import argparse
import json
import sys

import h5py
import numpy as np
from scipy.optimize import brentq


def rayleigh_speed(path):
    """c_R (m/s) of the first material, from E, nu, rho and the planar assumption."""
    with h5py.File(path, "r") as f:
        dim = int(f.attrs["dimension"])
        planar = f.attrs.get("planar", "plane_stress")
        planar = planar.decode() if isinstance(planar, bytes) else str(planar)
        m = f["materials"][sorted(f["materials"])[0]]
        E, nu, rho = (float(m[k][()]) for k in ("youngs_modulus", "poisson_ratio", "density"))
    cs = np.sqrt(E / (2 * rho * (1 + nu)))
    if dim == 2 and planar == "plane_stress":
        cd = np.sqrt(E / (rho * (1 - nu * nu)))
    else:
        cd = np.sqrt(E * (1 - nu) / (rho * (1 + nu) * (1 - 2 * nu)))
    k2 = (cs / cd) ** 2
    # Rayleigh equation in xi = c / c_s: (2 - xi^2)^2 = 4 sqrt(1 - k2 xi^2) sqrt(1 - xi^2).
    f = lambda xi: (2 - xi**2) ** 2 - 4 * np.sqrt(1 - k2 * xi**2) * np.sqrt(1 - xi**2)
    return brentq(f, 0.5, 0.9999) * cs, cs, cd


def summary(d):
    rows = np.genfromtxt(f"{d}/crack_summary.csv", delimiter=",", names=True, comments="#")
    return np.atleast_1d(rows)[0]


def check(a):
    cr, cs, cd = rayleigh_speed(a.file)
    lo, hi = (float(v) for v in a.angle.split(","))
    print(f"{a.file}: Rayleigh speed c_R = {cr:.0f} m/s (c_s = {cs:.0f}, c_d = {cd:.0f})")
    ok = True
    out = {"rayleigh_speed": cr}
    for name, d in (("right", a.right), ("left", a.left)):
        s = summary(d)
        out[name] = {k: float(s[k]) for k in ("angle_to_axis_deg", "path_angle_to_axis_deg",
                                              "length", "mean_speed", "peak_speed")}
        good = (lo <= s["angle_to_axis_deg"] <= hi and s["mean_speed"] < cr
                and s["peak_speed"] < cr)
        ok = ok and bool(good)
        print(f"  {name} crack: angle to the notch axis {s['angle_to_axis_deg']:.2f} deg "
              f"(whole path {s['path_angle_to_axis_deg']:.2f}), length {s['length'] * 1e3:.1f} mm "
              f"from t = {s['t_start'] * 1e6:.1f} to {s['t_end'] * 1e6:.1f} us, mean speed "
              f"{s['mean_speed']:.0f} m/s, peak {s['peak_speed']:.0f} m/s "
              f"({s['mean_speed'] / cr:.2f} / {s['peak_speed'] / cr:.2f} c_R): "
              f"{'ok' if good else 'FAIL'} (angle in [{lo:g}, {hi:g}], speeds < c_R)")
    if a.json:
        with open(a.json, "w") as j:
            json.dump(out, j, indent=1)
    return 0 if ok else 1


def plot(a):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    with h5py.File(a.file, "r") as f:
        x0 = f["nodes/reference_position"][:]
        dmg = f["particles/nodes/damage"]
        phi = dmg["value"][-1]
        t_end = dmg["time"][-1]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 3.4), gridspec_kw={"width_ratios": [2, 1]})
    top = x0[:, 2] >= x0[:, 2].max() - 1e-9  # 3D: the top face
    hit = top & (phi > 0.05)
    ax.scatter(x0[hit, 0] * 1e3, x0[hit, 1] * 1e3, c=phi[hit], s=1.5, cmap="Greys", vmin=0,
               vmax=0.6, linewidths=0, rasterized=True)
    sc = None
    for d in (a.right, a.left):
        n = np.genfromtxt(f"{d}/crack_nodes.csv", delimiter=",", names=True, comments="#")
        p = n[(n["on_path"] == 1) & (n["z0"] >= x0[:, 2].max() - 1e-9)]
        sc = ax.scatter(p["x0"] * 1e3, p["y0"] * 1e3, c=p["arrival_time"] * 1e6, s=2,
                        cmap="viridis", linewidths=0, rasterized=True)
        s = summary(d)
        o = np.argsort(p["arrival_time"])
        tip = np.maximum.accumulate(p["along"][o])
        bx.plot(p["arrival_time"][o] * 1e6, tip * 1e3,
                label=f"{'right' if d == a.right else 'left'}: {s['angle_to_axis_deg']:.1f} deg, "
                      f"{s['mean_speed']:.0f} m/s")
    cr = rayleigh_speed(a.file)[0]
    ts = np.array(bx.get_xlim())
    t0 = summary(a.right)["t_start"] * 1e6
    bx.plot(ts, (ts - t0) * cr * 1e-3, "k:", label=f"c_R = {cr:.0f} m/s")
    bx.set_ylim(0, 100)
    bx.set_xlabel("t (us)")
    bx.set_ylabel("crack tip along the path (mm)")
    bx.legend(fontsize=7)
    ax.plot([-100, 100, 100, -100, -100], [-50, -50, 50, 50, -50], "k", lw=0.6)
    for xn in (-25, 25):
        ax.plot([xn, xn], [-50, 0], "r", lw=1)
    ax.plot([-25, 25], [-50, -50], "b", lw=2, label="impact, 16 m/s")
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title(f"damage at t = {t_end * 1e6:.0f} us (grey), arrival time (colour)", fontsize=9)
    fig.colorbar(sc, ax=ax, label="arrival (us)", shrink=0.8)
    fig.tight_layout()
    fig.savefig(a.out, dpi=a.dpi)
    print(f"wrote {a.out}")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", choices=["check", "plot"])
    ap.add_argument("file")
    ap.add_argument("right")
    ap.add_argument("left")
    ap.add_argument("--angle", default="68,72", help="allowed angle to the notch axis (deg)")
    ap.add_argument("-o", "--out", default="kalthoff_winkler.png")
    ap.add_argument("--json", default=None, help="check: also write the numbers to this file")
    ap.add_argument("--dpi", type=int, default=80)
    a = ap.parse_args()
    return check(a) if a.what == "check" else plot(a)


if __name__ == "__main__":
    sys.exit(main())
