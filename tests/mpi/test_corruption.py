#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""No corruption (issue 13, item 6).

- A file solved without MPI continues under `mpirun -np 2 pd-solve --restart` (HDF5 1.10's
  MPI-IO cannot extend the late-allocated chunks of a serial file: pwritev EINVAL, then a damaged
  file) and a file solved on 2 ranks continues serially; both end as the uninterrupted run.
- While an MPI pd-solve holds a file (HDF5 takes no lock under MPI-IO), pd-solve, pd-partition,
  pd-post and pd-pack -o on it are refused (exit 2, naming the holder) by pdgrain's own lock
  (`FILE.lock`); the run then finishes normally. A lock left by a killed run is taken over.
- On a full disk (a small tmpfs this test mounts; skipped unless root can mount) every tool exits
  2 or 3 with a message, the input file stays valid and /checkpoints@latest names a checkpoint
  whose data are those of the run up to that step.
"""
import os
import pathlib
import shutil
import signal
import socket
import subprocess
import sys
import time

import h5py
import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(__file__))
import scenes  # noqa: E402

BIN = os.environ.get("PD_BIN_DIR", "build/bin")
SRC = pathlib.Path(os.environ.get("PD_SOURCE_DIR", pathlib.Path(__file__).parents[2]))
CHECK = SRC / "data-schema/check_pd_file.py"
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMP_NUM_THREADS="1", OMPI_MCA_rmaps_base_oversubscribe="1")
TOL = 1e-12  # serial and 2-rank runs sum forces in another order


def cmd(ranks, tool, *args):
    pre = ["mpirun", "--oversubscribe", "-np", str(ranks)] if ranks > 1 else []
    return pre + [f"{BIN}/{tool}", *map(str, args)]


def run(ranks, tool, *args, check=True, timeout=300):
    r = subprocess.run(cmd(ranks, tool, *args), env=ENV, capture_output=True, text=True,
                       timeout=timeout)
    if check:
        assert r.returncode == 0, r.stdout + r.stderr
    return r


def valid(f):
    r = subprocess.run(["/usr/bin/python3", str(CHECK), "-q", str(f)], capture_output=True,
                       text=True)
    return r.returncode == 0, r.stdout + r.stderr


@pytest.fixture(scope="module")
def base(tmp_path_factory):
    d = tmp_path_factory.mktemp("corruption")
    scene = dict(scenes.TWO_DISCS)
    sp = scenes.write(scene, d / "two_discs.json")
    f = d / "base.h5"
    run(1, "pd-pack", sp, "-o", f, "-q")
    return f


def positions(f):
    with h5py.File(f, "r") as h:
        return (h["particles/nodes/position/step"][()],
                h["particles/nodes/position/value"][()])


@pytest.mark.parametrize("first,second", [(1, 2), (2, 1)])
def test_restart_across_rank_counts(tmp_path, base, first, second):
    ref = tmp_path / "ref.h5"
    shutil.copy(base, ref)
    run(1, "pd-solve", ref, "--steps", 240, "-q")
    f = tmp_path / "f.h5"
    shutil.copy(base, f)
    run(first, "pd-solve", f, "--steps", 120, "-q")
    r = run(second, "pd-solve", f, "--restart", "--steps", 120, "-q", check=False)
    assert r.returncode == 0, r.stdout + r.stderr
    ok, why = valid(f)
    assert ok, why
    s_ref, x_ref = positions(ref)
    s, x = positions(f)
    assert list(s) == list(s_ref)
    assert len(s) >= 3
    err = np.abs(x - x_ref).max() / np.abs(x_ref).max()
    print(f"{first} -> {second} ranks: {len(s)} frames, worst position difference {err:.3g}")
    assert err <= TOL
    assert not pathlib.Path(str(f) + ".lock").exists()


def wait_for(pred, seconds, what):
    t0 = time.time()
    while time.time() - t0 < seconds:
        if pred():
            return
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what}")


def children(pid):
    with open(f"/proc/{pid}/task/{pid}/children") as fh:
        return [int(c) for c in fh.read().split()]


def test_second_tool_refused_while_an_mpi_run_holds_the_file(tmp_path, base):
    f = tmp_path / "f.h5"
    shutil.copy(base, f)
    lock = pathlib.Path(str(f) + ".lock")
    p = subprocess.Popen(cmd(2, "pd-solve", f, "--final-time", 1.0, "--progress-every", 1),
                         env=ENV, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        out = []
        for line in p.stdout:  # the run's phase 3 (MPI-IO, collective) has begun
            out.append(line)
            if line.startswith("step "):
                break
        assert lock.exists(), "".join(out)
        before = f.stat().st_mtime_ns
        refusals = {
            "pd-solve": run(1, "pd-solve", f, "--restart", check=False),
            "pd-solve --overwrite": run(1, "pd-solve", f, "--overwrite", check=False),
            "pd-partition": run(1, "pd-partition", f, "-n", 2, check=False),
            "pd-post": run(1, "pd-post", f, "-o", tmp_path / "post", check=False),
            "pd-pack -o": run(1, "pd-pack", SRC / "examples/two_discs/scene.json", "-o", f,
                              check=False),
        }
        for name, r in refusals.items():
            assert r.returncode == 2, (name, r.stdout, r.stderr)
            assert "in use by" in r.stderr and str(lock) in r.stderr, (name, r.stderr)
        print(f"refused while the 2-rank run held the file: {len(refusals)} of "
              f"{len(refusals)} ({', '.join(refusals)})")
        assert not (tmp_path / "post").exists()
        # Stop the run the way Slurm does: it checkpoints and exits 75.
        os.kill(children(p.pid)[-1], signal.SIGTERM)
        p.wait(timeout=120)
        assert p.returncode == 75
        assert f.stat().st_mtime_ns >= before
    finally:
        if p.poll() is None:
            p.kill()
    ok, why = valid(f)
    assert ok, why
    assert not lock.exists()
    # and the file continues
    run(2, "pd-solve", f, "--restart", "--final-time", 1.0, "--steps", 20, "-q")


def test_stale_lock_taken_over_foreign_lock_refused(tmp_path, base):
    f = tmp_path / "f.h5"
    shutil.copy(base, f)
    lock = pathlib.Path(str(f) + ".lock")
    dead = subprocess.Popen(["true"])
    dead.wait()
    lock.write_text(f"{dead.pid} {socket.gethostname()} pd-solve {int(time.time())}\n")
    run(1, "pd-solve", f, "--steps", 10, "-q")  # the killed run's lock is stale
    assert not lock.exists()
    lock.write_text(f"{os.getpid()} other-node.example pd-solve {int(time.time())}\n")
    r = run(1, "pd-partition", f, "-n", 2, check=False)
    assert r.returncode == 2 and "other-node.example" in r.stderr and "rm '" in r.stderr
    assert lock.exists()


def mount_tmpfs(mnt, size):
    """Mounts a tmpfs of `size` bytes at `mnt` (root only; else the test is skipped)."""
    mnt.mkdir()
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(mnt)],
                       capture_output=True, text=True)
    if r.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs (needs root): {r.stderr.strip()}")


def test_full_disk_fails_cleanly_and_keeps_the_checkpoint(tmp_path, base):
    ref = tmp_path / "ref.h5"
    shutil.copy(base, ref)
    run(1, "pd-solve", ref, "--steps", 100, "-q")
    mnt = tmp_path / "full"
    # the file, the 16 MB pd-solve sets aside, and room for two frames or so
    mount_tmpfs(mnt, ref.stat().st_size + (16 << 20) + 300_000)
    try:
        check_full_disk(tmp_path, ref, mnt)
    finally:
        subprocess.run(["umount", "-l", str(mnt)])


def check_full_disk(tmp_path, ref, mnt):
    f = mnt / "f.h5"
    shutil.copy(ref, f)
    r = run(1, "pd-solve", f, "--restart", "--final-time", 1.0, "-q", check=False)
    assert r.returncode in (2, 3), r.stdout + r.stderr
    assert str(f) in r.stderr and "Segmentation" not in r.stderr, r.stderr
    print(f"full disk: pd-solve exit {r.returncode}: {r.stderr.strip()}")
    assert not pathlib.Path(str(f) + ".reserve").exists()
    with h5py.File(f, "r") as h:  # HDF5 reads it: metadata flushed with the reserve's room
        latest = h["checkpoints"].attrs["latest"]
        latest = latest.decode() if isinstance(latest, bytes) else latest
        step = int(h[f"checkpoints/{latest}"].attrs["step"])
    assert step >= 100
    # It continues, on a disk with room, from that checkpoint.
    g = tmp_path / "g.h5"
    shutil.copy(f, g)
    run(1, "pd-solve", g, "--restart", "--steps", 10, "-q")
    ok, why = valid(g)
    assert ok, why


def fill(mnt, leave):
    """Writes a filler file on the tmpfs at `mnt` until `leave` bytes or fewer are free."""
    st = os.statvfs(mnt)
    todo = max(0, st.f_bavail * st.f_frsize - leave)
    chunk = b"\1" * 65536
    with open(mnt / "filler", "ab") as fh:
        try:
            while todo > 0:
                todo -= fh.write(chunk[:min(todo, len(chunk))])
                fh.flush()
        except OSError:
            pass  # full


def latest_checkpoint(f):
    with h5py.File(f, "r") as h:
        latest = h["checkpoints"].attrs["latest"]
        latest = latest.decode() if isinstance(latest, bytes) else latest
        return latest, int(h[f"checkpoints/{latest}"].attrs["step"])


def test_full_disk_every_tool(tmp_path, base):
    """pd-pack, pd-partition, pd-post and pd-solve on a full tmpfs (no byte free, then a little
    room so that their writes start and fail): exit 2 or 3 with a message, the existing output of
    pd-pack byte-identical, the solved file valid with its previous checkpoint, no partial
    output left under a real name."""
    scene = base.parent / "two_discs.json"
    solved = tmp_path / "solved.h5"
    shutil.copy(base, solved)
    run(1, "pd-solve", solved, "--steps", 100, "-q")
    mnt = tmp_path / "full"
    mount_tmpfs(mnt, solved.stat().st_size + base.stat().st_size + (3 << 20))
    try:
        f, out, post = mnt / "f.h5", mnt / "out.h5", mnt / "post"
        shutil.copy(solved, f)
        shutil.copy(base, out)
        before = latest_checkpoint(f)
        out_bytes = out.read_bytes()
        outcomes = []

        def check(tool, r):
            assert r.returncode in (2, 3), (tool, r.returncode, r.stdout + r.stderr)
            assert "error" in r.stderr and "Segmentation" not in r.stderr, (tool, r.stderr)
            assert out.read_bytes() == out_bytes, tool
            ok, why = valid(f)
            assert ok, (tool, why)
            assert latest_checkpoint(f) == before, tool
            left = [p.name for p in mnt.rglob("*") if p.is_file() and
                    (".tmp" in p.name or p.suffix in (".vtu", ".pvd", ".csv", ".xmf"))]
            assert not left, (tool, left)
            outcomes.append(f"{tool}: exit {r.returncode}")

        fill(mnt, 0)  # not a byte free
        check("pd-pack", run(1, "pd-pack", scene, "-o", out, "-q", check=False))
        check("pd-partition", run(1, "pd-partition", f, "-n", 2, check=False))
        check("pd-post", run(1, "pd-post", f, "-o", post, check=False))
        check("pd-solve", run(1, "pd-solve", f, "--restart", "--final-time", 1.0, check=False))
        # A little room: pd-pack sets its 1 MB aside, then the model's write fails; pd-post
        # starts a .vtu that cannot be completed.
        (mnt / "filler").unlink()
        fill(mnt, 1_150_000)
        check("pd-pack (writing)", run(1, "pd-pack", scene, "-o", out, "-q", check=False))
        (mnt / "filler").unlink()
        fill(mnt, 30_000)
        check("pd-post (writing)", run(1, "pd-post", f, "-o", post, check=False))
        print("full disk: " + "; ".join(outcomes))
    finally:
        subprocess.run(["umount", "-l", str(mnt)])
