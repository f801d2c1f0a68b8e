#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Examples travel (issue 28): two examples copied to a temporary folder run their `make quick`
there, finding the project's scripts through PDGRAIN (examples/common.mk) and the tools through
BIN; without PDGRAIN the copy stops at once and says what to set."""
import os
import pathlib
import shutil
import subprocess

import pytest

SRC = pathlib.Path(os.environ.get("PD_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BIN = pathlib.Path(os.environ.get("PD_BIN_DIR", SRC / "build" / "bin"))


def copy(name, tmp_path):
    dest = tmp_path / "elsewhere" / name
    shutil.copytree(SRC / "examples" / name, dest, ignore=shutil.ignore_patterns("out"))
    return dest


@pytest.mark.parametrize("name, passed", [("two_discs_wall", "restitution"),
                                          ("ellipse_on_tip", "all checks pass")])
def test_copied_example_runs_its_quick_target(tmp_path, name, passed):
    dest = copy(name, tmp_path)
    r = subprocess.run(["make", "-C", str(dest), "quick", f"PDGRAIN={SRC}", f"BIN={BIN}"],
                       capture_output=True, text=True, timeout=900)
    out = r.stdout + r.stderr
    assert r.returncode == 0, out[-4000:]
    assert passed in out, out[-4000:]
    assert any((dest / "out").glob("quick_*.h5")), "the outputs are in the copy's out/"


def test_copy_without_pdgrain_says_what_to_set(tmp_path):
    dest = copy("two_discs_wall", tmp_path)
    r = subprocess.run(["make", "-C", str(dest), "quick", f"BIN={BIN}"], capture_output=True,
                       text=True, timeout=60)
    assert r.returncode != 0
    assert "PDGRAIN" in r.stderr and "common.mk" in r.stderr, r.stderr
