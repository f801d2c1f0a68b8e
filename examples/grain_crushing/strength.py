#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Grain strength statistics of the crushing sweep (examples/grain_crushing, issue 31 item 3).

    strength.py sets [-o sweep_sets.csv]        the sweep's parameter sets (3 sizes x 20 seeds)
    strength.py table SWEEP_DIR [-o strength.csv] [--png strength.png] [--md strength.md]

`table` reads every SWEEP_DIR/runs/NNN/run.h5 (workflows/sweep/sweep.py expand + make, or the
Slurm array) with crush.py, and writes per run (d, seed, F_c, sigma = F_c / d, KE / elastic at
the peak, crushed or not) and per size: seeds, mean strength and its standard error, the
coefficient of variation, the Weibull modulus m_fit of the strengths (maximum likelihood,
two-parameter Weibull, and the least-squares line of ln(-ln Ps) against ln sigma with Ps_i =
1 - (i - 0.5) / n as a cross-check), and over the sizes the exponent b of mean sigma ~ d^b
(least squares of ln mean sigma against ln d). Compared with the flaw law put in (the file's
/materials/<m>/flaw_modulus m): m_fit against m (target within 20 %), b against -2/m (2D,
target within 0.1), and b against -2/m_fit (what weakest-link statistics at the grain level
would give for the measured scatter). Nothing is tuned: the fit is of the measured peaks."""
import argparse
import csv
import glob
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import crush  # noqa: E402

SIZES = (4.0e-4, 8.0e-4, 1.6e-3)  # m: the grains' diameters (h = 25 um fixed: d / h 16, 32, 64)
FINAL_TIME = {4.0e-4: 4.0e-5, 8.0e-4: 5.5e-5, 1.6e-3: 8.0e-5}  # s: ~1.45 x the peak of seed 1
SEEDS = range(1, 21)


def write_sets(path):
    cols = ["particles[0].radius", "walls[0].point", "walls[1].point",
            "materials.sand.flaws.seed", "solver.final_time", "solver.output_interval"]
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(cols)
        for d in SIZES:
            r, t = 0.5 * d, FINAL_TIME[d]
            for s in SEEDS:
                w.writerow([repr(r), json.dumps([0, -r]), json.dumps([0, r]), s, repr(t),
                            repr(t / 4)])
    print("%d sets -> %s" % (len(SIZES) * len(SEEDS), path))


def flaw_law(path):
    import h5py
    with h5py.File(path, "r") as f:
        for m in f["materials"]:
            g = f["materials"][m]
            if "flaw_modulus" in g:
                return float(g["flaw_modulus"][()])
    return float("nan")


def runs(sweep_dir):
    """One dict per finished run (crush.analyse + seed), sorted by d then seed."""
    out = []
    for h5 in sorted(glob.glob(os.path.join(sweep_dir, "runs", "*", "run.h5"))):
        d = os.path.dirname(h5)
        if not os.path.exists(os.path.join(d, "run.done")):
            continue
        with open(os.path.join(d, "params.json")) as fh:
            params = json.load(fh)
        res = crush.analyse(crush.read(h5))
        res["seed"] = int(params.get("materials.sand.flaws.seed", -1))
        res["run"] = os.path.basename(d)
        res["flaw_modulus"] = flaw_law(h5)
        res["cpu_seconds"] = run_seconds(d)
        out.append(res)
    out.sort(key=lambda r: (round(r["d"], 9), r["seed"]))
    return out


def run_seconds(d):
    try:
        with open(os.path.join(d, "status.json")) as fh:
            return float(json.load(fh).get("wall_seconds", float("nan")))
    except (OSError, ValueError):
        return float("nan")


def weibull_mle(x):
    """(m, sigma_0) of the two-parameter Weibull law by maximum likelihood."""
    from scipy import stats
    m, _, s0 = stats.weibull_min.fit(x, floc=0)
    return float(m), float(s0)


def weibull_lsq(x):
    """(m, sigma_0): the line ln(-ln Ps) = m ln sigma - m ln sigma_0, Ps_i = 1 - (i-0.5)/n."""
    x = np.sort(x)
    ps = 1 - (np.arange(1, len(x) + 1) - 0.5) / len(x)
    m, c = np.polyfit(np.log(x), np.log(-np.log(ps)), 1)
    return float(m), float(math.exp(-c / m))


def per_size(rows):
    sizes = sorted({round(r["d"], 9) for r in rows})
    table = []
    for d in sizes:
        rs = [r for r in rows if round(r["d"], 9) == d and r["crushed"]]
        s = np.array([r["sigma"] for r in rs])
        if len(s) < 3:
            continue
        m_mle, s0 = weibull_mle(s)
        m_lsq, _ = weibull_lsq(s)
        table.append({"d": d, "seeds": len(s), "not_crushed": sum(
            1 for r in rows if round(r["d"], 9) == d and not r["crushed"]),
            "mean_sigma": float(s.mean()), "sem_sigma": float(s.std(ddof=1) / math.sqrt(len(s))),
            "cov": float(s.std(ddof=1) / s.mean()), "m_fit": m_mle, "m_fit_lsq": m_lsq,
            "sigma_0": s0, "ke_over_elastic_max": max(r["ke_over_elastic_at_peak"] for r in rs),
            "nodes": rs[0]["nodes"], "cpu_seconds": float(np.nansum([r["cpu_seconds"]
                                                                     for r in rs])),
            "sigmas": s})
    return table


def size_exponent(d, sigma):
    """(b, its standard error, ln prefactor) of sigma ~ d^b (least squares in log-log)."""
    if len(d) < 2:
        return float("nan"), float("nan"), float("nan")
    x, y = np.log(d), np.log(sigma)
    p, cov = np.polyfit(x, y, 1, cov=True) if len(x) > 2 else (np.polyfit(x, y, 1), None)
    return float(p[0]), float(math.sqrt(cov[0, 0])) if cov is not None else float("nan"), \
        float(p[1])


def controls(paths):
    """(d, sigma) of the control runs (the same grains without flaws), sorted by d."""
    rs = sorted((crush.analyse(crush.read(p)) for p in paths), key=lambda r: r["d"])
    return np.array([r["d"] for r in rs]), np.array([r["sigma"] for r in rs])


def markdown(table, fit, m, ctrl):
    b, b_se = fit[0], fit[1]
    lines = ["| d (mm) | nodes | seeds | mean sigma = F_c/d (MPa) | CoV | m_fit (MLE) | "
             "m_fit (LSQ) | max KE/elastic at peak |", "|---|---|---|---|---|---|---|---|"]
    for t in table:
        lines.append("| %.2f | %d | %d | %.2f +- %.2f | %.3f | %.2f | %.2f | %.1e |" % (
            t["d"] * 1e3, t["nodes"], t["seeds"], t["mean_sigma"] * 1e-6,
            t["sem_sigma"] * 1e-6, t["cov"], t["m_fit"], t["m_fit_lsq"],
            t["ke_over_elastic_max"]))
    mf = [t["m_fit"] for t in table]
    lines.append("")
    lines.append("Flaw law put in: bond critical stretch s0 w, w Weibull, modulus m = %g, "
                 "median 1." % m)
    lines.append("m_fit per size: %s against m = %g (target within 20 %%: %.1f-%.1f)." % (
        ", ".join("%.2f" % x for x in mf), m, 0.8 * m, 1.2 * m))
    lines.append("Size exponent b = %.3f +- %.3f (mean sigma ~ d^b) against -2/m = %.3f "
                 "(target within 0.1); -2/m_fit (mean m_fit %.2f) = %.3f." % (
                     b, b_se, -2 / m, np.mean(mf), -2 / np.mean(mf)))
    if ctrl is not None:
        bc, bc_se, _ = size_exponent(*ctrl)
        lines.append("Control, the same grains without flaws: sigma = %s MPa at d = %s mm, "
                     "exponent %.3f +- %.3f." % (", ".join("%.2f" % (x * 1e-6) for x in ctrl[1]),
                                                 ", ".join("%.2g" % (x * 1e3) for x in ctrl[0]),
                                                 bc, bc_se))
    return "\n".join(lines)


def plot(table, fit, m, ctrl, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    for t in table:
        s = np.sort(t["sigmas"])
        ps = 1 - (np.arange(1, len(s) + 1) - 0.5) / len(s)
        line, = a1.plot(s * 1e-6, ps, "o", ms=4, label="d = %.1f mm (%d seeds), m_fit %.1f" % (
            t["d"] * 1e3, t["seeds"], t["m_fit"]))
        g = np.linspace(0.6 * s.min(), 1.3 * s.max(), 100)
        a1.plot(g * 1e-6, np.exp(-(g / t["sigma_0"]) ** t["m_fit"]), "-", lw=1,
                color=line.get_color())
    a1.set_xlabel("sigma = F_c / d (MPa)")
    a1.set_ylabel("survival probability Ps")
    a1.set_title("survival per size (lines: Weibull MLE fits)", fontsize=10)
    a1.legend(fontsize=7)
    d = np.array([t["d"] for t in table])
    ms = np.array([t["mean_sigma"] for t in table])
    a2.errorbar(d * 1e3, ms * 1e-6, yerr=[t["sem_sigma"] * 1e-6 for t in table], fmt="o",
                label="measured mean (+- s.e.)")
    a2.plot(d * 1e3, 1e-6 * np.exp(fit[2]) * d ** fit[0], "-", label="fit: d^%.3f" % fit[0])
    if ctrl is not None:
        bc = size_exponent(*ctrl)[0]
        a2.plot(ctrl[0] * 1e3, ctrl[1] * 1e-6, "s", mfc="none",
                label="no flaws (control), d^%.3f" % bc)
    a2.plot(d * 1e3, ms[0] * 1e-6 * (d / d[0]) ** (-2 / m), "k:",
            label="flaw law: d^(-2/m) = d^%.2f" % (-2 / m))
    a2.set_xscale("log")
    a2.set_yscale("log")
    a2.set_xlabel("grain diameter d (mm)")
    a2.set_ylabel("mean sigma (MPa)")
    a2.set_title("size effect", fontsize=10)
    a2.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)


def write_csv(rows, path):
    cols = ["run", "d", "seed", "F_c", "sigma", "u_c", "t_c", "ke_over_elastic_at_peak",
            "balance_end", "crushed", "broken_bonds_end", "nodes", "cpu_seconds"]
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=cols, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow(r)


def table_cmd(a):
    rows = runs(a.dir)
    if not rows:
        print("strength.py: no finished runs under %s/runs" % a.dir, file=sys.stderr)
        return 2
    write_csv(rows, a.output)
    table = per_size(rows)
    m = rows[0]["flaw_modulus"]
    fit = size_exponent([t["d"] for t in table], [t["mean_sigma"] for t in table])
    ctrl = controls(a.control) if a.control else None
    md = markdown(table, fit, m, ctrl)
    print(md)
    print("runs not crushed within their time: %d; CPU (wall s of the runs, summed): %.0f" % (
        sum(not r["crushed"] for r in rows), np.nansum([r["cpu_seconds"] for r in rows])))
    if a.md:
        with open(a.md, "w") as fh:
            fh.write(md + "\n")
    if a.png:
        plot(table, fit, m, ctrl, a.png)
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("sets", help="write the sweep's parameter sets")
    s.add_argument("-o", "--output", default="sweep_sets.csv")
    t = sub.add_parser("table", help="the strength table and plot from a finished sweep")
    t.add_argument("dir")
    t.add_argument("-o", "--output", default="strength.csv")
    t.add_argument("--png")
    t.add_argument("--md")
    t.add_argument("--control", nargs="+", help="runs of the same grains without flaws (.h5)")
    a = ap.parse_args()
    if a.cmd == "sets":
        write_sets(a.output)
        return 0
    return table_cmd(a)


if __name__ == "__main__":
    sys.exit(main())
