#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Pre-emption: SIGTERM (what Slurm sends before the wall-time limit) mid-run makes pd-solve
finish its step, write a checkpoint, record exit status 75 in /provenance and exit 75; under MPI
a signal to one rank stops every rank after the same step. pd-solve --restart then gives frames
and observables bitwise equal to those of an uninterrupted run on as many ranks."""
import os
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
EXIT_PREEMPTED = 75
# Running totals that are summed over ranks (see the assertion below).
# Series summed over steps on each rank: the integrals since t = 0, and the reactions averaged
# over the observation interval (the open interval's sums are checkpointed the same way).
ACCUMULATED = {"external_work", "fracture_energy", "damping_dissipation",
               "friction_dissipation", "viscous_dissipation", "wall_force", "wall_moment",
               "body_force", "body_moment"}


def launch(ranks, *args):
    # The 50-grain pack trips the interpenetration guard late in the run (see test_mpi.py
    # NO_GUARD); this test is about stopping and restarting, so the guard is off.
    cmd = ["mpirun", "--oversubscribe", "-np", str(ranks)] if ranks > 1 else []
    extra = ["--no-penetration-check"] if args[0] == "pd-solve" else []
    return cmd + [f"{BIN}/{args[0]}", *map(str, args[1:]), *extra]


def prepare(tmp_path, base, name, ranks, by):
    f = tmp_path / f"{name}.h5"
    shutil.copy(base, f)
    if ranks > 1:
        subprocess.run(launch(1, "pd-partition", f, "-n", ranks, "--by", by[ranks], "-q"),
                       env=ENV, check=True)
    return f


def children(pid):
    with open(f"/proc/{pid}/task/{pid}/children") as fh:
        return [int(c) for c in fh.read().split()]


def latest_checkpoint_step(h):
    latest = h["checkpoints"].attrs["latest"]
    latest = latest.decode() if isinstance(latest, bytes) else latest
    ck = h[f"checkpoints/{latest}"]
    assert ck.attrs["complete"] == 1
    return int(ck.attrs["step"])


@pytest.mark.parametrize("ranks", [1, 2])
def test_sigterm_checkpoints_exits_75_and_restart_is_bitwise(tmp_path, ranks):
    scene, by = scenes.SCENES["pack50"]
    sp = scenes.write(scene, tmp_path / "pack50.json")
    base = tmp_path / "base.h5"
    subprocess.run([f"{BIN}/pd-pack", str(sp), "-o", str(base), "-q"], check=True, env=ENV)
    ref = prepare(tmp_path, base, "ref", ranks, by)
    subprocess.run(launch(ranks, "pd-solve", ref, "-q"), env=ENV, check=True)

    f = prepare(tmp_path, base, "stopped", ranks, by)
    p = subprocess.Popen(launch(ranks, "pd-solve", f, "--progress-every", "0.02"), env=ENV,
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    seen, total, out = 0, 0, []
    for line in p.stdout:
        out.append(line)
        if line.startswith("step "):
            seen, total = map(int, line.split()[1].split("/"))
            if seen >= 300:  # past the first checkpoint, well before the end (591 steps; 0.5 s)
                break
    assert 300 <= seen < total - 100, "".join(out)
    # Slurm signals the tasks; here one rank only: the others must stop at the same step.
    target = p.pid if ranks == 1 else children(p.pid)[-1]
    os.kill(target, signal.SIGTERM)
    out += p.stdout.readlines()
    p.wait(timeout=120)
    text = "".join(out)
    assert p.returncode == EXIT_PREEMPTED, text
    assert "stopped by SIGTERM after step" in text and "--restart" in text, text
    with h5py.File(f, "r") as h:
        stopped = latest_checkpoint_step(h)
        last = h["provenance"][sorted(h["provenance"])[-1]]
        assert last.attrs["tool"] == "pd-solve" and last.attrs["exit_status"] == EXIT_PREEMPTED
        assert last.attrs["mpi_ranks"] == ranks
    assert seen <= stopped < total
    print(f"{ranks} rank(s): SIGTERM after step {seen}, stopped and checkpointed at step "
          f"{stopped} of {total}")

    r = subprocess.run(launch(ranks, "pd-solve", f, "--restart", "-q"), env=ENV,
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    with h5py.File(ref, "r") as a, h5py.File(f, "r") as b:
        names = [f"particles/nodes/{k}/{d}" for k in a["particles/nodes"]
                 if isinstance(a[f"particles/nodes/{k}"], h5py.Group)
                 for d in ("step", "time", "value") if d in a[f"particles/nodes/{k}"]]
        names += [f"observables/{k}/{d}" for k in a["observables"]
                  if isinstance(a[f"observables/{k}"], h5py.Group)
                  for d in ("step", "time", "value") if d in a[f"observables/{k}"]]
        assert len(names) > 20
        inexact = {}
        for n in names:
            x, y = a[n][...], b[n][...]
            assert x.shape == y.shape, n
            if ranks > 1 and n.split("/")[1] in ACCUMULATED and n.endswith("/value"):
                # Sums over ranks of running totals: the checkpoint holds their sum, carried
                # on by rank 0 after a restart, so the rounding differs in the last bits.
                rel = np.abs(x - y).max() / max(np.abs(x).max(), 1e-300)
                inexact[n.split("/")[1]] = rel
                assert rel <= 1e-12, (n, rel)
            else:
                assert np.array_equal(x, y), n
        print(f"bitwise equal: {len(names) - len(inexact)} series; to 1e-12: "
              + ", ".join(f"{k} {v:.2g}" for k, v in inexact.items()))
        assert latest_checkpoint_step(a) == latest_checkpoint_step(b) == total
