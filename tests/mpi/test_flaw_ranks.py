#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Issue 31, material flaws: the same bonds break at 1 and 2 ranks."""
import copy
import os
import sys

import h5py

sys.path.insert(0, os.path.dirname(__file__))
import scenes  # noqa: E402
from test_mpi import pack, run, worst_difference  # noqa: E402


def test_flaws_same_at_1_and_2_ranks(tmp_path):
    """Issue 31: the pulled LPS plate with Weibull flaws (m = 6) breaks the same bonds at 1 and
    2 ranks (each bond's factor hashes its nodes within the body, not the rank's numbering);
    and differently from the plate without flaws."""
    scene, by = scenes.SCENES["plate"]
    flawed = copy.deepcopy(scene)
    flawed["materials"]["m"]["flaws"] = {"law": "weibull", "modulus": 6, "seed": 3}
    scenes.SCENES["plate_flaws"] = (flawed, by)
    try:
        base, _ = pack(tmp_path, "plate_flaws")
    finally:
        del scenes.SCENES["plate_flaws"]
    one, two = run(tmp_path, base, by, 1), run(tmp_path, base, by, 2)
    frames, obs, damage = worst_difference(one, two)
    assert frames == 0 and obs <= 1e-12 and damage
    plain = run(tmp_path, pack(tmp_path, "plate")[0], by, 1)
    with h5py.File(one, "r") as a, h5py.File(plain, "r") as b:
        assert a["observables/broken_bonds/value"][-1] != b["observables/broken_bonds/value"][-1]
