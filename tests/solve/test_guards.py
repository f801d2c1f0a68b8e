#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""pd-solve guards and restarts, run as a user would: a scene dt above the stability estimate
is refused (exit 2) unless forced; a blow-up stops with exit 3 naming step, time, node and body
while the last good frame stays readable; --restart continues bit for bit."""
import json
import os
import shutil
import subprocess

import h5py
import numpy as np
import pytest

BIN = os.environ.get("PD_BIN_DIR", "build/bin")
SRC = os.environ.get("PD_SOURCE_DIR", ".")


def scene(**solver):
    s = {
        "dimension": 2,
        "materials": {"m1": {"density": 1200, "youngs_modulus": 3.24e7, "fracture_energy": 50}},
        "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
        "particles": [
            {"radius": 1e-3, "center": [-1.15e-3, 0], "material": "m1", "velocity": [0.5, 0]},
            {"radius": 1e-3, "center": [1.15e-3, 0], "material": "m1", "velocity": [-0.5, 0]},
        ],
        "solver": {"final_time": 4e-4, "output_interval": 4e-5},
    }
    s["solver"].update(solver)
    return s


def pack(tmp_path, name, sc):
    p = tmp_path / (name + ".json")
    p.write_text(json.dumps(sc))
    out = tmp_path / (name + ".h5")
    subprocess.run([f"{BIN}/pd-pack", str(p), "-o", str(out), "-q"], check=True)
    return out


def run(*args):
    return subprocess.run([f"{BIN}/{args[0]}", *map(str, args[1:])], capture_output=True,
                          text=True)


def test_dt_above_limit_is_refused_unless_forced(tmp_path):
    f = pack(tmp_path, "big_dt", scene(dt=1e-5))
    r = run("pd-solve", f, "-q")
    assert r.returncode == 2, r.stderr
    assert "/solver/dt" in r.stderr and "stability estimate" in r.stderr
    assert "governed by" in r.stderr
    # Nothing was lost: the file still validates as packed, with no frames; a run refused
    # before it started leaves the file as it was (no provenance entry either, issue 13).
    with h5py.File(f, "r") as h:
        assert "particles" not in h
        assert h["provenance"][sorted(h["provenance"])[-1]].attrs["tool"] == "pd-pack"


def test_blow_up_exits_3_and_keeps_the_last_good_frame(tmp_path):
    # 30x the stable step, forced: the run must blow up and stop.
    f = pack(tmp_path, "blow", scene(dt=1.5e-5, final_time=6e-3, output_interval=1.5e-4))
    r = run("pd-solve", f, "-q", "--force-dt")
    assert r.returncode == 3, r.stdout + r.stderr
    assert any(m in r.stderr for m in ("blow-up at step", "non-finite state at step",
                                       "energy balance broken at step"))
    assert "node" in r.stderr and "body" in r.stderr
    with h5py.File(f, "r") as h:
        pos = h["particles/nodes/position/value"]
        assert pos.shape[0] >= 2
        # The last frame is the failing state, flagged (issue 28); the frames before are good.
        nodes = h["particles/nodes"]
        assert nodes.attrs["failed_step"] == nodes["position/step"][-1]
        assert np.isfinite(pos[-2]).all()
        assert h["provenance"][sorted(h["provenance"])[-1]].attrs["exit_status"] == 3


def test_restart_matches_uninterrupted_run_bit_for_bit(tmp_path):
    sc = scene(checkpoint_interval=2e-5)
    a = pack(tmp_path, "a", sc)
    b = tmp_path / "b.h5"
    shutil.copy(a, b)
    assert run("pd-solve", a, "-q").returncode == 0
    # Interrupted after 470 steps (the surface law's automatic dt, 7.3e-7 s: the discs touch
    # from step 420 to 500, a checkpoint every 27 steps, the latest at 459: mid-contact), then
    # continued.
    assert run("pd-solve", b, "-q", "--steps", 470).returncode == 0
    r = run("pd-solve", b, "-q", "--restart")
    assert r.returncode == 0, r.stderr
    with h5py.File(a, "r") as ha, h5py.File(b, "r") as hb:
        for p in ["particles/nodes/position/value", "particles/nodes/velocity/value",
                  "particles/nodes/damage/value", "particles/nodes/position/time",
                  "observables/kinetic_energy/value", "observables/momentum/value",
                  "observables/contact_count/value", "observables/kinetic_energy/step"]:
            x, y = ha[p][...], hb[p][...]
            assert x.shape == y.shape, p
            assert np.array_equal(x, y), p
        assert hb["observables/contact_count/value"][:].max() > 0  # the restart was mid-contact?


def shattering(**solver):
    # Contact fails in this shatter: by 0.2 ms a detached node of one disc lies 4 h deep in the
    # other's cohesive material (an interior cell, edges stretched 0.997-0.998, its vertices'
    # damage 0.24-0.44), where boundary nodes broke off and their facets tore (the guard's
    # material test, lib/solver/surface_inside.cpp). These tests are about restarts and the
    # tear's energy booking, so the guard warns once and the run goes on.
    solver.setdefault("penetration", "warn")
    sc = scene(final_time=2e-4, **solver)
    sc["materials"]["m1"]["fracture_energy"] = 1
    sc["particles"][0]["velocity"], sc["particles"][1]["velocity"] = [5, 0], [-5, 0]
    return sc


def test_restart_between_rebuilds_of_a_breaking_contact_is_bit_for_bit(tmp_path):
    """The surface law rebuilds its contact list, and counts which boundary nodes lost half
    their bonds (torn facets), at positions it keeps: a checkpoint holds them
    (/checkpoints/*/surface_build_position and surface_build_whole), so a restart rebuilds when
    the run would have. Two brittle discs meet at 10 m/s and shatter; the run is cut 70 steps
    in, 3e-5 m after the last rebuild. Without the kept positions the restart rebuilds at once,
    facets tear sooner and the frames move by about 1e-3 m (0.7e-3 measured): the test sees it."""
    a = pack(tmp_path, "a", shattering())
    assert run("pd-solve", a, "-q").returncode == 0
    with h5py.File(a, "r") as h:
        assert h["observables/broken_bonds/value"][-1] > 1000  # they shatter
        ref = h["particles/nodes/position/value"][...]
    for keep in (True, False):
        b = pack(tmp_path, f"b{int(keep)}", shattering(checkpoint_interval=1e-5))
        assert run("pd-solve", b, "-q", "--steps", 70).returncode == 0
        with h5py.File(b, "r+") as h:
            ck = h["checkpoints"][h["checkpoints"].attrs["latest"]]
            x = h["nodes/reference_position"][()] + ck["displacement"][()]
            assert np.abs(ck["surface_build_position"][()] - x).max() > 1e-6  # between rebuilds
            if not keep:
                del ck["surface_build_position"], ck["surface_build_whole"]
        r = run("pd-solve", b, "-q", "--restart")
        assert r.returncode == 0, r.stderr
        with h5py.File(b, "r") as h:
            got = h["particles/nodes/position/value"][...]
        assert got.shape == ref.shape
        if keep:
            assert np.array_equal(got, ref)
        else:
            assert np.abs(got - ref).max() > 1e-5


def test_shattering_discs_keep_their_energy_when_facets_tear(tmp_path):
    """Two brittle discs meet at 10 m/s and shatter (2 111 bonds). A boundary node that lost
    half its bonds tears its facets at the next rebuild of the surface law's list: they stop
    pushing, and the contact energy they held goes with the tear, booked as fracture energy as
    a breaking bond's is. Without that booking the balance lost 3.5 % of the energy in play
    (measured), with it 1.4 % (the rest: the step's error on a shatter, +0.6 / -0.3 % at 0.5 /
    0.25 x the step)."""
    f = pack(tmp_path, "s", shattering(observe_every=1))
    assert run("pd-solve", f, "-q", "--energy-tolerance", 1).returncode == 0
    with h5py.File(f, "r") as h:
        o = h["observables"]
        e = sum(o[k]["value"][:] for k in ("kinetic_energy", "elastic_energy", "contact_energy",
                                            "fracture_energy", "damping_dissipation",
                                            "friction_dissipation", "viscous_dissipation"))
        e = e - o["external_work/value"][:]
        assert o["broken_bonds/value"][-1] > 1000
        assert np.abs(e - e[0]).max() < 0.025 * e[0], (e.min() - e[0]) / e[0]


def test_checkpoint_keeps_the_surface_depth_history_and_checks_it(tmp_path):
    """The surface law's depth rule reads the last evaluation's depths: a checkpoint holds them
    (/checkpoints/*/surface_depths, with their (node, body) pairs and time), so a restart decides
    as the run would have (tests/unit SurfaceContact.ARestartKeepsTheDepthHistory). A history
    that names no node or has a negative depth is refused with exit 2, the file unchanged."""
    f = pack(tmp_path, "d", scene(checkpoint_interval=2e-5))
    with h5py.File(f, "r+") as h:  # a file packed before these objects: pd-solve raises it
        h.attrs["schema_version"] = "1.8.1"
    assert run("pd-solve", f, "-q", "--steps", 470).returncode == 0  # mid-contact, as above
    with h5py.File(f, "r+") as h:
        assert h.attrs["schema_version"] == "1.9.1"
        ck = h["checkpoints"][h["checkpoints"].attrs["latest"]]
        assert 0 <= ck.attrs["surface_depth_time"] <= ck.attrs["time"]
        pairs, depths = ck["surface_depth_pairs"][()], ck["surface_depths"][()]
        assert pairs.shape == (len(depths), 2) and len(depths) > 0  # the discs touch
        assert ((depths > 0) | (depths == -1)).all() and (depths > 0).any()  # -1: held (1.9.1)
        assert (pairs[:, 1] <= 1).all()
        ck["surface_depths"][0] = -0.5  # -1 means held (1.9.1); other negatives are refused
    before = open(f, "rb").read()
    r = run("pd-solve", f, "-q", "--restart")
    assert r.returncode == 2 and "surface_depths" in r.stderr, r.stderr
    assert open(f, "rb").read() == before


def test_restart_without_checkpoint_is_an_input_error(tmp_path):
    f = pack(tmp_path, "nock", scene())
    r = run("pd-solve", f, "--restart")
    assert r.returncode == 2
    assert "/checkpoints" in r.stderr


def test_same_result_for_any_thread_count(tmp_path):
    """Rows are summed in a fixed order and contact records are sorted: the positions after 30
    steps of the 500-grain pack (53 000 nodes, threaded kernels) are identical bit for bit on
    1 and 2 threads."""
    src = os.path.join(SRC, "examples", "pack500", "scene.json")
    f1 = tmp_path / "t1.h5"
    subprocess.run([f"{BIN}/pd-pack", src, "-o", str(f1), "-q"], check=True)
    f2 = tmp_path / "t2.h5"
    shutil.copy(f1, f2)
    for f, n in ((f1, "1"), (f2, "2")):
        env = dict(os.environ, OMP_NUM_THREADS=n)
        r = subprocess.run([f"{BIN}/pd-solve", str(f), "-q", "--steps", "30"], env=env,
                           capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
    with h5py.File(f1, "r") as a, h5py.File(f2, "r") as b:
        assert a["provenance"][sorted(a["provenance"])[-1]].attrs["threads"] == 1
        assert b["provenance"][sorted(b["provenance"])[-1]].attrs["threads"] == 2
        ca = a["checkpoints"][a["checkpoints"].attrs["latest"]]
        cb = b["checkpoints"][b["checkpoints"].attrs["latest"]]
        for k in ("displacement", "velocity", "force_density"):
            assert np.array_equal(ca[k][...], cb[k][...]), k
