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


def test_preview_draws_a_wall_that_enters_later_dashed(pd_pack, tmp_path):
    """Issue 28: the preview draws a wall with start_time > 0 dashed and labelled (it is not
    there at t = 0), the others solid."""
    import sys

    import matplotlib
    matplotlib.use("Agg")
    from conftest import REPO
    sys.path.insert(0, str(REPO / "workflows" / "preview"))
    import preview

    sc = scene([])
    sc["walls"] = [{"name": "floor", "type": "plane", "point": [0, -2e-3], "normal": [0, 1]},
                   {"name": "plate", "type": "plane", "point": [0, 2e-3], "normal": [0, -1],
                    "velocity": [0, -0.1], "start_time": 5e-6}]
    sc["contact"] = {"radius_mesh_factor": 3}
    path = tmp_path / "two_walls.json"
    path.write_text(json.dumps(sc))
    h5 = tmp_path / "two_walls.h5"
    r = run(pd_pack, path, "-o", h5, "-q")
    assert r.returncode == 0, r.stderr
    import matplotlib.pyplot as plt
    drawn = []
    real_close = plt.close
    plt.close = lambda fig=None: drawn.append(fig) or real_close(fig)
    try:
        preview.draw(str(h5), str(tmp_path / "p.png"))
    finally:
        plt.close = real_close
    ax = drawn[-1].axes[0]
    from matplotlib.collections import LineCollection
    styles = [c.get_linestyle()[0] for c in ax.collections if isinstance(c, LineCollection)
              and len(c.get_segments()) == 1]
    solid = [s for s in styles if s[1] is None]
    dashed = [s for s in styles if s[1] is not None]
    assert len(solid) == 1 and len(dashed) == 1, styles
    assert any("enters at t = 5e-06 s" in t.get_text() for t in ax.texts)
    assert (tmp_path / "p.png").stat().st_size > 0
