#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Issue 26's "Why" figures re-measured on the default contact law (ISSUE26_WHY.md).

    why.py [--bin DIR] [--out DIR] [ITEM ...]

ITEM: box2d pour3d press sphere disc pair shipped n500 n500trace plate csg (default: all). Each item packs its
scene as a new user would (no contact factor: the materials and the scene only), solves it with
OMP_NUM_THREADS=1 and prints the figure the issue quotes. --bin: the directory holding pd-pack
and pd-solve (default build/bin); --out: where the .h5 files go (default /tmp/why26; they are
large and never committed). About 10 min of CPU in all (box2d 2.5 min, n500 2 x 1 min).
"""
import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", "..", ".."))
sys.path[:0] = [HERE, os.path.join(ROOT, "workflows", "accuracy"),
                os.path.join(ROOT, "workflows", "analysis"), os.path.join(ROOT, "workflows",
                                                                         "sweep")]
import hertz_surface as hs  # noqa: E402

ENV = dict(os.environ, OMP_NUM_THREADS="1", PD_SOURCE_DIR=ROOT)
A = None


def run(args, log=None):
    t0 = time.process_time()
    r0 = os.times()
    p = subprocess.run(args, env=ENV, capture_output=True, text=True)
    r1 = os.times()
    cpu = (r1.children_user - r0.children_user) + (r1.children_system - r0.children_system)
    if log:
        with open(log, "w") as fh:
            fh.write(p.stdout + p.stderr)
    return p.returncode, p.stdout + p.stderr, cpu


def pack(scene, name, sets=()):
    """scene: a path or a dict. Returns the .h5 path."""
    if isinstance(scene, dict):
        path = os.path.join(A.out, name + ".json")
        with open(path, "w") as fh:
            json.dump(scene, fh, indent=1)
        scene = path
    h5 = os.path.join(A.out, name + ".h5")
    args = [os.path.join(A.bin, "pd-pack"), scene, "-o", h5, "-q", "--overwrite"]
    for s in sets:
        args += ["--set", s]
    rc, out, _ = run(args)
    if rc:
        sys.exit(f"pd-pack {scene}: exit {rc}\n{out}")
    return h5


def solve(h5, *extra):
    rc, out, cpu = run([os.path.join(A.bin, "pd-solve"), h5, *extra], log=h5 + ".log")
    head = re.search(r"dt = [^\n]*", out)
    err = re.search(r"pd-solve: error: [^\n]*", out)
    return {"rc": rc, "cpu": cpu, "dt_line": head.group(0) if head else "",
            "error": err.group(0) if err else ""}


def check(h5):
    import check_run
    return {c.name: (c.ok, c.value, c.bound, c.detail) for c in check_run.check_file(h5)}


def show_checks(h5, names=("no_interpenetration", "no_wall_body_penetration",
                           "no_node_below_rigid_wall", "energy_balance")):
    c = check(h5)
    for n in names:
        ok, v, b, d = c[n]
        print(f"    {n}: {'PASS' if ok else ('SKIP' if ok is None else 'FAIL')} {v:.4g} "
              f"(bound {b:.4g}) {d}")
    return c


def last_time(h5):
    import h5py
    with h5py.File(h5, "r") as f:
        return float(f["observables/kinetic_energy/time"][-1])


# ------------------------------------------------------------------ item 1: box2d, pour3d

def settle(name, scene, final_time):
    import gaps
    h5 = pack(os.path.join(ROOT, "workflows", "bench", "contact", scene), name)
    r = solve(h5, "--final-time", str(final_time))
    print(f"{name}: exit {r['rc']}, t reached {last_time(h5):.4g} s, {r['cpu']:.0f} s CPU; "
          f"{r['dt_line']} {r['error']}")
    show_checks(h5)
    g = gaps.analyse(h5)
    h = g["h"]
    pg, wg = g["pair_gap"], g["floor_gap"]
    import h5py
    with h5py.File(h5, "r") as f:
        o = f["observables"]
        el, ce = o["elastic_energy/value"][-1], o["contact_energy/value"][-1]
    d = g["deepest"]
    print(f"    deepest node inside another grain at the end, behind its deformed boundary: "
          f"{d[0] * 1e6:.3g} um ({d[0] / h:+.4f} h), node {d[1]} of body {d[2]} in body {d[3]};"
          f" contact / elastic energy at the end {ce:.3g} / {el:.3g} J = {ce / el:.3g}")
    print(f"    at t = {g['t']:.4g} s (KE {g['ke']:.3g} J): grain pairs within h {g['pairs']} "
          f"(gap < 0.01 h: {g['pair_bins'][0]}, 0.01-0.25 h: {g['pair_bins'][1]}, >= 0.25 h: "
          f"{g['pair_bins'][2]}), gap min/median {pg[0] / h:+.4f} / {pg[1] / h:+.4f} h; "
          f"grain-floor lowest nodes min/median/max {wg[0] / h:+.4f} / {wg[1] / h:+.4f} / "
          f"{wg[2] / h:+.4f} h; largest nearest-support gap {g['nearest_support_max'] / h:+.4f} h"
          f" (grain {g['nearest_support_worst_grain']}), grains touching nothing: "
          f"{g['floating']}; pile height {g['pile_height'] * 1e3:.3f} mm")


def item_box2d():
    settle("box2d", "box2d.json", 0.15)  # 60 ms as in the bench: the top grains still fall


def item_pour3d():
    settle("pour3d", "pour3d.json", 0.03)


def item_press():
    """box2d_press.json (box2d settled to 60 ms, then a plate at 0.1 m/s from 60 to 90 ms) with
    breakable grains (fracture_energy 50 J/m2, PeriDEM's M1; the bench scene is unbreakable):
    the issue's "a plate's 3 mm of compaction breaks no bond"."""
    h5 = pack(os.path.join(ROOT, "workflows", "bench", "contact", "box2d_press.json"),
              "box2d_press_gc50", sets=["materials.m.fracture_energy=50"])
    r = solve(h5)
    import h5py
    import numpy as np
    with h5py.File(h5, "r") as f:
        o = f["observables"]
        t = o["broken_bonds/time"][()]
        nb = o["broken_bonds/value"][()]
        F = o["wall_force/value"][()]
        el, ce = o["elastic_energy/value"][()], o["contact_energy/value"][()]
    k = len(t) - 1
    print(f"box2d_press (fracture_energy 50): exit {r['rc']}, t reached {t[-1]:.4g} s, "
          f"{r['cpu']:.0f} s CPU; broken bonds at the end {int(nb[-1])}, plate force "
          f"{np.abs(F[-1, -1, 1]):.4g} N/m (largest {np.abs(F[:, -1, 1]).max():.4g}); contact / "
          f"elastic energy at the end {ce[k]:.3g} / {el[k]:.3g} J {r['error']}")
    show_checks(h5)


# ------------------------------------------------------------------ items 2, 3: Hertz

def impact(dim, h, v, pair=False, eps=None):
    """A gmsh disc / sphere (R = 1 mm, E = 32.4 MPa, rho 1200, PMB) on a rigid wall (or two at
    +-v) as hertz_surface.py builds it (its scene names "law": "surface", the default, and no
    factor), with frames every t_c / 20 to see the deepest node."""
    runner = hs.Runner(os.path.dirname(A.bin), A.out)
    runner.bin = A.bin
    tag = f"why_{dim}d_{'pair' if pair else 'wall'}_{h:.3g}_{v:g}"
    lift = hs.gap(dim, h) - hs.lowest_gap(runner, tag, dim, h, "gmsh", ())
    sc = hs.scene(dim, h, v, "gmsh", pair, lift, {})
    if not pair:
        sc["solver"]["output_interval"] = hs.REFERENCE[dim][v][0] / 20
    h5 = pack(sc, tag)
    r = solve(h5)
    out = {"dim": dim, "h": h, "v": v, "rc": r["rc"], "cpu": r["cpu"], "error": r["error"]}
    if r["rc"] == 0:
        tc, fmax, n, lat = hs.measure(h5, dim, pair, v)
        rt, rf = hs.REFERENCE[dim][v]
        out.update(tc=tc, fmax=fmax, nodes=n, tc_err=tc / rt - 1, f_err=fmax / rf - 1)
    if not pair:
        import h5py
        import numpy as np
        with h5py.File(h5, "r") as f:
            y = f["particles/nodes/position/value"][:, :, 1]
            out["lowest"] = float(y.min()) / h  # the wall's surface is y = 0
    os.remove(h5)
    return out


def show_impact(o):
    s = (f"  {o['dim']}D h = {o['h'] * 1e3:g} mm, {o['v']:g} m/s: exit {o['rc']}, "
         f"{o['cpu']:.1f} s CPU")
    if "tc" in o:
        s += (f", t_c {o['tc'] * 1e6:.2f} us ({100 * o['tc_err']:+.1f} %), F_max {o['fmax']:.4g}"
              f" ({100 * o['f_err']:+.1f} %), {o['nodes']} nodes")
    if "lowest" in o:
        s += f", lowest node {o['lowest']:+.3f} h from the wall's surface"
    print(s + (" " + o["error"] if o["error"] else ""))


def item_sphere():
    print("3D sphere on a rigid wall (reference t_c 79.40 / 55.32 us, F_max 0.2372 / 1.762 N at"
          " 1 / 5 m/s):")
    for v in (1.0, 5.0):
        for h in (2e-4, 1e-4):
            show_impact(impact(3, h, v))


def item_disc():
    print("2D disc on a rigid wall (reference t_c 56.35 / 46.53 / 40.46 us, F_max 22.15 / 259.1"
          " / 1519 N/m):")
    for h in (1e-4, 1.25e-5):
        for v in (0.1, 1.0, 5.0):
            show_impact(impact(2, h, v))


def item_pair():
    """tests/sweep/two_discs.json, the scene of the issue's 27 % (accuracy.py restitution at
    h = 0.05 mm), with its contact factors removed: restitution 0.8 only."""
    from sweep import measure
    with open(os.path.join(ROOT, "tests", "sweep", "two_discs.json")) as fh:
        s = json.loads("\n".join(ln for ln in fh.read().splitlines()
                                 if not ln.lstrip().startswith("//")))
    s["contact"] = {"restitution": 0.8}
    s["solver"].pop("checkpoint_interval", None)
    s["solver"]["fields"] = ["velocity"]
    for h in (2e-4, 1e-4, 5e-5):
        s["discretization"]["mesh_size"] = h
        h5 = pack(s, f"why_pair_eps_{h:.3g}")
        r = solve(h5)
        m = measure(h5)
        print(f"  two discs head-on, eps 0.8, h = {h * 1e3:g} mm: exit {r['rc']}, restitution "
              f"{m['restitution']:.4f} ({100 * (m['restitution'] / 0.8 - 1):+.2f} %), separated "
              f"{m['separated']}")
        os.remove(h5)


# ------------------------------------------------------------------ item 4: shipped scenes

def item_shipped():
    for d in ("examples", os.path.join("tests", "stress")):
        for dirpath, _, files in sorted(os.walk(os.path.join(ROOT, d))):
            for fn in sorted(files):
                if not fn.endswith((".json", ".py")):
                    continue
                p = os.path.join(dirpath, fn)
                with open(p) as fh:
                    text = fh.read()
                keys = sorted(set(re.findall(r'"?(stiffness_factor|radius_mesh_factor|'
                                             r'radius_factor)"?\s*[:=]\s*([0-9.e+-]+)', text)))
                law = re.findall(r'"law":\s*"(node|surface)"|law="(node)"', text)
                if keys:
                    print(f"  {os.path.relpath(p, ROOT)}: "
                          + ", ".join(f"{k} {v}" for k, v in keys)
                          + (f" (law {sorted({a or b for a, b in law})})" if law else
                             " (no law named: a radius key selects the node law)"))
    ex = os.path.join(ROOT, "examples", "compressive_small")
    h5 = pack(os.path.join(ex, "scene.json"), "compressive_small")
    r = solve(h5)
    print(f"compressive_small (scene.json as shipped, 50 ms): exit {r['rc']}, "
          f"{r['cpu']:.1f} s CPU; {r['dt_line']} {r['error']}")
    show_checks(h5)


def item_n500():
    """The quick scene as shipped (the PeriDEM-parity node law) with the guard on, and the same
    scene on the default law (law and stiffness_factor removed) with the guard on."""
    src = os.path.join(ROOT, "examples", "compressive_n500")
    work = os.path.join(A.out, "n500")
    shutil.rmtree(work, ignore_errors=True)
    shutil.copytree(src, work, ignore=shutil.ignore_patterns("*.png", "out*"))
    with open(os.path.join(work, "scene_quick.json")) as fh:
        text = fh.read()
    s = json.loads("\n".join(ln for ln in text.splitlines() if not ln.lstrip().startswith("//")))
    s["contact"] = {k: v for k, v in s["contact"].items()
                    if k not in ("law", "stiffness_factor")}
    with open(os.path.join(work, "scene_quick_default.json"), "w") as fh:
        json.dump(s, fh, indent=1)
    for name, extra in (("scene_quick.json", ()), ("scene_quick.json",
                                                   ("--no-penetration-check",)),
                        ("scene_quick_default.json", ())):
        h5 = pack(os.path.join(work, name), "n500_" + name[:-5] + ("_nocheck" if extra else ""))
        r = solve(h5, *extra)
        print(f"compressive_n500/{name} {' '.join(extra)}: exit {r['rc']}, t reached "
              f"{last_time(h5):.4g} s of 0.0275, {r['cpu']:.1f} s CPU; {r['dt_line']} "
              f"{r['error']}")
        show_checks(h5)
        # as `make quick` reads it (examples/compressive_n500/Makefile)
        rc, out, _ = run(["/usr/bin/python3", os.path.join(src, "reaction.py"), h5, "-o",
                          h5[:-3] + "_reaction.csv", "--length", "0.01462", "--window", "1e-4",
                          "--check", os.path.join(src, "bounds_quick.json")])
        print("    reaction.py --check bounds_quick.json: exit", rc)
        print("\n".join("      " + ln for ln in out.strip().splitlines()))


def item_n500trace():
    """The default-law quick run again with a frame every 2e-5 s up to 27.07 ms (the same dt: it
    follows final_time, not the frames), and the depth of every grain node behind every other
    grain's deformed boundary segments (check_run.polygon_depth), frame by frame from 25.8 ms:
    how the deepest node got there and what the boundary it crossed was made of."""
    import h5py
    import numpy as np
    import check_run
    work = os.path.join(A.out, "n500")
    if not os.path.exists(os.path.join(work, "scene_quick_default.json")):
        item_n500()
    h5 = pack(os.path.join(work, "scene_quick_default.json"), "n500_fine",
              sets=["solver.output_interval=2e-5"])
    r = solve(h5, "--steps", "33100")
    print(f"n500 quick, default law, frames every 2e-5 s: exit {r['rc']}; {r['dt_line']}")
    with h5py.File(h5, "r") as f:
        m = check_run.Model(f)
        pn = f["particles/nodes"]
        T = pn["position/time"][()]
        grains = [b for b in range(m.nb) if m.kind[b] == 0 and not m.fixed[b]]
        worst = None
        from scipy.spatial import cKDTree
        r = 2.0 * float(m.h.max())
        for k in np.flatnonzero(T >= 0.0258):
            y, dmg = pn["position/value"][k], pn["damage/value"][k]
            dc = m.depth_with_cracks(dmg)  # nodes of damage > 0.1 count as boundary
            for b in grains:
                sl = m.body_nodes(b)
                tree = cKDTree(y[sl])
                oth = np.flatnonzero(m.body != b)
                near = tree.query_ball_point(y[oth], r)
                sel = [q for q, nb_ in enumerate(near) if nb_]
                if not sel:
                    continue
                # check_run's rule: the pair estimate max_j (D_j - |y_i - y_j|) over the nodes j
                # of b within reach (D_j: reference depth, crack faces counting as boundary),
                # capped by the depth behind b's deformed boundary segments
                est = np.array([max(dc[sl.start + j] - np.linalg.norm(y[oth[q]] - y[sl.start + j])
                                    for j in near[q]) for q in sel])
                nodes = oth[sel]
                d = np.minimum(est, check_run.polygon_depth(m.boundary_edges(b), y, y[nodes]))
                i = int(np.argmax(d))
                if worst is None or d[i] > worst[0]:
                    worst = (float(d[i]), float(T[k]), int(nodes[i]), int(m.body[nodes[i]]), b)
        dep, t, node, nb, b = worst
        print(f"    deepest: node {node} (body {nb}) {dep * 1e6:.0f} um behind body {b}'s deformed"
              f" boundary at t = {t * 1e3:.3f} ms (body {b}: h = {m.h[b] * 1e6:.0f} um)")
        e = m.boundary_edges(b)
        sl = m.body_nodes(b)
        for k in np.flatnonzero((T >= t - 4.2e-4) & (T <= t))[::2]:
            y, dmg = pn["position/value"][k], pn["damage/value"][k]
            d = check_run.polygon_depth(e, y, y[[node]])[0]
            A_, B_ = y[e[:, 0], :2], y[e[:, 1], :2]
            ev = B_ - A_
            sp = np.clip(np.sum((y[node, :2] - A_) * ev, 1) / np.sum(ev * ev, 1), 0, 1)
            j = int(np.argmin(np.linalg.norm(y[node, :2] - (A_ + sp[:, None] * ev), axis=1)))
            dist = np.linalg.norm(y[sl] - y[node], axis=1)
            nn = np.argsort(dist)[:3]
            print(f"    t = {T[k] * 1e3:.3f} ms: depth {d * 1e6:+6.0f} um, damage {dmg[node]:.2f};"
                  f" closest facet {e[j].tolist()} (vertex damage {dmg[e[j][0]]:.2f}, "
                  f"{dmg[e[j][1]]:.2f}); nearest nodes of body {b}: "
                  + ", ".join(f"{sl.start + q} at {dist[q] * 1e6:.0f} um (damage {dmg[sl.start + q]:.2f},"
                              f" reference depth {m.depth[sl.start + q] * 1e6:.0f} um)"
                              for q in nn))
    os.remove(h5)


# ------------------------------------------------------------------ item 5, 6

def item_plate():
    import first_contact
    for safety in (0.85, 0.425):
        h5 = pack(os.path.join(HERE, "plate_cube.json"), f"plate_cube_{safety}",
                  sets=[f"solver.dt_safety={safety}"])
        r = solve(h5)
        print(f"plate at 10 m/s onto a cube, dt_safety {safety}: exit {r['rc']}; {r['dt_line']} "
              f"{r['error']}")
        first_contact.main(h5)


def item_csg():
    h5 = pack(os.path.join(ROOT, "examples", "three_d_csg", "scene.json"), "three_d_csg")
    r = solve(h5, "--steps", "1", "-v")
    with open(h5 + ".log") as fh:
        lines = [ln for ln in fh if re.search(r"dt|limit|stab|contact.*bound|Lanczos", ln)]
    print("three_d_csg:", r["dt_line"])
    for ln in lines[:12]:
        print("   ", ln.rstrip())


ITEMS = {"box2d": item_box2d, "pour3d": item_pour3d, "press": item_press, "sphere": item_sphere, "disc": item_disc,
         "pair": item_pair, "shipped": item_shipped, "n500": item_n500, "n500trace": item_n500trace, "plate": item_plate,
         "csg": item_csg}


def main():
    global A
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "bin"))
    ap.add_argument("--out", default="/tmp/why26")
    ap.add_argument("items", nargs="*", default=list(ITEMS))
    A = ap.parse_args()
    A.bin = os.path.abspath(A.bin)
    os.makedirs(A.out, exist_ok=True)
    for it in A.items:
        ITEMS[it]()
        sys.stdout.flush()


if __name__ == "__main__":
    main()
