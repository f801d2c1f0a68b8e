#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Energies and momentum over time from a pd-file's /observables, with h5py + matplotlib. Copy
and edit. Total = kinetic + elastic + contact; with external work W, total - W should stay flat
(up to the dissipation of contact damping and broken bonds).

    plot_energies.py FILE.h5 [-o energies.png]"""

import argparse

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ENERGIES = ("kinetic_energy", "elastic_energy", "contact_energy", "external_work")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("-o", "--out", default="energies.png")
    a = ap.parse_args()
    with h5py.File(a.file, "r") as f:
        obs = f["observables"]
        t = obs["kinetic_energy/time"][()]
        e = {k: obs[k + "/value"][()] for k in ENERGIES if k in obs}
        p = obs["momentum/value"][()] if "momentum" in obs else None
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    for k, v in e.items():
        ax[0].plot(t * 1e3, v, label=k.replace("_", " "), lw=0.9)
    total = sum(e[k] for k in ENERGIES[:3] if k in e)
    ax[0].plot(t * 1e3, total, "k--", label="total", lw=0.9)
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
