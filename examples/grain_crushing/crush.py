#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""One crushing run of examples/grain_crushing read with h5py: the upper platen's reaction F
against its travel u = v t, the crushing force F_c (the peak), sigma = F_c / d, and at the peak
the kinetic over the elastic energy (quasi-static check), the energy balance and the secant
compliance against the 2D line-contact (Hertz-type) reference. Used by strength.py and `make`.

    crush.py FILE.h5 [--png F_u.png] [--csv F_u.csv] [--check REF.json] [--json OUT.json]

--check: the quick run's checks (make quick), bounds in REF.json (measured values and the
tolerances stated there); exit 1 when one fails.

The 2D reference (a disc of radius R, plane stress, between two flat rigid platens, load P per
unit thickness): the shortening of the loaded diameter,
    u_H(P) = (2 P / (pi E)) (2 ln(4 R / b) - 1),   b = sqrt(4 P R / (pi E)),
b the Hertz half-width. Derivation: along the loaded diameter the disc under diametral point
loads has sigma_xx = 2P/(pi d), sigma_yy = -(2P/pi)(1/(R-y) + 1/(R+y)) + 2P/(pi d); integrating
(sigma_yy - nu sigma_xx)/E to a distance c of each pole gives (2P/(pi E))(2 ln(2R/c) - 1 + nu);
Hertz's pressure p0 sqrt(1 - x^2/b^2) replaces the point load's near field by c = (b/2)
exp(nu/2) (the integrals of Hertz's sigma_z and sigma_x along the axis), and nu cancels
(Johnson, Contact Mechanics (1985), ch. 5, line contact). The platen travel also holds the contact law's penalty and the
softer peridynamic surface layer, both of width ~h, so u / u_H falls towards 1 as d / h grows."""
import argparse
import json
import sys

import h5py
import numpy as np

ENERGIES = ("kinetic_energy", "elastic_energy", "contact_energy", "fracture_energy",
            "damping_dissipation", "friction_dissipation", "viscous_dissipation")


def wall_index(f, name):
    names = [s.decode() if isinstance(s, bytes) else s for s in f["walls"].attrs["names"]]
    return names.index(name)


def read(path, wall="top"):
    """dict: t, u (platen travel, m), F (reaction, N/m), the energies, d, E, v."""
    with h5py.File(path, "r") as f:
        k = wall_index(f, wall)
        o = f["observables"]
        t = o["wall_force/time"][()]
        n = f["walls/normal"][k]
        n = n / np.linalg.norm(n)
        v = float(f["walls/velocity"][k] @ n)  # speed towards the grain (n points into it)
        r = {"t": t, "u": v * t, "F": -(o["wall_force/value"][:, k, :] @ n), "v": v}
        for e in ENERGIES + ("external_work", "broken_bonds"):
            r[e] = o[e + "/value"][()] if e in o else np.zeros_like(t)
        x0 = f["nodes/position"][()] if "nodes/position" in f else None
        r["d"] = diameter(f, x0)
        r["E"] = youngs_modulus(f)
        r["nodes"] = int(f["nodes/volume"].shape[0]) if "nodes/volume" in f else 0
    return r


def diameter(f, x0):
    """The grain's diameter (2 x its bounding radius; else its nodes' extent along y), m."""
    if "bodies/bounding_radius" in f:
        return 2.0 * float(f["bodies/bounding_radius"][0])
    if x0 is None:
        for key in ("nodes/x0", "nodes/reference_position"):
            if key in f:
                x0 = f[key][()]
    if x0 is None:
        raise KeyError("no reference node positions in the file")
    return float(x0[:, 1].max() - x0[:, 1].min())


def youngs_modulus(f):
    for m in f["materials"]:
        g = f["materials"][m]
        for key in ("youngs_modulus", "E"):
            if key in g.attrs:
                return float(g.attrs[key])
            if key in g:
                return float(g[key][()])
    return float("nan")


def hertz_2d(P, R, E):
    """Platen travel u_H (m) of a disc between two flat rigid platens at load P (N/m)."""
    b = np.sqrt(4 * P * R / (np.pi * E))
    return 2 * P / (np.pi * E) * (2 * np.log(4 * R / b) - 1)


def analyse(r):
    """The run's numbers (a dict)."""
    F, u = r["F"], r["u"]
    k = int(np.argmax(F))
    fc = float(F[k])
    after = F[k:]
    e = sum(r[x] for x in ENERGIES)
    w = r["external_work"]
    bal = (e - e[0] - w) / np.maximum(e[0] + np.abs(w), 1e-300)
    j = int(np.argmax(F >= 0.5 * fc))
    R = 0.5 * r["d"]
    out = {"d": r["d"], "speed": r["v"], "F_c": fc, "u_c": float(u[k]), "t_c": float(r["t"][k]),
           "sigma": fc / r["d"], "ke_over_elastic_at_peak":
           float(r["kinetic_energy"][k] / max(r["elastic_energy"][k], 1e-300)),
           "contact_over_elastic_at_peak":
           float(r["contact_energy"][k] / max(r["elastic_energy"][k], 1e-300)),
           "balance_at_peak": float(bal[k]), "balance_end": float(bal[-1]),
           "balance_max": float(np.max(np.abs(bal[k // 4:]))),
           "force_end_over_peak": float(after[-1] / fc) if fc > 0 else 1.0,
           "min_after_peak_over_peak": float(after.min() / fc) if fc > 0 else 1.0,
           "peak_fraction_of_run": float(r["t"][k] / r["t"][-1]),
           "broken_bonds_end": int(r["broken_bonds"][-1]),
           "u_over_hertz_at_half_peak": float(u[j] / hertz_2d(F[j], R, r["E"]))
           if np.isfinite(r["E"]) else float("nan"),
           "nodes": r["nodes"]}
    out["crushed"] = bool(out["min_after_peak_over_peak"] < 0.2 and out["peak_fraction_of_run"]
                          < 0.97)
    return out


def check(res, ref):
    """The quick run's checks: [(name, ok, text)]."""
    c = []
    tol = ref["F_c_tolerance"]
    c.append(("F_c", abs(res["F_c"] / ref["F_c"] - 1) <= tol,
              "F_c = %.5g N/m, measured %.5g +- %g %%" % (res["F_c"], ref["F_c"], 100 * tol)))
    c.append(("crushed", res["crushed"],
              "force after the peak falls to %.3f F_c (crushed: < 0.2)" %
              res["min_after_peak_over_peak"]))
    q = ref["ke_over_elastic_max"]
    c.append(("quasi-static", res["ke_over_elastic_at_peak"] <= q,
              "KE / elastic at the peak %.2e (<= %g)" % (res["ke_over_elastic_at_peak"], q)))
    b = ref["balance_tolerance"]
    c.append(("energy balance", max(abs(res["balance_at_peak"]), abs(res["balance_end"])) <= b,
              "balance at the peak %+.2e, at the end %+.2e of the energy in play (<= %g)" %
              (res["balance_at_peak"], res["balance_end"], b)))
    lo, hi = ref["u_over_hertz_at_half_peak"]
    h = res["u_over_hertz_at_half_peak"]
    c.append(("elastic slope", lo <= h <= hi,
              "platen travel / 2D Hertz line contact at F_c / 2: %.3f (stated band %g-%g)" %
              (h, lo, hi)))
    return c


def plot(r, res, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5.5, 4))
    ax.plot(r["u"] * 1e6, r["F"] * 1e-3, "-", lw=1.2, label="top platen reaction")
    P = np.linspace(0.02, 1, 60) * res["F_c"]
    ax.plot(hertz_2d(P, 0.5 * r["d"], r["E"]) * 1e6, P * 1e-3, "k:", lw=1,
            label="2D Hertz line contact (rigid platens)")
    ax.plot([res["u_c"] * 1e6], [res["F_c"] * 1e-3], "ro",
            label="F_c = %.3g kN/m, sigma = F_c/d = %.3g MPa" % (res["F_c"] * 1e-3,
                                                                   res["sigma"] * 1e-6))
    ax.set_xlabel("platen displacement u (um)")
    ax.set_ylabel("force per unit thickness F (kN/m)")
    ax.set_title("d = %.2g mm, platen at %.3g m/s" % (r["d"] * 1e3, r["v"]), fontsize=10)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("--png")
    ap.add_argument("--csv")
    ap.add_argument("--json")
    ap.add_argument("--check")
    a = ap.parse_args()
    r = read(a.file)
    res = analyse(r)
    for k, v in res.items():
        print("%-28s %s" % (k, "%.6g" % v if isinstance(v, float) else v))
    if a.png:
        plot(r, res, a.png)
    if a.csv:
        np.savetxt(a.csv, np.column_stack([r["t"], r["u"], r["F"]]), delimiter=",",
                   header="time_s,platen_displacement_m,force_N_per_m", comments="")
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(res, fh, indent=1)
    if a.check:
        with open(a.check) as fh:
            ref = json.load(fh)
        bad = 0
        for name, ok, text in check(res, ref):
            print("%-5s %-15s %s" % ("ok" if ok else "FAIL", name, text))
            bad += not ok
        return 1 if bad else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
