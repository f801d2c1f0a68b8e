# SPDX-License-Identifier: MIT
"""Observables at their own interval (issue 15): a scene without solver.observe_every observes
every 10 steps; a row's energies, momentum and integrals (external work, dissipation) are the
per-step run's values at that step, bitwise; its wall and body reactions are the mean of the
per-step rows since the previous row (so the impulse over an interval is exact); and a run cut
between two rows and restarted writes the rows of the uncut run bit for bit (the open
interval's sums are checkpointed), also when the process was killed while it appended a row
(some value series one row longer than step and time: the restart cuts every series back to
the checkpoint)."""

import json
import shutil

import h5py
import numpy as np
import pytest

from post_helpers import run

# Disc A falls onto a rigid floor, disc B rises into a fixed meshed slab (body 0): both touch
# within some 40 steps and chatter, so the reactions change from step to step.
SCENE = {
    "title": "reactions averaged over the observation interval",
    "dimension": 2,
    "materials": {"m1": {"law": "pmb", "density": 1200, "youngs_modulus": 3.24e7,
                         "fracture_energy": 50}},
    "discretization": {"mesh_size": 2.0e-4, "horizon_factor": 3},
    "shapes": {"slab": {"type": "rectangle", "corners": [[-2e-3, -0.3e-3], [2e-3, 0.3e-3]]}},
    "particles": [
        {"shape": "slab", "center": [6e-3, 2.7e-3], "material": "m1", "fixed": True},
        {"shape": "disc", "radius": 1.0e-3, "center": [0, 1.05e-3], "material": "m1",
         "velocity": [0, -1]},
        {"shape": "disc", "radius": 1.0e-3, "center": [6e-3, 1.35e-3], "material": "m1",
         "velocity": [0, 1]}],
    "walls": [{"type": "plane", "point": [0, 0], "normal": [0, 1]}],
    "contact": {"restitution": 0.5},
    "loading": {"gravity": [0, -10]},
    "solver": {"final_time": 0.03, "dt": "auto", "output_interval": 1.0e-4},
}
STEPS = 300
SERIES = ("kinetic_energy", "elastic_energy", "contact_energy", "external_work", "momentum",
          "contact_count", "broken_bonds", "fracture_energy", "damping_dissipation",
          "friction_dissipation", "viscous_dissipation")
AVERAGED = ("wall_force", "wall_moment", "body_force", "body_moment")


def observables(h5):
    with h5py.File(h5, "r") as f:
        o = f["observables"]
        return {k: o[k + "/value"][()] for k in o if "value" in o[k]}, o["kinetic_energy/step"][()]


@pytest.fixture(scope="module")
def runs(tmp_path_factory, bin_dir):
    tools = {t: bin_dir / t for t in ("pd-pack", "pd-solve")}
    for exe in tools.values():
        if not exe.is_file():
            pytest.skip("%s missing in PD_BIN_DIR" % exe)
    d = tmp_path_factory.mktemp("observe_interval")
    (d / "scene.json").write_text(json.dumps(SCENE))
    packed = d / "packed.h5"
    r = run(tools["pd-pack"], d / "scene.json", "-o", packed, "-q")
    assert r.returncode == 0, r.stderr
    with h5py.File(packed, "r") as f:
        assert f["solver/observe_every"][()] == 10  # the scene default
    files = {k: d / (k + ".h5") for k in ("every", "default", "cut", "torn")}
    for path in files.values():
        shutil.copy(packed, path)
    with h5py.File(files["every"], "a") as f:
        f["solver/observe_every"][()] = 1
    for args in [(files["every"], "--steps", STEPS), (files["default"], "--steps", STEPS)]:
        r = run(tools["pd-solve"], *args, "-q")
        assert r.returncode == 0, r.stderr
    # The cut: a step inside an interval, neither a multiple of 10 nor a frame's (frames fall
    # where output_interval / dt puts them: at 137 and 274 on the surface law's step).
    rows = set(observables(files["default"])[1])
    cut_at = next(k for k in range(131, 150) if k % 10 and k not in rows)
    for path in (files["cut"], files["torn"]):
        r = run(tools["pd-solve"], path, "--steps", cut_at, "-q")
        assert r.returncode == 0, r.stderr
    # A kill during an append: values written, step and time not yet (the append order).
    with h5py.File(files["torn"], "a") as f:
        n = f["observables/kinetic_energy/step"].shape[0]
        for name in ("kinetic_energy", "wall_force"):
            v = f["observables/%s/value" % name]
            assert v.shape[0] == n
            v.resize(n + 1, axis=0)
            v[n] = 7.0
    for path in (files["cut"], files["torn"]):
        r = run(tools["pd-solve"], path, "--restart", "--steps", STEPS - cut_at, "-q")
        assert r.returncode == 0, r.stderr
    return dict({k: observables(v) for k, v in files.items()}, cut_at=cut_at)


def test_rows_at_the_interval_hold_the_step_values(runs):
    every, steps1 = runs["every"]
    sparse, steps = runs["default"]
    assert np.array_equal(steps1, np.arange(STEPS + 1))
    assert steps[0] == 0 and set(range(0, STEPS + 1, 10)) <= set(steps)
    assert 30 < len(steps) < 45  # every 10 steps and the frames between
    for name in SERIES:
        np.testing.assert_array_equal(sparse[name], every[name][steps], err_msg=name)


def test_reactions_are_interval_means(runs):
    every, _ = runs["every"]
    sparse, steps = runs["default"]
    for name in AVERAGED:
        assert name in sparse, name
        full = every[name]
        scale = np.abs(full).max()
        assert scale > 0, name  # the contacts did form
        want = [full[0]] + [full[p + 1:s + 1].mean(axis=0) for p, s in zip(steps, steps[1:])]
        np.testing.assert_allclose(sparse[name], np.array(want), rtol=0, atol=1e-12 * scale,
                                   err_msg=name)
        # The impulse over the run is exact, whatever the interval.
        impulse = (sparse[name][1:] * np.diff(steps)[:, None, None]).sum(axis=0)
        np.testing.assert_allclose(impulse, full[1:].sum(axis=0), rtol=0,
                                   atol=1e-10 * scale * STEPS, err_msg=name)
        # A sample would differ: the reactions change within an interval.
        assert np.abs(sparse[name][1:] - full[steps[1:]]).max() > 1e-3 * scale, name


def test_a_restart_between_rows_continues_the_interval_bitwise(runs):
    sparse, steps = runs["default"]
    cut, cut_steps = runs["cut"]
    np.testing.assert_array_equal(cut_steps, steps)
    assert runs["cut_at"] not in steps  # the cut falls inside an interval
    for name in sparse:
        np.testing.assert_array_equal(cut[name], sparse[name], err_msg=name)


def test_a_restart_after_a_torn_append_cuts_every_series(runs):
    sparse, steps = runs["default"]
    torn, torn_steps = runs["torn"]
    np.testing.assert_array_equal(torn_steps, steps)
    for name in sparse:
        np.testing.assert_array_equal(torn[name], sparse[name], err_msg=name)
