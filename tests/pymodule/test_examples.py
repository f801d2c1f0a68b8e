# SPDX-License-Identifier: MIT
"""Issue 30: the examples' problem.py against the C++ pipeline (JSON + pd-pack + pd-solve +
pd-post), and the loading conditions written from Python.
- kalthoff_winkler (h = 2 mm, 100 us): the run driven step by step from Python leaves the file
  pd-solve writes, bit for bit; the arrival times recorded at the frames equal pd-post's
  crack_nodes.csv node by node, the step-resolved ones lie within a frame interval of them,
  and both cracks' path and angle are pd-post's crack_summary.csv.
- compressive_n500 quick, the first 15 ms (settling and the plate's entry at 14 ms): the file
  equals pd-solve --no-penetration-check's.
- every other example's problem.py, the first 30 steps: the file equals pd-solve --steps 30's.
- conditions: an amplitude written before the first step equals the packed value (bitwise);
  hold() keeps the displacement; a time function written mid-run applies from the next step."""
import csv
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import BIN, SRC, tool
from test_module import assert_same

KW = SRC / "examples/kalthoff_winkler"
KW_SETS = ["discretization.mesh_size=0.002", "solver.final_time=0.0001"]
CRACKS = {"right": ("0.025,0", "0.94,0.34"), "left": ("-0.025,0", "-0.94,0.34")}


def python(script, *args, timeout=600):
    env = dict(os.environ, PD_BIN_DIR=str(BIN))
    r = subprocess.run([sys.executable, str(script), *map(str, args)], capture_output=True,
                       text=True, env=env, timeout=timeout)
    assert r.returncode == 0, r.stdout + r.stderr
    return r.stdout


def cli(scene, h5, sets, *solve_args):
    tool("pd-pack", scene, "-o", h5, "-q", *[a for s in sets for a in ("--set", s)])
    tool("pd-solve", h5, "-q", *solve_args)
    return h5


def read_csv(path):
    with open(path) as f:
        return [r for r in csv.DictReader(line for line in f if not line.startswith("#"))]


def test_kalthoff_winkler_arrivals_match_pd_post(tmp_path):
    out = python(KW / "problem.py", "--quick", "--out", tmp_path / "py")
    rec = json.loads((tmp_path / "py/arrivals.json").read_text())
    ref = cli(KW / "scene_2d.json", tmp_path / "cli.h5", KW_SETS)
    assert_same(ref, rec["file"])  # reading the damage between steps changes nothing
    frame = 2e-6  # the scene's output_interval
    for name, (origin, direction) in CRACKS.items():
        post = tmp_path / ("post_" + name)
        tool("pd-post", ref, "-o", post, "-q", "--no-vtu", "--no-xdmf", "--no-grains",
             "--no-walls", "--crack-axis", "0,1", "--crack-fit-radius", "0.04", "--crack-origin",
             origin, "--crack-direction", direction)
        nodes = {int(r["node"]): float(r["arrival_time"])
                 for r in read_csv(post / "crack_nodes.csv") if r["on_path"] == "1"}
        summary = read_csv(post / "crack_summary.csv")[0]
        at_frames, at_steps = rec["cracks"][name]["frames"], rec["cracks"][name]["steps"]
        # The frames record is pd-post's, node by node (CSV: 10 significant digits).
        assert len(nodes) > 20 and sorted(at_frames["nodes"]) == sorted(nodes)
        got = dict(zip(at_frames["nodes"], at_frames["arrival"]))
        assert np.allclose([got[i] for i in nodes], list(nodes.values()), rtol=1e-9, atol=0)
        for key in ("angle_to_axis_deg", "path_angle_to_axis_deg", "length", "t_start", "t_end",
                    "mean_speed"):
            assert at_frames[key] == pytest.approx(float(summary[key]), rel=1e-8), key
        # The step-resolved record: every path node pd-post found, within a frame of its time.
        steps = dict(zip(at_steps["nodes"], at_steps["arrival"]))
        assert set(nodes) <= set(steps)
        diff = np.array([steps[i] - t for i, t in nodes.items()])
        assert np.abs(diff).max() <= frame * (1 + 1e-9)
        assert at_steps["angle_to_axis_deg"] == pytest.approx(at_frames["angle_to_axis_deg"],
                                                              abs=1.0)
        assert float(at_steps["tip_arrival"]["10"]) < float(at_steps["t_end"])
    # The two cracks are mirror images (the grid and the load are symmetric).
    r, left = rec["cracks"]["right"]["steps"], rec["cracks"]["left"]["steps"]
    assert r["angle_to_axis_deg"] == pytest.approx(left["angle_to_axis_deg"], abs=1e-6)
    assert "tip arrival: 10 mm" in out


def test_compressive_n500_quick_parity(tmp_path):
    scene = SRC / "examples/compressive_n500/scene_quick.json"
    python(scene.with_name("problem.py"), "--final-time", 0.015, "--out", tmp_path / "py")
    ref = cli(scene, tmp_path / "cli.h5", ["solver.final_time=0.015"], "--no-penetration-check")
    assert_same(ref, tmp_path / "py/quick.h5")
    curve = json.loads((tmp_path / "py/curve.json").read_text())
    rows = np.array(curve["rows"])
    # The plate entered at 14 ms and touched nothing yet (0.82 mm above the settled pack).
    assert rows[-1, 0] == pytest.approx(0.015) and rows[-1, 1] == pytest.approx(3e-4)
    assert np.all(rows[:, 2] == 0)


def test_ellipse_on_tip_quick(tmp_path):
    """Both rings to 1 ms (make quick): the files equal pd-solve's; the records read between
    steps (measured: first broken bond 0.379 / 0.347 ms, rebound 0.639 / 0.644 ms, LPS / PMB)
    and the broken bonds read at the end agree with the file's observables."""
    folder = SRC / "examples/ellipse_on_tip"
    python(folder / "problem.py", "--quick", "--out", tmp_path / "py", "--json",
           tmp_path / "r.json")
    rec = json.loads((tmp_path / "r.json").read_text())
    import h5py
    for s in ("lps", "pmb"):
        ref = cli(folder / ("scene_%s.json" % s), tmp_path / ("cli_%s.h5" % s),
                  ["solver.final_time=1e-3"])
        assert_same(ref, rec[s]["file"])
        r = rec[s]
        assert r["exit_code"] == 0 and r["time"] == pytest.approx(1e-3)
        assert 2e-4 < r["first_break"] < r["rebound"] < 9e-4
        assert r["ring_vy"] > 1.0  # going up after the bounce (from -4 m/s)
        with h5py.File(ref, "r") as h:
            assert r["broken_bonds"] == h["observables/broken_bonds/value"][-1] > 100


GENERIC = sorted(p.parent.name for p in SRC.glob("examples/*/problem.py")
                 if "pdgrain.example" in p.read_text())


@pytest.mark.parametrize("example", GENERIC)
def test_example_problem_py_equals_the_pipeline(tmp_path, example):
    """problem.py --steps 30 (packed and stepped in process) against pd-pack + pd-solve --steps
    30 on the same scene: frames and observables bit for bit."""
    folder = SRC / "examples" / example
    out = python(folder / "problem.py", "--steps", 30, "--no-post", "--out", tmp_path / "py")
    assert "30 steps in" in out
    force = ["--force-dt"] if "force_dt=True" in (folder / "problem.py").read_text() else []
    ref = cli(folder / "scene.json", tmp_path / "cli.h5", [], "--steps", "30", *force)
    assert_same(ref, tmp_path / "py" / (example + ".h5"))


@pytest.fixture()
def kw_file(pdgrain, tmp_path):
    return pdgrain.pack(KW / "scene_2d.json", tmp_path / "kw.h5",
                        sets=["discretization.mesh_size=0.004", "solver.final_time=2e-5"])


def frames(path):
    """(time, {field: values}) of /particles/nodes (h5py)."""
    import h5py
    with h5py.File(path, "r") as h:
        g = h["particles/nodes"]
        return g["position/time"][()], {k: g[k]["value"][()] for k in g if "value" in g[k]}


def test_condition_written_before_the_first_step_runs_as_the_packed_value(pdgrain, tmp_path,
                                                                          kw_file):
    """Impact speed 16 -> 8 m/s written at t = 0 (after the t = 0 frame): every later frame
    equals the run of the scene packed with 8 m/s bit for bit; the kinetic energy taken out is
    counted as external work, so the energy balance still closes."""
    with pdgrain.Simulation(kw_file, threads=1) as sim:
        c = sim.condition("impact")
        assert (c.kind, c.components, c.time_function, c.amplitude) == (
            "displacement", "y", "linear", 16.0)
        ke0 = sim.observe()["kinetic_energy"]
        c.amplitude = 8.0
        assert np.all(sim.velocities[c.nodes, 1] == 8.0)  # applied at once
        assert sim.observe()["kinetic_energy"] == pytest.approx(ke0 / 4, rel=1e-12)
        sim.run()
    ref = cli(KW / "scene_2d.json", tmp_path / "ref.h5",
              ["discretization.mesh_size=0.004", "solver.final_time=2e-5",
               "loading.conditions[0].value=8.0"])
    (t, a), (tr, b) = frames(kw_file), frames(ref)
    assert np.array_equal(t, tr) and len(t) > 3
    for k in b:
        assert np.array_equal(a[k][1:], b[k][1:]), k
    obs, ref_obs = kw_file.observables(), pdgrain.File(ref).observables()
    ke, ref_ke = obs["kinetic_energy"], ref_obs["kinetic_energy"]
    assert ke[0] == ke0 and ref_ke[0] == pytest.approx(ke0 / 4, rel=1e-12)  # t = 0: 16 m/s
    assert np.array_equal(ke[1:], ref_ke[1:])
    shift = obs["external_work"][1:] - ref_obs["external_work"][1:]
    assert np.allclose(shift, -0.75 * ke0, rtol=1e-9, atol=0)  # what the write took out


def balance(obs):
    """The energy balance per observable row: the change since t = 0 of KE + elastic + contact
    + fracture + dissipated, less the external work, over the energy in play E(0) + |W|."""
    e = sum(obs[k] for k in ("kinetic_energy", "elastic_energy", "contact_energy",
                             "fracture_energy", "damping_dissipation", "friction_dissipation",
                             "viscous_dissipation"))
    w = obs["external_work"]
    return (e - e[0] - w) / (e[0] + np.abs(w))


def test_condition_hold_keeps_the_value_and_the_energy_balance(pdgrain, kw_file):
    with pdgrain.Simulation(kw_file, threads=1) as sim:
        c = sim.condition("impact")
        nodes, u, v = c.nodes, sim.displacements, sim.velocities
        assert len(nodes) > 0 and not nodes.flags.writeable
        sim.step(5)
        assert np.array_equal(u[nodes, 1], np.full(len(nodes), 16.0 * sim.time))
        t_hold = sim.time
        c.hold()  # constant from now on, at the value of t_hold: no jump, v = 0 at once
        assert (c.time_function, c.amplitude) == ("constant", 16.0 * t_hold)
        assert np.all(v[nodes, 1] == 0)
        sim.run()  # the energy guard (5 %) runs at every observation
        assert sim.step_index == sim.last_step
        assert np.array_equal(u[nodes, 1], np.full(len(nodes), 16.0 * t_hold))
        assert np.all(v[nodes, 1] == 0)
        assert sim.close() == 0
    drift = balance(kw_file.observables())
    print("hold(): energy balance drift at the end %.3g %%" % (100 * drift[-1]))
    assert abs(drift[-1]) < 0.02  # measured 1.2 % (0.17 % without hold(), h = 4 mm)


def test_condition_rules_and_a_jump(pdgrain, kw_file):
    # A jump in value is not counted in the balance (stated): the guard is off for this run.
    with pdgrain.Simulation(kw_file, threads=1, energy_tolerance=1e9) as sim:
        c = sim.condition("impact")
        nodes, u, v = c.nodes, sim.displacements, sim.velocities
        sim.step(5)
        c.time_function, c.amplitude = "linear", 2.0  # the value the new settings give now
        assert np.array_equal(u[nodes, 1], np.full(len(nodes), 2.0 * sim.time))
        sim.step(1)
        assert np.array_equal(u[nodes, 1], np.full(len(nodes), 2.0 * sim.time))
        assert np.all(v[nodes, 1] == 2.0)
        c.time_parameters = (1.0, 2.0, 3.0)
        c.space_parameter = 1.0
        assert c.time_parameters == [1.0, 2.0, 3.0] and c.value(2.0) == 4.0
        with pytest.raises(pdgrain.InputError, match="rotation"):
            c.time_function = "rotation"
        with pytest.raises(pdgrain.InputError, match="force conditions only"):
            c.time_function = "linear_step"
        with pytest.raises(pdgrain.InputError, match="finite"):
            c.amplitude = float("nan")
        with pytest.raises(KeyError):
            sim.condition("no such")
        assert c.amplitude == 2.0 and c.time_function == "linear"
        assert "impact" in repr(c)
