# SPDX-License-Identifier: MIT
"""Command-line contract of the four tools (run with `/usr/bin/python3 -m pytest tests/cli`):
--help exits 0, --version prints a version, and pd-post on a truncated or missing file exits 2
with one stderr line naming the file. PD_BIN_DIR = build bin directory (skipped when unset)."""

import os
import pathlib
import re
import subprocess
import sys

import pytest

TOOLS = ["pd-pack", "pd-partition", "pd-solve", "pd-post"]
HERE = pathlib.Path(__file__).resolve().parent


@pytest.fixture(scope="module")
def bin_dir():
    d = os.environ.get("PD_BIN_DIR")
    if not d:
        pytest.skip("PD_BIN_DIR is not set (build bin directory)")
    return pathlib.Path(d)


def run(exe, *args):
    return subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize("tool", TOOLS)
def test_help_exits_0(bin_dir, tool):
    r = run(bin_dir / tool, "--help")
    assert r.returncode == 0, r.stderr
    assert tool in r.stdout and "Usage" in r.stdout


@pytest.mark.parametrize("tool", TOOLS)
def test_version(bin_dir, tool):
    r = run(bin_dir / tool, "--version")
    assert r.returncode == 0, r.stderr
    assert re.search(r"\b\d+\.\d+\.\d+\b", r.stdout), r.stdout


@pytest.fixture
def good_file(tmp_path):
    """A valid pd-file: the pipeline's if PD_PIPELINE_DIR is set, else a hand-made one."""
    pipeline = os.environ.get("PD_PIPELINE_DIR")
    if pipeline and (pathlib.Path(pipeline) / "two_discs.h5").is_file():
        return pathlib.Path(pipeline) / "two_discs.h5"
    sys.path.insert(0, str(HERE.parent / "python"))
    import synthetic

    return pathlib.Path(synthetic.make(str(tmp_path / "synthetic.h5")))


def assert_one_line_naming(r, path):
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2, r.stderr
    assert len(lines) == 1, r.stderr
    assert str(path) in lines[0]
    assert lines[0].startswith("pd-post: error: ")


@pytest.mark.parametrize("check", [False, True], ids=["export", "check"])
def test_pd_post_truncated_file(bin_dir, good_file, tmp_path, check):
    data = good_file.read_bytes()
    bad = tmp_path / "truncated.h5"
    bad.write_bytes(data[: len(data) // 2])
    r = run(bin_dir / "pd-post", bad, *(["--check"] if check else ["-o", tmp_path / "out"]))
    assert_one_line_naming(r, bad)


@pytest.mark.parametrize("check", [False, True], ids=["export", "check"])
def test_pd_post_missing_file(bin_dir, tmp_path, check):
    missing = tmp_path / "no_such_file.h5"
    r = run(bin_dir / "pd-post", missing, *(["--check"] if check else []))
    assert_one_line_naming(r, missing)


def test_pd_post_not_hdf5(bin_dir, tmp_path):
    bad = tmp_path / "scene.h5"
    bad.write_text("{}\n")
    assert_one_line_naming(run(bin_dir / "pd-post", bad), bad)


def test_pd_post_usage_error(bin_dir):
    r = run(bin_dir / "pd-post")
    assert r.returncode == 2  # a usage error is bad input (CLI11's own 100-127 before)
    assert "file is required" in r.stderr, r.stderr
