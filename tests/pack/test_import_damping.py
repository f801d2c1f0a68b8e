# SPDX-License-Identifier: MIT
"""PeriDEM's particle damping under `--parity peridem` (issue 28 item 6): PeriDEM 0.2 damps two
grains while they approach, from a centre distance R_i + R_j + 1.01 R_c on, with the coefficient
beta_n sqrt(kappa R_c m_eq) on their centre nodes' velocities (solver/terms/approach_damping.cpp);
pdgrain's own damping acts on unloading. The default import keeps pdgrain's restitution. The
damped two-disc drop reproduces the restitution PeriDEM printed (Jha et al., JMPS 151, 2021,
Table 2)."""
import json
import math
import re

import h5py
import numpy as np
import pytest

from conftest import REPO, run

G = 9.81
UNDAMPED_IMPACT = 0.1316137  # m/s, the undamped parity run (test_import.py) one step before contact


def twop_circ(pd_pack, shared_dir, tmp_path, *args, eps=None):
    src = shared_dir / "data" / "peridem" / "twop_circ"
    for p in src.iterdir():
        (tmp_path / p.name).write_bytes(p.read_bytes())
    deck = tmp_path / "input_0.yaml"
    if eps is not None:
        deck.write_text(deck.read_text().replace("Epsilon: 9.000000e-01", f"Epsilon: {eps}"))
    h5 = tmp_path / ("parity.h5" if args else "default.h5")
    r = run(pd_pack, "--from-peridem", deck, *args, "-o", h5, "-q",
            "--set", "solver.observe_every=1")
    assert r.returncode == 0, r.stderr
    return h5


def beta_n(eps, factor):
    """PeriDEM's DEMModel::setupContact."""
    le = math.log(eps)
    return factor * (-2 * le / math.sqrt(math.pi ** 2 + le * le))


def test_default_import_keeps_restitution(pd_pack, shared_dir, tmp_path):
    with h5py.File(twop_circ(pd_pack, shared_dir, tmp_path), "r") as f:
        assert "approach_damping" not in f["contact"]
        assert np.all(f["contact/restitution"][()] == 0.9)


def test_parity_maps_approach_damping(pd_pack, shared_dir, tmp_path):
    """A = beta_n sqrt(kappa), kappa = 2 K K / (K + K) of the deck's K = 2.16e7 Pa, Epsilon 0.9,
    Beta_n_Factor 100; pdgrain's restitution off. Solved: the upper disc slows down before any
    node touches (gap from 1.01 R_c to R_c: dv/dt = -c v + g, c = beta / (rho pi R^2)), the
    contact keeps the energy balance, and the rebound is pinned."""
    h5 = twop_circ(pd_pack, shared_dir, tmp_path, "--parity", "peridem")
    with h5py.File(h5, "r") as f:
        A = f["contact/approach_damping"][()]
        assert A == pytest.approx(np.full(3, beta_n(0.9, 100) * math.sqrt(2.16e7)),
                                  rel=1e-12)
        assert np.all(f["contact/restitution"][()] == 1)
        rc = f["contact/radius"][0]
        R = f["bodies/bounding_radius"][()]
        assert list(R) == [1e-3, 1e-3]
        rho = f["materials"][next(iter(f["materials"]))]["density"][()]
    r = run(pd_pack.parent / "pd-solve", h5, "-q", "--force-dt")
    assert r.returncode == 0, r.stderr
    with h5py.File(h5, "r") as f:
        o = f["observables"]
        step = o["momentum/step"][()]
        off = f["bodies/node_offsets"][()]
        mass = rho * f["nodes/volume"][off[1]:off[2]].sum()
        vy = o["momentum/value"][()][:, 1] / mass  # the lower disc is fixed
        on = np.nonzero(o["contact_count/value"][()] > 0)[0]
        dissipated = o["damping_dissipation/value"][()]
        balance = sum(o[k + "/value"][()] for k in (
            "kinetic_energy", "elastic_energy", "contact_energy", "gravity_potential",
            "damping_dissipation")) - o["external_work/value"][()]
    # Before contact: only the damping window slows the disc (v0 - v1 = c 0.01 R_c, plus g tau).
    m = rho * math.pi * 1e-6
    c = A[0] * math.sqrt(rc * m) / m  # m_eq = 2 m m / (m + m) = m
    tau = 0.01 * rc / UNDAMPED_IMPACT
    want = UNDAMPED_IMPACT - c * 0.01 * rc + G * tau
    dv_step = (c * UNDAMPED_IMPACT + G) * 3e-7  # the sample's uncertainty: one step
    assert -vy[on[0] - 1] == pytest.approx(want, abs=2 * dv_step)
    assert UNDAMPED_IMPACT - (-vy[on[0] - 1]) > 30 * dv_step  # the window did act
    assert dissipated[on[0] - 1] > 0
    # Energy: the balance moves by < 1 % of what the damping took across the whole contact.
    across = slice(on[0] - 40, on[-1] + 2)
    assert abs(balance[across][-1] - balance[across][0]) < 1e-2 * dissipated[across][-1]
    # Separating: no damping, so the dissipation stops growing after the contact ends.
    assert dissipated[on[-1] + 2] == pytest.approx(dissipated[-1], rel=1e-12)
    # Measured here: 14059-14216, impact 0.123963 m/s, rebound 0.115210 m/s; pdgrain's
    # restitution 0.9 gives 0.117980, 2.3 % faster, as issue 28 measured against PeriDEM.
    assert (step[on[0]], step[on[-1]]) == (14059, 14216)
    assert vy[on[-1] + 1] == pytest.approx(0.115210, abs=2e-6)


# Jha et al. 2021, Table 2: the coefficient of restitution sqrt(H1 / H0) of the upper disc
# (H0 = 1 mm: the 0.6 mm gap plus the 0.4 mm of drop in its initial speed; H1 the apex of the
# surface gap after the first rebound) at Beta_n_Factor 100, as PeriDEM printed it.
PAPER_CR = {0.9: 0.893, 0.8: 0.796}


@pytest.mark.parametrize("eps", sorted(PAPER_CR))
def test_damped_drop_matches_peridem_table2(pd_pack, shared_dir, tmp_path, eps):
    """twop_circ with its Epsilon set, run to the rebound's apex: within 0.5 % of the paper's
    restitution (measured 0.8931 and 0.7939; 0.9958 / 0.9434 / 0.8437 at 1 / 0.95 / 0.85
    against 1 / 0.946 / 0.845; with 1.8.0's half damping 0.967 at 0.9)."""
    h5 = twop_circ(pd_pack, shared_dir, tmp_path, "--parity", "peridem", eps=eps)
    r = run(pd_pack.parent / "pd-solve", h5, "-q", "--force-dt", "--final-time", "0.018")
    assert r.returncode == 0, r.stderr
    with h5py.File(h5, "r") as f:
        o = f["observables"]
        t = o["momentum/time"][()]
        off = f["bodies/node_offsets"][()]
        vol = f["nodes/volume"][off[1]:off[2]]
        vy = o["momentum/value"][()][:, 1] / (1200 * vol.sum())
        cc = o["contact_count/value"][()]
        y0 = (f["nodes/reference_position"][off[1]:off[2], 1] * vol).sum() / vol.sum()
    # The centre's height from its velocity (trapezoids over every step), the gap above 3 mm.
    gap = y0 - 3e-3 + np.concatenate([[0], np.cumsum(0.5 * (vy[1:] + vy[:-1]) * np.diff(t))])
    first = np.argmax(cc > 0)
    up = first + np.argmax(vy[first:] > 0)
    sep = up + np.argmax(cc[up:] == 0)
    apex = sep + np.argmax(vy[sep:] <= 0)
    assert apex > sep > up > first > 0 and vy[apex - 1] > 0  # the apex was reached
    assert math.sqrt(gap[apex] / 1e-3) == pytest.approx(PAPER_CR[eps], rel=5e-3)


@pytest.mark.parametrize("sets, message", [
    (["contact.law=node", "contact.approach_damping=1"], "2D only"),
    (['contact={"law": "surface", "approach_damping": 1}'], "node law"),
    (["contact.approach_damping=1"], "node law"),  # the default law of a scene naming none
    (["contact.law=node", "contact.approach_damping=-1"], "must be in [0, 1e30)"),
])
def test_refused_outside_the_2d_node_law(pd_pack, tmp_path, sets, message):
    scene = REPO / "examples" / ("two_spheres_3d" if "2D" in message else "two_discs") / "scene.json"
    args = [a for s in sets for a in ("--set", s)]
    out = tmp_path / "x.h5"
    r = run(pd_pack, scene, *args, "-o", out, "-q")
    assert r.returncode == 2, r.stderr
    assert "approach_damping" in r.stderr and message in r.stderr
    assert not out.exists()


def test_grain_on_a_peridem_wall_is_damped_only_in_contact(pd_pack, tmp_path):
    """A disc falls at 0.5 m/s onto a fixed meshed floor marked "wall" (PeriDEM's wall zone):
    the wall's nodes damp it only once they are within R_c of its nodes (no pre-contact window as
    between two grains), the energy it takes is counted, and the disc rebounds slower."""
    scene = json.loads(re.sub(r"(?m)^\s*//.*$", "", (
        REPO / "examples" / "two_discs_wall" / "scene_meshed.json").read_text()))
    scene["particles"] = [
        {"radius": 1e-3, "center": [0, 1.3e-3], "material": "m1", "velocity": [0, -0.5]},
        {"shape": "floor", "center": [0, 0], "material": "wall", "group": 1, "fixed": True,
         "wall": True}]
    scene["contact"] = {"radius_factor": 0.95, "stiffness": "auto", "approach_damping": 22030.0}
    scene["solver"].update({"final_time": 1.2e-3, "observe_every": 1})
    (tmp_path / "s.json").write_text(json.dumps(scene))
    h5 = tmp_path / "s.h5"
    for cmd in ([pd_pack, tmp_path / "s.json", "-o", h5, "-q"],
                [pd_pack.parent / "pd-solve", h5, "-q"]):
        r = run(*cmd)
        assert r.returncode == 0, r.stderr
    with h5py.File(h5, "r") as f:
        assert list(f["bodies/kind"][()]) == [0, 1]
        o = f["observables"]
        off = f["bodies/node_offsets"][()]
        mass = 1200 * f["nodes/volume"][off[0]:off[1]].sum()
        vy = o["momentum/value"][()][:, 1] / mass
        on = np.nonzero(o["contact_count/value"][()] > 0)[0]
        dissipated = o["damping_dissipation/value"][()]
        balance = sum(o[k + "/value"][()] for k in (
            "kinetic_energy", "elastic_energy", "contact_energy", "damping_dissipation"))
    assert len(on) > 10 and on[-1] < len(vy) - 2  # one contact, over before the end
    assert np.all(dissipated[:on[0]] == 0) and dissipated[on[-1]] > 0
    impact, rebound = -vy[on[0] - 1], vy[on[-1] + 1]
    assert impact == pytest.approx(0.5, rel=1e-9)
    assert 0.45 < rebound / impact < 0.95  # measured 0.571
    assert abs(balance[-1] - balance[0]) < 1e-2 * dissipated[-1]


def test_every_shared_deck_runs_damped_under_parity(pd_pack, shared_dir, tmp_path):
    """Every shared PeriDEM deck, with damping switched on wherever it gives an Epsilon, imports
    with --parity peridem and (but the one-step configuration deck) runs 300 steps at its own dt (exit 0); compression_small_set (15
    grains in a meshed container under a lid, walls of kind 1) runs 10 ms, damped, to the same
    frames at 1 and 2 ranks (whole grains per rank, as the damping needs)."""
    solve = pd_pack.parent / "pd-solve"
    names = sorted(p.parent.name for p in (shared_dir / "data" / "peridem").glob("*/input_0.yaml"))
    assert {"compression_small_set", "twop_circ"} <= set(names)
    for case in names:
        d = tmp_path / case
        d.mkdir()
        for p in (shared_dir / "data" / "peridem" / case).iterdir():
            (d / p.name).write_bytes(p.read_bytes())
        deck = d / "input_0.yaml"
        deck.write_text(deck.read_text().replace("Damping_On: false", "Damping_On: true"))
        h5 = d / "p.h5"
        r = run(pd_pack, "--from-peridem", deck, "--parity", "peridem", "-o", h5, "-q")
        assert r.returncode == 0, f"{case}: {r.stderr}"
        if "Time_Steps: 1\n" in deck.read_text():
            continue  # compressive_n500's initial-configuration deck: one step of 0.06 s
        copies = [h5]
        if case == "compression_small_set":
            with h5py.File(h5, "r") as f:
                assert f["contact/approach_damping"][0] > 0
                assert list(f["bodies/kind"][()]) == [0] * 15 + [1, 1]
            copies.append(d / "p2.h5")
            copies[1].write_bytes(h5.read_bytes())
            assert run(pd_pack.parent / "pd-partition", copies[1], "-n", "2", "-q").returncode == 0
        for i, c in enumerate(copies):
            steps = 4000 if len(copies) == 2 else 300  # 10 ms: grains on the container
            cmd = [solve, c, "-q", "--steps", steps, "--force-dt"]
            if i:
                cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", 2] + cmd
            r = run(*cmd)
            assert r.returncode == 0, f"{case}: {r.stderr}"
        if len(copies) == 2:
            r = run("/usr/bin/python3", REPO / "workflows" / "analysis" / "compare_frames.py",
                    *copies)
            assert r.returncode == 0 and "identical" in r.stdout, r.stdout + r.stderr
            with h5py.File(h5, "r") as f:
                assert f["observables/damping_dissipation/value"][-1] > 0


def test_half_damped_file_of_1_8_0_refused(pd_pack, shared_dir, tmp_path):
    """A pd-file 1.8.0 file with approach damping held half PeriDEM's (kappa and m_eq were
    a b / (a + b)): pd-solve refuses it, names the dataset and the remedy, and leaves it as is."""
    h5 = twop_circ(pd_pack, shared_dir, tmp_path, "--parity", "peridem")
    with h5py.File(h5, "a") as f:
        f.attrs["schema_version"] = "1.8.0"
    before = h5.read_bytes()
    r = run(pd_pack.parent / "pd-solve", h5, "-q", "--force-dt", "--steps", "10")
    assert r.returncode == 2
    assert "/contact/approach_damping" in r.stderr and "import the deck again" in r.stderr
    assert h5.read_bytes() == before
