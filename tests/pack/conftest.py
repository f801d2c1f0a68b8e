# SPDX-License-Identifier: MIT
"""Shared fixtures of the pd-pack suite (`/usr/bin/python3 -m pytest tests/pack`).
PD_BIN_DIR: the build's bin directory (skipped when unset); PD_SHARED_DIR: the shared data
(default <repo>/../shared)."""

import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def pd_pack():
    d = os.environ.get("PD_BIN_DIR")
    if not d:
        pytest.skip("PD_BIN_DIR is not set (the build's bin directory)")
    exe = pathlib.Path(d) / "pd-pack"
    if not exe.is_file():
        pytest.skip(f"{exe} is not built")
    return exe


@pytest.fixture(scope="session")
def shared_dir():
    d = pathlib.Path(os.environ.get("PD_SHARED_DIR", REPO.parent / "shared"))
    if not (d / "data" / "peridem").is_dir():
        pytest.skip(f"no PeriDEM data under {d}/data/peridem (set PD_SHARED_DIR)")
    return d


def run(*args, timeout=300):
    """Runs a command, returns the CompletedProcess (text)."""
    return subprocess.run([str(a) for a in args], capture_output=True, text=True, timeout=timeout)
