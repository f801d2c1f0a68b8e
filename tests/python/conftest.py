# SPDX-License-Identifier: MIT
"""Fixtures of the Python tests (run with `/usr/bin/python3 -m pytest tests/python`).

Environment:
  PD_PIPELINE_DIR  directory holding two_discs.h5 after pd-pack -> pd-partition -> pd-solve and
                   post/ written by `pd-post two_discs.h5 -o post`; tests that need it are
                   skipped when it is unset.
  PD_BIN_DIR       build bin directory with pd-pack, pd-partition, pd-solve, pd-post; tests that
                   run a tool are skipped when it is unset.
Tests on the hand-made file of synthetic.py need neither.
"""

import os
import pathlib
import sys

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
SCHEMA_DIR = REPO / "data-schema"
sys.path.insert(0, str(SCHEMA_DIR))
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))


@pytest.fixture(scope="session")
def pipeline_dir():
    d = os.environ.get("PD_PIPELINE_DIR")
    if not d:
        pytest.skip("PD_PIPELINE_DIR is not set (pipeline output of the two_discs example)")
    return pathlib.Path(d)


@pytest.fixture(scope="session")
def h5file(pipeline_dir):
    f = pipeline_dir / "two_discs.h5"
    assert f.is_file(), "%s missing: run pd-pack, pd-partition, pd-solve first" % f
    return f


@pytest.fixture(scope="session")
def post_dir(pipeline_dir):
    d = pipeline_dir / "post"
    assert d.is_dir(), "%s missing: run `pd-post two_discs.h5 -o post` first" % d
    return d


@pytest.fixture(scope="session")
def bin_dir():
    d = os.environ.get("PD_BIN_DIR")
    if not d:
        pytest.skip("PD_BIN_DIR is not set (build bin directory)")
    return pathlib.Path(d)


@pytest.fixture(scope="session")
def pd_post(bin_dir):
    exe = bin_dir / "pd-post"
    assert exe.is_file(), "%s missing" % exe
    return exe


@pytest.fixture
def synthetic_file(tmp_path):
    import synthetic

    return synthetic.make(str(tmp_path / "synthetic.h5"))
