#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The surface contact law against the elastodynamic reference of issue 26 (item 2): contact
duration t_c and peak force F_max of an elastic disc (2D plane stress, nu = 1/3) or sphere (3D,
nu = 1/4) on a rigid wall, and of two equal ones head-on at +-v (the same problem by symmetry),
R = 1 mm, E = 32.4 MPa, rho = 1200, PMB, m = 3, no damping, at three speeds and three h.

  /usr/bin/python3 workflows/accuracy/hertz_surface.py [--build build] [--out DIR]
      [--dim 2] [--h 1e-4,5e-5] [--v 0.1,1,5] [--mesh grid,gmsh,rot17] [--pair | --meshed-wall]
      [--set key=value ...] [--settings JSON] [--json FILE]
  /usr/bin/python3 workflows/accuracy/hertz_surface.py --restitution 0.5,0.8,0.95,1
      [--kinds pair,unequal,wall] [--dim 2] [--h ...] [--json FILE]
  /usr/bin/python3 workflows/accuracy/hertz_surface.py --markdown FILE.json ...

Tables and the error's decomposition: SURFACE_LAW.md.

The reference values are the issue's finite-element figures (linear elastodynamics, graded
mesh, converged to 0.2 %). Disc on a wall: t_c from the wall force (observed every step: first
to last step with a nonzero force), F_max its largest value. Two discs: t_c from the contact
count (every step), F_max = m dv/dt of one disc's mean velocity between velocity frames written
every t_c / 100 (the difference quotient of a half sine at that interval is within 5e-5 of it).
--meshed-wall: the wall is a fixed grid slab (2D: 4 R x 4 h, top row of nodes 0.002 h below the
disc's lowest node), t_c and F_max as for two discs. Every case also reports the lateral speed:
the largest |x velocity| of a disc's centre of mass at the last frame over the impact speed (a
frictionless head-on impact has none; issue 26 item 4 asks < 1 %).
"""
import argparse
import json
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from accuracy import Runner  # noqa: E402

E_REF, RHO_REF, R_REF = 3.24e7, 1200.0, 1e-3
# v (m/s): (t_c s, F_max N/m in 2D, N in 3D)
REFERENCE = {
    2: {0.1: (56.35e-6, 22.15), 1.0: (46.53e-6, 259.1), 5.0: (40.46e-6, 1519.0)},
    3: {0.1: (129.8e-6, 0.01434), 1.0: (79.40e-6, 0.2372), 5.0: (55.32e-6, 1.762)},
}
ORIENT = math.radians(17)


def shape(dim, mesh):
    s = {"type": "circle" if dim == 2 else "sphere", "radius": R_REF,
         "mesh": "grid" if mesh in ("grid", "rot17") else "gmsh"}
    return s


def scene(dim, h, v, mesh, pair, lift, settings, wall="plane"):
    """lift: the gap between the lowest (pair: innermost) node and the wall (the mid-plane)."""
    tc = REFERENCE[dim][v][0]
    T = lift / v + 3 * tc
    nu = 1.0 / 3 if dim == 2 else 0.25
    mat = {"law": settings.get("law", "pmb"), "density": RHO_REF, "youngs_modulus": E_REF}
    if mat["law"] == "lps":
        mat["poisson_ratio"] = nu
    up = [0, 1, 0] if dim == 3 else [0, 1]
    part = {"shape": "s", "center": [0, R_REF + lift] + ([0] if dim == 3 else []),
            "material": "m", "velocity": [0, -v] + ([0] if dim == 3 else [])}
    if mesh == "rot17":
        part["orientation"] = ORIENT if dim == 2 else [ORIENT, 0, 0]
    contact = {"law": "surface", "restitution": 1.0}
    contact.update(settings.get("contact", {}))
    s = {"dimension": dim,
         "materials": {"m": mat},
         "discretization": {"mesh_size": h, "horizon_factor": settings.get("m", 3)},
         "shapes": {"s": shape(dim, mesh)},
         "particles": [part],
         "contact": contact,
         "solver": {"final_time": T, "output_interval": T, "fields": ["velocity"],
                    "observe_every": 1}}
    if pair:
        low = dict(part, center=[0, -R_REF - lift] + ([0] if dim == 3 else []),
                   velocity=[0, v] + ([0] if dim == 3 else []))
        if mesh == "rot17":  # the mirror image of the upper disc's mesh
            low["orientation"] = -ORIENT if dim == 2 else [-ORIENT, 0, 0]
        s["particles"].append(low)
        s["solver"]["output_interval"] = tc / 100
    elif wall == "meshed":
        if dim != 2:
            raise SystemExit("--meshed-wall: 2D only")
        s["shapes"]["slab"] = {"type": "rectangle",
                               "corners": [[-2 * R_REF, -4 * h], [2 * R_REF, 0]]}
        s["particles"].append({"shape": "slab", "center": [0, 0], "material": "m",
                               "fixed": True})
        s["solver"]["output_interval"] = tc / 100
    else:
        s["walls"] = [{"type": "plane", "point": [0] * dim, "normal": up}]
    return s


def lowest_gap(runner, tag, dim, h, mesh, sets, wall="plane"):
    """The lowest node's y of the packed disc with its centre at y = R, above the wall's surface
    (a meshed wall: its top row of nodes)."""
    import h5py
    sc = scene(dim, h, 1.0, mesh, False, 0.0, {}, wall)
    sc.pop("walls", None)  # (a rotated grid's lowest node may lie below y = 0 here)
    if wall == "meshed":  # the slab R lower, clear of the disc
        sc["particles"][1]["center"] = [0, -R_REF]
    h5, _, _ = runner.run(tag + "_pack", sc, sets=sets, solve=False)
    with h5py.File(h5, "r") as f:
        y = f["nodes/reference_position"][:, 1]
        body = f["nodes/body"][:]
    os.remove(h5)
    top = y[body == 1].max() + R_REF if wall == "meshed" else 0.0
    return y[body == 0].min() - top


def gap(dim, h):
    """The lowest node's start above the wall or mid-plane: 0.002 h; 0.02 h in 3D, where a
    facet of the other sphere (a chord) lies up to h^2 / (8 R) = 0.0125 h inside its sphere."""
    return (0.002 if dim == 2 else 0.02) * h


def measure(h5, dim, pair, v, wall="plane"):
    """t_c, F_max, node count and lateral speed / v."""
    import h5py
    import numpy as np
    with h5py.File(h5, "r") as f:
        n = len(f["nodes/volume"])
        t = f["observables/kinetic_energy/time"][:]
        vol, body = f["nodes/volume"][:], f["nodes/body"][:]
        vx = f["particles/nodes/velocity/value"][-1, :, 0]
        lateral = max(abs((vx * vol)[body == b].sum() / vol[body == b].sum())
                      for b in (range(2) if pair else [0])) / v
        if not pair and wall != "meshed":
            F = np.abs(f["observables/wall_force/value"][:, 0, 1])
            on = np.nonzero(F > 0)[0]
            peak = F.max()
        else:
            cc = f["observables/contact_count/value"][:]
            on = np.nonzero(cc.reshape(len(cc), -1).sum(axis=1) > 0)[0]
            vol = f["nodes/volume"][:]
            rho = f["nodes/density"][:] if "nodes/density" in f else RHO_REF * np.ones(n)
            body = f["nodes/body"][:]
            up = body == 0
            mass = (rho * vol)[up]
            vel = f["particles/nodes/velocity/value"][:, up, 1]
            tf = f["particles/nodes/velocity/time"][:]
            vm = (vel * mass).sum(axis=1) / mass.sum()
            peak = (np.abs(np.diff(vm)) / np.diff(tf)).max() * mass.sum()
    if len(on) == 0 or on[-1] + 1 >= len(t):
        raise RuntimeError(f"{h5}: the contact did not end within the run")
    return t[on[-1] + 1] - t[on[0]], peak, n, lateral


def run_case(runner, dim, h, v, mesh, pair, settings, sets, wall="plane"):
    kind = "pair" if pair else ("mwall" if wall == "meshed" else "wall")
    tag = f"hs{dim}_{mesh}_{kind}_{h:.3g}_{v:g}"
    # The lowest node gap(dim, h) above the wall (the mid-plane): the centre at R + lift.
    # (A meshed wall 0.02 h below: pd-pack checks its nodes against the disc's circle, up to
    # h^2 / (8 R) = 0.0125 h below the polygon.)
    lift = (0.02 * h if wall == "meshed" else gap(dim, h)) - lowest_gap(runner, tag, dim, h,
                                                                        mesh, sets, wall)
    h5, cp, cs = runner.run(tag, scene(dim, h, v, mesh, pair, lift, settings, wall), sets=sets)
    tc, fmax, n, lateral = measure(h5, dim, pair, v, wall)
    os.remove(h5)
    rt, rf = REFERENCE[dim][v]
    r = {"dim": dim, "h": h, "v": v, "mesh": mesh, "pair": pair, "nodes": int(n),
         "tc": tc, "fmax": fmax, "tc_err": tc / rt - 1, "f_err": fmax / rf - 1,
         "lateral": lateral, "cpu": cp + cs}
    if wall == "meshed":
        r["wall"] = "meshed"
    return r


def restitution_case(runner, dim, h, kind, eps, v=1.0, mesh="gmsh", sets=()):
    """Rebound / impact speed (of the centres of mass, from the first and last velocity frame)
    with contact restitution eps: kind "wall" (disc on a wall), "pair" (two equal discs at
    +-v), "unequal" (R and R / 2 at +-v)."""
    import h5py
    tag = f"eps{dim}_{mesh}_{kind}_{h:.3g}_{eps:g}"
    lift = gap(dim, h) - lowest_gap(runner, tag, dim, h, mesh, sets)
    sc = scene(dim, h, v, mesh, kind != "wall", lift, {"contact": {"restitution": eps}})
    tc = REFERENCE[dim][v][0]
    sc["solver"]["output_interval"] = sc["solver"]["final_time"] / 4
    if kind == "unequal":
        sc["shapes"]["s2"] = dict(shape(dim, mesh), radius=0.5 * R_REF)
        low = sc["particles"][1]
        low["shape"] = "s2"
        low["center"] = [0, -0.5 * R_REF - 0.05 * h] + ([0] if dim == 3 else [])
    h5, _, _ = runner.run(tag, sc, sets=sets)
    with h5py.File(h5, "r") as f:
        vol, body = f["nodes/volume"][:], f["nodes/body"][:]
        u = f["particles/nodes/velocity/value"]
        first, last = u[0, :, 1], u[-1, :, 1]
        cc = f["observables/contact_count/value"][:]
    os.remove(h5)
    if cc.reshape(len(cc), -1)[-1].sum() != 0:
        raise RuntimeError(f"{tag}: still in contact at the end ({tc})")
    mean = [lambda w, b=b: (w * vol)[body == b].sum() / vol[body == b].sum()
            for b in range(int(body.max()) + 1)]
    if kind == "wall":
        return mean[0](last) / -mean[0](first)
    return (mean[0](last) - mean[1](last)) / -(mean[0](first) - mean[1](first))


def markdown(files):
    """One table per (dimension, mesh, wall or pair) of the --json files: t_c and F_max errors
    against the reference, per speed (rows) and h (columns)."""
    rows = []
    for fn in files:
        with open(fn) as fh:
            rows += [r for r in json.load(fh) if "tc" in r]
    out = []
    def key_of(r):
        return r["dim"], r["mesh"], r["pair"], r.get("wall", "plane")
    for key in sorted({key_of(r) for r in rows}):
        sel = [r for r in rows if key_of(r) == key]
        body = "disc" if key[0] == 2 else "sphere"
        hs = sorted({r["h"] for r in sel}, reverse=True)
        out += ["", f"{key[0]}D, {key[1]}, " + (f"two equal {body}s" if key[2] else f"a {body} on a {key[3]} wall")
                + ": "
                "t_c / F_max error (%)", "",
                "| v (m/s) | " + " | ".join(f"h = {h * 1e3:.3g} mm" for h in hs) + " |",
                "|---" * (len(hs) + 1) + "|"]
        for v in sorted({r["v"] for r in sel}):
            cells = []
            for h in hs:
                r = [x for x in sel if x["v"] == v and x["h"] == h]
                cells.append(f"{100 * r[0]['tc_err']:+.1f} / {100 * r[0]['f_err']:+.1f}"
                             if r else "-")
            out.append(f"| {v:g} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=os.path.join(os.path.dirname(os.path.dirname(HERE)),
                                                    "build"))
    ap.add_argument("--out", default=None)
    ap.add_argument("--dim", type=int, default=2)
    ap.add_argument("--h", default="1e-4,5e-5,2.5e-5")
    ap.add_argument("--v", default="0.1,1,5")
    ap.add_argument("--mesh", default="grid")
    ap.add_argument("--pair", action="store_true")
    ap.add_argument("--meshed-wall", action="store_true",
                    help="a fixed grid slab instead of the rigid plane (2D)")
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--settings", default="{}", help="JSON: contact (dict), law, m")
    ap.add_argument("--json", default=None)
    ap.add_argument("--restitution", default=None,
                    help="comma-separated eps: restitution of --kinds instead of t_c, F_max")
    ap.add_argument("--kinds", default="pair,unequal,wall")
    ap.add_argument("--markdown", nargs="+", default=None, help="tables of these --json files")
    a = ap.parse_args()
    if a.markdown:
        print(markdown(a.markdown))
        return
    runner = Runner(a.build, a.out or os.path.join(a.build, "accuracy", "hertz_surface"))
    settings = json.loads(a.settings)
    rows = []
    if a.restitution:
        for kind in a.kinds.split(","):
            for eps in [float(x) for x in a.restitution.split(",")]:
                for h in [float(x) for x in a.h.split(",")]:
                    e = restitution_case(runner, a.dim, h, kind, eps, sets=a.set)
                    rows.append({"dim": a.dim, "kind": kind, "eps": eps, "h": h,
                                 "measured": e, "err": e / eps - 1})
                    print(f"{a.dim}D {kind:7s} eps={eps:g} h={h * 1e3:.3g}mm: {e:.4f} "
                          f"({100 * (e / eps - 1):+.2f} %)", flush=True)
        if a.json:
            with open(a.json, "w") as fh:
                json.dump(rows, fh, indent=1)
        return
    for mesh in a.mesh.split(","):
        for v in [float(x) for x in a.v.split(",")]:
            for h in [float(x) for x in a.h.split(",")]:
                kind = "pair" if a.pair else ("mwall" if a.meshed_wall else "wall")
                try:
                    r = run_case(runner, a.dim, h, v, mesh, a.pair, settings, a.set,
                                 "meshed" if a.meshed_wall else "plane")
                except subprocess.CalledProcessError as e:  # a guard stopped the run
                    print(f"{a.dim}D {mesh:5s} {kind} v={v:g} h={h * 1e3:.3g}mm: failed "
                          f"({e})", flush=True)
                    continue
                rows.append(r)
                print(f"{a.dim}D {mesh:5s} {kind} v={v:g} "
                      f"h={h * 1e3:.3g}mm n={r['nodes']}: t_c {1e6 * r['tc']:.2f} us "
                      f"({100 * r['tc_err']:+.1f} %), F_max {r['fmax']:.4g} "
                      f"({100 * r['f_err']:+.1f} %), lateral {100 * r['lateral']:.3f} %, "
                      f"{r['cpu']:.1f} CPU s", flush=True)
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(rows, fh, indent=1)


if __name__ == "__main__":
    main()
