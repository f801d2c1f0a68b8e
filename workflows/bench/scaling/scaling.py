#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Memory, ghosts and halo traffic per rank against the rank count (issue 29 item 6).

Packs the 3D PMB block of workflows/bench/startup/block3d.json, partitions it for each rank
count (pd-partition) and runs pd-solve for a few steps under mpirun (oversubscribed), each rank
under /usr/bin/time. Reads pd-solve's per-rank report (`-v`: "rank r: owned ... ghosts ...",
lib/pipeline/rank_report.cpp) and tabulates per P: peak RSS per rank (max, mean), ghosts per
rank (bond and contact halo), bytes and messages sent per rank per step, the loop's halo share.

  strong: one block (edge 63 h at --h, default 1 mm: 262 144 nodes), P = 1 2 4 8 16
  weak:   N/P fixed, the same box at h = 0.063 / round(--weak-edge * P^(1/3))
  granular (--granular FILE): a packed pack of grains, whole grains per rank

Then `--model RESULTS.json` prints the model of time per step and memory per rank at 64 and
1024 ranks from the measured figures (assumptions in the output and in RESULTS.md).
Results: workflows/bench/RESULTS.md ("Issue 29 item 6").
"""
import argparse
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys

import h5py

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "startup", "block3d.json")
BOX = 0.063  # the block's edge, m
# pd-solve's peak at one rank, RESULTS.md "Issue 29 item 3": 60 MB + 385 B/node + 22 B/bond (PMB)
MEM_BASE, MEM_NODE, MEM_BOND = 60e6, 385, 22
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMP_NUM_THREADS="1", OMP_WAIT_POLICY="passive")
RANK_LINE = re.compile(r"rank (\d+): (.*)$")


def sh(cmd, **kw):
    print("+", " ".join(cmd), flush=True)
    return subprocess.run(cmd, env=ENV, check=True, text=True, capture_output=True, **kw)


def pack(bindir, out, h):
    f = os.path.join(out, f"block_h{h * 1e6:.0f}um.h5")
    if not os.path.exists(f):
        sh([f"{bindir}/pd-pack", SCENE, "-o", f, "-q", "--max-nodes", "1e7",
            "--set", f"discretization.mesh_size={h!r}"])
    return f


def parse_rank_fields(text):
    """{'owned': .., 'ghosts': .., ...} from pd-solve's 'rank r: owned 1 ghosts 2 ...' line."""
    tok = text.replace("B/step", "B_per_step").replace("msgs/step", "msgs_per_step")
    tok = tok.replace("reductions/step", "reductions_per_step").split()
    out, i = {}, 0
    while i < len(tok):  # a key is one or more words, its value the next number
        key = []
        while i < len(tok):
            try:
                val = float(tok[i])
                break
            except ValueError:
                key.append(tok[i])
                i += 1
        if i < len(tok):
            out["_".join(key)] = val
        i += 1
    return out


def parse_ranks(stdout):
    ranks = {}
    for line in stdout.splitlines():
        m = RANK_LINE.search(line)
        if m and "owned" in m.group(2):
            ranks[int(m.group(1))] = parse_rank_fields(m.group(2))
    return [ranks[r] for r in sorted(ranks)]


def partitioned(bindir, base, ranks, by="node"):
    """A copy of `base` with /partition for `ranks` (kept: METIS on 4e7 bonds takes a while)."""
    f = base.replace(".h5", f"_p{ranks}.part.h5")
    if not os.path.exists(f):
        shutil.copy(base, f + ".tmp")
        if ranks > 1:
            sh([f"{bindir}/pd-partition", f + ".tmp", "-n", str(ranks), "--by", by, "-q"])
        os.rename(f + ".tmp", f)
    return f


def solve(bindir, base, ranks, steps, out, fields, by="node"):
    f = base.replace(".h5", f"_p{ranks}.h5")
    shutil.copy(partitioned(bindir, base, ranks, by), f)
    if fields != "all":
        # The frame fields of the run (/solver@fields, pd-file 6.13): without `fragment`, whose
        # frames gather the whole bond list on every rank (it sets the peak of a node split).
        with h5py.File(f, "r+") as h:
            h["solver"].attrs["fields"] = fields
    tdir = f.replace(".h5", "_time")
    os.makedirs(tdir, exist_ok=True)
    wrap = (f'exec /usr/bin/time -f "%e %U %S %M" -o {tdir}/rank.${{OMPI_COMM_WORLD_RANK:-0}} '
            f'{bindir}/pd-solve {f} --steps {steps} --overwrite -v --checkpoint-every-wall 0')
    r = sh(["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks),
            "sh", "-c", wrap])
    with open(f.replace(".h5", ".log"), "w") as log:
        log.write(r.stdout + r.stderr)
    per_rank = parse_ranks(r.stdout)
    for p, rk in enumerate(per_rank):
        with open(f"{tdir}/rank.{p}") as t:
            wall, user, sys_, kb = t.read().split()[-4:]
        rk.update(wall=float(wall), user=float(user), sys=float(sys_), maxrss_kb=float(kb))
    hdr = re.search(r"(\d+) nodes, (\d+) bonds", r.stdout)
    os.remove(f)  # the files are large; the figures are in the log and the JSON
    return {"ranks": ranks, "steps": steps, "nodes": int(hdr.group(1)),
            "bonds": int(hdr.group(2)), "per_rank": per_rank}


def summary(run):
    pr = run["per_rank"]
    col = lambda k: [r[k] for r in pr]  # noqa: E731
    rss = [r["maxrss_kb"] * 1024 / 1e6 for r in pr]
    loop = max(col("loop_s"))
    return {
        "P": run["ranks"], "nodes": run["nodes"], "bonds": run["bonds"],
        "rss_max_MB": max(rss), "rss_mean_MB": statistics.mean(rss),
        "vmhwm_max_MB": max(col("peak_rss_B")) / 1e6,
        "owned_mean": statistics.mean(col("owned")),
        "ghosts_max": max(col("ghosts")), "ghosts_mean": statistics.mean(col("ghosts")),
        "bond_ghosts_max": max(col("bond")), "contact_ghosts_max": max(col("contact")),
        "peers_max": max(col("peers")),
        "sent_max_B": max(col("sent_B_per_step")),
        "sent_mean_B": statistics.mean(col("sent_B_per_step")),
        "msgs_max": max(col("msgs_per_step")),
        "reductions": max(col("reductions_per_step")),
        "gathered_max_B": max(col("gathered_B")),
        "loop_s": loop, "busy_sum_s": sum(col("busy_s")),
        # the step: compute (busy) + ghost exchange (halo, waiting for the peers included)
        "halo_share_max": max(r["halo_s"] / (r["halo_s"] + r["busy_s"]) for r in pr),
        "halo_share_mean": statistics.mean(r["halo_s"] / (r["halo_s"] + r["busy_s"]) for r in pr),
        "step_s": max(r["halo_s"] + r["busy_s"] for r in pr) / run["steps"],
        "cpu_s": sum(r["user"] + r["sys"] for r in pr),
        "wall_s": max(col("wall")),
    }


def table(rows):
    print("| P | nodes | bonds | peak RSS max / mean (MB) | owned / rank | ghosts max / mean "
          "(bond, contact max) | peers max | sent B/step max / mean | msgs/step max | "
          "halo share max / mean | step ms (max rank) | CPU s (all ranks, whole run) |")
    print("|---" * 12 + "|")
    for s in rows:
        print(f"| {s['P']} | {s['nodes']} | {s['bonds']} | {s['rss_max_MB']:.0f} / "
              f"{s['rss_mean_MB']:.0f} | {s['owned_mean']:.0f} | {s['ghosts_max']:.0f} / "
              f"{s['ghosts_mean']:.0f} ({s['bond_ghosts_max']:.0f}, "
              f"{s['contact_ghosts_max']:.0f}) | {s['peers_max']:.0f} | {s['sent_max_B']:.3g} / "
              f"{s['sent_mean_B']:.3g} | {s['msgs_max']:.0f} | {s['halo_share_max']:.3f} / "
              f"{s['halo_share_mean']:.3f} | {s['step_s'] * 1e3:.1f} | {s['cpu_s']:.1f} |")


def measure(a):
    os.makedirs(a.out, exist_ok=True)
    res = {"strong": [], "weak": [], "granular": [], "steps": a.steps, "fields": a.fields}
    if a.granular:
        for p in a.ranks:
            res["granular"].append(solve(a.bin, a.granular, p, a.steps, a.out, a.fields, "grain"))
    if a.partition_only:
        for p in a.ranks:
            partitioned(a.bin, pack(a.bin, a.out, a.h), p)
            partitioned(a.bin, pack(a.bin, a.out, BOX / round(a.weak_edge * p ** (1 / 3))), p)
        return
    if not a.skip_strong:
        base = pack(a.bin, a.out, a.h)
        for p in a.ranks:
            res["strong"].append(solve(a.bin, base, p, a.steps, a.out, a.fields))
    if not a.skip_weak:
        for p in a.ranks:
            edge = round(a.weak_edge * p ** (1 / 3))
            base = pack(a.bin, a.out, BOX / edge)
            res["weak"].append(solve(a.bin, base, p, a.steps, a.out, a.fields))
    with open(os.path.join(a.out, a.json), "w") as f:
        json.dump(res, f, indent=1)
    for k in ("strong", "weak", "granular"):
        if res[k]:
            print(f"\n{k}:")
            table([summary(r) for r in res[k]])


def cube_halo(own, layers):
    """Ghosts of an interior rank owning a cube of `own` grid nodes: the shell `layers` deep."""
    n = own ** (1 / 3)
    return (n + 2 * layers) ** 3 - n ** 3


def mem_today(nodes, bonds, p):
    """Peak per rank today (RESULTS.md item 3 fit): whole node arrays, own bond rows."""
    return MEM_BASE + MEM_NODE * nodes + MEM_BOND * bonds / p


def mem_item1(nodes, bonds, p, ghosts):
    """The same with item 1 done: owned nodes and ghosts only."""
    return MEM_BASE + MEM_NODE * (nodes / p + ghosts) + MEM_BOND * bonds / p


def check_model(res, layers):
    """The measured figures against the model's pieces: memory today, ghosts of one face."""
    print("| series | P | peak RSS max (MB) | model today (MB) | ghosts max | one face x "
          f"{layers} layers (P = 2) | sent B per peer ghost |")
    print("|---" * 7 + "|")
    for k in ("strong", "weak"):
        for r in res[k]:
            s = summary(r)
            face = round(r["nodes"] ** (1 / 3)) ** 2 * layers if r["ranks"] == 2 else float("nan")
            per = (s["sent_mean_B"] / s["ghosts_mean"]) if s["ghosts_mean"] else float("nan")
            print(f"| {k} | {r['ranks']} | {s['rss_max_MB']:.0f} | "
                  f"{mem_today(r['nodes'], r['bonds'], r['ranks']) / 1e6:.0f} | "
                  f"{s['ghosts_max']:.0f} | {face:.0f} | {per:.1f} |")


def model(a):
    with open(a.model) as f:
        res = json.load(f)
    runs = res["strong"] + res["weak"]
    multi = [summary(r) for r in runs if r["ranks"] > 1]
    wall_rate = max(r["bonds"] * res["steps"] / summary(r)["busy_sum_s"]
                    for r in runs if r["ranks"] == 1)
    b_per_ghost = statistics.mean(s["sent_mean_B"] / s["ghosts_mean"] for s in multi)
    red = max(s["reductions"] for s in multi)
    check_model(res, a.layers)
    bw, lat = a.bandwidth * 1e9 / 8, a.latency * 1e-6
    print(f"\nmeasured: {b_per_ghost:.1f} B sent per ghost per step (u, v: 48; x, u, v before: 72); {red:.2f} "
          f"all-reduces per step; 1-rank loop {wall_rate:.3g} bond updates per wall s (shared "
          f"host)\nassumed: {a.rate:.3g} bond updates per CPU s per core; {a.bonds_per_node} "
          f"bonds per node; an interior rank owns a cube and its ghosts are the shell "
          f"{a.layers} node layers deep; {a.peers:g} messages per step; {a.bandwidth:g} Gb/s, "
          f"{a.latency:g} us per message, no overlap with compute; packing and unpacking "
          f"at {a.copy:g} GB/s per core; an all-reduce costs "
          f"2 log2(P) latencies; memory {MEM_BASE / 1e6:.0f} MB + {MEM_NODE} B per node + "
          f"{MEM_BOND} B per bond\n")
    print("| N | P | N/P | ghosts/rank | compute ms | halo MB/step | comm ms | step ms | "
          "comm share | memory/rank today | memory/rank, item 1 |")
    print("|---" * 11 + "|")
    for n in a.model_nodes:
        for p in (64, 1024):
            own = n / p
            g = cube_halo(own, a.layers)
            comp = own * a.bonds_per_node / a.rate
            byts = g * b_per_ghost
            copy = 2 * byts / (a.copy * 1e9)  # pack what is sent, unpack what arrives
            comm = a.peers * lat + byts / bw + red * 2 * math.log2(p) * lat + copy
            b = n * a.bonds_per_node
            print(f"| {n:.3g} | {p} | {own:.3g} | {g:.3g} | {comp * 1e3:.3g} | "
                  f"{byts / 1e6:.3g} | {comm * 1e3:.3g} | {(comp + comm) * 1e3:.3g} | "
                  f"{comm / (comp + comm):.3f} | {mem_today(n, b, p) / 1e9:.3g} GB | "
                  f"{mem_item1(n, b, p, g) / 1e9:.3g} GB |")


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="build/bin")
    ap.add_argument("--out", default="build/scaling")
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 4, 8, 16])
    ap.add_argument("--steps", type=int, default=50)
    ap.add_argument("--h", type=float, default=1e-3, help="strong series node spacing (m)")
    ap.add_argument("--weak-edge", type=int, default=25, help="nodes along the edge at P = 1")
    ap.add_argument("--skip-strong", action="store_true")
    ap.add_argument("--skip-weak", action="store_true")
    ap.add_argument("--granular", help="a packed granular pd-file (e.g. examples/pack3d_1000's "
                    "1000 grains): the same runs, whole grains per rank (--by grain)")
    ap.add_argument("--fields", default="velocity,displacement",
                    help="frame fields of the runs (/solver@fields); 'all': the file's")
    ap.add_argument("--json", default="scaling.json", help="results file in --out")
    ap.add_argument("--partition-only", action="store_true", help="pack and partition, no run")
    ap.add_argument("--model", help="scaling.json of a measurement: print the model")
    ap.add_argument("--model-nodes", type=float, nargs="+", default=[5e6, 1e8])
    ap.add_argument("--bandwidth", type=float, default=100, help="Gb/s (InfiniBand EDR)")
    ap.add_argument("--latency", type=float, default=1.5, help="us")
    ap.add_argument("--peers", type=float, default=26, help="messages per step at scale")
    ap.add_argument("--rate", type=float, default=6e8, help="bond updates per CPU s per core")
    ap.add_argument("--bonds-per-node", type=float, default=179.6,
                    help="bond entries per node (3D grid, delta = 3 h, families to 3.5 h)")
    ap.add_argument("--copy", type=float, default=5, help="GB/s of packing/unpacking a core")
    ap.add_argument("--layers", type=float, default=3, help="node layers of the ghost shell")
    a = ap.parse_args()
    if a.model:
        model(a)
    else:
        measure(a)


if __name__ == "__main__":
    sys.exit(main())
