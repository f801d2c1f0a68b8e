#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The shape of the fragment size distribution of a run (issue 31 item 5: Iliev et al., arXiv
1901.04801, log-normal for a single crushed grain, a power law for a bed), from the last frame's
/particles/nodes/fragment (a piece: a connected component of intact bonds) with h5py.

    psd_shape.py FILE.h5 [FILE.h5 ...] [--frame K]

Per file: the pieces that are not the remnant of their grain (less than half its mass), how many
nodes each has, and, when their sizes are resolved (at least MIN_SIZES different node counts),
the maximum-likelihood log-normal and power law (continuous, x_min the smallest piece) of their
masses with the Kolmogorov-Smirnov distance and p-value of each. Pieces of a few nodes are not
resolved: their masses are node volumes, not fragment sizes, and no fit is made."""
import argparse

import h5py
import numpy as np
from scipy import stats

MIN_SIZES = 5


def pieces(path, k):
    """(mass, node count, mass / its grain's mass, time) of every piece of moving grains."""
    with h5py.File(path, "r") as f:
        fr = f["particles/nodes/fragment/value"][k]
        m = f["particles/nodes/mass"][()]
        body = f["nodes/body"][()]
        keep = (f["bodies/kind"][()][body] == 0) & (f["bodies/fixed"][()][body] == 0)
        t = float(f["particles/nodes/position/time"][k])
    ids, inv, cnt = np.unique(fr[keep], return_inverse=True, return_counts=True)
    mass = np.bincount(inv, weights=m[keep])
    parent = np.zeros(len(ids), int)
    parent[inv] = body[keep]
    grain = np.bincount(body[keep], weights=m[keep])
    return mass, cnt, mass / grain[parent], t


def fits(x):
    """KS distance and p of the MLE log-normal and power law of the sample x (> 0)."""
    mu, sg = np.log(x).mean(), np.log(x).std()
    ln = stats.kstest(x, "lognorm", args=(sg, 0, np.exp(mu)))
    xmin = x.min()
    alpha = 1 + len(x) / np.sum(np.log(x / xmin))
    pl = stats.kstest(x, lambda q: 1 - (q / xmin) ** (1 - alpha))
    return {"lognormal": (mu, sg, ln.statistic, ln.pvalue),
            "power_law": (alpha, pl.statistic, pl.pvalue)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--frame", type=int, default=-1)
    a = ap.parse_args()
    for path in a.files:
        mass, cnt, rel, t = pieces(path, a.frame)
        child = rel < 0.5
        sizes = np.unique(cnt[child])
        hist = ", ".join("%d x %d" % (np.sum(cnt[child] == n), n) for n in sizes)
        rem = "remnants >= %.3f of their grain" % rel[~child].min() if (~child).any() \
            else "no remnant"
        print("%s, t = %.4g ms: %d pieces, %d not a grain's remnant (pieces x nodes: %s); %s"
              % (path, t * 1e3, len(mass), child.sum(), hist or "none", rem))
        if len(sizes) < MIN_SIZES:
            print("  not resolved: %d node count(s) among the pieces (< %d), no fit"
                  % (len(sizes), MIN_SIZES))
            continue
        r = fits(mass[child])
        print("  log-normal (mu %.3g, sigma %.3g): KS D %.3f, p %.3g; power law (alpha %.3f): "
              "KS D %.3f, p %.3g" % (r["lognormal"] + r["power_law"]))
    return 0


if __name__ == "__main__":
    main()
