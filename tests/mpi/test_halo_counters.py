#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""pd-solve's per-rank report (issue 29 item 6, lib/pipeline/rank_report.cpp) counts what an
independent count from the file gives.

A 3D PMB block split by node over 2 ranks: rank r's ghosts are the nodes of the other rank that
are bond neighbours of r's nodes (/bonds/offsets, /bonds/neighbor, /partition/owner). Each step
exchanges u and v of the ghosts (6 doubles = 48 B a node; x = x0 + u is recomputed) in one
message to the one peer: rank r sends 48 B for every ghost of the other rank, per step. Two discs split by grain: no bond
crosses the ranks, every ghost is a contact ghost."""
import os
import re
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import scenes  # noqa: E402
from test_mpi import BIN, ENV, mpirun  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "workflows", "bench",
                                "scaling"))
from scaling import parse_ranks  # noqa: E402

BLOCK = {
    "dimension": 3,
    "materials": {"g": {"law": "pmb", "density": 2440, "youngs_modulus": 72e9,
                        "fracture_energy": 135}},
    "discretization": {"mesh_size": 1e-3, "horizon_factor": 3},
    "shapes": {"block": {"type": "box", "size": [0.011, 0.007, 0.005], "mesh": "grid"}},
    "particles": [{"shape": "block", "center": [0, 0, 0], "material": "g",
                   "velocity": [1, 0, 0]}],
    "solver": {"final_time": 1e-3, "dt": "auto", "output_interval": 1e-3,
               "fields": ["velocity"]},
}
STEPS = 7


def pack_split(tmp_path, scene, name, by, steps=STEPS):
    sp = scenes.write(scene, tmp_path / f"{name}.json")
    f = tmp_path / f"{name}.h5"
    subprocess.run([f"{BIN}/pd-pack", str(sp), "-o", str(f), "-q"], check=True, env=ENV)
    mpirun(1, "pd-partition", str(f), "-n", "2", "--by", by, "-q")
    r = mpirun(2, "pd-solve", str(f), "-v", "--steps", str(steps))
    ranks = parse_ranks(r.stdout)
    assert len(ranks) == 2, r.stdout
    summary = re.search(r"halo over (\d+) steps, max/mean of 2 ranks: ghosts (\d+)/", r.stdout)
    assert summary and int(summary.group(1)) == steps, r.stdout
    assert int(summary.group(2)) == max(rk["ghosts"] for rk in ranks)
    return f, ranks


def test_block_ghosts_and_bytes_match_the_bond_list(tmp_path):
    f, ranks = pack_split(tmp_path, BLOCK, "block", "node")
    with h5py.File(f, "r") as h:
        off = h["bonds/offsets"][()]
        nb = h["bonds/neighbor"][()]
        owner = h["partition/owner"][()]
    row = np.repeat(np.arange(len(off) - 1), np.diff(off))
    cross = owner[row] != owner[nb]
    ghosts = [np.unique(nb[cross & (owner[row] == r)]).size for r in (0, 1)]
    owned = [int((owner == r).sum()) for r in (0, 1)]
    assert min(ghosts) > 0
    for r in (0, 1):
        rk = ranks[r]
        assert rk["owned"] == owned[r]
        assert rk["ghosts"] == ghosts[r]
        assert rk["bond"] == ghosts[r]
        assert rk["contact"] == 0  # one body: no contact list
        assert rk["peers"] == 1
        assert rk["msgs_per_step"] == 1  # x, u, v in one message per step
        assert rk["sent_B_per_step"] == 48 * ghosts[1 - r]
        assert rk["recv_B_per_step"] == 48 * ghosts[r]
        assert rk["peak_rss_B"] > 0
        assert 0 <= rk["halo_s"] <= rk["loop_s"]


def test_grain_split_has_contact_ghosts_only(tmp_path):
    # the discs close their 0.3 mm gap at 1 m/s: in contact range from about step 300
    _, ranks = pack_split(tmp_path, scenes.TWO_DISCS, "two_discs", "body", 400)
    for rk in ranks:
        assert rk["bond"] == 0  # whole grains per rank: no bond crosses
        assert rk["contact"] > 0
        assert rk["ghosts"] == rk["contact"]
        assert rk["sent_B_per_step"] > 0


def test_counts_continue_across_a_rebalance(tmp_path):
    """--rebalance hands the run to a new domain, whose counts go on from the old one's
    (Domain::continue_traffic): the report stays whole after a re-partition. A sanity check
    only: without continue_traffic the figures here stay positive too (the loop's start held
    few counts), only smaller."""
    sp = scenes.write(scenes.PACK50, tmp_path / "pack50.json")
    f = tmp_path / "pack50.h5"
    subprocess.run([f"{BIN}/pd-pack", str(sp), "-o", str(f), "-q"], check=True, env=ENV)
    mpirun(1, "pd-partition", str(f), "-n", "2", "--by", "grain", "-q")
    with h5py.File(f, "r+") as h:  # a poor partition: the first checkpoint re-partitions
        owner = h["partition/owner"]
        owner[...] = np.arange(owner.shape[0]) % 2
    r = mpirun(2, "pd-solve", str(f), "--rebalance", "-v")
    assert "re-partitioned" in r.stdout
    ranks = parse_ranks(r.stdout)
    assert len(ranks) == 2
    for rk in ranks:
        assert rk["sent_B_per_step"] > 0 and rk["recv_B_per_step"] > 0
        assert rk["msgs_per_step"] > 0 and rk["reductions_per_step"] > 0
        assert rk["gathered_B"] > 0
