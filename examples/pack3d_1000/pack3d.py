#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""One run of examples/pack3d_1000 read with h5py: the settled pack (walls' reaction against its
weight, kinetic energy against the potential energy released), the plate's reaction against
the vertical strain, check_run.py's physics checks, and the quick run's checks.

    pack3d.py FILE.h5 [--analysis DIR] [--json OUT.json] [--png OUT.png] [--check REF.json]

Settled: the mean over the observations in the last SETTLE_WINDOW of the settling stage (before
the plate enters at /walls/start_time) of the vertical force the grains push on the box (floor
and side walls: friction on the sides carries part of the weight) against the weight M g (M
from the nodes' volumes and the material's density), alone and plus what the viscous damping c
of that stage (--settle-damping) holds, -c P_z (P the grains' momentum, /observables/momentum);
KE at the end of the stage against the potential energy released
(-/observables/gravity_potential). Compression: the plate's reaction (the rigid wall "plate",
along -normal) over the box's cross-section, averaged over a strain window
(default 0.005), against the plate's travel over the height it entered at, H0.

--check REF.json: exit 1 when a check fails (bounds in REF.json): |(box reaction - c P_z) /
weight - 1| <= balance_tol, |box reaction / weight - 1| <= weight_tol; KE / PE released <=
ke_ratio_max; the plate's final stress >= rise_min x its stress halfway through the travel
after the onset, and within final_stress_band (Pa); with --grains, no node deeper than
overlap_max_h x h inside another grain's exact shape (overlap.py); the check_run.py checks
listed in check_run pass."""
import argparse
import json
import os
import sys

import h5py
import numpy as np

SETTLE_WINDOW = 2.0e-3  # s: the averaging window at the end of the pour


def wall_names(f):
    return [s.decode() if isinstance(s, bytes) else s for s in f["walls"].attrs["names"]]


def series(o, name, t):
    return np.interp(t, o[name + "/time"][()], o[name + "/value"][()]) if name in o \
        else np.zeros_like(t)


def read(path):
    """dict of the run: observation times, walls' forces, energies, plate, mass, sizes."""
    with h5py.File(path, "r") as f:
        names = wall_names(f)
        k = names.index("plate")
        pts = f["walls/point"][()]
        n = f["walls/normal"][k] / np.linalg.norm(f["walls/normal"][k])
        o = f["observables"]
        t = o["wall_force/time"][()]
        mat = f["materials"][sorted(f["materials"])[0]]
        r = {"t": t, "F": o["wall_force/value"][()], "names": names, "plate": k,
             "t1": float(f["walls/start_time"][k]), "speed": float(f["walls/velocity"][k] @ n),
             "H0": float(pts[k][2] - pts[names.index("floor")][2]),
             "area": float((pts[names.index("x1")][0] - pts[names.index("x0")][0]) *
                           (pts[names.index("y1")][1] - pts[names.index("y0")][1])),
             "rho": float(np.asarray(mat["density"])), "g": float(
                 np.linalg.norm(f["loading/gravity"][()])),
             "volume": float(f["nodes/volume"][()].sum()),
             "nodes": int(f["nodes/volume"].shape[0]), "grains": int(f["bodies/kind"].shape[0]),
             # pd-pack's count: each bond is stored in the rows of both its nodes
             "bonds": int(f["bonds/neighbor"].shape[0]) if "bonds/neighbor" in f else -1,
             "frames": int(f["particles/nodes/position/value"].shape[0])}
        r["plate_normal"] = n
        for e in ("kinetic_energy", "gravity_potential"):
            r[e] = series(o, e, t)
        r["momentum_z"] = np.interp(t, o["momentum/time"][()], o["momentum/value"][:, 2])
    r["mass"] = r["rho"] * r["volume"]
    return r


def settled(r, damping):
    """The pack at the end of the settling stage: the box's vertical reaction against the
    weight, and against the weight less what the viscous damping (c, s^-1) holds, c P_z (P the
    grains' momentum: a creeping pack leans on the damping); KE / PE released."""
    t = r["t"]
    t1 = min(r["t1"], float(t[-1]))  # a run stopped before the plate entered: its end
    sel = (t > t1 - SETTLE_WINDOW) & (t <= t1)
    box = [j for j, s in enumerate(r["names"]) if s != "plate"]
    fz = -float(r["F"][sel][:, box, 2].sum(axis=1).mean())
    floor = -float(r["F"][sel][:, r["names"].index("floor"), 2].mean())
    held = -damping * float(r["momentum_z"][sel].mean())
    weight = r["mass"] * r["g"]
    i1 = int(np.flatnonzero(t <= t1)[-1])
    released = -float(r["gravity_potential"][i1])
    return {"weight": weight, "box_reaction": fz, "floor_reaction": floor,
            "damping_held": held, "reaction_over_weight": fz / weight,
            "floor_over_weight": floor / weight, "balance": (fz + held) / weight,
            "ke_settled": float(r["kinetic_energy"][i1]), "pe_released": released,
            "ke_over_pe": float(r["kinetic_energy"][i1]) / released, "settle_time": t1,
            "settle_damping": damping}


def compression(r, window):
    """The plate's stress against strain after it entered; onset, mid and final stress."""
    on = r["t"] >= r["t1"]
    strain = r["speed"] * (r["t"][on] - r["t1"]) / r["H0"]
    stress = -(r["F"][on][:, r["plate"], :] @ r["plate_normal"]) / r["area"]
    sm = np.array([stress[np.abs(strain - e) <= 0.5 * window].mean() for e in strain])
    below = np.flatnonzero(sm < 0.05 * sm[-1])
    onset = min(int(below[-1]) + 1 if len(below) else 0, len(sm) - 1)
    mid = onset + (len(sm) - 1 - onset) // 2
    return strain, stress, sm, {
        "H0": r["H0"], "area": r["area"], "plate_speed": r["speed"],
        "strain_end": float(strain[-1]), "onset_strain": float(strain[onset]),
        "stress_end": float(sm[-1]), "stress_mid": float(sm[mid]),
        "strain_mid": float(strain[mid]), "rise_ratio": float(sm[-1] / max(sm[mid], 1e-300)),
        "stress_max": float(sm.max()),
        "stress_at": {"%.3f" % q: float(np.interp(q, strain, sm))
                      for q in np.arange(0.01, strain[-1] + 1e-9, 0.01)}}


def physics(path, analysis):
    sys.path.insert(0, analysis)
    import check_run
    return {c.name: {"ok": c.ok, "value": c.value, "bound": c.bound, "detail": c.detail}
            for c in check_run.check_file(path)}


def check(res, ref):
    """The quick run's checks: [(name, ok, text)]."""
    s, c = res["settled"], res["compression"]
    out = [("box reaction + damping = weight", abs(s["balance"] - 1) <= ref["balance_tol"],
            "(%.4g + %.4g N) / M g %.4g N = %.4f (within %g)" % (
                s["box_reaction"], s["damping_held"], s["weight"], s["balance"],
                ref["balance_tol"])),
           ("box reaction = weight", abs(s["reaction_over_weight"] - 1) <= ref["weight_tol"],
            "%.4g N / M g = %.4f (within %g)" % (s["box_reaction"], s["reaction_over_weight"],
                                                  ref["weight_tol"])),
           ("settled", s["ke_over_pe"] <= ref["ke_ratio_max"],
            "KE %.3g J / PE released %.3g J = %.3g (<= %g)" % (
                s["ke_settled"], s["pe_released"], s["ke_over_pe"], ref["ke_ratio_max"])),
           ("plate reaction rises", c["rise_ratio"] >= ref["rise_min"],
            "final %.4g kPa = %.3f x %.4g kPa at strain %.4f (>= %g)" % (
                c["stress_end"] / 1e3, c["rise_ratio"], c["stress_mid"] / 1e3,
                c["strain_mid"], ref["rise_min"]))]
    if "overlap" in res:
        o = res["overlap"]
        out.append(("no node inside another grain", o["depth_over_h"] <= ref["overlap_max_h"],
                    "deepest %.3g mm = %.3f h at %.4g ms (<= %g h; overlap.py)" % (
                        o["depth"] * 1e3, o["depth_over_h"], o["time"] * 1e3,
                        ref["overlap_max_h"])))
    lo, hi = ref["final_stress_band"]
    out.append(("final stress", lo <= c["stress_end"] <= hi, "%.4g kPa at strain %.4f (band "
                "%g-%g kPa)" % (c["stress_end"] / 1e3, c["strain_end"], lo / 1e3, hi / 1e3)))
    for name in ref["check_run"] if "checks" in res else ():
        ch = res["checks"][name]
        out.append(("check_run " + name, bool(ch["ok"]), "%.4g (bound %.4g)" % (
            ch["value"], ch["bound"])))
    return out


def plot(r, res, strain, stress, sm, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    box = [j for j, s in enumerate(r["names"]) if s != "plate"]
    w = res["settled"]["weight"]
    ax[0].plot(r["t"] * 1e3, -r["F"][:, box, 2].sum(axis=1) / w, lw=0.8, label="box (all walls)")
    ax[0].plot(r["t"] * 1e3, -r["F"][:, r["names"].index("floor"), 2] / w, lw=0.8,
               label="floor")
    ax[0].axhline(1, color="k", ls=":", lw=0.8)
    ax[0].axvline(r["t1"] * 1e3, color="grey", ls="--", lw=0.8, label="plate enters")
    ax[0].set_ylim(0, 3)
    ax[0].set_xlabel("time (ms)")
    ax[0].set_ylabel("vertical reaction / weight")
    ax[0].legend(fontsize=7)
    ax[1].plot(strain * 100, stress / 1e3, lw=0.5, color="0.7", label="plate reaction / area")
    ax[1].plot(strain * 100, sm / 1e3, lw=1.5, label="smoothed")
    ax[1].set_xlabel("vertical strain (%)")
    ax[1].set_ylabel("vertical stress on the plate (kPa)")
    ax[1].legend(fontsize=7)
    fig.suptitle("pack3d: %d grains, %d nodes; settled reaction / weight %.4f; plate at %.3g m/s"
                 % (r["grains"], r["nodes"], res["settled"]["reaction_over_weight"],
                    r["speed"]), fontsize=9)
    fig.tight_layout()
    fig.savefig(png, dpi=80)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("--window", type=float, default=0.005, help="strain window of the mean")
    ap.add_argument("--settle-damping", type=float, required=True,
                    help="viscous damping of the settling stage (s^-1)")
    ap.add_argument("--analysis", help="workflows/analysis (adds check_run.py's checks)")
    ap.add_argument("--grains", help="the scene's grain list: adds overlap.py's depth")
    ap.add_argument("--json")
    ap.add_argument("--png")
    ap.add_argument("--check", help="bounds of the quick run (JSON)")
    a = ap.parse_args()
    r = read(a.file)
    pressed = r["t"][-1] > r["t1"] + SETTLE_WINDOW
    strain, stress, sm, comp = compression(r, a.window) if pressed else (
        np.zeros(1), np.zeros(1), np.zeros(1), None)
    res = {k: r[k] for k in ("grains", "nodes", "bonds", "frames", "mass")}
    res.update({"settled": settled(r, a.settle_damping), "compression": comp})
    if a.analysis:
        res["checks"] = physics(a.file, os.path.abspath(a.analysis))
    if a.grains:
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        import overlap
        res["overlap"] = overlap.run(a.file, a.grains)
    s = res["settled"]
    print("%s: %d grains, %d nodes, %d bonds, M = %.4g kg" % (
        a.file, r["grains"], r["nodes"], res["bonds"], r["mass"]))
    print("settled at %.3g ms: box reaction %.4g N = %.4f x weight (floor %.4f), with what the "
          "damping holds %.4f; KE / PE released %.3g" % (
              s["settle_time"] * 1e3, s["box_reaction"], s["reaction_over_weight"],
              s["floor_over_weight"], s["balance"], s["ke_over_pe"]))
    if comp is None:
        print("the run ends at %.4g ms, before the plate entered: no compression" % (
            r["t"][-1] * 1e3))
    else:
        print("plate: H0 %.3f mm; stress %.4g kPa at strain %.4f, %.3f x %.4g kPa at %.4f "
              "(onset %.4f)" % (comp["H0"] * 1e3, comp["stress_end"] / 1e3, comp["strain_end"],
                                comp["rise_ratio"], comp["stress_mid"] / 1e3,
                                comp["strain_mid"], comp["onset_strain"]))
    if "overlap" in res:
        o = res["overlap"]
        print("deepest node inside another grain (exact shapes): %.3g mm = %.3f h at %.4g ms"
              % (o["depth"] * 1e3, o["depth_over_h"], o["time"] * 1e3))
    for name, ch in res.get("checks", {}).items():
        print("  check_run %-28s %s %s" % (name, {True: "PASS", False: "FAIL", None: "SKIP"}[
            ch["ok"]], ch["detail"]))
    if a.png:
        plot(r, res, strain, stress, sm, a.png)
    if a.json:
        with open(a.json, "w") as out:
            json.dump(res, out, indent=1)
    if not a.check:
        return 0
    with open(a.check) as f:
        ref = json.load(f)
    bad = 0
    for name, ok, text in check(res, ref):
        print("%-34s %s  %s" % (name, "PASS" if ok else "FAIL", text))
        bad += not ok
    print("%d check(s) failed" % bad if bad else "all checks pass")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
