#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""workflows/sweep under a real, single-node Slurm: the test writes a slurm.conf and a munge key
into its own folder, starts munged, slurmctld and slurmd (root, own ports and sockets), submits
the 6-run CI sweep as a job array (sbatch DIR/slurm.sh) and gathers it. Needs slurm-wlm and munge
(tools/install-deps.sh --slurm); skipped, with the reason, when they are missing or the daemons
do not start."""
import csv
import os
import shutil
import signal
import socket
import subprocess
import time

import pytest

BIN = os.environ.get("PD_BIN_DIR", "build/bin")
SRC = os.environ.get("PD_SOURCE_DIR", ".")
SWEEP = os.path.join(SRC, "workflows", "sweep", "sweep.py")
SWEEP_SPEC = os.path.join(SRC, "tests", "sweep", "sweep.json")
NEEDED = ["munged", "slurmctld", "slurmd", "sbatch", "sinfo", "scontrol"]


def which(x):
    return shutil.which(x) or shutil.which(x, path="/usr/sbin:/usr/bin:/sbin")


def tail(path, n=15):
    try:
        return "".join(open(path).readlines()[-n:])
    except OSError:
        return "(no log)"


@pytest.fixture
def slurm(tmp_path):
    missing = [x for x in NEEDED if not which(x)]
    if missing:
        pytest.skip(f"Slurm not installed ({', '.join(missing)} missing): run "
                    "tools/install-deps.sh --slurm")
    if os.geteuid() != 0:
        pytest.skip("the single-node Slurm test starts the daemons as root")
    d = tmp_path / "slurm"
    for sub in ("state", "spool", "munge"):
        (d / sub).mkdir(parents=True)
    os.chmod(d / "munge", 0o700)
    host = socket.gethostname().split(".")[0]
    key = d / "munge" / "munge.key"
    key.write_bytes(os.urandom(1024))
    os.chmod(key, 0o400)
    sock = d / "munge" / "munge.sock"
    conf = d / "slurm.conf"
    conf.write_text(f"""ClusterName=pdtest
SlurmctldHost={host}
SlurmUser=root
SlurmdUser=root
SlurmctldPort=16917
SlurmdPort=16918
AuthType=auth/munge
AuthInfo=socket={sock}
CredType=cred/munge
StateSaveLocation={d}/state
SlurmdSpoolDir={d}/spool
SlurmctldPidFile={d}/slurmctld.pid
SlurmdPidFile={d}/slurmd.pid
SlurmctldLogFile={d}/slurmctld.log
SlurmdLogFile={d}/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
SlurmdParameters=config_overrides
NodeName={host} CPUs=2 State=UNKNOWN
PartitionName=debug Nodes={host} Default=YES MaxTime=INFINITE State=UP
""")
    env = dict(os.environ, SLURM_CONF=str(conf))
    started = []

    def start(cmd, log):
        r = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=30)
        if r.returncode != 0:
            pytest.skip(f"{cmd[0]} did not start (exit {r.returncode}): {r.stderr.strip()} "
                        f"{tail(log)}")

    start([which("munged"), "--force", f"--key-file={key}", f"--socket={sock}",
           f"--pid-file={d}/munge/munged.pid", f"--log-file={d}/munge/munged.log",
           f"--seed-file={d}/munge/seed"], d / "munge" / "munged.log")
    started.append(d / "munge" / "munged.pid")
    start([which("slurmctld"), "-f", str(conf)], d / "slurmctld.log")
    started.append(d / "slurmctld.pid")
    start([which("slurmd"), "-f", str(conf)], d / "slurmd.log")
    started.append(d / "slurmd.pid")
    deadline, state = time.time() + 60, ""
    while time.time() < deadline:
        r = subprocess.run(["sinfo", "-h", "-o", "%T"], env=env, capture_output=True, text=True)
        state = r.stdout.strip() + r.stderr.strip()
        if state.startswith("idle"):
            break
        time.sleep(1)
    try:
        if not state.startswith("idle"):
            pytest.skip(f"the Slurm node did not come up (sinfo: {state!r}); slurmctld: "
                        f"{tail(d / 'slurmctld.log', 5)} slurmd: {tail(d / 'slurmd.log', 5)}")
        yield env
    finally:
        subprocess.run(["scontrol", "shutdown"], env=env, capture_output=True)
        time.sleep(2)
        for pid_file in started:  # the daemons this test started, by their pid files
            try:
                os.kill(int(pid_file.read_text().split()[0]), signal.SIGTERM)
            except (OSError, ValueError):
                pass


def test_sweep_as_a_slurm_job_array(tmp_path, slurm):
    env = dict(slurm, PD_BIN_DIR=os.path.abspath(BIN), OMP_NUM_THREADS="1")
    d = tmp_path / "sw"
    r = subprocess.run(["/usr/bin/python3", SWEEP, "expand", SWEEP_SPEC, "-o", str(d)], env=env,
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    t0 = time.time()
    r = subprocess.run(["sbatch", "--wait", str(d / "slurm.sh")], env=env, capture_output=True,
                       text=True, timeout=600)
    wall = time.time() - t0
    outs = "".join(tail(p, 5) for p in sorted((d / "runs").glob("slurm-*.out")))
    assert r.returncode == 0, r.stdout + r.stderr + outs
    print(f"sbatch --wait (6-task array on 2 CPUs): {wall:.1f} s; {r.stdout.strip()}")
    r = subprocess.run(["/usr/bin/python3", SWEEP, "gather", str(d)], env=env,
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    rows = list(csv.DictReader(open(d / "results.csv")))
    assert len(rows) == 6 and all(row["exit_status"] == "0" for row in rows), rows
    for row in rows:
        asked, got = float(row["contact.restitution"]), float(row["restitution"])
        assert abs(got / asked - 1) < 0.05, row


def test_sigterm_to_the_batch_script_requeues_and_restarts(tmp_path, slurm):
    """What --signal=B:TERM@120 does before the wall-time limit, sent now (scancel --batch):
    the script passes SIGTERM on, pd-solve checkpoints and exits 75, the task requeues itself
    and continues with pd-solve --restart to exit 0."""
    import h5py
    import json
    env = dict(slurm, PD_BIN_DIR=os.path.abspath(BIN), OMP_NUM_THREADS="1")
    # 20 ms: the run must outlive the SIGTERM (1.2 ms ended first once dt grew 2x, Lanczos
    # estimate; 4 ms, 4569 steps, ended in 0.5 s on an idle machine before the signal came)
    spec = {"base": os.path.join(SRC, "tests", "sweep", "two_discs.json"),
            "list": [{"discretization.mesh_size": 1e-4, "solver.final_time": 2e-2}],
            "solve_args": ["--progress-every", "0.2"], "slurm": {"time": "00:10:00"}}
    sp = tmp_path / "s.json"
    sp.write_text(json.dumps(spec))
    d = tmp_path / "sw"
    r = subprocess.run(["/usr/bin/python3", SWEEP, "expand", str(sp), "-o", str(d)], env=env,
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    r = subprocess.run(["sbatch", "--parsable", str(d / "slurm.sh")], env=env,
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    job = r.stdout.strip().split(";")[0]
    log, status = d / "runs" / "000" / "run.log", d / "runs" / "000" / "status.json"
    deadline = time.time() + 120
    while time.time() < deadline and not (log.exists() and "step " in log.read_text()):
        time.sleep(0.2)
    assert log.exists() and "step " in log.read_text(), tail(log)
    r = subprocess.run(["scancel", "--signal=TERM", "--batch", job], env=env,
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    deadline = time.time() + 120
    while time.time() < deadline and not (status.exists() and
                                          json.loads(status.read_text())["exit_code"] == 75):
        time.sleep(0.2)
    # A requeued job waits (begin time about 2 minutes on): let it start now.
    time.sleep(1)
    subprocess.run(["scontrol", "update", f"JobId={job}_0", "StartTime=now"], env=env,
                   capture_output=True)
    deadline, st = time.time() + 300, {}
    while time.time() < deadline:
        if (d / "runs" / "000" / "run.done").exists():
            st = json.loads(status.read_text())
            break
        time.sleep(1)
    outs = "".join(tail(p, 10) for p in sorted((d / "runs").glob("slurm-*.out")))
    assert st.get("exit_code") == 0 and st.get("restarted") == 1, (st, outs, tail(log, 30))
    with h5py.File(d / "runs" / "000" / "run.h5", "r") as h:
        codes = [int(h["provenance"][k].attrs["exit_status"]) for k in sorted(h["provenance"])
                 if h["provenance"][k].attrs["tool"] == "pd-solve"]
    assert codes == [75, 0], codes
    print(f"Slurm: SIGTERM to the batch script -> exit 75, requeued, restarted -> exit 0 "
          f"({st['attempts']} attempts, {st['wall_seconds']:.1f} s)")
