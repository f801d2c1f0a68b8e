#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""pd-solve under mpirun gives the same answers at 1, 2 and 4 ranks (oversubscribed on two
cores), survives SIGKILL mid-run and restarts on another rank count, and writes files that
plain h5py reads.

Norm: for every frame field, max over frames, nodes and components of |a - b| divided by max |a|
(the field's own scale); for observables the same per series, momentum against its natural scale
sqrt(2 M KE). Frame fields are required to agree to 1e-12 (they are in fact bitwise equal: every
force sum runs in the same order at any rank count); observables are sums over ranks, 1e-12."""
import json
import os
import shutil
import signal
import subprocess
import sys
import time

import h5py
import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(__file__))
import scenes  # noqa: E402

BIN = os.environ.get("PD_BIN_DIR", "build/bin")
SRC = os.environ.get("PD_SOURCE_DIR", ".")
TOL = 1e-12
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMP_NUM_THREADS="1", OMPI_MCA_rmaps_base_oversubscribe="1")


# PACK50 (gravity 3000 m/s^2, default contact) presses a node more than R_c + h/2 into another
# grain by step ~860 (measured; the stress suite's checker agrees): pd-solve's interpenetration
# guard would stop it with exit 3. These tests are about identical answers at any rank count,
# so they run pd-solve with the guard off.
NO_GUARD = "--no-penetration-check"


def mpirun(n, *args, **kw):
    cmd = ["mpirun", "--oversubscribe", "-np", str(n)] if n > 1 else []
    extra = [NO_GUARD] if args[0] == "pd-solve" else []
    return subprocess.run(cmd + [f"{BIN}/{args[0]}", *args[1:], *extra], env=ENV, check=True,
                          capture_output=True, text=True, **kw)


def pack(tmp_path, name):
    scene, by = scenes.SCENES[name]
    sp = scenes.write(scene, tmp_path / f"{name}.json")
    f = tmp_path / f"{name}.h5"
    subprocess.run([f"{BIN}/pd-pack", str(sp), "-o", str(f), "-q"], check=True, env=ENV)
    return f, by


def run(tmp_path, base, by, ranks, *extra):
    f = tmp_path / f"{base.stem}_{ranks}.h5"
    shutil.copy(base, f)
    if ranks > 1:
        mpirun(1, "pd-partition", str(f), "-n", str(ranks), "--by", by[ranks], "-q")
    mpirun(ranks, "pd-solve", str(f), "-q", *extra)
    return f


def frame_fields(h):
    g = h["particles/nodes"]
    return [k for k in g if isinstance(g[k], h5py.Group) and "value" in g[k]]


def worst_difference(fa, fb):
    """Largest normalised difference over frame fields and over observables."""
    with h5py.File(fa, "r") as a, h5py.File(fb, "r") as b:
        frames = 0.0
        assert sorted(frame_fields(a)) == sorted(frame_fields(b))
        for k in frame_fields(a):
            x = a[f"particles/nodes/{k}/value"][:]
            y = b[f"particles/nodes/{k}/value"][:]
            assert x.shape == y.shape, k
            scale = np.abs(x).max()
            if scale > 0:
                frames = max(frames, np.abs(x - y).max() / scale)
        obs = 0.0
        mass = a["particles/nodes/mass"][:].sum() if "mass" in a["particles/nodes"] else 0
        for k in a["observables"]:
            if "value" not in a[f"observables/{k}"]:
                continue
            x = a[f"observables/{k}/value"][:]
            y = b[f"observables/{k}/value"][:]
            assert x.shape == y.shape, k
            scale = np.abs(x).max()
            if k == "momentum":
                ke = a["observables/kinetic_energy/value"][:]
                scale = np.sqrt(2 * mass * ke.max())
            if scale > 0:
                obs = max(obs, np.abs(x - y).max() / scale)
        damage = [np.array_equal(a[f"particles/nodes/{k}/value"][:],
                                 b[f"particles/nodes/{k}/value"][:])
                  for k in ("damage", "broken_bonds") if k in a["particles/nodes"]]
    return frames, obs, all(damage)


@pytest.mark.parametrize("name", ["two_discs", "two_discs_3h", "pack50", "plate"])
def test_same_answers_at_1_2_4_ranks(tmp_path, name):
    base, by = pack(tmp_path, name)
    ref = run(tmp_path, base, by, 1)
    with h5py.File(ref, "r") as h:
        broken = h["observables/broken_bonds/value"][-1]
        contacts = h["observables/contact_count/value"][:].max()
    if name == "plate":
        assert broken > 1000  # the crack grows (pre-crack: 521 pairs)
    else:
        assert contacts > 0
    for ranks in (2, 4):
        f = run(tmp_path, base, by, ranks)
        frames, obs, damage = worst_difference(ref, f)
        print(f"{name}: {ranks} ranks: frames {frames:.3g}, observables {obs:.3g}, "
              f"damage identical {damage}")
        assert frames <= TOL and obs <= TOL and damage


def test_meshed_wall_reactions_same_at_1_and_2_ranks(tmp_path):
    """The fixed floor (body 0) and the driven plate (body 4) record their contact reactions;
    summed over 2 ranks (grains split between them) they equal the 1-rank ones."""
    base, by = pack(tmp_path, "meshed_walls")
    ref = run(tmp_path, base, by, 1)
    two = run(tmp_path, base, by, 2)
    with h5py.File(ref, "r") as a, h5py.File(two, "r") as b:
        assert list(a["observables/body_force/body"][()]) == [0, 4]
        fa, fb = a["observables/body_force/value"][()], b["observables/body_force/value"][()]
        ma, mb = a["observables/body_moment/value"][()], b["observables/body_moment/value"][()]
        owners = set(b["partition/owner"][()])
    assert fa[:, 1, 1].max() > 0  # the discs push the plate up ...
    assert fa[:, 0, 1].min() < 0  # ... and the floor down
    assert len(owners) == 2
    assert np.abs(fa - fb).max() <= TOL * np.abs(fa).max()
    assert np.abs(ma - mb).max() <= TOL * np.abs(ma).max()


def test_sigkill_then_restart_on_1_and_4_ranks(tmp_path):
    base, by = pack(tmp_path, "pack50")
    ref = run(tmp_path, base, by, 1)
    killed = tmp_path / "killed.h5"
    shutil.copy(base, killed)
    mpirun(1, "pd-partition", str(killed), "-n", "2", "--by", by[2], "-q")
    p = subprocess.Popen(["mpirun", "--oversubscribe", "-np", "2", f"{BIN}/pd-solve",
                          str(killed), "--progress-every", "0.2", NO_GUARD], env=ENV,
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    step, total = 0, 0
    # wait until at least three checkpoints exist: one every 1/10 of the run (M steps, from the
    # progress line "step k/M": 690 on the node law, more on the surface law's step); killed
    # from step 0.435 M on, the fourth is complete (from 0.29 M on the third could still be in
    # writing: the test failed on a loaded machine with the latest at the second)
    for line in p.stdout:
        if line.startswith("step "):
            step, total = (int(v) for v in line.split()[1].split("/"))
            if step >= 0.435 * total:
                break
    assert total > 0 and step >= 0.435 * total, "the run ended before it could be killed"
    subprocess.run(["pkill", "-KILL", "-f", f"pd-solve {killed}"], check=False)
    p.wait(timeout=60)
    assert p.returncode != 0
    with h5py.File(killed, "r") as h:  # readable; the latest checkpoint is complete
        latest = h["checkpoints"].attrs["latest"]
        latest = latest.decode() if isinstance(latest, bytes) else latest
        ck = h[f"checkpoints/{latest}"]
        # a checkpoint every 1/10 of the run: killed at step >= 0.435 M, the third or later
        assert ck.attrs["complete"] == 1 and ck.attrs["step"] >= 0.29 * total
        print(f"killed at step >= {step} of {total}; latest checkpoint at step {ck.attrs['step']}")
    for ranks in (1, 4):
        f = tmp_path / f"restart_{ranks}.h5"
        shutil.copy(killed, f)
        mpirun(ranks, "pd-solve", str(f), "--restart", "-q")
        frames, obs, damage = worst_difference(ref, f)
        print(f"restart on {ranks} ranks: frames {frames:.3g}, observables {obs:.3g}")
        assert frames <= TOL and obs <= TOL and damage


def test_plain_h5py_reads_every_frame_written_by_4_ranks(tmp_path):
    base, by = pack(tmp_path, "pack50")
    f = run(tmp_path, base, by, 4, "--compress", "4")  # gzip chunks, written in parallel
    with h5py.File(f, "r") as h:
        assert h["particles/nodes/position/value"].compression == "gzip"
        runs = [h["provenance"][k] for k in h["provenance"]]  # rank 0, after the parallel run
        assert any(r.attrs["tool"] == "pd-solve" and r.attrs["mpi_ranks"] == 4 for r in runs)
        pos = h["particles/nodes/position/value"]
        n = h["nodes/volume"].shape[0]
        assert pos.shape[0] == h["particles/nodes/position/step"].shape[0] >= 10
        assert pos.shape[1] == n
        for k in range(pos.shape[0]):  # every frame, every node written by some rank
            x = pos[k]
            assert np.all(np.isfinite(x))
            assert np.abs(x[:, :2]).max() > 0
    subprocess.run(["/usr/bin/python3", f"{SRC}/data-schema/check_pd_file.py", str(f)],
                   check=True)


def test_rebalance_repartitions_and_keeps_the_answer(tmp_path):
    base, by = pack(tmp_path, "pack50")
    ref = run(tmp_path, base, by, 1)
    f = tmp_path / "rebalanced.h5"
    shutil.copy(base, f)
    mpirun(1, "pd-partition", str(f), "-n", "2", "--by", "grain", "-q")
    with h5py.File(f, "r+") as h:  # a poor partition: alternate grains between the ranks
        owner = h["partition/owner"]
        owner[...] = np.arange(owner.shape[0]) % 2
    out = mpirun(2, "pd-solve", str(f), "--rebalance").stdout
    moves = [line for line in out.splitlines() if "re-partitioned" in line]
    print("\n".join(moves[:2]))
    assert moves, out
    first = moves[0].split("across ranks ")[1].split(")")[0]  # "203 -> 6"
    before, after = (int(v) for v in first.split(" -> "))
    assert after < before / 3
    frames, obs, damage = worst_difference(ref, f)
    print(f"rebalanced run against 1 rank: frames {frames:.3g}, observables {obs:.3g}")
    assert frames <= TOL and obs <= TOL and damage


def test_a_blow_up_stops_every_rank_with_one_message(tmp_path):
    scene = dict(scenes.TWO_DISCS, solver=dict(scenes.TWO_DISCS["solver"], dt=3e-6))
    f = tmp_path / "blow.h5"
    subprocess.run([f"{BIN}/pd-pack", str(scenes.write(scene, tmp_path / "blow.json")), "-o",
                    str(f), "-q"], check=True, env=ENV)
    mpirun(1, "pd-partition", str(f), "-n", "2", "--by", "grain", "-q")
    r = subprocess.run(["mpirun", "--oversubscribe", "-np", "2", f"{BIN}/pd-solve", str(f),
                        "--force-dt"], env=ENV, capture_output=True, text=True, timeout=120)
    assert r.returncode == 3
    # rank 0 reports, nobody hangs
    assert (r.stderr.count("blow-up at step") + r.stderr.count("energy balance broken at step")
            == 1), r.stderr
    assert "MPI_ABORT" not in r.stderr
    with h5py.File(f, "r") as h:  # readable, the good frames kept, the status recorded
        assert h["particles/nodes/position/value"].shape[0] >= 1
        last = sorted(h["provenance"])[-1]
        assert h["provenance"][last].attrs["exit_status"] == 3


def test_threads_combine_with_ranks(tmp_path):
    """2 ranks x 2 threads on the 53 000-node pack (rows above the threading threshold) give the
    frames of 1 rank x 1 thread, bit for bit."""
    f1 = tmp_path / "p1.h5"
    subprocess.run([f"{BIN}/pd-pack", f"{SRC}/examples/pack500/scene.json", "-o", str(f1), "-q"],
                   check=True, env=ENV)
    f2 = tmp_path / "p2.h5"
    shutil.copy(f1, f2)
    mpirun(1, "pd-partition", str(f2), "-n", "2", "--by", "grain", "-q")
    subprocess.run([f"{BIN}/pd-solve", str(f1), "--steps", "60", "-q"], env=ENV, check=True)
    env2 = dict(ENV, OMP_NUM_THREADS="2")
    subprocess.run(["mpirun", "--oversubscribe", "-np", "2", "-x", "OMP_NUM_THREADS",
                    f"{BIN}/pd-solve", str(f2), "--steps", "60", "-q"], env=env2, check=True)
    def state(h):  # the checkpoint written at the last step
        latest = h["checkpoints"].attrs["latest"]
        ck = h["checkpoints"][latest.decode() if isinstance(latest, bytes) else latest]
        assert ck.attrs["step"] == 60
        return ck["displacement"][:], ck["velocity"][:], ck["force_density"][:]

    with h5py.File(f1, "r") as a, h5py.File(f2, "r") as b:
        for x, y in zip(state(a), state(b)):
            assert np.abs(x).max() > 0 and np.array_equal(x, y)
        assert b["provenance"][sorted(b["provenance"])[-1]].attrs["threads"] == 2


def test_h5py_mpi_reads_every_frame_written_by_4_ranks(tmp_path):
    base, by = pack(tmp_path, "pack50")
    f = run(tmp_path, base, by, 4)
    r = subprocess.run(["mpirun", "--oversubscribe", "-np", "2", "/usr/bin/python3",
                        os.path.join(os.path.dirname(__file__), "read_mpio.py"), str(f)],
                       env=ENV, check=True, capture_output=True, text=True)
    sums = json.loads(r.stdout.strip().splitlines()[-1])
    with h5py.File(f, "r") as h:  # the same sums read serially
        assert set(sums) == set(frame_fields(h))
        for k, s in sums.items():
            ref = float(sum(h[f"particles/nodes/{k}/value"][i].sum()
                            for i in range(h[f"particles/nodes/{k}/value"].shape[0])))
            assert s == pytest.approx(ref, rel=1e-12, abs=1e-300), k
