#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""pdgrain and LAMMPS side by side on LAMMPS' bench/POTENTIALS/in.peri (README.md here).

Packs scene.json, then runs, interleaved and --repeat times each, pdgrain (the Python module:
the deck's velocity ramp is written into the velocities, then `Simulation.step(N)`) and Debian's
LAMMPS (`lmp -in in.peri.lmp`), both at 1 thread (OMP_NUM_THREADS=1) and 1 rank (--ranks 2:
mpirun -np 2 for both). Prints per code: steps, directed bonds (i-j and j-i both counted, as
both codes store them), loop wall time, loop CPU, process CPU (user + sys of the child and its
children), bond updates per loop-CPU second, min and median, and the ratio pdgrain / LAMMPS.
LAMMPS is a benchmark reference only: without `lmp` the script says so and exits 2.
"""
import argparse
import json
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
H = 5.0e-4           # lattice spacing (m)
LX = 39.5 * H        # the deck's ramp spans x in [0, 39.5 h]
NX, NY, NZ = 40, 32, 25
MPIRUN = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np"]


def child_cpu(cmd, env, cwd=None):
    """Run cmd; return (stdout, process CPU s of the child and its children)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run(cmd, env=env, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: exit {r.returncode}: {r.stderr.strip()[-600:]}")
    return r.stdout, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def lammps_bonds():
    """The deck's bond count: directed pairs of lattice nodes within 1.01 delta (|n|^2 <= 9 in
    lattice units), less the pairs of type 2 (x <= 19.75 h, y >= 21.5 h) and type 3 (x > 19.75 h,
    y >= 21.5 h), whose cut-off is 0. Each pair i-j counts twice (i-j and j-i), as the PERI
    package's partner lists hold it."""
    import numpy as np
    g = np.meshgrid(np.arange(NX), np.arange(NY), np.arange(NZ), indexing="ij")
    ix, iy, iz = (a.ravel() for a in g)

    def kind(x, y):
        return np.where(y >= 21.5, np.where(x <= 19.75, 2, 3), 1)
    ti, total = kind(ix, iy), 0
    for a in range(-3, 4):
        for b in range(-3, 4):
            for c in range(-3, 4):
                if not 0 < a * a + b * b + c * c <= 9:
                    continue
                jx, jy, jz = ix + a, iy + b, iz + c
                ok = (jx >= 0) & (jx < NX) & (jy >= 0) & (jy < NY) & (jz >= 0) & (jz < NZ)
                tj = kind(jx, jy)
                total += int((ok & (ti * tj != 6)).sum())
    return total


def pdgrain_child(a):
    """In the child process: open the packed file, set the ramp, step, print the loop's figures."""
    import numpy as np
    import pdgrain
    with pdgrain.Simulation(a.child, threads=1, overwrite=True,
                            energy_tolerance=0) as sim:
        x0 = sim.reference_positions
        v = sim.velocities
        v[:, 0] = -10.0 + 20.0 * x0[:, 0] / LX
        v[:, 1:] = 0.0
        c0, w0 = time.process_time(), time.perf_counter()
        n = sim.step(a.steps)
        cpu, wall = time.process_time() - c0, time.perf_counter() - w0
        rows = np.asarray(sim.rows) if hasattr(sim, "rows") else np.arange(len(x0))
        dmg = float(np.asarray(sim.damage)[rows].sum())
        rank = os.environ.get("OMPI_COMM_WORLD_RANK", "0")
        with open(f"{a.child}.rank{rank}.json", "w") as out:
            json.dump({"steps": n, "cpu": cpu, "wall": wall, "damage": dmg,
                       "nodes": int(len(rows))}, out)


def run_pdgrain(a, h5, env):
    cmd = [sys.executable, os.path.abspath(__file__), "--child", h5, "--steps", str(a.steps)]
    if a.ranks > 1:
        cmd = MPIRUN + [str(a.ranks)] + cmd
    _, proc_cpu = child_cpu(cmd, env)
    recs = []
    for k in range(a.ranks):
        with open(f"{h5}.rank{k}.json") as f:
            recs.append(json.load(f))
        os.remove(f"{h5}.rank{k}.json")
    return {"steps": recs[0]["steps"], "wall": max(r["wall"] for r in recs),
            "cpu": sum(r["cpu"] for r in recs), "proc": proc_cpu,
            "damage": sum(r["damage"] for r in recs)}


def run_lammps(a, env, work):
    cmd = ["lmp", "-in", os.path.join(HERE, "in.peri.lmp"), "-var", "steps", str(a.steps),
           "-var", "thermo", str(a.steps), "-log", "none", "-echo", "none"]
    if a.ranks > 1:
        cmd = MPIRUN + [str(a.ranks)] + cmd
    out, proc_cpu = child_cpu(cmd, env, cwd=work)
    m = re.search(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps", out)
    u = re.search(r"([0-9.]+)% CPU use with (\d+) MPI tasks", out)
    if not m or not u:
        raise RuntimeError("no 'Loop time' / 'CPU use' line in LAMMPS' output:\n" + out[-800:])
    wall, procs, steps = float(m.group(1)), int(m.group(2)), int(m.group(3))
    thermo = [line.split() for line in out.splitlines()
              if re.match(r"^\s*\d+\s+[0-9.eE+-]+\s+[0-9.eE+-]+\s+[0-9.eE+-]+\s*$", line)]
    return {"steps": steps, "wall": wall, "cpu": wall * float(u.group(1)) / 100.0 * procs,
            "proc": proc_cpu, "damage": float(thermo[-1][3]) if thermo else float("nan")}


def table(rows, bonds, a):
    print(f"in.peri: {NX * NY * NZ} nodes, {a.steps} steps, {a.ranks} rank(s) x 1 thread, "
          f"{a.repeat} runs each (interleaved); min / median")
    print(f"{'code':8} {'steps':>5} {'bonds':>9} {'loop wall s':>15} {'loop CPU s':>15} "
          f"{'process CPU s':>15} {'bond-upd/CPU-s':>17} {'damage sum':>10}")
    rate = {}
    for code, runs in rows.items():
        w = [r["wall"] for r in runs]
        c = [r["cpu"] for r in runs]
        p = [r["proc"] for r in runs]
        st = runs[0]["steps"]
        rate[code] = (bonds[code] * st / min(c), bonds[code] * st / statistics.median(c))
        print(f"{code:8} {st:5d} {bonds[code]:9d} {min(w):7.3f}/{statistics.median(w):<7.3f} "
              f"{min(c):7.3f}/{statistics.median(c):<7.3f} {min(p):7.3f}/{statistics.median(p):<7.3f}"
              f" {rate[code][0]:8.3g}/{rate[code][1]:<8.3g} {runs[-1]['damage']:10.1f}")
    r0, r1 = (rate["pdgrain"][k] / rate["lammps"][k] for k in (0, 1))
    print(f"ratio pdgrain / LAMMPS of bond updates per loop-CPU second: {r0:.2f} (min CPU), "
          f"{r1:.2f} (median)")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=os.path.join(HERE, "../../../build"))
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--child", help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.child:
        return pdgrain_child(a)
    if shutil.which("lmp") is None:
        print("run.py: LAMMPS' `lmp` is not on PATH. This benchmark compares against Debian's "
              "LAMMPS: apt-get install --no-install-recommends lammps (a benchmark reference "
              "only, not a build or test dependency of pdgrain).", file=sys.stderr)
        return 2
    build = os.path.abspath(a.build)
    env = dict(os.environ, OMP_NUM_THREADS="1", PYTHONPATH=os.path.join(build, "python"),
               PD_BIN_DIR=os.path.join(build, "bin"))
    work = tempfile.mkdtemp(prefix="pd_lammps_bench_")
    try:
        h5 = os.path.join(work, "in_peri.h5")
        subprocess.run([os.path.join(build, "bin", "pd-pack"), os.path.join(HERE, "scene.json"),
                        "-o", h5, "-q"], check=True)
        import h5py
        with h5py.File(h5, "r") as f:
            bonds = {"pdgrain": int(f["/bonds/neighbor"].shape[0]), "lammps": lammps_bonds()}
        rows = {"pdgrain": [], "lammps": []}
        for _ in range(a.repeat):
            rows["pdgrain"].append(run_pdgrain(a, h5, env))
            rows["lammps"].append(run_lammps(a, env, work))
        table(rows, bonds, a)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
