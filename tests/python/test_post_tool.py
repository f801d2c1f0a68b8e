# SPDX-License-Identifier: MIT
"""pd-post as a tool, on the hand-made file of synthetic.py: default output directory, --no-vtu /
--no-csv, /provenance appended on success and on failure, --check leaves the file untouched."""

import shutil
import subprocess

import h5py
import pytest


def run(exe, *args):
    return subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True, timeout=120)


def provenance(path):
    with h5py.File(path, "r") as f:
        return [(k, f["provenance"][k].attrs["tool"], int(f["provenance"][k].attrs["exit_status"]))
                for k in sorted(f["provenance"])]


def test_default_output_directory_and_provenance(pd_post, synthetic_file, tmp_path):
    before = provenance(synthetic_file)
    r = run(pd_post, synthetic_file)
    assert r.returncode == 0, r.stderr
    out = tmp_path / "post"
    assert (out / "synthetic.pvd").is_file()
    assert sorted(p.name for p in out.glob("synthetic_*.vtu")) == [
        "synthetic_%06d.vtu" % k for k in range(3)] + [
        "synthetic_walls_%06d.vtu" % k for k in range(3)]  # its rigid wall, one file per frame
    assert (out / "synthetic_walls.pvd").is_file()
    assert (out / "observables.csv").is_file()
    assert "3 frame(s)" in r.stdout and "observables.csv" in r.stdout
    after = provenance(synthetic_file)
    assert after[:-1] == before
    assert after[-1] == ("%03d_pd_post" % len(before), "pd-post", 0)


@pytest.mark.parametrize("flag, present, absent", [
    ("--no-vtu", ["observables.csv"], ["synthetic.pvd", "synthetic_000000.vtu"]),
    ("--no-csv", ["synthetic.pvd", "synthetic_000000.vtu"], ["observables.csv"]),
])
def test_no_vtu_no_csv(pd_post, synthetic_file, tmp_path, flag, present, absent):
    out = tmp_path / "out"
    r = run(pd_post, synthetic_file, "-o", out, flag)
    assert r.returncode == 0, r.stderr
    for name in present:
        assert (out / name).is_file(), name
    for name in absent:
        assert not (out / name).exists(), name


def test_refusal_is_not_recorded(pd_post, synthetic_file, tmp_path):
    """A refusal (exit 2) leaves the file byte for byte: no /provenance entry (issue 27)."""
    bad = tmp_path / "bad.h5"
    shutil.copyfile(synthetic_file, bad)
    with h5py.File(bad, "a") as f:
        del f["nodes/volume"]
    before = provenance(bad)
    data = open(bad, "rb").read()
    r = run(pd_post, bad, "-o", tmp_path / "out")
    assert r.returncode == 2
    assert "/nodes/volume" in r.stderr and str(bad) in r.stderr
    assert provenance(bad) == before and open(bad, "rb").read() == data


def test_check_writes_nothing(pd_post, synthetic_file):
    data = open(synthetic_file, "rb").read()
    r = run(pd_post, "--check", synthetic_file)
    assert r.returncode == 0, r.stderr
    assert open(synthetic_file, "rb").read() == data


def test_pack_only_file(pd_post, synthetic_file, tmp_path):
    """A file without frames or observables (after pd-pack alone) is valid; pd-post exports
    nothing and says so."""
    f0 = tmp_path / "packed.h5"
    shutil.copyfile(synthetic_file, f0)
    with h5py.File(f0, "a") as f:
        for g in ("particles", "observables", "partition"):
            del f[g]
        for k in list(f["provenance"]):
            if k != "000_pd_pack":
                del f["provenance"][k]
    assert run(pd_post, "--check", f0).returncode == 0
    r = run(pd_post, f0, "-o", tmp_path / "out")
    assert r.returncode == 0, r.stderr
    assert "0 frame(s)" in r.stdout
    assert "no frames" in r.stderr
    assert not list((tmp_path / "out").glob("*.vtu"))


def test_stale_frames_removed(pd_post, synthetic_file, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    for k in (3, 4):
        (out / ("synthetic_%06d.vtu" % k)).write_text("stale")
        (out / ("synthetic_walls_%06d.vtu" % k)).write_text("stale")
    r = run(pd_post, synthetic_file, "-o", out)
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in out.glob("*.vtu")) == [
        "synthetic_%06d.vtu" % k for k in range(3)] + [
        "synthetic_walls_%06d.vtu" % k for k in range(3)]
