#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""pd-solve's default thread count against fixed ones on the examples' quick runs (issue 28).

    threads.py BIN_DIR [--repeat 3] [--work DIR] [--only NAME ...]

Packs each quick scene once, then solves a copy of it under each setting, --repeat times,
interleaved (setting after setting, so a change of the machine's load hits every setting alike),
and prints a Markdown table: CPU (user + sys of pd-solve, all its threads) and wall time, min and
median, with the 1-minute load average when the runs started. Settings:
  default   no OMP_* variable: pdgrain's default (cores per rank, fewer when the machine is
            busy) and its passive OpenMP wait
  1         OMP_NUM_THREADS=1
  2         OMP_NUM_THREADS=2 (passive wait, set by pdgrain)
  2 spin    OMP_NUM_THREADS=2 GOMP_SPINCOUNT=300000: libgomp's own default wait (what pd-solve
            did before issue 28)
"""
import argparse
import os
import pathlib
import resource
import shutil
import statistics
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[3]
# name: (scene, pd-pack extra arguments, pd-solve extra arguments), as the examples' quick targets
CASES = {
    "attrition_sim1": ("examples/attrition_sim1/scene.json", [], ["--final-time", "0.005"]),
    "two_discs_wall (meshed)": ("examples/two_discs_wall/scene_meshed.json",
                                ["--set", "discretization.mesh_size=2e-4"], []),
    "ellipse_on_tip (pmb)": ("examples/ellipse_on_tip/scene_pmb.json", [], ["--final-time", "1e-3"]),
    "n12 (1 rank)": ("examples/n12/scene.json", [], ["--final-time", "0.003"]),
}
SETTINGS = {
    "default": {},
    "1": {"OMP_NUM_THREADS": "1"},
    "2": {"OMP_NUM_THREADS": "2"},
    "2 spin": {"OMP_NUM_THREADS": "2", "GOMP_SPINCOUNT": "300000"},
}


def clean_env(extra):
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("OMP_", "GOMP_", "PD_OMP_"))}
    env.update(extra)
    return env


def timed(cmd, env):
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    r = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)}: exit {r.returncode}\n{r.stderr[-2000:]}")
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    threads = next((line.split(" x ")[1].split()[0] for line in r.stdout.splitlines()
                    if " x " in line and "thread" in line), "?")
    return cpu, wall, threads


def load():
    return float(pathlib.Path("/proc/loadavg").read_text().split()[0])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("bin", type=pathlib.Path)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--work", type=pathlib.Path, default=pathlib.Path("/tmp/pd_threads_bench"))
    ap.add_argument("--only", nargs="*")
    a = ap.parse_args()
    a.work.mkdir(parents=True, exist_ok=True)
    print(f"nproc {os.cpu_count()}, load average at start {load():.2f}")
    print("\n| quick run | setting | threads | CPU min / median (s) | wall min / median (s) "
          "| CPU / CPU(1 thread) | load at start |")
    print("|---|---|---|---|---|---|---|")
    for name, (scene, pack_args, solve_args) in CASES.items():
        if a.only and not any(o in name for o in a.only):
            continue
        packed = a.work / (name.split()[0] + ".h5")
        subprocess.run([str(a.bin / "pd-pack"), str(ROOT / scene), "-o", str(packed), "-q",
                        *pack_args], check=True)
        res = {s: [] for s in SETTINGS}
        loads = {s: [] for s in SETTINGS}
        used = {}
        for _ in range(a.repeat):
            for s, extra in SETTINGS.items():
                run = a.work / "run.h5"
                shutil.copyfile(packed, run)
                loads[s].append(load())
                cpu, wall, used[s] = timed([str(a.bin / "pd-solve"), str(run), *solve_args],
                                           clean_env(extra))
                res[s].append((cpu, wall))
        one = statistics.median(c for c, _ in res["1"])
        for s in SETTINGS:
            cpus = [c for c, _ in res[s]]
            walls = [w for _, w in res[s]]
            print(f"| {name} | {s} | {used[s]} | {min(cpus):.2f} / {statistics.median(cpus):.2f} "
                  f"| {min(walls):.2f} / {statistics.median(walls):.2f} "
                  f"| {statistics.median(cpus) / one:.2f} "
                  f"| {min(loads[s]):.1f}-{max(loads[s]):.1f} |", flush=True)


if __name__ == "__main__":
    main()
