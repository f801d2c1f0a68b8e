# SPDX-License-Identifier: MIT
"""A tiny hand-made pd-file (two 2D bodies of 3 nodes, 3 frames) written with h5py, following
data-schema/pd-file.md. It tests the validators without running the pipeline; it is not physics."""

import h5py
import numpy as np

STR = h5py.string_dtype()


def _ds(f, path, data, unit=None, dtype=None, extendible=False):
    data = np.asarray(data, dtype=dtype)
    kw = {}
    if extendible:
        kw = {"maxshape": (None,) + data.shape[1:],
              "chunks": (max(1, data.shape[0]),) + data.shape[1:]}
    d = f.create_dataset(path, data=data, **kw)
    if unit is not None:
        d.attrs["unit"] = unit
    return d


def make(path, frames=3, dimension=2):
    n = 6  # two bodies of 3 nodes
    with h5py.File(path, "w") as f:
        f.attrs.update({"schema": "pd-file", "schema_version": "1.0.0", "units": "SI",
                        "title": "synthetic", "planar": "plane_stress"})
        f.attrs["dimension"] = np.int32(dimension)
        f.attrs["thickness"] = np.float64(1.0)
        h = f.create_group("h5md")
        h.attrs["version"] = np.array([1, 1], dtype=np.int32)
        f.create_group("h5md/author").attrs["name"] = "test"
        c = f.create_group("h5md/creator")
        c.attrs.update({"name": "pdgrain", "version": "0.1.0"})
        u = f.create_group("h5md/modules/units")
        u.attrs["version"] = np.array([1, 0], dtype=np.int32)
        u.attrs["system"] = "SI"
        f.create_dataset("parameters/scene", data="{}", dtype=STR)
        m = f.create_group("materials/glass")
        m.attrs["law"] = "pmb"
        m.attrs["index"] = np.int32(0)
        for k, v, unit in [("density", 1200.0, "kg m-3"), ("youngs_modulus", 3e7, "Pa"),
                           ("poisson_ratio", 1 / 3, "1"), ("fracture_energy", 50.0, "J m-2")]:
            _ds(f, "materials/glass/" + k, np.float64(v), unit)
        g = f.create_group("reference_meshes/mesh_0")
        g.attrs.update({"name": "tri", "cell_type": "triangle"})
        _ds(g, "nodes", [[0, 0, 0], [1e-3, 0, 0], [0, 1e-3, 0]], "m", np.float64)
        _ds(g, "cells", [[0, 1, 2]], "1", np.int32)
        x0 = np.array([[0, 0, 0], [1e-3, 0, 0], [0, 1e-3, 0]] * 2, dtype=np.float64)
        x0[3:, 0] += 5e-3
        b = f.create_group("bodies")
        _ds(b, "node_offsets", [0, 3, 6], "1", np.int64)
        for k, v, dt in [("material", [0, 0], np.int32), ("group", [0, 0], np.int32),
                         ("ref_mesh", [0, 0], np.int32), ("kind", [0, 0], np.uint8),
                         ("fixed", [0, 0], np.uint8)]:
            _ds(b, k, v, "1", dt)
        _ds(b, "center", [[0, 0, 0], [5e-3, 0, 0]], "m", np.float64)
        _ds(b, "bounding_radius", [1e-3, 1e-3], "m", np.float64)
        _ds(b, "orientation", [0, 0], "rad", np.float64)
        _ds(b, "scale", [1, 1], "1", np.float64)
        _ds(b, "initial_velocity", [[1, 0, 0], [-1, 0, 0]], "m s-1", np.float64)
        _ds(b, "mesh_size", [1e-3, 1e-3], "m", np.float64)
        _ds(b, "horizon", [3e-3, 3e-3], "m", np.float64)
        _ds(f, "nodes/reference_position", x0, "m")
        _ds(f, "nodes/volume", np.full(n, 1e-6), "m3")
        _ds(f, "nodes/body", [0, 0, 0, 1, 1, 1], "1", np.int32)
        nbr = [1, 2, 0, 2, 0, 1, 4, 5, 3, 5, 3, 4]
        _ds(f, "bonds/offsets", [0, 2, 4, 6, 8, 10, 12], "1", np.int64)
        _ds(f, "bonds/neighbor", nbr, "1", np.int32)
        _ds(f, "contact/group_a", [0], "1", np.int32)
        _ds(f, "contact/group_b", [0], "1", np.int32)
        for k, v, unit in [("radius", 1e-4, "m"), ("stiffness", 1e20, "N m-7"),
                           ("restitution", 1.0, "1"), ("friction", 0.0, "1")]:
            _ds(f, "contact/" + k, [v], unit, np.float64)
        w = f.create_group("walls")  # one plane below the bodies
        w.attrs["names"] = np.array(["floor"], dtype=STR)
        _ds(w, "shape", [0], "1", np.uint8)
        _ds(w, "group", [0], "1", np.int32)
        for k, v, unit in [("point", [0, -2e-3, 0], "m"), ("normal", [0, 1, 0], "1"),
                           ("velocity", [0, 0, 0], "m s-1"),
                           ("angular_velocity", [0, 0, 0], "rad s-1"),
                           ("centre", [0, 0, 0], "m")]:
            _ds(w, k, [v], unit, np.float64)
        _ds(w, "radius", [0.0], "m", np.float64)
        _ds(f, "loading/gravity", [0, 0, 0], "m s-2", np.float64)
        _ds(f, "loading/viscous_damping", np.float64(0.0), "s-1")
        c = f.create_group("loading/conditions/000")
        c.attrs.update({"name": "push", "kind": "displacement"})
        for a, v in [("dofs", 1), ("time_function", 1), ("space_function", 0)]:
            c.attrs[a] = np.int32(v)
        _ds(c, "nodes", [0, 1], "1", np.int32)
        _ds(c, "amplitude", np.float64(1e-3), "m")
        _ds(c, "parameters", [0.0, 0.0, 0.0, 0.0], "1", np.float64)
        _ds(f, "cracks/segments", [[[0, 0, 0], [5e-4, 5e-4, 0]]], "m", np.float64)
        s = f.create_group("solver")
        s.attrs["integrator"] = "velocity_verlet"
        for k, v, unit in [("final_time", 1e-3, "s"), ("dt", 0.0, "s"), ("dt_safety", 0.5, "1"),
                           ("output_interval", 5e-4, "s"), ("contact_skin", 0.0, "m")]:
            _ds(s, k, np.float64(v), unit)
        _ds(s, "observe_every", np.int64(1), "1")
        p = f.create_group("partition")
        p.attrs.update({"by": "body", "method": "trivial"})
        p.attrs["num_parts"] = np.int32(1)
        p.attrs["edge_cut"] = np.int64(0)
        p.attrs["imbalance"] = np.float64(1.0)
        _ds(p, "owner", [0, 0], "1", np.int32)
        # frames
        pn = f.create_group("particles/nodes")
        box = pn.create_group("box")
        box.attrs["dimension"] = np.int32(3)
        box.attrs["boundary"] = np.array(["none"] * 3, dtype=STR)
        _ds(pn, "species", [0, 0, 0, 1, 1, 1], "1", np.int32)
        _ds(pn, "mass", np.full(n, 1.2e-3), "kg")
        times = np.arange(frames) * 5e-4
        steps = np.arange(frames, dtype=np.int64) * 100
        v = np.zeros((n, 3))
        v[:3, 0], v[3:, 0] = 1.0, -1.0
        fields = {
            "position": (np.stack([x0 + v * t for t in times]), "m"),
            "velocity": (np.stack([v] * frames), "m s-1"),
            "displacement": (np.stack([v * t for t in times]), "m"),
            "force": (np.zeros((frames, n, 3)), "N"),
            "damage": (np.zeros((frames, n)), "1"),
        }
        for name, (val, unit) in fields.items():
            _ds(pn, name + "/value", val, unit, np.float64, extendible=True)
            if name == "position":
                _ds(pn, "position/step", steps, None, np.int64, extendible=True)
                _ds(pn, "position/time", times, "s", np.float64, extendible=True)
            else:
                pn[name + "/step"] = pn["position/step"]
                pn[name + "/time"] = pn["position/time"]
        nobs = 2 * frames
        t_obs = np.arange(nobs) * 2.5e-4
        obs = {"kinetic_energy": (np.full(nobs, 7.2e-3), "J"),
               "elastic_energy": (np.zeros(nobs), "J"),
               "contact_energy": (np.zeros(nobs), "J"),
               "external_work": (np.zeros(nobs), "J"),
               "momentum": (np.zeros((nobs, 3)), "kg m s-1"),
               "contact_count": (np.zeros(nobs), "1"),
               "broken_bonds": (np.zeros(nobs), "1")}
        obs["wall_force"] = (np.arange(nobs * 3, dtype=np.float64).reshape(nobs, 1, 3), "N")
        obs["wall_moment"] = (np.zeros((nobs, 1, 3)), "N m")
        for name, (val, unit) in obs.items():
            _ds(f, "observables/%s/value" % name, val, unit, np.float64, extendible=True)
            if name == "kinetic_energy":
                _ds(f, "observables/kinetic_energy/step", np.arange(nobs, dtype=np.int64) * 50,
                    None, extendible=True)
                _ds(f, "observables/kinetic_energy/time", t_obs, "s", extendible=True)
            else:
                f["observables/%s/step" % name] = f["observables/kinetic_energy/step"]
                f["observables/%s/time" % name] = f["observables/kinetic_energy/time"]
        for k, tool in enumerate(["pd-pack", "pd-partition", "pd-solve"]):
            g = f.create_group("provenance/%03d_%s" % (k, tool.replace("-", "_")))
            g.attrs.update({"tool": tool, "version": "0.1.0", "git_commit": "unknown",
                            "command_line": tool + " x.h5", "start_time": "2026-01-01T00:00:00Z",
                            "end_time": "2026-01-01T00:00:01Z"})
            for a, val in [("mpi_ranks", 1), ("threads", 1), ("exit_status", 0)]:
                g.attrs[a] = np.int32(val)
    return path


if __name__ == "__main__":
    import sys

    make(sys.argv[1] if len(sys.argv) > 1 else "synthetic.h5")
