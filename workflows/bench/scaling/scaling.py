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

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "startup", "block3d.json")
BOX = 0.063  # the block's edge, m
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


def partitioned(bindir, base, ranks):
    """A copy of `base` with /partition for `ranks` (kept: METIS on 4e7 bonds takes a while)."""
    f = base.replace(".h5", f"_p{ranks}.part.h5")
    if not os.path.exists(f):
        shutil.copy(base, f + ".tmp")
        if ranks > 1:
            sh([f"{bindir}/pd-partition", f + ".tmp", "-n", str(ranks), "-q"])
        os.rename(f + ".tmp", f)
    return f


def solve(bindir, base, ranks, steps, out):
    f = base.replace(".h5", f"_p{ranks}.h5")
    shutil.copy(partitioned(bindir, base, ranks), f)
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
        "halo_share_max": max(r["halo_s"] / r["loop_s"] for r in pr if r["loop_s"] > 0),
        "halo_share_mean": statistics.mean(r["halo_s"] / r["loop_s"] for r in pr),
        "cpu_s": sum(r["user"] + r["sys"] for r in pr),
        "wall_s": max(col("wall")),
    }


def table(rows):
    print("| P | nodes | bonds | peak RSS max / mean (MB) | owned / rank | ghosts max / mean "
          "(bond, contact max) | peers max | sent B/step max / mean | msgs/step max | "
          "halo share max / mean | loop s | CPU s (all ranks) |")
    print("|---" * 12 + "|")
    for s in rows:
        print(f"| {s['P']} | {s['nodes']} | {s['bonds']} | {s['rss_max_MB']:.0f} / "
              f"{s['rss_mean_MB']:.0f} | {s['owned_mean']:.0f} | {s['ghosts_max']:.0f} / "
              f"{s['ghosts_mean']:.0f} ({s['bond_ghosts_max']:.0f}, "
              f"{s['contact_ghosts_max']:.0f}) | {s['peers_max']:.0f} | {s['sent_max_B']:.3g} / "
              f"{s['sent_mean_B']:.3g} | {s['msgs_max']:.0f} | {s['halo_share_max']:.3f} / "
              f"{s['halo_share_mean']:.3f} | {s['loop_s']:.2f} | {s['cpu_s']:.1f} |")


def measure(a):
    os.makedirs(a.out, exist_ok=True)
    res = {"strong": [], "weak": [], "steps": a.steps}
    if a.partition_only:
        for p in a.ranks:
            partitioned(a.bin, pack(a.bin, a.out, a.h), p)
            partitioned(a.bin, pack(a.bin, a.out, BOX / round(a.weak_edge * p ** (1 / 3))), p)
        return
    if not a.skip_strong:
        base = pack(a.bin, a.out, a.h)
        for p in a.ranks:
            res["strong"].append(solve(a.bin, base, p, a.steps, a.out))
    if not a.skip_weak:
        for p in a.ranks:
            edge = round(a.weak_edge * p ** (1 / 3))
            base = pack(a.bin, a.out, BOX / edge)
            res["weak"].append(solve(a.bin, base, p, a.steps, a.out))
    with open(os.path.join(a.out, "scaling.json"), "w") as f:
        json.dump(res, f, indent=1)
    for k in ("strong", "weak"):
        if res[k]:
            print(f"\n{k}:")
            table([summary(r) for r in res[k]])


def fit_halo(runs):
    """ghosts per rank = c (N/P)^(2/3), least squares in log space over P >= 2 (max rank)."""
    pts = [(math.log(summary(r)["owned_mean"]), math.log(summary(r)["ghosts_max"]))
           for r in runs if r["ranks"] > 1]
    if not pts:
        return None
    xs, ys = zip(*pts)
    # the slope fitted, and c at the slope 2/3 of a surface over a volume
    mx, my = statistics.mean(xs), statistics.mean(ys)
    slope = (sum((x - mx) * (y - my) for x, y in pts) / sum((x - mx) ** 2 for x in xs)
             if len(pts) > 1 else float("nan"))
    c = math.exp(statistics.mean(y - 2 / 3 * x for x, y in pts))
    return slope, c


def model(a):
    with open(a.model) as f:
        res = json.load(f)
    runs = res["strong"] + res["weak"]
    one = [summary(r) for r in runs if r["ranks"] == 1]
    rate = max(r["bonds"] * res["steps"] / s["busy_sum_s"] for r, s in
               ((r, summary(r)) for r in runs if r["ranks"] == 1))
    slope, c = fit_halo(runs)
    multi = [summary(r) for r in runs if r["ranks"] > 1]
    b_per_ghost = statistics.mean(s["sent_mean_B"] / s["ghosts_mean"] for s in multi)
    bonds_per_node = statistics.mean(s["bonds"] / s["nodes"] for s in one)
    bw, lat = a.bandwidth * 1e9 / 8, a.latency * 1e-6
    peers = max(s["peers_max"] for s in multi)
    red = max(s["reductions"] for s in multi)
    print(f"measured: {rate:.3g} bond updates per CPU s (1 rank, loop busy time); halo fit "
          f"ghosts = {c:.3g} (N/P)^(2/3) (free slope {slope:.3f}); {b_per_ghost:.1f} B sent per "
          f"ghost per step; {bonds_per_node:.1f} bond entries per node; peers up to {peers:.0f}; "
          f"{red:.2f} all-reduces per step")
    print(f"assumed: {a.bandwidth:g} Gb/s per rank, {a.latency:g} us latency, messages not "
          f"overlapped with compute, {a.peers:g} peers per rank at scale, all-reduce "
          f"2 log2(P) latencies, 385 B per node + 22 B per bond + 60 MB per rank (RESULTS.md "
          f"item 3 fit)")
    print("| N | P | N/P | compute ms | ghosts/rank | halo MB/step | comm ms | step ms | "
          "comm share | memory/rank today | memory/rank, item 1 |")
    print("|---" * 11 + "|")
    for n in a.model_nodes:
        for p in (64, 1024):
            own = n / p
            g = c * own ** (2 / 3)
            comp = own * bonds_per_node / rate
            byts = g * b_per_ghost
            comm = a.peers * lat + byts / bw + red * 2 * math.log2(p) * lat
            b = n * bonds_per_node
            today = 60e6 + 385 * n + 22 * b / p
            dist = 60e6 + 385 * (own + g) + 22 * b / p
            print(f"| {n:.3g} | {p} | {own:.3g} | {comp * 1e3:.3g} | {g:.3g} | {byts / 1e6:.3g} | "
                  f"{comm * 1e3:.3g} | {(comp + comm) * 1e3:.3g} | {comm / (comp + comm):.3f} | "
                  f"{today / 1e9:.3g} GB | {dist / 1e9:.3g} GB |")


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
    ap.add_argument("--partition-only", action="store_true", help="pack and partition, no run")
    ap.add_argument("--model", help="scaling.json of a measurement: print the model")
    ap.add_argument("--model-nodes", type=float, nargs="+", default=[5e6, 1e8])
    ap.add_argument("--bandwidth", type=float, default=100, help="Gb/s (InfiniBand EDR)")
    ap.add_argument("--latency", type=float, default=1.5, help="us")
    ap.add_argument("--peers", type=float, default=26, help="messages per step at scale")
    a = ap.parse_args()
    if a.model:
        model(a)
    else:
        measure(a)


if __name__ == "__main__":
    sys.exit(main())
