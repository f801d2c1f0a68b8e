#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""One oedometer run of examples/oedometer_3d read with h5py: the vertical stress on the plate
against the vertical strain, Hardin's relative breakage B_r (pd-post --fragments, psd.csv)
against that stress, the quasi-static and energy figures, and the quick run's checks.

    oedo.py FILE.h5 --psd POST/psd.csv [--png curve.png] [--csv curve.csv] [--json OUT.json]
            [--check REF.json] [--analysis DIR] [--window W]

Stress: the force the grains push on the plate (the rigid wall named "plate",
/observables/wall_force, along -normal) over the plate area, the box's inner cross-section
(walls x0, x1, y0, y1). Strain: the plate's travel since it entered (/walls/start_time; it
enters at /walls/point, placed there by pd-solve, "enter": "above_grains") over the height it
entered at above the floor, H0. The stress is averaged over a centred strain window W (default
0.01). First peak: the largest smoothed stress before the curve first falls more than PEAK_DROP
(0.3) below its running maximum, counted once that maximum has reached PEAK_LEAST (0.2) of the
run's largest stress (the loose lattice collapses first: the plate touches grains that then fall
away); the lowest stress after it, before the stress climbs back above it. Onset: the strain
from which on the smoothed stress stays above 5 % of the first peak up to it.

With --analysis DIR (workflows/analysis) the run's physics checks (check_run.py) are added:
the deepest penetration of a node into another grain or behind a wall and the energy balance.
With fragments.csv next to psd.csv: the fastest centre of mass of a resolved piece (>=
--fines-nodes nodes) and of a grain's fines.

--check REF.json: the quick run's checks (make quick), bounds in REF.json (README, "make quick",
for each bound's derivation); exit 1 when one fails: the first peak within peak_factor of the
estimate columns x E s0 h^2 / area and rise_min x the stress halfway from the onset to it; the
fall after it >= peak_fall_min with B_r higher at its lowest point than at the peak; the final
stress >= end_over_peak_min x the first peak; B_r never falls from frame to frame, reaches
B_r_end_min, and B_r at the onset <= onset_over_end_max x B_r at the end; the resolved pieces'
centre-of-mass speed within check_run.py's speed bound; check_run.py's checks named in
check_run pass. Reported, not checked: KE / (elastic + contact) and the inertial number
I = (v / H0) d sqrt(rho / stress) at the end (quasi-static: I < 1e-3)."""
import argparse
import json
import os
import sys

import h5py
import numpy as np

# The first peak: the largest smoothed stress before the curve first falls more than this
# fraction below its running maximum (a yield-like drop as grains chip and the columns give way).
PEAK_DROP = 0.3
# ... counted once the running maximum has reached this fraction of the run's largest stress.
PEAK_LEAST = 0.2
ENERGIES = ("kinetic_energy", "elastic_energy", "contact_energy", "external_work",
            "fracture_energy", "friction_dissipation", "damping_dissipation", "broken_bonds")


def wall_names(f):
    return [s.decode() if isinstance(s, bytes) else s for s in f["walls"].attrs["names"]]


def box(f):
    """(plate index, plate area m2, floor height m, box width x, y)."""
    names = wall_names(f)
    p = f["walls/point"][()]
    w = {n: p[k] for k, n in enumerate(names)}
    lx, ly = w["x1"][0] - w["x0"][0], w["y1"][1] - w["y0"][1]
    return names.index("plate"), lx * ly, float(w["floor"][2]), lx, ly


def material(f):
    """(E, rho, s0) of the first material, s0 the median critical stretch of 3D PMB
    sqrt(5 Gc / (9 K delta)), K = E / (3 (1 - 2 nu)), delta the largest horizon."""
    g = f["materials"][sorted(f["materials"])[0]]
    e, rho, nu, gc = (float(np.asarray(g[k])) for k in (
        "youngs_modulus", "density", "poisson_ratio", "fracture_energy"))
    delta = float(f["bodies/horizon"][()].max())
    return e, rho, np.sqrt(5 * gc / (9 * e / (3 * (1 - 2 * nu)) * delta))


def read(path):
    """dict of the run: time, plate travel, stress, strain, energies, box and material."""
    with h5py.File(path, "r") as f:
        k, area, floor, lx, ly = box(f)
        n = f["walls/normal"][k] / np.linalg.norm(f["walls/normal"][k])
        t1 = float(f["walls/start_time"][k]) if "walls/start_time" in f else 0.0
        speed = float(f["walls/velocity"][k] @ n)
        z0 = float(f["walls/point"][k][2])
        o = f["observables"]
        t = o["wall_force/time"][()]
        r = {"t": t, "force": -(o["wall_force/value"][:, k, :] @ n), "t1": t1, "speed": speed,
             "area": area, "H0": z0 - floor, "width": (lx, ly)}
        for e in ENERGIES:
            r[e] = np.interp(t, o[e + "/time"][()], o[e + "/value"][()]) if e in o \
                else np.zeros_like(t)
        r["E"], r["rho"], r["s0"] = material(f)
        r["nodes"] = int(f["nodes/volume"].shape[0])
        r["grains"] = int(f["bodies/kind"].shape[0])
        r["d_mean"] = 2.0 * float(np.mean(f["bodies/bounding_radius"][()]))
        r["delta"] = float(f["bodies/horizon"][()].max())
    r["u"] = speed * np.maximum(t - t1, 0.0)
    r["strain"] = r["u"] / r["H0"]
    r["stress"] = r["force"] / area
    return r


def smooth(strain, stress, window):
    """Centred moving average of stress over a strain window (loading part only)."""
    out = np.empty_like(stress)
    for i, e in enumerate(strain):
        sel = np.abs(strain - e) <= 0.5 * window
        out[i] = stress[sel].mean()
    return out


def read_psd(path):
    d = np.genfromtxt(path, delimiter=",", names=True, comments="#")
    return {k: np.atleast_1d(d[k]) for k in d.dtype.names}


def first_peak(sm, drop, least=PEAK_LEAST):
    """Index of the first peak of the smoothed stress: the largest value before the curve first
    falls more than `drop` of its running maximum once that maximum has passed `least` of the
    largest stress of the run (the transients of the collapsing lattice stay below; the last
    index when it never falls), and the index of the lowest value after it, before the stress
    climbs back above the peak."""
    runmax = np.maximum.accumulate(sm)
    fall = np.flatnonzero((sm < (1.0 - drop) * runmax) & (runmax >= least * sm.max()))
    if not len(fall):
        return len(sm) - 1, len(sm) - 1
    p = int(np.argmax(sm[:fall[0]]))
    back = np.flatnonzero(sm[p + 1:] > sm[p])
    end = p + 1 + int(back[0]) if len(back) else len(sm)
    return p, p + int(np.argmin(sm[p:end]))


def curve(r, window, drop=PEAK_DROP):
    """The loading part (t >= t1): strain, raw and smoothed stress, onset index, first peak
    index, the lowest index after it. Onset: the first index from which on the smoothed stress
    stays above 5 % of the first peak up to it."""
    on = r["t"] >= r["t1"]
    e, s = r["strain"][on], r["stress"][on]
    sm = smooth(e, s, window)
    p, low = first_peak(sm, drop)
    below = np.flatnonzero(sm[:p + 1] < 0.05 * sm[p])
    onset = int(below[-1]) + 1 if len(below) else 0
    return on, e, s, sm, min(onset, p), p, low


def stress_figures(r, window):
    on, e, s, sm, onset, p, low = curve(r, window)
    final = float(sm[-1])
    after = sm[onset:]
    runmax = np.maximum.accumulate(after)
    drop = float(np.max((runmax - after) / np.maximum(runmax, 1e-300)))
    mid = onset + (p - onset) // 2
    ke = r["kinetic_energy"][on][onset:]
    stored = (r["elastic_energy"] + r["contact_energy"])[on][onset:]
    c = np.sqrt(r["E"] / r["rho"])
    # inertial number I = strain rate x mean grain diameter x sqrt(rho / stress) (GDR MiDi
    # 2004): quasi-static below ~1e-3
    inertial = r["speed"] / r["H0"] * r["d_mean"] * np.sqrt(r["rho"] / max(float(sm[-1]), 1e-300))
    return {"grains": r["grains"], "nodes": r["nodes"], "H0": r["H0"], "area": r["area"],
            "plate_speed": r["speed"], "wave_speed": float(c), "s0": float(r["s0"]),
            "youngs_modulus": r["E"], "horizon": r["delta"],
            "speed_over_wave": r["speed"] / c,
            "speed_over_wave_s0": r["speed"] / (c * r["s0"]) if r["s0"] > 0 else float("nan"),
            "strain_end": float(e[-1]), "onset_strain": float(e[onset]),
            "stress_end": final, "stress_max": float(sm.max()), "stress_mid": float(sm[mid]),
            "strain_mid": float(e[mid]), "rise_ratio": float(sm[p]) / max(float(sm[mid]), 1e-300),
            "peak_strain": float(e[p]), "peak_stress": float(sm[p]), "low_strain": float(e[low]),
            "low_stress": float(sm[low]), "peak_fall": 1.0 - float(sm[low]) / max(float(sm[p]),
                                                                                   1e-300),
            "end_over_peak": final / max(float(sm[p]), 1e-300), "peak_time": float(
                r["t"][on][p]), "low_time": float(r["t"][on][low]), "onset_time": float(
                r["t"][on][onset]),
            "max_drop": drop, "stress_at": {"%.2f" % q: float(np.interp(q, e, sm))
                                            for q in np.arange(0.02, e[-1] + 1e-9, 0.02)},
            "ke_over_stored_max": float(np.max(ke / np.maximum(stored, 1e-300))),
            "ke_over_stored_end": float(ke[-1] / max(stored[-1], 1e-300)),
            "broken_bonds_end": int(r["broken_bonds"][-1]), "inertial_number_end": float(inertial),
            "d_mean": r["d_mean"]}


def br_at(psd, t):
    """B_r of the last psd frame at or before time t."""
    return float(psd["B_r"][max(int(np.searchsorted(psd["time"], t, side="right")) - 1, 0)])


def breakage_figures(r, psd, window, res):
    """B_r against the smoothed stress at the psd frames; B_r at the onset, the first peak and
    the lowest stress after it; the largest fall of B_r from one frame to the next."""
    on, e, s, sm, onset, p, low = curve(r, window)
    tt = r["t"][on]
    st = np.where(psd["time"] >= r["t1"], np.interp(psd["time"], tt, sm), 0.0)
    br = psd["B_r"]
    return {"B_r_end": float(br[-1]), "B_r_at_onset": br_at(psd, tt[onset]),
            "B_r_at_peak": br_at(psd, tt[p]), "B_r_at_low": br_at(psd, tt[low]),
            "B_r_largest_fall": float(max(np.max(br[:-1] - br[1:], initial=0.0), 0.0)),
            "fines_mass_end": float(psd["fines_mass"][-1]),
            "fragments_end": int(psd["fragments"][-1]),
            "largest_over_parent_min_end": float(psd["largest_over_parent_min"][-1]),
            "fines_end": int(psd["fines"][-1]), "d50_end": float(psd["d50"][-1]),
            "d50_start": float(psd["d50"][0]), "frames": [
                {"time": float(psd["time"][j]), "stress": float(st[j]), "B_r": float(br[j])}
                for j in range(len(br))]}


def fragment_speeds(path, fines_nodes):
    """The fastest centre-of-mass speed of a resolved piece (>= fines_nodes nodes, rows of
    fragments.csv with fragment >= 0) and of a fine (a piece below), over every frame, with
    where they happened."""
    d = np.genfromtxt(path, delimiter=",", names=True, comments="#")
    v = np.sqrt(d["vx"] ** 2 + d["vy"] ** 2 + d["vz"] ** 2)
    big = (d["fragment"] >= 0) & (d["nodes"] >= fines_nodes)
    out = {}
    for key, sel in (("piece", big), ("fine", ~big)):
        if not sel.any():
            out[key] = {"speed": 0.0}
            continue
        k = np.flatnonzero(sel)[int(np.argmax(v[sel]))]
        out[key] = {"speed": float(v[k]), "time": float(d["time"][k]), "body": int(d["body"][k]),
                    "nodes": int(d["nodes"][k]), "mass": float(d["mass"][k])}
    return out


def physics(path, analysis):
    """check_run.py's checks on the file (deepest penetration, energy balance)."""
    sys.path.insert(0, analysis)
    import check_run
    out = {}
    for c in check_run.check_file(path):
        out[c.name] = {"ok": c.ok, "value": c.value, "bound": c.bound, "detail": c.detail}
    return out


def peak_estimate(res, ref):
    """The bed stress at which a grain column's contact reaches the bonds' strength: each of the
    ref["columns"] columns carries stress x area / columns through a contact of one node's face,
    h^2 (h = horizon / horizon_factor), and its bonds fail when the contact stress reaches
    E s0 (Pa)."""
    h = res["horizon"] / ref["horizon_factor"]
    return ref["columns"] * res["youngs_modulus"] * res["s0"] * h * h / res["area"]


def check(res, ref):
    """The quick run's checks: [(name, ok, text)]."""
    c = []
    est = peak_estimate(res, ref)
    lo, hi = est / ref["peak_factor"], est * ref["peak_factor"]
    c.append(("first peak", lo <= res["peak_stress"] <= hi and res["rise_ratio"] >= ref[
        "rise_min"], "%.4g kPa at strain %.4f (estimate %.3g kPa, band %.3g-%.3g); %.3f x the "
        "stress halfway from the onset (>= %g)" % (res["peak_stress"] / 1e3, res["peak_strain"],
                                                   est / 1e3, lo / 1e3, hi / 1e3,
                                                   res["rise_ratio"], ref["rise_min"])))
    c.append(("yield-like drop with breakage", res["peak_fall"] >= ref["peak_fall_min"]
              and res["B_r_at_low"] > res["B_r_at_peak"],
              "the stress falls %.3f of the peak (>= %g) to %.4g kPa at strain %.4f; B_r %.4g "
              "there > %.4g at the peak" % (res["peak_fall"], ref["peak_fall_min"],
                                            res["low_stress"] / 1e3, res["low_strain"],
                                            res["B_r_at_low"], res["B_r_at_peak"])))
    c.append(("hardens again", res["end_over_peak"] >= ref["end_over_peak_min"],
              "final stress %.4g kPa at strain %.4f = %.3f x the first peak (>= %g)" % (
                  res["stress_end"] / 1e3, res["strain_end"], res["end_over_peak"],
                  ref["end_over_peak_min"])))
    c.append(("B_r never falls", res["B_r_largest_fall"] <= 1e-12,
              "largest fall from one frame to the next %.3g" % res["B_r_largest_fall"]))
    c.append(("B_r rises with stress", res["B_r_end"] >= ref["B_r_end_min"]
              and res["B_r_at_onset"] <= ref["onset_over_end_max"] * res["B_r_end"],
              "B_r %.4g at the end (%.4g kPa; >= %g), %.4g at the peak, %.4g at the onset "
              "(strain %.4f; <= %g x the end)" % (
                  res["B_r_end"], res["stress_end"] / 1e3, ref["B_r_end_min"],
                  res["B_r_at_peak"], res["B_r_at_onset"], res["onset_strain"],
                  ref["onset_over_end_max"])))
    checks = res.get("checks", {})
    for name, ch in checks.items():
        if ch["ok"] is not None and name in ref["check_run"]:
            c.append(("check_run " + name, bool(ch["ok"]), "%.4g (bound %.4g)" % (
                ch["value"], ch["bound"])))
    if "speed_bound" in checks and "fragment_speed" in res:
        piece, bound = res["fragment_speed"]["piece"], checks["speed_bound"]["bound"]
        c.append(("resolved pieces' speed", piece["speed"] <= bound,
                  "fastest centre of mass of a piece of >= %d nodes %.3g m/s (bound %.3g, "
                  "check_run's speed bound)" % (ref["fines_nodes"], piece["speed"], bound)))
    return c


def plot(r, res, window, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    on, e, s, sm, onset, p, low = curve(r, window)
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].plot(e * 100, s / 1e3, "-", lw=0.5, color="0.7", label="plate reaction / area")
    ax[0].plot(e * 100, sm / 1e3, "-", lw=1.5, label="smoothed (strain window %g)" % window)
    ax[0].axvline(e[onset] * 100, color="grey", ls=":", lw=0.8, label="onset")
    ax[0].plot(e[[p, low]] * 100, sm[[p, low]] / 1e3, "v", color="C3", ms=5,
               label="first peak, lowest after it")
    ax[0].set_xlabel("vertical strain (%)")
    ax[0].set_ylabel("vertical stress (kPa)")
    ax[0].legend(fontsize=7)
    fr = res["frames"]
    ax[1].plot([q["stress"] / 1e3 for q in fr], [q["B_r"] for q in fr], "o-", ms=3)
    ax[1].set_xlabel("vertical stress (kPa)")
    ax[1].set_ylabel("Hardin's relative breakage B_r")
    fig.suptitle("oedometer: %d grains, %d nodes, plate at %.3g m/s; B_r = %.3g at %.4g kPa"
                 % (res["grains"], res["nodes"], res["plate_speed"], res["B_r_end"],
                    res["stress_end"] / 1e3), fontsize=9)
    fig.tight_layout()
    fig.savefig(png, dpi=80)


def write_csv(r, window, path):
    on, e, s, sm, _, _, _ = curve(r, window)
    with open(path, "w") as out:
        out.write("time,strain,stress,stress_smoothed,kinetic_energy,elastic_energy,"
                  "contact_energy,broken_bonds\n")
        for j, i in enumerate(np.flatnonzero(on)):
            out.write("%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d\n" % (
                r["t"][i], e[j], s[j], sm[j], r["kinetic_energy"][i], r["elastic_energy"][i],
                r["contact_energy"][i], r["broken_bonds"][i]))


def report(path, res):
    print("%s: %d grains, %d nodes, H0 = %.3f mm, plate at %.3g m/s (%.2e c, %.3f c s0)" % (
        path, res["grains"], res["nodes"], res["H0"] * 1e3, res["plate_speed"],
        res["speed_over_wave"], res["speed_over_wave_s0"]))
    print("KE / (elastic + contact) at the end %.3g; inertial number %.3g; v / c %.2e"
          % (res["ke_over_stored_end"], res["inertial_number_end"], res["speed_over_wave"]))
    print("onset at strain %.4f; first peak %.4g kPa at strain %.4f, falls %.3f to %.4g kPa at "
          "%.4f; stress %.4g kPa at strain %.4f (max %.4g kPa)" % (
              res["onset_strain"], res["peak_stress"] / 1e3, res["peak_strain"],
              res["peak_fall"], res["low_stress"] / 1e3, res["low_strain"],
              res["stress_end"] / 1e3, res["strain_end"], res["stress_max"] / 1e3))
    print("B_r %.4g at the end, %.4g at the lowest stress after the peak, %.4g at the peak, "
          "%.4g at the onset; %d fragments, %d fines (%.3g kg), largest piece / its grain >= "
          "%.3f; broken bonds %d" % (res["B_r_end"], res["B_r_at_low"], res["B_r_at_peak"],
                                     res["B_r_at_onset"], res["fragments_end"], res["fines_end"],
                                     res["fines_mass_end"], res["largest_over_parent_min_end"],
                                     res["broken_bonds_end"]))
    for key, q in res.get("fragment_speed", {}).items():
        if q["speed"] > 0:
            print("fastest %s (centre of mass): %.3g m/s at %.4g ms, grain %d, %d nodes, %.3g kg"
                  % ("resolved piece" if key == "piece" else "fines of a grain", q["speed"],
                     q["time"] * 1e3, q["body"], q["nodes"], q["mass"]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("--psd", required=True, help="psd.csv of pd-post --fragments")
    ap.add_argument("--window", type=float, default=0.01, help="strain window of the mean")
    ap.add_argument("--png")
    ap.add_argument("--csv")
    ap.add_argument("--json")
    ap.add_argument("--check", help="bounds of the quick run (JSON)")
    ap.add_argument("--analysis", help="workflows/analysis (adds check_run.py's checks)")
    ap.add_argument("--fines-nodes", type=int, default=10, help="as pd-post --fines-nodes")
    a = ap.parse_args()
    r = read(a.file)
    res = stress_figures(r, a.window)
    res.update(breakage_figures(r, read_psd(a.psd), a.window, res))
    frag = os.path.join(os.path.dirname(a.psd), "fragments.csv")
    if os.path.exists(frag):
        res["fragment_speed"] = fragment_speeds(frag, a.fines_nodes)
    if a.analysis:
        res["checks"] = physics(a.file, os.path.abspath(a.analysis))
    report(a.file, res)
    if a.png:
        plot(r, res, a.window, a.png)
    if a.csv:
        write_csv(r, a.window, a.csv)
    if a.json:
        with open(a.json, "w") as out:
            json.dump(res, out, indent=1)
    if a.check:
        with open(a.check) as f:
            ref = json.load(f)
        bad = 0
        for name, ok, text in check(res, ref):
            print("%-34s %s  %s" % (name, "PASS" if ok else "FAIL", text))
            bad += not ok
        print("%d check(s) failed" % bad if bad else "all checks pass")
        return 1 if bad else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
