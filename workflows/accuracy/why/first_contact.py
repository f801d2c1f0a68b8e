#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""A moving wall's work at first contact (issue 26, "Why" item 5), from a solved pd-file whose
observables were written every step.

    first_contact.py FILE.h5

Prints, at the first step with a nonzero wall force and the next four: the wall's counted work
W, the contact energy, KE + elastic, and the balance E - W (E = KE + elastic + contact +
dissipation) relative to the energy in play; then the largest |E - W - (E - W)(0)| / play over
the run (the quantity pd-solve's guard checks against its 5 % tolerance).
"""
import sys

import h5py
import numpy as np


def main(path):
    with h5py.File(path, "r") as f:
        o = f["observables"]
        t = o["kinetic_energy/time"][()]
        g = {k: o[k]["value"][()] for k in o if k in (
            "kinetic_energy", "elastic_energy", "contact_energy", "external_work",
            "damping_dissipation", "friction_dissipation", "fracture_energy",
            "viscous_dissipation")}
        F = o["wall_force/value"][()] if "wall_force" in o else None
    E = g["kinetic_energy"] + g["elastic_energy"] + g["contact_energy"]
    D = sum(g.get(k, 0) for k in ("damping_dissipation", "friction_dissipation",
                                  "fracture_energy", "viscous_dissipation"))
    W = g["external_work"]
    bal = E + D - W
    play = np.maximum.accumulate(g["kinetic_energy"] + np.abs(g["elastic_energy"]) +
                                 np.abs(g["contact_energy"]) + np.abs(W))
    rel = np.abs(bal - bal[0]) / np.where(play > 0, play, np.inf)
    on = np.flatnonzero(np.linalg.norm(F.reshape(len(F), -1), axis=1) > 0) if F is not None \
        else np.flatnonzero(g["contact_energy"] > 0)
    print(f"{path}: {len(t)} observations, t = {t[0]:.3g} .. {t[-1]:.3g} s")
    if len(on) == 0:
        print("no contact")
        return
    k0 = int(on[0])
    print("step  t (s)       W (J)       contact (J)  KE+elastic (J)  (E+D-W)-(E+D-W)(0) / play")
    for k in range(max(k0 - 1, 0), min(k0 + 5, len(t))):
        print(f"{k:4d}  {t[k]:.4e}  {W[k]:.4e}  {g['contact_energy'][k]:.4e}   "
              f"{g['kinetic_energy'][k] + g['elastic_energy'][k]:.4e}      {rel[k]:+.4f}")
    m = int(np.argmax(rel))
    print(f"largest |balance drift| / play: {rel[m]:.4f} at step {m} (t = {t[m]:.4g} s); "
          f"at the end {rel[-1]:.4f}")


if __name__ == "__main__":
    main(sys.argv[1])
