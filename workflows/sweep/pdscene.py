#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Scenes from Python (what PeriDEM 0.3's problem.py files do through a binding), pure Python:
build a pdgrain scene as a dict with a few helpers, validate it against
data-schema/scene.schema.json (python3-jsonschema), write it, run the tools and get the file
for h5py. No compiled extension: the tools do the work.

    from pdscene import Scene
    s = Scene("two discs", dimension=2)
    s.material("m1", law="pmb", density=1200, youngs_modulus=3.24e7, fracture_energy=50)
    s.discretization(mesh_size=1e-4, horizon_factor=3)
    s.disc(radius=1e-3, center=[-1.15e-3, 0], material="m1", velocity=[0.5, 0])
    s.contact(stiffness="auto")                 # the default (surface) law
    s.solver(final_time=6e-4, dt="auto", output_interval=2e-5)
    h5 = s.run("out/two_discs")          # pd-pack, pd-solve (and pd-post with post=True)

Every helper returns the scene, so calls chain; `scene.data` is the dict itself for anything the
helpers do not cover (keys as in data-schema/scene.schema.json)."""

import importlib.util
import os
import pathlib
import subprocess

REPO = pathlib.Path(__file__).resolve().parents[2]
SCHEMA = REPO / "data-schema" / "scene.schema.json"

# The helpers are the Python package's (python/pdgrain/scene.py), loaded by path from the source
# tree (no build needed) or from an installed prefix (<prefix>/share/pdgrain/workflows/sweep ->
# <prefix>/lib/python3/dist-packages/pdgrain); this module adds run(), the tools as subprocesses.
_BASE = [REPO / "python" / "pdgrain" / "scene.py",
         REPO.parents[1] / "lib" / "python3" / "dist-packages" / "pdgrain" / "scene.py"]
_spec = importlib.util.spec_from_file_location(
    "_pdgrain_scene", next((p for p in _BASE if p.exists()), _BASE[0]))
_base = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_base)
_base.SCHEMA = SCHEMA
SceneError = _base.SceneError


class Scene(_base.Scene):
    def run(self, folder, bin_dir=None, ranks=1, post=False, solve_args=()):
        """Writes <folder>/scene.json, runs pd-pack and pd-solve (under mpirun with ranks > 1,
        after pd-partition) and, with post, pd-post into <folder>/post. Returns the .h5 path;
        a tool's failure raises subprocess.CalledProcessError with its message."""
        bin_dir = pathlib.Path(bin_dir or os.environ.get("PD_BIN_DIR", REPO / "build" / "bin"))
        folder = pathlib.Path(folder)
        scene = self.write(folder / "scene.json")
        h5 = folder / "run.h5"

        def tool(*args, mpi=False):
            cmd = [str(bin_dir / args[0]), *map(str, args[1:])]
            if mpi and ranks > 1:
                cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)] + cmd
            subprocess.run(cmd, check=True, capture_output=True, text=True)

        tool("pd-pack", scene, "-o", h5, "-q")
        if ranks > 1:
            tool("pd-partition", h5, "-n", ranks, "-q")
        tool("pd-solve", h5, "-q", *solve_args, mpi=True)
        if post:
            tool("pd-post", h5, "-o", folder / "post", "-q")
        return h5


def two_discs():
    """examples/two_discs/scene.json rebuilt with the helpers (tests/sweep/test_pdscene.py
    checks that pd-pack resolves both to the same scene and the same model)."""
    s = Scene.__new__(Scene)
    s.data = _base.two_discs().data
    return s
