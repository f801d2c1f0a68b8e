# SPDX-License-Identifier: MIT
"""pd-pack's warning about nodes that start within a rigid wall's contact radius counts each node
against the law between its grain's group and the wall's: a grain the wall does not act on (pair
stiffness 0, e.g. a protrusion that turns with the drum) is not "pushed off at t = 0"."""

import json

from conftest import run


def scene(pairs):
    disc = {"type": "circle", "radius": 1e-3}
    return {
        "dimension": 2,
        "materials": {"m": {"law": "lps", "density": 1200, "youngs_modulus": 1.5e4,
                            "poisson_ratio": 0.25, "fracture_energy": 50}},
        "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
        "shapes": {"disc": disc},
        # Both discs 0.1 mm from the drum (R_c = 0.6 mm): group 0 at -x, group 1 at +x.
        "particles": [{"shape": "disc", "center": [-8.9e-3, 0], "material": "m", "group": 0},
                      {"shape": "disc", "center": [8.9e-3, 0], "material": "m", "group": 1}],
        "walls": [{"name": "drum", "type": "circle_inside", "center": [0, 0], "radius": 0.01}],
        "contact": {"radius_mesh_factor": 3, "pairs": pairs},
        "solver": {"final_time": 1e-5},
    }


def warned(pd_pack, tmp_path, name, pairs):
    path = tmp_path / f"{name}.json"
    path.write_text(json.dumps(scene(pairs)))
    r = run(pd_pack, path, "-o", tmp_path / f"{name}.h5")
    assert r.returncode == 0, r.stderr
    lines = [ln for ln in r.stderr.splitlines() if "start within the contact radius" in ln]
    assert len(lines) <= 1, r.stderr
    if not lines:
        return 0
    return int(lines[0].split("walls[0]: ")[1].split(" nodes")[0])


def test_wall_start_warning_follows_the_pair_law(pd_pack, tmp_path):
    both = warned(pd_pack, tmp_path, "both", [])
    # The wall (group 2) does not act on group 0: only group 1's nodes are counted, and the
    # other way round; the two counts add up to the default's.
    only1 = warned(pd_pack, tmp_path, "only1", [{"groups": [0, 2], "stiffness": 0}])
    only0 = warned(pd_pack, tmp_path, "only0", [{"groups": [1, 2], "stiffness": 0}])
    assert only0 > 0 and only1 > 0 and only0 + only1 == both
    assert warned(pd_pack, tmp_path, "none", [{"groups": [0, 2], "stiffness": 0},
                                              {"groups": [1, 2], "stiffness": 0}]) == 0
