# SPDX-License-Identifier: MIT
"""The scene builder (workflows/sweep/pdscene.py's Scene, in the package): a pdgrain scene as a
dict built with chained helpers; `pdgrain.pack(scene, "out.h5")` packs it in process.

    s = Scene("two discs", dimension=2)
    s.material("m1", law="pmb", density=1200, youngs_modulus=3.24e7, fracture_energy=50)
    s.disc(radius=1e-3, center=[-1.15e-3, 0], material="m1", velocity=[0.5, 0])
"""

import json
import os
import pathlib

_HERE = pathlib.Path(__file__).resolve().parent
# The schema: the source tree's (build/python/pdgrain -> ../../..) or the installed one
# (<prefix>/lib/python3/dist-packages/pdgrain -> <prefix>/share/pdgrain/data-schema).
_SCHEMAS = [pathlib.Path(os.environ.get("PD_SCHEMA_DIR", "/nonexistent")) / "scene.schema.json",
            _HERE.parents[3] / "share" / "pdgrain" / "data-schema" / "scene.schema.json",
            pathlib.Path("@PROJECT_SOURCE_DIR@") / "data-schema" / "scene.schema.json"]
SCHEMA = next((p for p in _SCHEMAS if p.exists()), _SCHEMAS[-1])


class SceneError(ValueError):
    """The scene breaks data-schema/scene.schema.json (the message names the key)."""


class Scene:
    def __init__(self, title, dimension=2):
        self.data = {"title": title, "dimension": dimension}

    # -- the parts of a scene, in the order pd-pack documents them ----------------------------
    def material(self, name, **props):
        """A material: law (pmb | lps | rnp), density, two of E/K/G/nu, fracture_energy..."""
        self.data.setdefault("materials", {})[name] = dict(props)
        return self

    def discretization(self, **kw):
        """mesh_size, horizon_factor (x mesh_size) or horizon, bond_cutoff..."""
        self.data.setdefault("discretization", {}).update(kw)
        return self

    def shape(self, name, type, **kw):
        """A named reference shape (circle, hexagon, rectangle, union, difference, sphere...)."""
        self.data.setdefault("shapes", {})[name] = dict(type=type, **kw)
        return self

    def particle(self, **kw):
        """One particle: shape (a name or a built-in like "disc") or radius, center, material,
        velocity, orientation, group, fixed..."""
        self.data.setdefault("particles", []).append(dict(kw))
        return self

    def disc(self, radius, center, material, **kw):
        return self.particle(shape="disc", radius=radius, center=list(center), material=material,
                             **kw)

    def random_pack(self, container, count, radius, material, **kw):
        """A random pack: container shape dict, count, radius [min, max], shapes fractions,
        gap, seed..."""
        return self.particle(generate="random_pack", container=container, count=count,
                             radius=radius, material=material, **kw)

    def wall(self, name, type="plane", **kw):
        """A rigid analytic wall (plane, circle inside/outside; velocity, angular_velocity...)."""
        self.data.setdefault("walls", []).append(dict(name=name, type=type, **kw))
        return self

    def contact(self, **kw):
        """Contact defaults (radius_factor, stiffness, restitution, friction) and pairs."""
        self.data.setdefault("contact", {}).update(kw)
        return self

    def gravity(self, g):
        self.data.setdefault("loading", {})["gravity"] = list(g)
        return self

    def condition(self, **kw):
        """A displacement or force condition (name, kind, region or particles, components,
        time_function, value...)."""
        self.data.setdefault("loading", {}).setdefault("conditions", []).append(dict(kw))
        return self

    def solver(self, **kw):
        """final_time, dt ("auto" or s), output_interval, checkpoint_interval, fields..."""
        self.data.setdefault("solver", {}).update(kw)
        return self

    # -- checking, writing, running ------------------------------------------------------------
    def validate(self):
        """Checks the scene against data-schema/scene.schema.json; raises SceneError naming the
        key. pd-pack checks the rest (values, overlaps, closest key names)."""
        import jsonschema
        schema = json.loads(SCHEMA.read_text())
        errors = sorted(jsonschema.Draft7Validator(schema).iter_errors(self.data),
                        key=lambda e: list(e.absolute_path))
        if errors:
            e = errors[0]
            where = ".".join(str(p) for p in e.absolute_path) or "(scene)"
            raise SceneError("%s: %s" % (where, e.message))
        return self

    def write(self, path):
        """Writes the scene as plain JSON (validated first); returns the path."""
        self.validate()
        path = pathlib.Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(self.data, indent=1) + "\n")
        return path


def two_discs():
    """examples/two_discs/scene.json rebuilt with the helpers (tests/sweep/test_pdscene.py
    checks that pd-pack resolves both to the same scene and the same model)."""
    return (Scene("two discs, head-on elastic collision", dimension=2)
            .material("m1", law="pmb", density=1200, youngs_modulus=3.24e7, fracture_energy=50)
            .discretization(mesh_size=1.0e-4, horizon_factor=3)
            .disc(1.0e-3, [-1.15e-3, 0], "m1", velocity=[0.5, 0])
            .disc(1.0e-3, [1.15e-3, 0], "m1", velocity=[-0.5, 0], orientation=0.5)
            .contact(stiffness="auto")
            .gravity([0, 0])
            .solver(final_time=6.0e-4, dt="auto", output_interval=2.0e-5))
