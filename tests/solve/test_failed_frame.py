#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""A failing step you can inspect (issue 28): two discs driven into each other through a contact
far too soft (stiffness_factor 1e-4) interpenetrate; pd-solve stops with exit 3, writes the state
at the failing step as a last frame flagged by /particles/nodes@failed_step, and its message
gives the numbers (depth reached, R_c, K_n, dt and its limit) and the README's advice (a larger
contact radius, not a stiffer K_n)."""
import json
import os
import re
import subprocess

import h5py
import numpy as np
import pytest

BIN = os.environ.get("PD_BIN_DIR", "build/bin")


def scene():
    return {
        "dimension": 2,
        "materials": {"m1": {"density": 1200, "youngs_modulus": 3.24e7, "fracture_energy": 50}},
        "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
        "particles": [
            {"radius": 1e-3, "center": [-1.15e-3, 0], "material": "m1", "velocity": [5, 0]},
            {"radius": 1e-3, "center": [1.15e-3, 0], "material": "m1", "velocity": [-5, 0]},
        ],
        "contact": {"radius_factor": 0.95, "stiffness": "auto", "stiffness_factor": 1e-4},
        "solver": {"final_time": 4e-4, "output_interval": 1e-4},
    }


def stopped(tmp_path, name, sc):
    """Packs and solves `sc`; the run must stop with exit 3. Returns the file and the message."""
    p = tmp_path / (name + ".json")
    p.write_text(json.dumps(sc))
    f = tmp_path / (name + ".h5")
    subprocess.run([f"{BIN}/pd-pack", str(p), "-o", str(f), "-q"], check=True)
    r = subprocess.run([f"{BIN}/pd-solve", str(f), "-q"], capture_output=True, text=True)
    assert r.returncode == 3, r.stdout + r.stderr
    return f, r.stderr


def test_interpenetration_writes_the_failing_state_as_a_flagged_last_frame(tmp_path):
    f, msg = stopped(tmp_path, "soft", scene())
    assert "grains interpenetrate at step" in msg, msg
    step = int(re.search(r"interpenetrate at step (\d+)", msg).group(1))
    depth = float(re.search(r"depth reached ([0-9.eE+-]+) m", msg).group(1))
    rc = float(re.search(r"R_c = ([0-9.eE+-]+) m", msg).group(1))
    h = float(re.search(r"h = ([0-9.eE+-]+) m", msg).group(1))
    # R_c = 0.95 x the smallest node spacing (radius_factor), h the grain's mesh size
    assert 0.5 * 2e-4 < rc < 2e-4 and 0.5 * 2e-4 < h <= 2e-4, msg
    assert depth > rc + h / 2, msg  # deeper than the guard's bound
    assert re.search(r"K_n = [0-9.eE+-]+ N m-7", msg) and "stability limit" in msg
    assert re.search(r"dt = [0-9.eE+-]+ s", msg)
    # The advice matches the README (Tunnelling and the contact radius), not "raise stiffness".
    assert "radius_mesh_factor" in msg and "raise contact.stiffness_factor" not in msg
    # ... and names the soft contact of this scene (stiffness_factor 1e-4) as the first suspect.
    assert "far softer than the grains" in msg
    with h5py.File(f, "r") as h:
        nodes = h["particles/nodes"]
        assert nodes.attrs["failed_step"] == step
        assert nodes.attrs["failure"] in ("interpenetration", b"interpenetration")
        steps = nodes["position/step"][:]
        assert steps[-1] == step and steps[-2] < step  # the failing state is the last frame
        pos = nodes["position/value"]
        assert np.isfinite(pos[-1]).all()
        # The observables end at the failing step too.
        assert h["observables/kinetic_energy/step"][-1] == step



def test_surface_law_breach_says_so_and_names_its_bound(tmp_path):
    """On the surface law (the default) the guard's bound is h/2 behind the boundary, with no
    radius: two soft discs (E = 100 kPa) meeting at 20 m/s each, twice their wave speed
    (9.1 m/s), go through (the stiffness follows the scene's speeds only up to the wave speed,
    lib/pipeline/scene/contact_speed.cpp: at 10 m/s each it now holds them). The message names
    the law, its bound and c, and advises a finer mesh or the node law with a radius, not a radius
    the law does not have."""
    s = scene()
    del s["contact"]
    s["materials"]["m1"]["youngs_modulus"] = 1e5
    s["particles"][0]["velocity"], s["particles"][1]["velocity"] = [20, 0], [-20, 0]
    _, msg = stopped(tmp_path, "fast", s)
    assert ("node pair(s) more than h/2 behind a facet it came through, or in an intact cell"
            in msg), msg
    h = float(re.search(r"surface law, h = ([0-9.eE+-]+) m", msg).group(1))
    bound = float(re.search(r"bound h/2 = ([0-9.eE+-]+) m", msg).group(1))
    assert 0.5 * 2e-4 < h <= 2e-4 and abs(bound - h / 2) < 1e-3 * h, msg  # 4 digits
    assert re.search(r"c = [0-9.eE+-]+ N m-5", msg) and "R_c =" not in msg, msg
    assert '"law": "node", "radius_mesh_factor": 3' in msg and "Refine the mesh" in msg, msg


@pytest.mark.parametrize("off_pair", [False, True])
def test_surface_law_wall_breach_advises_no_factor(tmp_path, off_pair):
    """A node through a rigid wall on the surface law: the message names what the law can do
    (its pressure at h/2, kappa / 2 h, grows as 1 / h; the stiffness follows the speeds up to
    the wave speed), not a stiffness factor it has none of. A soft disc (E = 100 kPa, wave speed
    9.1 m/s) at 50 m/s goes through the floor within 10 steps. With off_pair, another grain's
    group and the wall's are switched off (stiffness 0, as attrition_sim1's drum and protrusion:
    pd-pack records such a pair as a node-law one): the advice still follows the breaching
    node's pair, not that one (it advised a stiffness factor)."""
    s = scene()
    del s["contact"]
    s["materials"]["m1"]["youngs_modulus"] = 1e5
    s["particles"] = [{"radius": 1e-3, "center": [0, 1.2e-3], "material": "m1",
                       "velocity": [0, -50]}]
    s["walls"] = [{"type": "plane", "point": [0, 0], "normal": [0, 1]}]
    if off_pair:
        s["particles"][0]["group"] = 0
        s["particles"].append({"radius": 1e-3, "center": [5e-3, 1.2e-3], "material": "m1",
                               "group": 2})
        s["walls"][0]["group"] = 1
        s["contact"] = {"pairs": [{"groups": [2, 1], "stiffness": 0}]}
    _, msg = stopped(tmp_path, "wall", s)
    assert "nodes pass through a rigid wall" in msg, msg
    assert "surface law's pressure at h/2 behind the wall" in msg and "refine the mesh" in msg, msg
    assert "stiffness_factor" not in msg, msg


def test_penetration_warn_runs_on_as_peridem_decks_do(tmp_path):
    """solver.penetration "warn" (what pd-pack --from-peridem writes: PeriDEM has no such guard and
    runs its decks through the tunnelling R_c = 0.95 h allows; e.g. its drum deck
    attrition_mix_particles_small_set, where a wall node tunnels into a grain at 5.7 ms): the same
    run says it once and goes on to its final time, with no frame flagged; the file records it."""
    s = scene()
    s["solver"]["penetration"] = "warn"
    p = tmp_path / "soft.json"
    p.write_text(json.dumps(s))
    f = tmp_path / "soft.h5"
    subprocess.run([f"{BIN}/pd-pack", str(p), "-o", str(f), "-q"], check=True)
    r = subprocess.run([f"{BIN}/pd-solve", str(f), "-q"], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stderr.count("grains interpenetrate at step") == 1, r.stderr
    assert "solver.penetration: warn" in r.stderr
    assert "last frame" not in r.stderr  # nothing is flagged, and the warning does not say so
    with h5py.File(f, "r") as h:
        assert h["solver/penetration_warns"][()] == 1
        nodes = h["particles/nodes"]
        assert "failed_step" not in nodes.attrs
        assert nodes["position/time"][-1] == pytest.approx(4e-4)
