#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Stability map of pd-solve's time step (issue 11, item 3).

    stability_map.py run    --bin build/bin --out map.json [--scenes a,b] [--k 0.25,1,2] [--work DIR]
    stability_map.py report --after map.json [--before before.json] --md RESULTS.md --png map.png

`run`: for each scene, pack it once with dt "auto", read pd-solve's stability estimate E and its
automatic dt from the log line of a one-step run, then solve copies of the packed file at
dt = k x E (--force-dt) for every k, and one at the automatic dt. A run is *stable* when
pd-solve exits 0 (its guards exit 3 on an energy-balance drift above 5 % of the energy in play,
on interpenetration, a node through a rigid wall, or a blow-up) and every check of
workflows/analysis/check_run.py passes. Recorded per run: exit code, failed checks, energy-balance
drift (max |E + D - E0 - D0| / S, check_run's), broken bonds at the end against the k = 0.25
run, process CPU time (user + sys) of pd-solve. The largest stable k is the largest k of the
grid with every k' <= k stable; the margin of the automatic dt is auto / largest stable.

`report`: writes the tables (before and after, if a before map is given) to RESULTS.md and one
PNG (stable / unstable runs against dt / E, automatic dt marked).
"""
import argparse
import copy
import json
import os
import pathlib
import re
import resource
import shutil
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[3]
sys.path.insert(0, str(ROOT / "workflows" / "analysis"))

K_DEFAULT = [0.25, 0.5, 0.7, 0.8, 0.85, 0.9, 0.95, 1.0, 1.05, 1.1, 1.25, 1.5, 2.0, 2.5, 3.0]

M1 = {"density": 1200, "youngs_modulus": 3.24e7, "fracture_energy": 50}
M1_LPS = dict(M1, law="lps", poisson_ratio=0.25)
M1_PMB = dict(M1, law="pmb")


def load_scene(path):
    text = re.sub(r"^\s*//.*$", "", pathlib.Path(path).read_text(), flags=re.M)
    return json.loads(text)


def two_discs():
    """examples/two_discs: two PMB discs (R 1 mm, h 0.1 mm) meet head-on at 1 m/s."""
    return load_scene(ROOT / "examples" / "two_discs" / "scene.json")


def pull(v):
    return {"conditions": [
        {"name": "top", "kind": "displacement", "region": {"min": [-1, 0.0046], "max": [1, 1]},
         "components": ["y"], "time_function": "linear", "value": v},
        {"name": "bottom", "kind": "displacement",
         "region": {"min": [-1, -1], "max": [1, 0.0004]}, "components": ["y"],
         "time_function": "linear", "value": -v}]}


def notched_pmb_plate():
    """PMB plate 10 x 5 mm (M1, h 0.2 mm, delta 3 h), notch 3 x 0.4 mm, pulled at 1 m/s (the
    stress suite's dt-sweep plate)."""
    return {"dimension": 2, "materials": {"m": M1_PMB},
            "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
            "shapes": {"plate": {"type": "difference",
                                 "base": {"type": "rectangle", "corners": [[0, 0], [0.01, 0.005]]},
                                 "minus": [{"type": "rectangle",
                                            "corners": [[-1e-3, 0.0023], [0.003, 0.0027]]}]}},
            "particles": [{"shape": "plate", "center": [0, 0], "material": "m"}],
            "loading": pull(1.0),
            "solver": {"final_time": 1.2e-4, "output_interval": 1.2e-5}}


def precracked_lps_plate():
    """LPS plate 10 x 5 mm (M1, Gc 5, grid h 0.2 mm), pre-crack 4 mm, pulled at 2 m/s."""
    return {"dimension": 2, "materials": {"m": dict(M1_LPS, fracture_energy=5)},
            "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
            "shapes": {"plate": {"type": "rectangle", "corners": [[0, 0], [0.01, 0.005]],
                                 "mesh": "grid"}},
            "particles": [{"shape": "plate", "center": [0, 0], "material": "m"}],
            "cracks": [{"from": [-1e-3, 0.00251], "to": [0.004, 0.00251]}],
            "loading": pull(2.0),
            "solver": {"final_time": 1.2e-4, "output_interval": 1.2e-5}}


def pack500_contact():
    """examples/pack500 (500 LPS grains, 3 walls) packed 0.05 mm apart, inside the contact
    radius (0.19 mm), so every close pair starts in contact; 0.1 ms (shortened)."""
    s = load_scene(ROOT / "examples" / "pack500" / "scene.json")
    s["particles"][0]["gap"] = 5e-5
    s["solver"].update({"final_time": 1e-4, "output_interval": 2.5e-5, "observe_every": 10})
    return s


def two_spheres_3d():
    """examples/two_spheres_3d (LPS spheres R 1 mm, h 0.25 mm, one fixed): the free one starts
    0.3 mm above the other at 1 m/s and bounces, 0.4 ms."""
    s = load_scene(ROOT / "examples" / "two_spheres_3d" / "scene.json")
    s["particles"][1]["center"] = [0, 0.0033, 0]
    s["particles"][1]["velocity"] = [0, -1.0, 0]
    s["solver"].update({"final_time": 4e-4, "output_interval": 4e-5})
    return s


SCENES = {"two_discs": two_discs, "pmb_notched": notched_pmb_plate,
          "lps_precracked": precracked_lps_plate, "pack500": pack500_contact,
          "spheres_3d": two_spheres_3d}

LOG_RE = re.compile(r"dt = ([0-9.eE+-]+) s \(([0-9.eE+-]+) x stability limit ([0-9.eE+-]+) s")


def cpu_run(cmd):
    """Runs cmd; returns (CompletedProcess, CPU seconds user + sys of the child)."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run(cmd, capture_output=True, text=True)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def solve_copy(bin_dir, packed, dest, dt):
    """Solves a copy of `packed` at dt (s; 0 = auto). Returns a result row."""
    import check_run
    import h5py
    shutil.copyfile(packed, dest)
    with h5py.File(dest, "r+") as f:
        f["solver/dt"][()] = dt
    cmd = [str(bin_dir / "pd-solve"), str(dest)] + (["--force-dt"] if dt > 0 else [])
    r, cpu = cpu_run(cmd)
    row = {"exit": r.returncode, "cpu": cpu}
    m = LOG_RE.search(r.stdout + r.stderr)
    if m:
        row.update(dt=float(m.group(1)), estimate=float(m.group(3)))
    if r.returncode not in (0, 3):
        row["error"] = (r.stderr or r.stdout)[-400:]
        return row
    if r.returncode == 3:
        row["stop"] = (r.stderr.strip().splitlines() or [""])[-1][:300]
    try:
        checks = check_run.check_file(dest)
        row["failed"] = [c.name for c in check_run.failed(checks)]
        for c in checks:
            if c.name == "energy_balance" and c.value is not None:
                row["drift"] = float(c.value)
    except Exception as e:  # a file cut short by a guard may lack frames
        row["failed"] = ["check_run: %s" % e]
    with h5py.File(dest, "r") as f:
        row["broken"] = int(f["observables/broken_bonds/value"][-1])
        row["t_end"] = float(f["observables/broken_bonds/time"][-1])
    stamp(row)
    return row


NOT_DT = ("speed_bound",)


def stamp(row):
    """Stable: exit 0 and every check passes but speed_bound, which is listed and does not
    decide stability: it fails at isolated k between sound runs (the LPS plate's crack at
    k = 0.5 after, 0.9 before), a property of the crack's fragments, not of dt."""
    failed = row.get("failed", [])
    row["stable"] = row["exit"] == 0 and all(c in NOT_DT for c in failed)
    row["flags"] = [c for c in failed if c in NOT_DT]


def run(args):
    bin_dir = pathlib.Path(args.bin).resolve()
    work = pathlib.Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    names = args.scenes.split(",") if args.scenes else list(SCENES)
    ks = [float(k) for k in args.k.split(",")] if args.k else K_DEFAULT
    out = {"bin": str(bin_dir), "k": ks, "scenes": {}}
    if pathlib.Path(args.out).exists():
        out = json.loads(pathlib.Path(args.out).read_text())
        out["k"] = sorted(set(out["k"]) | set(ks))
    for name in names:
        scene = SCENES[name]()
        scene["solver"]["dt"] = "auto"
        src = work / (name + ".json")
        src.write_text(json.dumps(scene, indent=1))
        packed = work / (name + ".h5")
        r = subprocess.run([str(bin_dir / "pd-pack"), str(src), "-o", str(packed), "-q"],
                           capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit("pd-pack %s: %s" % (name, r.stderr))
        est_file = work / (name + "_est.h5")
        shutil.copyfile(packed, est_file)
        r = subprocess.run([str(bin_dir / "pd-solve"), str(est_file), "--steps", "1"],
                           capture_output=True, text=True)
        m = LOG_RE.search(r.stdout + r.stderr)
        if not m:
            sys.exit("pd-solve %s: no estimate in the log:\n%s" % (name, r.stdout + r.stderr))
        est = float(m.group(3))
        rec = out["scenes"].get(name, {"runs": {}})
        rec.update(estimate=est, doc=SCENES[name].__doc__.split("\n")[0].strip())
        print("%s: estimate %.4g s" % (name, est), flush=True)
        for k in ks:
            row = solve_copy(bin_dir, packed, work / ("%s_k%g.h5" % (name, k)), k * est)
            rec["runs"]["%g" % k] = row
            print("  k %-5g exit %d stable %s drift %s broken %s cpu %.1f s %s" % (
                k, row["exit"], row.get("stable"), row.get("drift"), row.get("broken"),
                row["cpu"], ",".join(row.get("failed", []))), flush=True)
            if not args.keep:
                (work / ("%s_k%g.h5" % (name, k))).unlink(missing_ok=True)
        row = solve_copy(bin_dir, packed, work / ("%s_auto.h5" % name), 0.0)
        rec["auto"] = row
        print("  auto dt %.4g s (%.3g x estimate) exit %d stable %s cpu %.1f s" % (
            row.get("dt", 0), row.get("dt", 0) / est, row["exit"], row.get("stable"),
            row["cpu"]), flush=True)
        out["scenes"][name] = rec
        pathlib.Path(args.out).write_text(json.dumps(out, indent=1))


def summarise(rec):
    """(largest stable k, k of the automatic dt, auto stable?) of one scene."""
    for row in list(rec["runs"].values()) + [rec.get("auto", {})]:
        if "exit" in row and "failed" in row:
            stamp(row)
    ks = sorted(float(k) for k in rec["runs"])
    best = 0.0
    for k in ks:
        if rec["runs"]["%g" % k].get("stable"):
            best = k
        else:
            break
    auto = rec.get("auto", {})
    k_auto = auto.get("dt", 0) / rec["estimate"]
    return best, k_auto, bool(auto.get("stable"))


def table(data, title):
    ks = data["k"]
    lines = ["### " + title, "",
             "| scene | estimate E (s) | " + " | ".join("%g" % k for k in ks) +
             " | largest stable k | auto dt / E | auto stable | auto / largest stable |",
             "|---" * (len(ks) + 6) + "|"]
    for name, rec in data["scenes"].items():
        best, k_auto, ok = summarise(rec)  # stamps the rows first
        cells = []
        for k in ks:
            row = rec["runs"].get("%g" % k)
            if row is None:
                cells.append("")
            elif row.get("stable"):
                cells.append("ok*" if row.get("flags") else "ok")
            elif row["exit"] == 3:
                cells.append("**3**")
            else:
                cells.append("**x**")
        best, k_auto, ok = summarise(rec)
        lines.append("| %s | %.4g | %s | %g | %.3f | %s | %.2f |" % (
            name, rec["estimate"], " | ".join(cells), best, k_auto, "yes" if ok else "**no**",
            k_auto / best if best > 0 else float("nan")))
    lines += ["", "ok: exit 0 and every check_run.py check passes; **3**: a guard stopped the "
              "run (exit 3); **x**: exit 0 but a check failed; ok*: exit 0, every check but "
              "speed_bound passes (the LPS plate's crack, see the runs below).", ""]
    return lines


def details(data):
    lines = ["| scene | k | dt (s) | exit | energy drift (% of S) | broken bonds (k=0.25: ref) "
             "| CPU s | failed checks / stop |", "|---|---|---|---|---|---|---|---|"]
    for name, rec in data["scenes"].items():
        ref = rec["runs"].get("0.25", {}).get("broken")
        rows = sorted(rec["runs"].items(), key=lambda kv: float(kv[0]))
        rows.append(("auto", rec.get("auto", {})))
        for k, row in rows:
            if not row:
                continue
            why = ",".join(row.get("failed", []))
            if row.get("stop"):
                stop = re.sub(r"\S*/([^/\s]+\.h5):", r"\1:", row["stop"])  # no machine paths
                why = (why + "; " if why else "") + re.sub(
                    r"^.*?: (.*?) at step.*$", r"\1", stop)[:60]
            lines.append("| %s | %s | %.4g | %d | %s | %s (%s) | %.1f | %s |" % (
                name, k, row.get("dt", float("nan")), row["exit"],
                "%.3f" % (100 * row["drift"]) if "drift" in row else "-",
                row.get("broken", "-"), ref, row["cpu"], why))
    return lines


def report(args):
    after = json.loads(pathlib.Path(args.after).read_text())
    before = json.loads(pathlib.Path(args.before).read_text()) if args.before else None
    md = pathlib.Path(args.md)
    head = md.read_text().split("<!-- generated -->")[0] if md.exists() else ""
    lines = ["<!-- generated -->", ""]
    if before:
        lines += table(before, "Before: row-sum estimate, auto dt = 0.7 E")
    lines += table(after, "After: Lanczos bond spectrum + contact bound")
    lines += ["### Every run (after)", ""] + details(after) + [""]
    if before:
        lines += ["### Every run (before)", ""] + details(before) + [""]
    md.write_text(head + "\n".join(lines))
    plot(before, after, args.png)


def plot(before, after, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    panels = [(before, "before"), (after, "after")] if before else [(after, "after")]
    fig, axes = plt.subplots(1, len(panels), figsize=(6.5 * len(panels), 3.6), squeeze=False)
    for ax, (data, label) in zip(axes[0], panels):
        names = list(data["scenes"])
        for y, name in enumerate(names):
            rec = data["scenes"][name]
            for k, row in rec["runs"].items():
                ok = row.get("stable")
                ax.plot(float(k), y, "o" if ok else "x", color="tab:green" if ok else "tab:red",
                        ms=7)
            best, k_auto, auto_ok = summarise(rec)
            ax.plot(k_auto, y, marker="|", color="k", ms=18, mew=2)
            ax.annotate("auto %.2f\n%.0f%% of max" % (k_auto, 100 * k_auto / best if best else 0),
                        (k_auto, y + 0.18), fontsize=7, ha="center")
        ax.set_yticks(range(len(names)))
        ax.set_yticklabels(names)
        ax.set_ylim(-0.6, len(names) - 0.3)
        ax.set_xscale("log")
        ks = data["k"]
        ax.set_xticks(ks)
        ax.set_xticklabels(["%g" % k for k in ks], rotation=90, fontsize=7)
        ax.set_xlabel("dt / stability estimate (%s)" % label)
        ax.set_title("%s: green o stable, red x unstable, | automatic dt" % label, fontsize=9)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = p.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("--bin", default=str(ROOT / "build" / "bin"))
    r.add_argument("--out", required=True)
    r.add_argument("--work", default="/tmp/pd_stability_map")
    r.add_argument("--scenes")
    r.add_argument("--k")
    r.add_argument("--keep", action="store_true", help="keep the solved files")
    q = sub.add_parser("report")
    q.add_argument("--after", required=True)
    q.add_argument("--before")
    q.add_argument("--md", required=True)
    q.add_argument("--png", required=True)
    a = p.parse_args()
    run(a) if a.cmd == "run" else report(a)


if __name__ == "__main__":
    main()
