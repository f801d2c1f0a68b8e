#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Energies, the energy balance and momentum over time from a pd-file's /observables, with h5py +
matplotlib. Copy and edit. Mechanical = kinetic + elastic + contact; dissipated = fracture +
damping + friction + viscous (pd-file 1.2); balance = mechanical + dissipated - external work W
stays at its t = 0 value up to the integrator's error (pd-solve stops, exit 3, when it drifts by
more than --energy-tolerance of the energy in play). The gravitational potential -sum m g . u is
the part of W gravity did. Files from before pd-file 1.2 show no dissipation and no balance.

    plot_energies.py FILE.h5 [-o energies.png]"""

import argparse

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ENERGIES = ("kinetic_energy", "elastic_energy", "contact_energy", "external_work")
DISSIPATED = ("fracture_energy", "damping_dissipation", "friction_dissipation",
              "viscous_dissipation")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("-o", "--out", default="energies.png")
    a = ap.parse_args()
    with h5py.File(a.file, "r") as f:
        obs = f["observables"]
        t = obs["kinetic_energy/time"][()]
        e = {k: obs[k + "/value"][()] for k in ENERGIES if k in obs}
        d = {k: obs[k + "/value"][()] for k in DISSIPATED if k in obs}
        gp = obs["gravity_potential/value"][()] if "gravity_potential" in obs else None
        p = obs["momentum/value"][()] if "momentum" in obs else None
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for k, v in e.items():
        ax[0].plot(t * 1e3, v, label=k.replace("_", " "), lw=0.9)
    for k, v in d.items():
        if np.any(v != 0):
            ax[0].plot(t * 1e3, v, ":", label=k.replace("_", " "), lw=1.1)
    if gp is not None and np.any(gp != 0):
        ax[0].plot(t * 1e3, gp, "-.", label="gravitational potential", lw=0.9)
    total = sum(e[k] for k in ENERGIES[:3] if k in e)
    ax[0].plot(t * 1e3, total, "k--", label="mechanical (KE + elastic + contact)", lw=0.9)
    if len(d) == len(DISSIPATED) and "external_work" in e:
        bal = total + sum(d.values()) - e["external_work"]
        ax[0].plot(t * 1e3, bal, "r-", label="balance (+ dissipated - W)", lw=1.4)
        scale = np.max(total + sum(d.values()) + np.abs(e["external_work"]))
        if scale > 0:
            drift = np.max(np.abs(bal - bal[0])) / scale
            ax[0].set_title("balance drift %.2g %% of the energy in play" % (100 * drift),
                            fontsize=9)
    ax[0].set_xlabel("time (ms)")
    ax[0].set_ylabel("energy (J; per m of thickness in 2D)")
    ax[0].legend(fontsize=8)
    if p is not None:
        for c, name in enumerate("xyz"):
            ax[1].plot(t * 1e3, p[:, c], label="p_" + name, lw=0.9)
        ax[1].plot(t * 1e3, np.linalg.norm(p, axis=1), "k--", label="|p|", lw=0.9)
        ax[1].legend(fontsize=8)
    ax[1].set_xlabel("time (ms)")
    ax[1].set_ylabel("momentum (kg m s-1)")
    fig.suptitle(a.file)
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    print("wrote", a.out)


if __name__ == "__main__":
    main()
