#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Restitution of grains bouncing off a wall, and the energy balance, from a pd-file (h5py).
Per body in --bodies: the velocity of its centre of mass (nodal volumes as weights: one density
per body) along --axis in the first frame (impact speed v0, the run must start before contact)
and in the last frame (rebound speed v1, after separation: the last --settle fraction of the
frames must show a constant velocity), restitution e = -v1 / v0. Energy balance as
plot_energies.py: mechanical (kinetic + elastic + contact) + dissipated (fracture, damping,
friction, viscous) - external work; drift = max |balance - balance(0)| over the largest energy in
play; and KE(t) <= E(0) + W(t) (no energy source but the external work). Exit 0 if every e is
within --tolerance (absolute) of --restitution and the drift (and the KE excess) is below
--energy-tolerance, 1 if not, 2 if the file lacks frames, velocities or observables.

    check_impact.py FILE.h5 [--bodies 0,1 --restitution 0.8] [--tolerance 0.02]
                    [--energy-tolerance 0.01] [--axis y] [--json out.json]"""

import argparse
import json
import sys

import h5py
import numpy as np

ENERGIES = ("kinetic_energy", "elastic_energy", "contact_energy")
DISSIPATED = ("fracture_energy", "damping_dissipation", "friction_dissipation",
              "viscous_dissipation")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("--bodies", default="", help="comma-separated body indices (none: the "
                    "energy checks only)")
    ap.add_argument("--restitution", type=float, help="expected e (with --bodies)")
    ap.add_argument("--tolerance", type=float, default=0.02, help="allowed |e - expected|")
    ap.add_argument("--energy-tolerance", type=float, default=0.01,
                    help="allowed balance drift, fraction of the energy in play")
    ap.add_argument("--axis", default="y", choices=["x", "y", "z"])
    ap.add_argument("--settle", type=float, default=0.1,
                    help="last fraction of the frames that must show a constant velocity")
    ap.add_argument("--json", help="also write the numbers to this JSON file")
    a = ap.parse_args()
    ax = "xyz".index(a.axis)
    bodies = [int(b) for b in a.bodies.split(",") if b.strip()]
    if bodies and a.restitution is None:
        ap.error("--bodies needs --restitution")
    try:
        f = h5py.File(a.file, "r")
    except OSError as e:
        print(f"check_impact.py: {a.file}: {e}", file=sys.stderr)
        return 2
    with f:
        if "particles/nodes/velocity" not in f or "observables/kinetic_energy" not in f:
            print(f"check_impact.py: {a.file}: no velocity frames or observables (scene "
                  "solver.fields must list velocity; run pd-solve)", file=sys.stderr)
            return 2
        body = f["nodes/body"][()]
        vol = f["nodes/volume"][()]
        vel = f["particles/nodes/velocity/value"]
        nf = vel.shape[0]
        last = max(2, int(round(a.settle * nf)))
        out = {"file": a.file, "bodies": {}}
        ok = True
        for b in bodies:
            sel = body == b
            if not sel.any():
                print(f"check_impact.py: {a.file}: no body {b}", file=sys.stderr)
                return 2
            w = vol[sel] / vol[sel].sum()
            vc = np.array([w @ vel[k][sel, ax] for k in range(nf)])
            v0, v1 = vc[0], vc[-1]
            tail = vc[-last:]
            settled = np.ptp(tail) <= 1e-3 * abs(v0)
            e = -v1 / v0 if v0 != 0 else float("nan")
            good = settled and abs(e - a.restitution) <= a.tolerance
            ok = ok and good
            out["bodies"][b] = {"v0": v0, "v1": v1, "restitution": e, "separated": bool(settled)}
            print(f"body {b}: v0 {v0:.6g} m/s, v1 {v1:.6g} m/s, e = {e:.4f} (expected "
                  f"{a.restitution} +- {a.tolerance}){'' if settled else ', NOT separated'}: "
                  f"{'ok' if good else 'FAIL'}")
        o = f["observables"]
        mech = sum(o[k + "/value"][()] for k in ENERGIES if k in o)
        diss = sum(o[k + "/value"][()] for k in DISSIPATED if k in o)
        work = o["external_work/value"][()] if "external_work" in o else 0 * mech
        bal = mech + diss - work
        scale = float(np.max(mech + diss + np.abs(work)))
        drift = float(np.max(np.abs(bal - bal[0])) / scale) if scale > 0 else 0.0
        damp = float(o["damping_dissipation/value"][-1]) if "damping_dissipation" in o else 0.0
        # No energy source but the external work: KE <= E(0) + W(t), whatever the bookkeeping of
        # the stored energies.
        ke = o["kinetic_energy/value"][()]
        excess = float(np.max(ke - (mech[0] - work[0] + work)) / scale) if scale > 0 else 0.0
        good = drift <= a.energy_tolerance and excess <= a.energy_tolerance
        ok = ok and good
        out.update(kinetic_excess=excess)
        frac = float(o["fracture_energy/value"][-1]) if "fracture_energy" in o else 0.0
        out.update(energy_drift=drift, kinetic_first=float(o["kinetic_energy/value"][0]),
                   kinetic_last=float(o["kinetic_energy/value"][-1]), damping=damp,
                   fracture=frac)
        print(f"energy: KE {out['kinetic_first']:.6g} -> {out['kinetic_last']:.6g} J, damping "
              f"dissipated {damp:.6g} J, balance drift {drift:.3g} of the energy in play "
              f"(allowed {a.energy_tolerance}), max KE - (E(0) + W) {excess:.3g} of it: "
              f"{'ok' if good else 'FAIL'}")
    if a.json:
        with open(a.json, "w") as j:
            json.dump(out, j, indent=1)
    print("ok" if ok else "FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
