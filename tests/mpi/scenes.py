# SPDX-License-Identifier: MIT
"""Scenes of the MPI tests: small, but each exercises what distribution can get wrong."""
import json

TWO_DISCS = {  # examples/two_discs, shorter: contact between two grains on two ranks
    "dimension": 2,
    "materials": {"m1": {"law": "pmb", "density": 1200, "youngs_modulus": 3.24e7,
                         "fracture_energy": 50}},
    "discretization": {"mesh_size": 1.0e-4, "horizon_factor": 3},
    "particles": [
        {"shape": "disc", "radius": 1.0e-3, "center": [-1.15e-3, 0], "material": "m1",
         "velocity": [0.5, 0]},
        {"shape": "disc", "radius": 1.0e-3, "center": [1.15e-3, 0], "material": "m1",
         "velocity": [-0.5, 0], "orientation": 0.5}],
    "contact": {"radius_factor": 0.95, "stiffness": "auto"},
    "solver": {"final_time": 4.0e-4, "dt": "auto", "output_interval": 5e-5,
               "fields": ["velocity", "displacement", "force", "damage", "fragment"]},
}

PACK50 = {  # 50 grains falling on three walls: contact, damping and friction across ranks
    "dimension": 2,
    "materials": {"m": {"law": "pmb", "density": 1200, "youngs_modulus": 3.24e7,
                        "fracture_energy": 50}},
    "discretization": {"mesh_size": 2.5e-4, "horizon_factor": 3},
    "shapes": {"circle": {"type": "circle", "radius": 1e-3},
               "hexagon": {"type": "hexagon", "radius": 1e-3}},
    "particles": [{"generate": "random_pack",
                   "container": {"type": "rectangle", "corners": [[0, 0], [0.02, 0.014]]},
                   "count": 50, "radius": [0.9e-3, 1.1e-3],
                   "shapes": {"circle": 0.5, "hexagon": 0.5},
                   "gap": 1e-4, "seed": 3, "material": "m"}],
    "walls": [{"name": "floor", "type": "plane", "point": [0, 0], "normal": [0, 1]},
              {"name": "left", "type": "plane", "point": [0, 0], "normal": [1, 0]},
              {"name": "right", "type": "plane", "point": [0.02, 0], "normal": [-1, 0]}],
    "contact": {"restitution": 0.8, "friction": 0.3},
    "loading": {"gravity": [0, -3000]},
    "solver": {"final_time": 1.5e-3, "output_interval": 1.5e-4, "checkpoint_interval": 1.5e-4,
               "fields": ["velocity", "force", "damage"]},
}

PLATE = {  # one LPS plate with a pre-crack, pulled apart: bonds (and breaking) across ranks
    "dimension": 2,
    "materials": {"m": {"law": "lps", "density": 1200, "youngs_modulus": 3.24e7,
                        "poisson_ratio": 0.25, "fracture_energy": 5}},
    "discretization": {"mesh_size": 2e-4, "horizon_factor": 3},
    "shapes": {"plate": {"type": "rectangle", "corners": [[0, 0], [0.01, 0.005]],
                         "mesh": "grid"}},
    "particles": [{"shape": "plate", "center": [0, 0], "material": "m"}],
    "cracks": [{"from": [-1e-3, 0.00251], "to": [0.004, 0.00251]}],
    "loading": {"conditions": [
        {"name": "top", "kind": "displacement", "region": {"min": [-1, 0.0046], "max": [1, 1]},
         "components": ["y"], "time_function": "linear", "value": 2.0},
        {"name": "bottom", "kind": "displacement", "region": {"min": [-1, -1],
                                                              "max": [1, 0.0004]},
         "components": ["y"], "time_function": "linear", "value": -2.0}]},
    "solver": {"final_time": 6e-5, "output_interval": 6e-6,
               "fields": ["velocity", "displacement", "damage", "damage_z", "broken_bonds",
                          "fragment"]},
}

# Partition method per rank count: whole grains where there are enough, else nodes (the two
# discs on 4 ranks are split in halves, so bonds cross ranks there too).
MESHED_WALLS = {  # three discs between a fixed meshed floor and a driven meshed plate
    "dimension": 2,
    "materials": {"m": {"law": "lps", "density": 1200, "youngs_modulus": 3.24e7,
                        "poisson_ratio": 0.25, "fracture_energy": 50}},
    "discretization": {"mesh_size": 2.5e-4, "horizon_factor": 3},
    "shapes": {"slab": {"type": "rectangle", "corners": [[-4e-3, -0.75e-3], [4e-3, 0]]}},
    "particles": [
        {"shape": "slab", "center": [0, 0], "material": "m", "fixed": True, "group": 1},
        {"shape": "disc", "radius": 1e-3, "center": [-2.2e-3, 1.2e-3], "material": "m"},
        {"shape": "disc", "radius": 1e-3, "center": [0, 1.2e-3], "material": "m"},
        {"shape": "disc", "radius": 1e-3, "center": [2.2e-3, 1.2e-3], "material": "m"},
        {"shape": "slab", "center": [0.3e-3, 3.1e-3], "material": "m", "group": 2}],
    "contact": {"restitution": 0.8, "friction": 0.3},
    "loading": {"gravity": [0, -10], "conditions": [
        {"name": "down", "kind": "displacement", "particles": [4], "components": ["y"],
         "time_function": "linear", "value": -2.0},
        {"name": "still", "kind": "displacement", "particles": [4], "components": ["x"],
         "value": 0}]},
    "solver": {"final_time": 3e-4, "output_interval": 5e-5, "fields": ["velocity", "force"]},
}

# The same discs with the contact radius tied to the mesh (3 x mesh_size, issue 10): some 10x
# more node pairs in contact, the surface-layer guard with its min(R_c, h) distance.
TWO_DISCS_3H = dict(TWO_DISCS, contact={"radius_mesh_factor": 3, "stiffness": "auto"})

SCENES = {"two_discs": (TWO_DISCS, {2: "grain", 4: "node"}),
          "two_discs_3h": (TWO_DISCS_3H, {2: "grain", 4: "node"}),
          "pack50": (PACK50, {2: "grain", 4: "grain"}),
          "plate": (PLATE, {2: "node", 4: "node"}),
          "meshed_walls": (MESHED_WALLS, {2: "grain", 4: "grain"})}


def write(scene, path):
    path.write_text(json.dumps(scene, indent=1))
    return path
