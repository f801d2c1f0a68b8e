#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Kalthoff-Winkler 2D from Python, in process (issue 30): scene_2d.json packed, the time loop
driven step by step from Python, each node's crack arrival time recorded as the run advances
(the first time its damage exceeds 0.3), then each crack's path from its notch tip, its angle
to the notch axis and the times its tip reaches 10, 20, 30 ... mm: what PeriDEM's
Kalthoff-Winkler script records, here read from the numpy state between steps.

Two records: after every --every steps (interpolated linearly between two records), and at the
frames only with pd-post's interpolation, which equals pd-post's crack_nodes.csv (the path and
the angle are pd-post's --crack-origin/--crack-direction/--crack-axis 0,1 algorithm, in numpy).

    PYTHONPATH=build/python /usr/bin/python3 examples/kalthoff_winkler/problem.py \\
        [--quick] [--mesh-size H] [--final-time T] [--out DIR] [--json FILE]

--quick: h = 2 mm, T = 100 us (CI: a few seconds); the default is the scene (h = 1 mm, 170 us).
"""
import argparse
import json
import pathlib
import time

import h5py
import numpy as np

import pdgrain

HERE = pathlib.Path(__file__).resolve().parent
THRESHOLD = 0.3  # pd-post's default --crack-threshold
FIT_RADIUS = 0.04  # the Makefile's --crack-fit-radius: the initiation direction
CRACKS = {"right": ((0.025, 0.0), (0.94, 0.34)), "left": ((-0.025, 0.0), (-0.94, 0.34))}


class Arrival:
    """Per node, the first time damage > threshold, linear in time between two records (as
    pd-post's ArrivalTracker)."""

    def __init__(self, n):
        self.t = np.full(n, np.nan)
        self.prev = np.zeros(n)
        self.t_prev = None

    def add(self, t, phi):
        new = np.isnan(self.t) & (phi > THRESHOLD)
        if self.t_prev is None:
            self.t[new] = t
        else:
            rising = new & (phi > self.prev)
            frac = (THRESHOLD - self.prev[rising]) / (phi[rising] - self.prev[rising])
            self.t[rising] = self.t_prev + frac * (t - self.t_prev)
            self.t[new & ~rising] = t
        self.prev = phi.copy()
        self.t_prev = t


def tls_direction(r, d):
    """Unit direction of the total-least-squares line through the origin of the points r
    (m x 2), oriented along d."""
    sxx, syy, sxy = (r[:, 0] ** 2).sum(), (r[:, 1] ** 2).sum(), (r[:, 0] * r[:, 1]).sum()
    a = 0.5 * np.arctan2(2 * sxy, sxx - syy)
    u = np.array([np.cos(a), np.sin(a)])
    return -u if u @ d < 0 else u


def crack_path(x0, arrival, origin, direction, link):
    """pd-post's path: the arrived nodes ahead of the origin, linked to it through arrived
    nodes at most `link` apart; the angles to the notch axis (+y), the projections, the tip."""
    o, d = np.asarray(origin), np.asarray(direction) / np.hypot(*direction)
    r = x0[:, :2] - o
    sel = np.flatnonzero(~np.isnan(arrival) & (r @ d > 0))
    linked = np.hypot(*r[sel].T) <= link
    queue = list(np.flatnonzero(linked))
    while queue:
        near = np.hypot(*(r[sel] - r[sel[queue.pop()]]).T) <= link
        grow = np.flatnonzero(near & ~linked)
        linked[grow] = True
        queue.extend(grow)
    path = sel[linked]
    if len(path) < 2:
        return None
    u = tls_direction(r[path], d)
    near = path[np.hypot(*r[path].T) <= FIT_RADIUS]
    v = tls_direction(r[near], d) if len(near) >= 2 else u
    along = r[path] @ u
    t = arrival[path]
    first = np.lexsort((along, t))[0]
    far = np.lexsort((t, -along))[0]
    tip = {"%g" % (mm): float(t[along >= mm * 1e-3].min())
           for mm in range(10, 110, 10) if (along >= mm * 1e-3).any()}
    return {"nodes": path.tolist(), "arrival": t.tolist(),
            "angle_to_axis_deg": float(np.degrees(np.arccos(np.clip(v[1], -1, 1)))),
            "path_angle_to_axis_deg": float(np.degrees(np.arccos(np.clip(u[1], -1, 1)))),
            "length": float(along[far]), "t_start": float(t[first]), "t_end": float(t[far]),
            "mean_speed": float((along[far] - along[first]) / (t[far] - t[first]))
            if t[far] > t[first] else None,
            "tip_arrival": tip}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="h = 2 mm, T = 100 us (CI)")
    ap.add_argument("--mesh-size", type=float, help="m (default: the scene's 1 mm)")
    ap.add_argument("--final-time", type=float, help="s (default: the scene's 170 us)")
    ap.add_argument("--every", type=int, default=1, help="steps between damage records")
    ap.add_argument("--out", default="out_kalthoff_winkler", help="output folder")
    ap.add_argument("--json", help="write the records here (default OUT/arrivals.json)")
    a = ap.parse_args()
    h = a.mesh_size or (2e-3 if a.quick else None)
    final = a.final_time or (1.0e-4 if a.quick else None)
    sets = (["discretization.mesh_size=%r" % h] if h else []) + \
        (["solver.final_time=%r" % final] if final else [])
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    f = pdgrain.pack(HERE / "scene_2d.json", out / "kw2d.h5", sets=sets, overwrite=True)
    with h5py.File(f, "r") as hf:
        link = float(hf["bodies/horizon"][()].max())
    cpu = time.process_time()
    with pdgrain.Simulation(f, threads=1, overwrite=True) as sim:
        every, frames = Arrival(sim.num_nodes), Arrival(sim.num_nodes)
        x0 = np.array(sim.reference_positions)
        phi = sim.damage
        every.add(sim.time, phi)
        frames.add(sim.time, phi)
        print("%d nodes, dt = %.3e s, %d steps, a frame every %d" % (
            sim.num_nodes, sim.dt, sim.last_step, sim.output_every))
        while not sim.finished:
            sim.step(min(a.every, sim.last_step - sim.step_index))
            phi = sim.damage  # a copy, computed now
            every.add(sim.time, phi)
            if sim.step_index % sim.output_every == 0 or sim.step_index == sim.total_steps:
                frames.add(sim.time, phi)
        steps, dt = sim.step_index, sim.dt
    cpu = time.process_time() - cpu
    rec = {"mesh_size": h, "final_time": final, "dt": dt, "steps": steps, "cpu_seconds": cpu,
           "every": a.every, "file": str(f), "cracks": {}}
    for name, (origin, direction) in CRACKS.items():
        rec["cracks"][name] = {
            "steps": crack_path(x0, every.t, origin, direction, link),
            "frames": crack_path(x0, frames.t, origin, direction, link)}
        c = rec["cracks"][name]["steps"]
        if c is None:
            print("%s crack: none" % name)
            continue
        print("%s crack: %d nodes, %.2f deg to the notch axis (whole path %.2f), %.1f mm, "
              "t = %.1f to %.1f us, mean speed %.0f m/s" % (
                  name, len(c["nodes"]), c["angle_to_axis_deg"], c["path_angle_to_axis_deg"],
                  c["length"] * 1e3, c["t_start"] * 1e6, c["t_end"] * 1e6, c["mean_speed"] or 0))
        print("  tip arrival: " + ", ".join("%s mm %.1f us" % (k, v * 1e6)
                                            for k, v in c["tip_arrival"].items()))
    print("%d steps in %.1f s of CPU (damage read after every %d)" % (steps, cpu, a.every))
    path = pathlib.Path(a.json) if a.json else out / "arrivals.json"
    path.write_text(json.dumps(rec, indent=1))


if __name__ == "__main__":
    main()
