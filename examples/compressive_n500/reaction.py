#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Reaction stress on the plate against its penetration for the compressive test (spec 8.3),
from a solved pd-file: CSV, PNG beside PeriDEM's published curve, and a shape check.

    reaction.py RUN.h5 [-o reaction.csv] [--png reaction.png] [--check BOUNDS.json]

The plate is the rigid wall named "plate" (pd-file 1.3 /walls/start_time: it enters at t1 and
moves at constant velocity). Penetration = its travel since t1 (PeriDEM: since t = 0.06 s, the
restart), or with --reference Y its depth below the height Y (m, along -normal): the full run's
plate enters higher than PeriDEM's 31.22 mm (the pack is not at rest at 0.06 s), and
--reference 0.03122 counts penetration from PeriDEM's entry height, so the curves compare.
Stress = the force the grains push on it, per unit thickness, divided by its loaded
length (the box's inner width, 0.06894 m for n500, as PeriDEM). The curve is smoothed with a
centred moving average over --window seconds (PeriDEM's figure: 75, 300, 900 us).

--check BOUNDS.json tests the smoothed curve (exit 1 when a bound fails, 2 on bad input):
  onset_mm [lo, hi]: first penetration where the stress exceeds onset_kPa;
  at_mm {"p": [lo_kPa, hi_kPa]}: stress at these penetrations;
  plateau_mm [a, b] with plateau_kPa [lo, hi]: mean stress over [a, b] mm, and
  plateau_spread: (max - min) / mean over that range at most this;
  plateau_max_slope: |least-squares slope| over that range at most this many kPa/mm (a curve
  that keeps rising through force-chain noise fails it where the spread alone may not);
  rise_to_mm: the smoothed stress grows from onset to there: its mean over the last quarter of
  that range is at least rise_min_ratio (default 2) x its mean over the first quarter, and its
  least-squares slope at least rise_min_slope kPa/mm (default 0);
  broken_bonds_min: bonds broken by the end of the run at least this many;
  after_onset: true makes at_mm, plateau_mm and rise_to_mm count from the onset."""

import argparse
import json
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# PeriDEM, JMPS 2021 / JOSS 2025 summary figure panel (a), read off the plot (spec 8.3).
PAPER = np.array([[0.5, 0.0], [0.9, 20.0], [1.3, 40.0], [1.6, 60.0], [1.85, 80.0]])
PAPER_PLATEAU = (1.85, 3.4, 85.0, 93.0)  # mm, mm, kPa, kPa


def fail(msg, code=2):
    print("reaction.py: error: " + msg, file=sys.stderr)
    sys.exit(code)


def read(path, length, reference=None):
    with h5py.File(path, "r") as f:
        if "observables/wall_force" not in f:
            fail("%s: no /observables/wall_force (run pd-solve first)" % path)
        names = [s.decode() if isinstance(s, bytes) else s for s in f["walls"].attrs["names"]]
        if "plate" not in names:
            fail("%s: no rigid wall named 'plate' (walls: %s)" % (path, ", ".join(names)))
        k = names.index("plate")
        t = f["observables/wall_force/time"][()]
        force = f["observables/wall_force/value"][:, k, :]
        n = f["walls/normal"][k]
        v = f["walls/velocity"][k]
        t1 = float(f["walls/start_time"][k]) if "walls/start_time" in f else 0.0
        entry = float(f["walls/point"][k] @ -n)  # height of its face at t1, along -normal
        bb = "observables/broken_bonds/value"
        broken = int(f[bb][-1]) if bb in f else 0
    speed = float(v @ n)  # travel along its normal (into the grains), m/s
    keep = t >= t1
    t, force = t[keep], force[keep]
    pen = speed * (t - t1)
    if reference is not None:  # depth below the reference height instead of travel since t1
        pen += reference - entry
    stress = -(force @ n) / length  # Pa: the grains push the plate along -n
    return t, pen, stress, t1, speed, broken


def smooth(t, y, window):
    if len(t) < 3 or window <= 0:
        return y.copy()
    dt = np.median(np.diff(t))
    w = max(1, int(round(window / dt)))
    if w <= 1:
        return y.copy()
    c = np.convolve(y, np.ones(w) / w, mode="same")
    # edges: shrink the window instead of padding with zeros
    half = w // 2
    for i in list(range(min(half, len(y)))) + list(range(max(0, len(y) - half), len(y))):
        lo, hi = max(0, i - half), min(len(y), i + half + 1)
        c[i] = y[lo:hi].mean()
    return c


def check(pen_mm, s_kpa, bounds, broken, measured=None):
    """True when every bound holds; each checked number also goes into `measured` (--json)."""
    ok = True
    measured = {} if measured is None else measured

    def report(name, value, lo, hi, key):
        nonlocal ok
        measured[key] = value
        good = lo <= value <= hi
        ok &= good
        print("  %-28s %10.3f  in [%g, %g]  %s" % (name, value, lo, hi, "ok" if good else "FAIL"))

    thr = bounds.get("onset_kPa", 5.0)
    above = np.nonzero(s_kpa > thr)[0]
    onset = pen_mm[above[0]] if len(above) else np.inf
    if "onset_mm" in bounds:
        report("onset (mm, > %g kPa)" % thr, onset, *bounds["onset_mm"], key="onset_mm")
    if bounds.get("after_onset", False):
        # the other bounds count penetration from the onset: where the settled pack's top lies
        # is a property of stage 1 (how the grains settled), the curve after it of the
        # material and the contact
        if not np.isfinite(onset):
            print("  no onset: the stress never exceeds %g kPa  FAIL" % thr)
            return False
        print("  (penetrations below count from the onset, %.3f mm)" % onset)
        pen_mm, onset = pen_mm - onset, 0.0
    for p, (lo, hi) in bounds.get("at_mm", {}).items():
        p = float(p)
        if p > pen_mm[-1]:
            print("  stress at %.2f mm: the run ends at %.2f mm  FAIL" % (p, pen_mm[-1]))
            ok = False
            continue
        report("stress at %.2f mm (kPa)" % p, float(np.interp(p, pen_mm, s_kpa)), lo, hi,
               key="stress_at_%d_um" % round(p * 1000))
    if "plateau_mm" in bounds:
        a, b = bounds["plateau_mm"]
        sel = (pen_mm >= a) & (pen_mm <= b)
        if pen_mm[-1] < b or not sel.any():
            print("  plateau: the run ends at %.2f mm, before %.2f mm  FAIL" % (pen_mm[-1], b))
            ok = False
        else:
            mean = float(s_kpa[sel].mean())
            report("plateau mean (kPa)", mean, *bounds["plateau_kPa"], key="plateau_kPa")
            if "plateau_spread" in bounds:
                spread = float((s_kpa[sel].max() - s_kpa[sel].min()) / mean)
                report("plateau (max-min)/mean", spread, 0.0, bounds["plateau_spread"],
                       key="plateau_spread")
            if "plateau_max_slope" in bounds:
                slope = float(np.polyfit(pen_mm[sel], s_kpa[sel], 1)[0])
                report("plateau: |slope| (kPa/mm)", abs(slope), 0.0, bounds["plateau_max_slope"],
                       key="plateau_slope")
    if "rise_to_mm" in bounds and np.isfinite(onset):
        # the rise as a trend, robust to the force-chain noise: the mean stress over the last
        # quarter of [onset, end] over that of its first quarter, and the least-squares slope
        end = bounds["rise_to_mm"]
        sel = (pen_mm >= onset) & (pen_mm <= end)
        p, y = pen_mm[sel], s_kpa[sel]
        if len(p) < 4:
            print("  rise: onset %.2f mm leaves no curve before %.2f mm  FAIL" % (onset, end))
            return False
        q = (p[-1] - p[0]) / 4
        ratio = float(y[p >= p[-1] - q].mean() / max(y[p <= p[0] + q].mean(), 1e-30))
        report("rise: last / first quarter", ratio, bounds.get("rise_min_ratio", 2.0), np.inf,
               key="rise_ratio")
        slope = float(np.polyfit(p, y, 1)[0])
        report("rise: slope (kPa/mm)", slope, bounds.get("rise_min_slope", 0.0), np.inf,
               key="rise_slope")
    if "broken_bonds_min" in bounds:
        report("broken bonds at the end", float(broken), bounds["broken_bonds_min"], np.inf,
               key="broken_bonds")
    return ok


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("file")
    ap.add_argument("-o", "--csv", default="reaction.csv")
    ap.add_argument("--png", default=None)
    ap.add_argument("--length", type=float, default=0.06894, help="loaded plate length (m)")
    ap.add_argument("--window", type=float, default=3e-4, help="smoothing window (s)")
    ap.add_argument("--check", default=None, help="bounds JSON (see the docstring)")
    ap.add_argument("--json", default=None, help="with --check: write the checked numbers here")
    ap.add_argument("--reference", type=float, default=None,
                    help="count penetration below this height (m) instead of from entry")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    t, pen, stress, t1, speed, broken = read(a.file, a.length, a.reference)
    if len(t) < 2:
        fail("%s: no observations after the plate entered at t = %g s" % (a.file, t1))
    sm = smooth(t, stress, a.window)
    sm4 = smooth(t, stress, a.window / 4)
    with open(a.csv, "w") as out:
        out.write("time_s,penetration_m,stress_Pa,stress_smooth_%gus_Pa,stress_smooth_%gus_Pa\n"
                  % (a.window / 4 * 1e6, a.window * 1e6))
        for row in zip(t, pen, stress, sm4, sm):
            out.write(",".join("%.9g" % x for x in row) + "\n")
    pen_mm, s_kpa = pen * 1e3, sm / 1e3
    print("%s: plate enters at t = %g s at %g m/s; %d observations up to %.3f mm; "
          "peak smoothed stress %.1f kPa" % (a.file, t1, speed, len(t), pen_mm[-1], s_kpa.max()))
    if a.png:
        fig, ax = plt.subplots(figsize=(5.2, 3.4), dpi=90)
        ax.plot(pen_mm, sm4 / 1e3, lw=0.6, color="0.65", label="pdgrain, %g us" % (a.window / 4 * 1e6))
        ax.plot(pen_mm, s_kpa, lw=1.5, color="C0", label="pdgrain, %g us" % (a.window * 1e6))
        ax.plot(PAPER[:, 0], PAPER[:, 1], "o", color="C3", ms=4, label="PeriDEM (paper)")
        a0, b0, lo, hi = PAPER_PLATEAU
        ax.fill_between([a0, b0], lo, hi, color="C3", alpha=0.15, lw=0, label="PeriDEM plateau")
        ax.set_xlabel("plate penetration (mm)")
        ax.set_ylabel("reaction stress (kPa)")
        ax.set_xlim(0, max(3.6, pen_mm[-1]))
        ax.set_ylim(bottom=min(0, s_kpa.min() * 1.1))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left")
        if a.title:
            ax.set_title(a.title, fontsize=9)
        fig.tight_layout()
        fig.savefig(a.png)
        print("wrote %s, %s" % (a.csv, a.png))
    if a.check:
        try:
            bounds = json.load(open(a.check))
        except (OSError, ValueError) as e:
            fail("%s: %s" % (a.check, e))
        print("checking the smoothed curve against %s:" % a.check)
        measured = {}
        good = check(pen_mm, s_kpa, bounds, broken, measured)
        if a.json:
            with open(a.json, "w") as j:
                json.dump(measured, j, indent=1)
        if not good:
            fail("the reaction curve is outside the bounds of %s" % a.check, 1)
        print("reaction curve within bounds")


if __name__ == "__main__":
    main()
