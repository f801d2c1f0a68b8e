#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The kill -9 matrix (issue 13, item 7), CI-sized: a 2-rank pd-solve of two colliding discs
(826 nodes, 0.16 ms: about 160 steps at the automatic dt, a checkpoint every 10 us) is killed
with SIGKILL (every rank) at a few random steps, and each killed file is restarted on 1, 2 and
4 ranks; a serial run killed the same way is restarted on 2 and 4 ranks (serial-to-parallel).
Every killed file must be readable with a complete latest checkpoint, and every restart must
end with frames and checkpoints bitwise equal to the uninterrupted run. The number of kill
points and restarts is printed."""
import json
import os
import pathlib
import random
import shutil
import signal
import subprocess
import sys

import h5py
import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(__file__))
import scenes  # noqa: E402

BIN = os.environ.get("PD_BIN_DIR", "build/bin")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMP_NUM_THREADS="1", OMPI_MCA_rmaps_base_oversubscribe="1")
SEED = int(os.environ.get("PD_KILL_SEED", "13"))  # another seed, other kill points


def cmd(ranks, *args):
    pre = ["mpirun", "--oversubscribe", "-np", str(ranks)] if ranks > 1 else []
    return pre + [f"{BIN}/pd-solve", *map(str, args)]


def solve(ranks, *args):
    r = subprocess.run(cmd(ranks, *args), env=ENV, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr
    return r


def descendants(pid):
    out = []
    try:
        with open(f"/proc/{pid}/task/{pid}/children") as fh:
            kids = [int(c) for c in fh.read().split()]
    except OSError:
        return out
    for k in kids:
        out += [k, *descendants(k)]
    return out


def kill_at(ranks, f, step):
    """Runs pd-solve on `ranks` ranks and SIGKILLs every pd-solve process (and mpirun) once the
    progress line reports `step` or more. Returns the step reached."""
    p = subprocess.Popen(cmd(ranks, f, "--progress-every", 0.02), env=ENV,
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    reached, lines = -1, []
    try:
        for line in p.stdout:
            lines.append(line)
            if line.startswith("step "):
                reached = int(line.split()[1].split("/")[0])
                if reached >= step:
                    break
        ranks_pids = [q for q in descendants(p.pid) if "pd-solve" in _cmdline(q)]
        for q in ranks_pids or [p.pid]:
            os.kill(q, signal.SIGKILL)
        if ranks > 1:
            p.kill()
    finally:
        p.wait(timeout=60)
    assert reached >= step, "the run ended before it could be killed:\n" + "".join(lines)
    return reached


def _cmdline(pid):
    try:
        return pathlib.Path(f"/proc/{pid}/cmdline").read_bytes().decode(errors="replace")
    except OSError:
        return ""


def frames(f):
    with h5py.File(f, "r") as h:
        g = h["particles/nodes"]
        out = {k: (g[k]["step"][()].tolist(), g[k]["value"][()]) for k in sorted(g)
               if isinstance(g[k], h5py.Group) and "value" in g[k]}
        latest = h["checkpoints"].attrs["latest"]
        latest = latest.decode() if isinstance(latest, bytes) else latest
        ck = h[f"checkpoints/{latest}"]
        state = {k: ck[k][()] for k in sorted(ck) if isinstance(ck[k], h5py.Dataset)}
        return out, latest, state


def same(a, b):
    fa, la, sa = a
    fb, lb, sb = b
    if la != lb or sorted(fa) != sorted(fb) or sorted(sa) != sorted(sb):
        return False
    for k in fa:
        if fa[k][0] != fb[k][0] or fa[k][1].tobytes() != fb[k][1].tobytes():
            return False
    return all(np.asarray(sa[k]).tobytes() == np.asarray(sb[k]).tobytes() for k in sa)


@pytest.fixture(scope="module")
def base(tmp_path_factory):
    d = tmp_path_factory.mktemp("killmatrix")
    scene = json.loads(json.dumps(scenes.TWO_DISCS))
    scene["solver"].update(final_time=1.6e-4, output_interval=2e-5, checkpoint_interval=1e-5)
    sp = scenes.write(scene, d / "two_discs.json")
    f = d / "base.h5"
    subprocess.run([f"{BIN}/pd-pack", str(sp), "-o", str(f), "-q"], check=True, env=ENV)
    ref = d / "ref.h5"
    shutil.copy(f, ref)
    solve(2, ref, "-q")
    return f, frames(ref)


def test_kill_matrix(tmp_path, base):
    f0, ref = base
    rng = random.Random(SEED)
    total = max(next(iter(ref[0].values()))[0])  # the run's last step (frames end there)
    # (ranks of the killed run, kill step, restart rank counts)
    plan = [(2, rng.randint(30, total - 60), (1, 2, 4)) for _ in range(3)]
    plan.append((1, rng.randint(30, total - 60), (2, 4)))  # serial to parallel
    restarts = 0
    for i, (ranks, step, again) in enumerate(plan):
        killed = tmp_path / f"killed_{i}.h5"
        shutil.copy(f0, killed)
        reached = kill_at(ranks, killed, step)
        with h5py.File(killed, "r") as h:  # readable, the latest checkpoint complete
            latest = h["checkpoints"].attrs["latest"]
            latest = latest.decode() if isinstance(latest, bytes) else latest
            ck = h[f"checkpoints/{latest}"]
            assert ck.attrs["complete"] == 1
            ck_step = int(ck.attrs["step"])
        for r in again:
            f = tmp_path / f"killed_{i}_on_{r}.h5"
            shutil.copy(killed, f)
            solve(r, f, "--restart", "-q")
            assert same(frames(f), ref), f"kill {i} at step {reached} ({ranks} ranks), " \
                                         f"restart on {r} ranks: differs from the uninterrupted run"
            restarts += 1
        print(f"kill {i}: {ranks} rank(s) SIGKILLed at step {reached} (checkpoint {ck_step}), "
              f"restarted on {', '.join(map(str, again))} ranks: bitwise equal")
    print(f"kill -9 matrix: {len(plan)} kill points, {restarts} restarts, all bitwise equal to "
          f"the uninterrupted 2-rank run (seed {SEED})")
