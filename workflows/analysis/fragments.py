#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Fragments and grading of a pd-file with h5py + numpy: the same data as pd-post --fragments
(fragments.csv, psd.csv; lib/post/fragments.cpp), from /particles/nodes/fragment. Copy and edit.

    import fragments
    with h5py.File("run.h5") as f:
        for step, time, rows, g in fragments.frames(f, fines_nodes=10):
            ...  # rows: dicts per fragment (fragment -1: the fines of a body); g: the psd row

A fragment is a connected component of intact bonds (its id: its smallest node index); one of
fewer than `fines_nodes` nodes is a fine, summed per body into a row with fragment -1. Only
moving particle bodies count (not fixed or driven ones). d = equivalent diameter (2D: sqrt(4A/pi) of the area, 3D:
(6V/pi)^(1/3)); d10/d50/d90 are mass-weighted over every piece, each fine by itself; Hardin's
B_p = sum w ln(d/d_cut)+ over mass fractions w, B_t = B_p(first frame) - B_p, B_r = B_t /
B_p(first frame); d_cut defaults to the diameter of `fines_nodes` nodes of the mean volume."""

import numpy as np


def diameter(volume, dim):
    volume = np.asarray(volume, dtype=float)
    return np.sqrt(4 * volume / np.pi) if dim == 2 else np.cbrt(6 * volume / np.pi)


def counted_bodies(f):
    """Moving particles, not the meshed walls (fixed or driven bodies with recorded reactions)."""
    kind = f["bodies/kind"][:]
    fixed = f["bodies/fixed"][:]
    walls = set(f["observables/body_force/body"][:].tolist()) \
        if "observables/body_force/body" in f else set()
    return [b for b in range(len(kind)) if kind[b] == 0 and not fixed[b] and b not in walls]


def densities(f):
    """Density (kg m-3) of each body."""
    rho = {}
    for name, g in f["materials"].items():
        rho[int(g.attrs["index"])] = float(np.asarray(g["density"]))
    return np.array([rho[int(m)] for m in f["bodies/material"][:]])


def default_cutoff(f, fines_nodes):
    off = f["bodies/node_offsets"][:]
    vol = f["nodes/volume"][:]
    sel = np.concatenate([vol[off[b]:off[b + 1]] for b in counted_bodies(f)])
    return float(diameter(fines_nodes * sel.mean(), int(f.attrs["dimension"])))


def percentile(d, w, q):
    """Smallest d whose cumulative mass fraction reaches q (d sorted)."""
    cum = np.cumsum(w)
    return float(d[np.searchsorted(cum, q * cum[-1] * (1 - 1e-12))])


def frames(f, fines_nodes=10, cutoff=0.0):
    """Yields (step, time, rows, psd) per frame; rows as fragments.csv, psd as psd.csv."""
    dim = int(f.attrs["dimension"])
    off = f["bodies/node_offsets"][:]
    vol = f["nodes/volume"][:]
    rho_b = densities(f)
    bodies = counted_bodies(f)
    cutoff = cutoff or default_cutoff(f, fines_nodes)
    g = f["particles/nodes"]
    bp0 = None
    for k in range(g["fragment/value"].shape[0]):
        frag = g["fragment/value"][k].astype(np.int64)
        x = g["position/value"][k]
        v = g["velocity/value"][k] if "velocity" in g else np.zeros_like(x)
        rows, pieces, largest = [], [], []
        for b in bodies:
            lo, hi = off[b], off[b + 1]
            ids, inv = np.unique(frag[lo:hi], return_inverse=True)
            m = rho_b[b] * vol[lo:hi]
            nodes = np.bincount(inv)
            mass = np.bincount(inv, weights=m)
            volume = np.bincount(inv, weights=vol[lo:hi])
            mx = np.stack([np.bincount(inv, weights=m * x[lo:hi, c]) for c in range(3)], 1)
            mv = np.stack([np.bincount(inv, weights=m * v[lo:hi, c]) for c in range(3)], 1)
            big = nodes >= fines_nodes
            for j in np.flatnonzero(big):
                rows.append(dict(fragment=int(ids[j]), body=b, nodes=int(nodes[j]),
                                 volume=volume[j], mass=mass[j], diameter=float(
                                     diameter(volume[j], dim)), x=mx[j] / mass[j],
                                 v=mv[j] / mass[j]))
            if (~big).any():
                fm = mass[~big].sum()
                rows.append(dict(fragment=-1, body=b, nodes=int(nodes[~big].sum()),
                                 volume=volume[~big].sum(), mass=fm,
                                 diameter=float(diameter(volume[~big].sum(), dim)),
                                 x=mx[~big].sum(0) / fm, v=mv[~big].sum(0) / fm))
            pieces += [(diameter(volume[j], dim), mass[j], bool(big[j])) for j in range(len(ids))]
            largest.append(mass[big].max() / mass.sum() if big.any() else 0.0)
        d = np.array([p[0] for p in pieces])
        w = np.array([p[1] for p in pieces])
        order = np.argsort(d, kind="stable")
        d, w = d[order], w[order]
        bp = float((w * np.maximum(0.0, np.log(d / cutoff))).sum() / w.sum())
        bp0 = bp if bp0 is None else bp0
        big = np.array([p[2] for p in pieces])
        psd = dict(fragments=int(big.sum()), fines=int((~big).sum()),
                   fines_mass=float(sum(p[1] for p in pieces if not p[2])), mass=float(w.sum()),
                   d10=percentile(d, w, 0.1), d50=percentile(d, w, 0.5),
                   d90=percentile(d, w, 0.9), largest_over_parent_mean=float(np.mean(largest)),
                   largest_over_parent_min=float(np.min(largest)), B_p=bp, B_t=bp0 - bp,
                   B_r=(bp0 - bp) / bp0 if bp0 > 0 else 0.0, cutoff=cutoff)
        yield int(g["fragment/step"][k]), float(g["fragment/time"][k]), rows, psd
