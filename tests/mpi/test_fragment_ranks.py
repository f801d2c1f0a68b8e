#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Issue 31: pd-post --fragments gives the same fragments.csv and psd.csv (fragment ids, masses,
grading, B_r) for the pulled plate solved at 1 and at 2 ranks: the ids are the smallest node
index of each component, whatever the partition."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))
from test_mpi import mpirun, pack, run  # noqa: E402


def table(path):
    return [l for l in path.read_text().splitlines() if not l.startswith("#")]


def test_fragments_same_at_1_and_2_ranks(tmp_path):
    base, by = pack(tmp_path, "plate")
    out = {}
    for ranks in (1, 2):
        f = run(tmp_path, base, by, ranks)
        post = tmp_path / f"post{ranks}"
        mpirun(1, "pd-post", str(f), "-o", str(post), "-q", "--no-vtu", "--no-xdmf",
               "--fragments")
        out[ranks] = (table(post / "fragments.csv"), table(post / "psd.csv"))
    frags, psd = out[1]
    assert len(psd) > 2 and len(frags) >= len(psd)
    assert out[2] == out[1]

