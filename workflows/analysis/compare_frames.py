#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Compares the frames of pd-files bit for bit (h5py): every field under /particles/nodes
(position, velocity, damage, ...) and its step and time, against the first file. Prints, per file,
the number of frames, the fields, how many values differ and the largest difference relative to the
field's largest magnitude. Exit 0 if every file's frames equal the first file's exactly, 1 if not
(or if a file has other frames or fields), 2 on a missing file or frames.

    compare_frames.py REF.h5 OTHER.h5 [MORE.h5 ...]"""

import argparse
import os
import sys

import h5py
import numpy as np


def fields(h):
    g = h["particles/nodes"]
    return sorted(k for k in g if isinstance(g[k], h5py.Group) and "value" in g[k])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("files", nargs="+")
    a = ap.parse_args()
    if len(a.files) < 2:
        print("compare_frames.py: give at least two files", file=sys.stderr)
        return 2
    for p in a.files:
        if not os.path.isfile(p):
            print(f"compare_frames.py: {p}: no such file", file=sys.stderr)
            return 2
    ok = True
    with h5py.File(a.files[0], "r") as ref:
        if "particles/nodes/position" not in ref:
            print(f"compare_frames.py: {a.files[0]}: no frames (run pd-solve)", file=sys.stderr)
            return 2
        names = fields(ref)
        for p in a.files[1:]:
            with h5py.File(p, "r") as h:
                if "particles/nodes/position" not in h or fields(h) != names:
                    print(f"{p}: fields {fields(h) if 'particles/nodes' in h else []} differ from "
                          f"{names}")
                    ok = False
                    continue
                differ, worst, frames = 0, 0.0, 0
                for k in names:
                    for part in ("step", "time", "value"):
                        x = ref[f"particles/nodes/{k}/{part}"][()]
                        y = h[f"particles/nodes/{k}/{part}"][()]
                        if x.shape != y.shape:
                            print(f"{p}: {k}/{part} has shape {y.shape}, {a.files[0]} {x.shape}")
                            ok = False
                            differ += 1
                            continue
                        if part == "value":
                            frames = x.shape[0]
                        # bitwise: compare the bytes (NaN == NaN, -0.0 != 0.0)
                        neq = x.view(np.uint8).reshape(x.shape + (-1,)) != \
                            y.view(np.uint8).reshape(y.shape + (-1,))
                        n = int(np.any(neq, axis=-1).sum()) if x.ndim else int(np.any(neq))
                        differ += n
                        if n and part == "value":
                            scale = float(np.abs(x).max()) or 1.0
                            worst = max(worst, float(np.abs(x - y).max()) / scale)
                print(f"{p}: {frames} frames of {', '.join(names)}: {differ} values differ "
                      f"from {a.files[0]} (largest relative difference {worst:.3g})")
                ok = ok and differ == 0
    print("identical" if ok else "NOT identical")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
