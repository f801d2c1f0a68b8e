# SPDX-License-Identifier: MIT
"""The horizon a scene asks for (spec 2.3): horizon_factor x mesh_size is the same for circle and
hexagon grains (whose smallest node spacings differ), horizon_mesh_ratio x each grain's smallest
node spacing (PeriDEM's Horizon_Mesh_Ratio) differs; pd-pack prints each group's horizon range and
warns when the horizons of groups that can touch differ by more than 20 %, read from the file."""

import json

import h5py
import numpy as np

from conftest import run


def scene(disc, hex_mesh_size=None, pair_stiffness=None):
    hexagon = {"type": "hexagon", "radius": 1e-3}
    if hex_mesh_size:
        hexagon["mesh_size"] = hex_mesh_size
    s = {
        "dimension": 2,
        "materials": {"m1": {"law": "lps", "density": 1200, "youngs_modulus": 3.24e7,
                             "poisson_ratio": 0.25, "fracture_energy": 50}},
        "discretization": dict({"mesh_size": 2e-4}, **disc),
        "shapes": {"circle": {"type": "circle", "radius": 1e-3}, "hexagon": hexagon},
        "particles": [
            {"shape": "circle", "center": [0, 0], "radius": 1e-3, "material": "m1", "group": 0},
            {"shape": "circle", "center": [2.5e-3, 0], "radius": 0.9e-3, "material": "m1",
             "group": 0},
            {"shape": "hexagon", "center": [0, 2.5e-3], "radius": 1e-3, "material": "m1",
             "group": 1},
            {"shape": "hexagon", "center": [2.5e-3, 2.5e-3], "radius": 1.1e-3, "material": "m1",
             "group": 1}],
        "solver": {"final_time": 1e-5},
    }
    if pair_stiffness is not None:
        s["contact"] = {"pairs": [{"groups": [0, 1], "stiffness": pair_stiffness}]}
    return s


def pack(pd_pack, tmp_path, s, name):
    path = tmp_path / f"{name}.json"
    path.write_text(json.dumps(s))
    out = tmp_path / f"{name}.h5"
    r = run(pd_pack, path, "-o", out)
    assert r.returncode == 0, r.stderr
    with h5py.File(out, "r") as f:
        return r.stdout + r.stderr, f["bodies/horizon"][()], f["bodies/mesh_size"][()]


def test_horizon_factor_is_a_multiple_of_mesh_size(pd_pack, tmp_path):
    log, horizon, spacing = pack(pd_pack, tmp_path, scene({"horizon_factor": 3}), "factor")
    # Circles and hexagons (of three scales) have smallest node spacings > 20 % apart ...
    assert spacing.max() > 1.2 * spacing.min()
    # ... and one horizon, 3 x 0.2 mm.
    np.testing.assert_allclose(horizon, 6e-4, rtol=1e-12)
    assert "group 0: 2 grains, horizon 0.0006-0.0006 m" in log
    assert "group 1: 2 grains, horizon 0.0006-0.0006 m" in log
    assert "contact groups 0-1: surface law, c" in log  # the default law
    assert "horizons range" not in log


def test_horizon_mesh_ratio_follows_each_grains_spacing(pd_pack, tmp_path):
    log, horizon, spacing = pack(pd_pack, tmp_path, scene({"horizon_mesh_ratio": 3}), "ratio")
    np.testing.assert_allclose(horizon, 3 * spacing, rtol=1e-12)
    # PeriDEM's meaning: circles and hexagons of one mesh_size get horizons far apart (warned).
    assert horizon.max() > 1.2 * horizon.min()
    assert "horizons range" in log


def test_absolute_horizon_kept(pd_pack, tmp_path):
    _, horizon, _ = pack(pd_pack, tmp_path, scene({"horizon": 7e-4}), "abs")
    np.testing.assert_allclose(horizon, 7e-4, rtol=1e-12)


def test_mismatch_warning_threshold(pd_pack, tmp_path):
    # Hexagons meshed 25 % coarser: their horizon is 25 % larger than the circles'.
    log, horizon, _ = pack(pd_pack, tmp_path, scene({"horizon_factor": 3}, 2.5e-4), "25")
    np.testing.assert_allclose(sorted(set(np.round(horizon, 12))), [6e-4, 7.5e-4], rtol=1e-9)
    assert "contact groups 0-1: horizons range over 0.0006-0.00075 m (+25 %)" in log
    assert "groups 0-0: horizons range" not in log and "groups 1-1: horizons range" not in log
    # 10 %: no warning.
    log, horizon, _ = pack(pd_pack, tmp_path, scene({"horizon_factor": 3}, 2.2e-4), "10")
    np.testing.assert_allclose(horizon.max() / horizon.min(), 1.1, rtol=1e-9)
    assert "horizons range" not in log
    # 25 % between groups that cannot touch (stiffness 0): no warning.
    log, _, _ = pack(pd_pack, tmp_path, scene({"horizon_factor": 3}, 2.5e-4, 0), "apart")
    assert "horizons range" not in log


def test_three_horizon_keys_refused(pd_pack, tmp_path):
    path = tmp_path / "both.json"
    path.write_text(json.dumps(scene({"horizon_factor": 3, "horizon_mesh_ratio": 3})))
    r = run(pd_pack, path, "-o", tmp_path / "both.h5")
    assert r.returncode == 2
    assert "give exactly one of horizon (m), horizon_factor" in r.stderr
    assert "Traceback" not in r.stderr and not (tmp_path / "both.h5").exists()
