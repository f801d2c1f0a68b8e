# SPDX-License-Identifier: MIT
"""Issue 30: `import pdgrain` runs the solver in process. Parity: the frames and observables of a
scene packed and run from Python equal bitwise those of pd-pack + pd-solve (provenance aside);
the numpy views are views; a Python-driven run stopped early continues with pd-solve --restart
to the same file as an uninterrupted run."""
import h5py
import numpy as np
import pytest

from conftest import BIN, SRC, tool

# (scene, overrides): short runs of three checked examples (ellipse_on_tip: a fixed meshed body,
# the tip, and a PMB grain that breaks in the full run).
CASES = {
    "ellipse_on_tip": (SRC / "examples/ellipse_on_tip/scene_pmb.json",
                       ["solver.final_time=2e-4", "solver.output_interval=5e-5"]),
    "two_discs": (SRC / "examples/two_discs/scene.json", ["solver.final_time=1.2e-4"]),
    "two_discs_wall": (SRC / "examples/two_discs_wall/scene_rigid.json",
                       ["solver.final_time=1.0e-4", "solver.output_interval=1e-5"]),
}


def results(path):
    """Every dataset of /particles and /observables: name -> array."""
    out = {}
    with h5py.File(path, "r") as h:
        for root in ("particles", "observables"):
            h[root].visititems(lambda n, d: out.__setitem__(root + "/" + n, d[()])
                               if isinstance(d, h5py.Dataset) else None)
    return out


def assert_same(a, b):
    ra, rb = results(a), results(b)
    assert sorted(ra) == sorted(rb)
    for k in ra:
        assert ra[k].dtype == rb[k].dtype and ra[k].shape == rb[k].shape, k
        assert np.array_equal(ra[k], rb[k]), "%s differs" % k


def cli_run(tmp_path, name):
    scene, sets = CASES[name]
    h5 = tmp_path / ("cli_%s.h5" % name)
    tool("pd-pack", scene, "-o", h5, "-q", *[a for s in sets for a in ("--set", s)])
    tool("pd-solve", h5, "-q")
    return h5


@pytest.mark.parametrize("name", sorted(CASES))
def test_parity_with_the_tools(pdgrain, tmp_path, name):
    scene, sets = CASES[name]
    f = pdgrain.pack(scene, tmp_path / ("py_%s.h5" % name), sets=sets)
    with pdgrain.Simulation(f, threads=1) as sim:
        assert sim.step_index == 0 and sim.time == 0
        while not sim.finished:
            sim.step(7)  # chunks that do not divide the frame interval
        assert sim.step_index == sim.last_step
    assert_same(cli_run(tmp_path, name), f)


def test_scene_builder_packs_the_json_scene(pdgrain, tmp_path):
    a = pdgrain.pack(pdgrain.scene.two_discs().data, tmp_path / "dict.h5")
    b = pdgrain.pack(SRC / "examples/two_discs/scene.json", tmp_path / "json.h5")
    with h5py.File(a, "r") as ha, h5py.File(b, "r") as hb:
        assert np.array_equal(ha["nodes/reference_position"][()], hb["nodes/reference_position"][()])


def test_views_follow_the_run_and_velocities_are_writable(pdgrain, tmp_path):
    scene, sets = CASES["two_discs"]
    f = pdgrain.pack(scene, tmp_path / "views.h5", sets=sets)
    sim = pdgrain.Simulation(f, threads=1)
    v, x, body = sim.velocities, sim.positions, sim.body
    assert v.shape == (sim.num_nodes, 3) and v.base is not None
    assert np.shares_memory(v, sim.velocities)  # the same memory, not a copy
    assert not x.flags.writeable and v.flags.writeable
    assert sorted(set(body.tolist())) == [0, 1]
    x0 = x.copy()
    sim.step(100)
    assert sim.step_index == 100 and sim.time == pytest.approx(100 * sim.dt)
    assert not np.array_equal(x, x0)  # the view shows the new positions
    assert np.allclose(x, sim.reference_positions + sim.displacements)
    # A write: disc 1 stopped; the next step starts from it.
    v[body == 1] = 0.0
    sim.step(1)
    assert np.abs(v[body == 1, 0]).max() < 0.05
    assert sim.close() == 0
    with pytest.raises(RuntimeError):
        sim.positions


def test_break_bonds(pdgrain, tmp_path):
    scene, sets = CASES["two_discs"]
    f = pdgrain.pack(scene, tmp_path / "cut.h5", sets=sets + ['solver.fields=["damage"]'])
    with pdgrain.Simulation(f, threads=1) as sim:
        assert sim.damage.max() == 0
        c = -1.15e-3  # disc 0's centre: a vertical cut through it
        pairs = sim.break_bonds(segment=([c, -2e-3], [c, 2e-3]))
        assert pairs > 0
        alive = sim.bond_alive
        assert (alive == 0).sum() == 2 * pairs  # both ends
        d = sim.damage
        assert d[sim.body == 0].max() > 0.2 and d[sim.body == 1].max() == 0
        # A predicate: the bonds of disc 1 right of its centre line.
        more = sim.break_bonds(lambda xi, xj: (xi[:, 0] > 1.15e-3) != (xj[:, 0] > 1.15e-3))
        assert more > 0 and (sim.bond_alive == 0).sum() == 2 * (pairs + more)
        sim.run()
    with h5py.File(f, "r") as h:
        assert h["particles/nodes/damage/value"][-1].max() > 0.2


def test_python_run_continues_with_pd_solve_restart(pdgrain, tmp_path):
    scene, sets = CASES["two_discs"]
    f = pdgrain.pack(scene, tmp_path / "restart.h5", sets=sets)
    with pdgrain.Simulation(f, threads=1) as sim:
        sim.run(until=0.5 * 1.2e-4)
        stopped = sim.step_index
    assert 0 < stopped
    tool("pd-solve", f, "--restart", "-q")
    # The reference: the same scene through the tools in one go (checkpoints aside).
    ref = tmp_path / "ref.h5"
    tool("pd-pack", scene, "-o", ref, "-q", *[a for s in sets for a in ("--set", s)])
    tool("pd-solve", ref, "-q")
    assert_same(ref, f)
    with h5py.File(f, "r") as h:
        runs = sorted(h["provenance"])
    assert any(k.endswith("_pdgrain_python") for k in runs) and runs[-1].endswith("_pd_solve")


def test_errors_are_python_exceptions(pdgrain, tmp_path):
    with pytest.raises(pdgrain.InputError):
        pdgrain.pack({"title": "no particles", "dimension": 2}, tmp_path / "bad.h5")
    scene, sets = CASES["two_discs"]
    f = pdgrain.pack(scene, tmp_path / "twice.h5", sets=sets)
    pdgrain.Simulation(f).close()
    with pytest.raises(pdgrain.InputError, match="--restart"):
        pdgrain.Simulation(f)  # results in the file: restart or overwrite


@pytest.mark.parametrize("example", ["two_discs", "two_discs_wall"])
def test_example_problem_py(pdgrain, tmp_path, example):
    import os
    import subprocess
    import sys
    import re
    r = subprocess.run([sys.executable, str(SRC / "examples" / example / "problem.py"), "--quick",
                        "--out", str(tmp_path / example)], capture_output=True, text=True,
                       env=dict(os.environ, PD_BIN_DIR=str(BIN)))
    assert r.returncode == 0, r.stdout + r.stderr
    if example == "two_discs":
        # the views followed the run: the discs approach at 0.5 m/s, then slow in contact
        vx = [float(v) for v in re.findall(r"left ([+-][0-9.]+)", r.stdout)]
        assert vx[0] == pytest.approx(0.5, abs=1e-3) and vx[-1] < 0.4
        assert int(re.search(r"left disc: ([0-9]+) bonds", r.stdout).group(1)) > 100
        assert (tmp_path / example / "post" / "two_discs.pvd").exists()
    else:  # both discs bounce on the floor within the first ms
        assert len(re.findall(r"bounces at t = [0-9.]+e-0[34] s", r.stdout)) == 2


def test_mpi_two_ranks_equal_pd_solve_under_mpirun(pdgrain, tmp_path):
    """mpirun -np 2 python3 script.py: each rank steps its rows; the file equals pd-solve's under
    mpirun -np 2 bitwise (the frames also equal one rank's; the reduced energies follow the
    rank count)."""
    import os
    import shutil
    import subprocess
    import sys
    if not shutil.which("mpirun"):
        pytest.skip("no mpirun")
    scene, sets = CASES["two_discs"]
    py = pdgrain.pack(scene, tmp_path / "py.h5", sets=sets)
    script = tmp_path / "run.py"
    script.write_text("import sys, pdgrain\n"
                      "with pdgrain.Simulation(sys.argv[1], threads=1) as sim:\n"
                      "    while not sim.finished:\n"
                      "        sim.step(5)\n"
                      "    assert len(sim.rows) < sim.num_nodes\n")
    mpirun = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", "2", "-x", "PYTHONPATH",
              "-x", "OMP_NUM_THREADS=1"]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    r = subprocess.run(mpirun + [sys.executable, str(script), str(py)], capture_output=True,
                       text=True, env=env, timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr
    ref = tmp_path / "ref.h5"
    tool("pd-pack", scene, "-o", ref, "-q", *[a for s in sets for a in ("--set", s)])
    r = subprocess.run(mpirun + [str(BIN / "pd-solve"), str(ref), "-q"],
                       capture_output=True, text=True, env=env, timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr
    assert_same(ref, py)
