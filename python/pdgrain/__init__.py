# SPDX-License-Identifier: MIT
"""pdgrain in the Python process: pack a scene, run it step by step, read and change its state
through numpy views, and write frames, observables and checkpoints into the same pd-file that
pd-post reads and `pd-solve --restart` continues.

    import pdgrain
    f = pdgrain.pack(pdgrain.scene.two_discs(), "two_discs.h5")
    with pdgrain.Simulation(f, threads=1) as sim:
        v = sim.velocities            # (n, 3) view, writable
        sim.step(100)                 # v follows the run
        sim.break_bonds(segment=([0, -1e-3], [0, 1e-3]))
        sim.run(until=3e-4)

The rules of the views are in python/module.cpp (and the README)."""

import json
import os
import pathlib
import tempfile

import numpy as np

from . import _core, scene
from ._core import InputError, NumericalError

__version__ = _core.__version__
__all__ = ["File", "InputError", "NumericalError", "Simulation", "pack", "scene"]


class File:
    """A pd-file on disk (what pack() writes and a Simulation runs); h5py opens it as usual."""

    def __init__(self, path):
        self.path = os.fspath(path)
        if not os.path.exists(self.path):
            raise InputError("%s: no such pd-file" % self.path)

    def __fspath__(self):
        return self.path

    def __str__(self):
        return self.path

    def __repr__(self):
        return "pdgrain.File(%r)" % self.path

    def h5(self, mode="r"):
        """The file through h5py (closed by the caller)."""
        import h5py
        return h5py.File(self.path, mode)

    def frames(self, field="position"):
        """(steps, times, values[frames, n, comp]) of one field of /particles/nodes (h5py)."""
        with self.h5() as h:
            g = h["particles/nodes/" + field]
            return g["step"][()], g["time"][()], g["value"][()]

    def observables(self):
        """/observables as a dict of numpy arrays (h5py): each observable's values (H5MD
        /observables/<name>/value), and "time" and "step" of the rows."""
        with self.h5() as h:
            g = h["observables"]
            out = {k: v["value"][()] for k, v in g.items() if "value" in v}
            first = next(v for v in g.values() if "value" in v)
            out.update(time=first["time"][()], step=first["step"][()])
            return out


def pack(scene_or_path, output, sets=(), quiet=True, overwrite=False):
    """pd-pack in process: a scene (a dict, a scene.Scene, or the path of a JSON scene) into the
    pd-file `output`; returns the File. `sets`: "path=value" overrides as pd-pack --set;
    `overwrite`: pd-pack --overwrite (replace a file that holds the results of a run)."""
    output = os.fspath(output)
    if isinstance(scene_or_path, scene.Scene):
        scene_or_path = scene_or_path.data
    if isinstance(scene_or_path, dict):
        folder = os.path.dirname(os.path.abspath(output))
        with tempfile.NamedTemporaryFile("w", suffix=".json", dir=folder, delete=False) as t:
            json.dump(scene_or_path, t, indent=1)
        try:
            _core.pack(t.name, output, list(sets), quiet, overwrite)
        finally:
            os.unlink(t.name)
    else:
        _core.pack(os.fspath(scene_or_path), output, list(sets), quiet, overwrite)
    return File(output)


class Simulation(_core.Simulation):
    """pd-solve's run held open: Simulation(file, threads=0 (all), restart=False, overwrite=False,
    final_time=None, max_steps=None, energy_tolerance=0.05, penetration_check=True, force_dt=False,
    quiet=True, verbose=False): pd-solve's options of those names.

    On opening: t = 0 is written (a frame, an observable row) or the latest checkpoint restored
    (restart=True). step(n) advances at most n steps with pd-solve's scheduled actions after each
    (frames at the scene's output_interval, observables, checkpoints, guards), never past the
    final time; close() ends the run (a checkpoint at the current step if it stopped early, so
    `pd-solve --restart` continues it) and returns pd-solve's exit code."""

    def __init__(self, file, **kw):
        super().__init__(os.fspath(file), **kw)

    def run(self, until=None):
        """Steps to the time `until` (s; at most the final time) or to the last step."""
        if until is None:
            return self.step(self.last_step - self.step_index)
        n = int(np.ceil((until - self.time) / self.dt - 1e-9))
        return self.step(max(0, n))

    def break_bonds(self, where=None, segment=None):
        """Cuts bonds (both ends) and returns how many pairs: `segment=(p0, p1)`, the bonds that
        cross the segment p0-p1 in the xy plane at the current positions; or `where`, a function
        of the bond ends' current positions (xi, xj: (B, 3) arrays) returning a boolean mask of
        the bonds to cut (it should be symmetric in xi, xj)."""
        if segment is not None:
            p0, p1 = (list(p) + [0.0] * (3 - len(p)) for p in segment)
            return self.break_segment(p0, p1)
        i, j = self.bond_ends()
        x = self.positions
        mask = np.asarray(where(x[i], x[j]), dtype=bool)
        return self.break_mask(mask)

    def condition(self, name):
        """The loading condition `name` (a pdgrain.Condition: amplitude, time_function,
        time_parameters, space_parameter writable, hold(); the rules in python/module.cpp)."""
        for c in self.conditions:
            if c.name == name:
                return c
        raise KeyError("no condition %r (there are %s)" % (name, [c.name for c in self.conditions]))

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False
