# SPDX-License-Identifier: MIT
"""`import pdgrain` from the build (PYTHONPATH=build/python, set by ctest) and the tools."""
import os
import pathlib
import subprocess

import pytest

SRC = pathlib.Path(os.environ.get("PD_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BIN = pathlib.Path(os.environ.get("PD_BIN_DIR", SRC / "build" / "bin"))


def tool(*args):
    r = subprocess.run([str(BIN / args[0]), *map(str, args[1:])], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return r


@pytest.fixture(scope="session")
def pdgrain():
    return pytest.importorskip("pdgrain")
