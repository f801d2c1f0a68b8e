#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Physics checks on a solved pd-file, from the file alone (h5py, numpy, scipy), over all frames.

    check_run.py FILE.h5 [--strict] [--energy-tol 0.02] [--json]

prints one line per check (name, PASS/FAIL/SKIP, measured value, bound) and exits 1 when a check
fails (with --strict also when the energy balance cannot be checked), 0 otherwise. As a module:
`checks = check_file(path)`, each a `Check(name, ok, value, bound, detail)`, `ok` None = skipped.

The checks and their rules:

no_interpenetration, no_wall_body_penetration
    Node i of body A is inside body B (B != A, the pair has a contact law in /contact with
    R_c > 0 and K_n > 0) by `e_i = max_j (d_j - |y_i - y_j|) - R_c(A, B)` beyond the contact
    radius (0 for the surface law, /contact/law 1: it acts from contact on), the max over the nodes j of B within 2 h_max of y_i (current positions y). d_j is
    the reference depth of node j in B: its distance, in reference positions, to the nearest
    boundary node of B. Boundary nodes are the vertices of the reference-mesh facets used by one
    cell only (edges in 2D, faces in 3D; for a mesh without cells, the nodes with fewer than 90 %
    of the body's largest count of neighbours within 1.5 h); in a frame where B has nodes of
    damage > 0.1 (crack faces), those count as boundary nodes too, so a crack opens B. For a
    body moving rigidly, d_j - |y_i - y_j| is a lower bound of the depth of y_i inside B, and
    the node j just behind y_i makes it sharp to about h/2. A node held off by contact sits at
    depth ~ -R_c, so e ~ -2 R_c; the check fails when e > h_B / 2 (the discretisation error of
    a boundary drawn through boundary nodes) in any frame. Pairs are found with one
    cKDTree.query_pairs per frame. Bodies that are meshed walls (kind 1) or fixed are reported
    separately (no_wall_body_penetration).
no_node_below_rigid_wall
    Signed distance of every node to every rigid wall of /walls that it has a contact law with
    (plane: (y - p(t)).n(t); circle inside: R - |y - c(t)|; outside: |y - c(t)| - R; mesh: to
    the closest face, edge or vertex, signed by its (pseudo-)normal; the wall
    pose follows velocity, angular_velocity and the motion function T(t) as pd-solve does). A
    contact holds a node at d ~ R_c; the check fails when d < -h/2 (the node is below the wall
    surface by more than half a mesh spacing, i.e. overlapped by more than R_c + h/2).
energy_no_creation
    E(t) = KE + elastic + contact - external_work must not rise above E(0): damping, friction
    and fracture only remove energy. Fails when max_t (E(t) - E(0)) > tol * S, S = max_t (KE +
    |elastic| + |contact| + |external_work|), tol = --energy-tol (2 %). Checkable today.
kinetic_energy_bound
    Elastic and contact energies are >= 0 and dissipation removes energy, so KE(t) <= E(0) +
    external_work(t) whatever the bookkeeping of the other energies: fails when max_t (KE(t) -
    E(0) - W(t)) > tol * S.
energy_balance
    With the cumulative dissipation observables fracture_energy, damping_dissipation,
    friction_dissipation, viscous_dissipation (J, >= 0): max_t |E(t) + D(t) - E(0) - D(0)| <= tol
    * S. Without them: "not checkable (observables missing)": SKIP, a failure only with --strict.
elastic_energy_nonnegative
    Bond strain energy is a sum of squares: min_t elastic_energy >= -1e-9 S.
momentum
    Only when no external force acts (gravity 0, no /walls, no fixed or meshed-wall bodies, no
    /loading/conditions, no viscous damping): max_t |p(t) - p(0)| <= 1e-4 P, with
    P = sqrt(2 M max_t KE) (M the total mass). Else SKIP.
speed_bound
    max over frames and nodes of |v| <= 2 V0 + |g| T + 2 max(c s), where V0 is the largest of
    the initial node speeds, the rigid-wall surface speeds and the rates of the displacement
    conditions (plus a T/rho for force densities), T the last frame time, and the max runs over
    the materials of the moving (not fixed) bodies: c = sqrt(E/rho) the bar wave speed, s the
    critical stretch (the larger of the PMB sqrt(4 pi Gc / (9 E delta)) and the LPS
    sqrt(Gc / ((3G + (3/4)^4 (K - 5G/3)) delta)), capped at 1; 1 when Gc = 0). Why: a stress
    wave changes the particle velocity by c times the strain jump, an intact bond carries at
    most s, a reflection doubles it; gravity adds g T. A run that loses stability grows its
    speeds exponentially and passes this bound within a few steps. The velocity field is used
    when present, else position differences between frames.
pdsolve_exit (set by the caller, not here): the suite requires pd-solve to exit 3, never 0,
    when any of the checks above fails.
"""

import argparse
import dataclasses
import json
import math
import sys

import h5py
import numpy as np
from scipy.spatial import cKDTree

DISSIPATION = ("fracture_energy", "damping_dissipation", "friction_dissipation",
               "viscous_dissipation")
DAMAGE_BOUNDARY = 0.1


@dataclasses.dataclass
class Check:
    name: str
    ok: object  # True, False or None (not checkable)
    value: float = float("nan")
    bound: float = float("nan")
    detail: str = ""

    def line(self):
        st = {True: "PASS", False: "FAIL", None: "SKIP"}[self.ok]
        return "%-28s %s  value %-11.4g bound %-11.4g %s" % (self.name, st, self.value,
                                                            self.bound, self.detail)


# ---------------------------------------------------------------------------------------------
# static model

class Model:
    """What the checks need from the static part of the file, read once."""

    def __init__(self, f):
        self.dim = int(f.attrs["dimension"])
        self.x0 = f["nodes/reference_position"][()]
        self.n = len(self.x0)
        self.body = f["nodes/body"][()].astype(np.int64)
        b = f["bodies"]
        self.off = b["node_offsets"][()].astype(np.int64)
        self.nb = len(self.off) - 1
        self.group = b["group"][()].astype(np.int64)
        self.kind = b["kind"][()].astype(np.int64)
        self.fixed = b["fixed"][()].astype(np.int64)
        self.h = b["mesh_size"][()]
        self.delta = b["horizon"][()]
        self.ref_mesh = b["ref_mesh"][()]
        self.material = b["material"][()]
        self.init_velocity = b["initial_velocity"][()]
        c = f["contact"]
        # /contact/law (pd-file 1.5.0; absent: node law): the surface law's radius is its mesh
        # size, and its force acts from contact on (offset 0), not from R_c.
        law = c["law"][()] if "law" in c else np.zeros(len(c["radius"][()]), dtype=np.uint8)
        self.contact = [(int(a), int(bb), float(r) if int(lw) == 0 else 0.0, float(k))
                        for a, bb, r, k, lw in zip(c["group_a"][()], c["group_b"][()],
                                                   c["radius"][()], c["stiffness"][()], law)]
        self.interacts = [(int(a), int(bb)) for a, bb, r, k in zip(
            c["group_a"][()], c["group_b"][()], c["radius"][()], c["stiffness"][()])
            if r > 0 and k > 0]
        ng = int(max(self.group.max(initial=0), *(max(a, bb) for a, bb, _, _ in self.contact)
                     if self.contact else [0])) + 1
        if "walls" in f:
            ng = max(ng, int(f["walls/group"][()].max()) + 1)
        # the contact offset of a group pair (node law R_c, surface law 0), nan = no interaction
        self.rc = np.full((ng, ng), np.nan)
        offset = {(a, bb): r for a, bb, r, _ in self.contact}
        for a, bb in self.interacts:
            self.rc[a, bb] = self.rc[bb, a] = offset[(a, bb)]
        self.mats = {}
        for name, g in f["materials"].items():
            self.mats[int(g.attrs["index"])] = {
                "name": name, "law": str(g.attrs["law"]), "rho": float(g["density"][()]),
                "E": float(g["youngs_modulus"][()]), "nu": float(g["poisson_ratio"][()]),
                "Gc": float(g["fracture_energy"][()])}
        self.meshes = {}
        for name, g in f["reference_meshes"].items():
            k = int(name.split("_")[1])
            self.meshes[k] = (g["nodes"].shape[0], g["cells"][()], str(g.attrs["cell_type"]))
        self.walls = None
        if "walls" in f:
            w = f["walls"]
            nw = len(w["shape"])
            self.walls = {k: w[k][()] for k in ("shape", "group", "point", "normal", "radius",
                                                 "velocity", "angular_velocity", "centre")}
            self.walls["motion"] = w["motion"][()] if "motion" in w else np.ones(nw, np.int32)
            self.walls["motion_parameters"] = (w["motion_parameters"][()]
                                               if "motion_parameters" in w
                                               else np.zeros((nw, 4)))
            # a wall with a start_time (two-stage runs) is absent before it, then moves by
            # its time function of t - start_time (pd-file 1.3)
            self.walls["start_time"] = (w["start_time"][()] if "start_time" in w
                                        else np.zeros(nw))
            # triangulated walls (pd-file 1.7): their surface at the t = 0 pose
            self.walls["mesh"] = {int(k): MeshSurface(g["points"][()], g["cells"][()])
                                  for k, g in w["mesh"].items()} if "mesh" in w else {}
        ld = f["loading"]
        self.gravity = ld["gravity"][()]
        self.viscous = float(ld["viscous_damping"][()]) if "viscous_damping" in ld else 0.0
        self.conditions = []
        if "conditions" in ld:
            for g in ld["conditions"].values():
                self.conditions.append({
                    "kind": str(g.attrs["kind"]), "tf": int(g.attrs["time_function"]),
                    "sf": int(g.attrs["space_function"]), "nodes": g["nodes"][()],
                    "a": float(g["amplitude"][()]), "p": g["parameters"][()],
                    "centre": g["centre"][()] if "centre" in g else np.zeros(3)})
        self.depth = self._reference_depth()

    def body_nodes(self, b):
        return slice(self.off[b], self.off[b + 1])

    def boundary_mask(self, b):
        """Boundary nodes of body b, from its reference mesh's facets used by one cell."""
        sl = self.body_nodes(b)
        nn = sl.stop - sl.start
        nmesh, cells, ctype = self.meshes[int(self.ref_mesh[b])]
        if len(cells) and nmesh == nn:
            if ctype == "tetra":
                fac = np.concatenate([cells[:, [0, 1, 2]], cells[:, [0, 1, 3]],
                                      cells[:, [0, 2, 3]], cells[:, [1, 2, 3]]])
            else:
                k = cells.shape[1]
                fac = np.concatenate([cells[:, [i, (i + 1) % k]] for i in range(k)])
            fac = np.sort(fac, axis=1)
            u, cnt = np.unique(fac, axis=0, return_counts=True)
            mask = np.zeros(nn, bool)
            mask[u[cnt == 1].ravel()] = True
            return mask
        x = self.x0[sl]
        cnt = np.array([len(r) for r in cKDTree(x).query_ball_point(x, 1.5 * self.h[b])])
        return cnt < 0.9 * cnt.max()

    def _reference_depth(self):
        d = np.zeros(self.n)
        self.bmask = np.zeros(self.n, bool)
        for b in range(self.nb):
            sl = self.body_nodes(b)
            m = self.boundary_mask(b)
            self.bmask[sl] = m
            if m.any():
                d[sl] = cKDTree(self.x0[sl][m]).query(self.x0[sl])[0]
        return d

    def boundary_edges(self, b):
        """2D: the boundary segments of body b's reference mesh (global node ids; a segment used
        by one cell), or None (3D, or no mesh); cached."""
        if not hasattr(self, "_edges"):
            self._edges = {}
        if b not in self._edges:
            sl = self.body_nodes(b)
            nmesh, cells, ctype = self.meshes[int(self.ref_mesh[b])]
            e = None
            if self.dim == 2 and len(cells) and nmesh == sl.stop - sl.start and ctype != "tetra":
                k = cells.shape[1]
                fac = np.concatenate([cells[:, [i, (i + 1) % k]] for i in range(k)])
                _, idx, cnt = np.unique(np.sort(fac, axis=1), axis=0, return_index=True,
                                        return_counts=True)
                e = fac[idx[cnt == 1]] + sl.start
            self._edges[b] = e
        return self._edges[b]

    def depth_with_cracks(self, damage):
        """Reference depth when damaged nodes (crack faces) also count as boundary."""
        d = self.depth.copy()
        hot = damage > DAMAGE_BOUNDARY
        for b in np.unique(self.body[hot]):
            sl = self.body_nodes(b)
            m = self.bmask[sl] | hot[sl]
            d[sl] = cKDTree(self.x0[sl][m]).query(self.x0[sl])[0]
        return d

    def strain_scale(self, mat, delta):
        m = self.mats[mat]
        if m["Gc"] <= 0:
            return 1.0
        E, nu = m["E"], m["nu"]
        G, K = E / (2 * (1 + nu)), E / (3 * (1 - 2 * nu))
        s_pmb = math.sqrt(4 * math.pi * m["Gc"] / (9 * E * delta))
        den = (3 * G + 0.75 ** 4 * (K - 5 * G / 3)) * delta
        s_lps = math.sqrt(m["Gc"] / den) if den > 0 else s_pmb
        return min(1.0, max(s_pmb, s_lps))


def time_function(code, p, t):
    """T(t) and its largest rate on [0, t] for the codes of /loading/conditions@time_function."""
    p1, p2, p3 = p[1], p[2], p[3]
    if code == 0:
        return 1.0, 0.0
    if code in (1, 4):
        return t, 1.0
    if code == 2:
        return t + p1 * t * t, max(abs(1.0), abs(1 + 2 * p1 * t))
    if code == 3:
        return math.sin(math.pi * p1 * t), abs(math.pi * p1)
    if code == 5:
        P = p1 + p2
        k = math.floor(t / P) if P > 0 else 0
        return (t - k * p2 if t < k * P + p1 else (k + 1) * p1), 1.0
    if code == 6:
        r = p2 if t <= p1 else p3
        return r * t, max(abs(p2), abs(p3))
    raise ValueError("unknown time function %d" % code)


def rotate(v, theta):
    """Rotation by the vector theta (axis * angle), Rodrigues."""
    a = np.linalg.norm(theta)
    if a == 0:
        return np.array(v, dtype=float)
    k = theta / a
    v = np.asarray(v, dtype=float)
    return v * math.cos(a) + np.cross(k, v) * math.sin(a) + k * np.dot(k, v) * (1 - math.cos(a))


class MeshSurface:
    """A triangulated (3D) or polyline (2D) wall: signed distance to the closest point, signed
    by the face normal or, at an edge or a vertex, the angle-weighted pseudo-normal (as
    lib/model/wall_mesh.cpp); a closest point on an open rim counts as outside."""

    def __init__(self, points, cells):
        self.p = np.asarray(points, dtype=float)
        self.c = np.asarray(cells, dtype=np.int64)
        P = self.p[self.c]
        if self.c.shape[1] == 3:
            n = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
        else:
            e = P[:, 1] - P[:, 0]
            n = np.stack([-e[:, 1], e[:, 0], np.zeros(len(e))], axis=1)
        self.n = n / np.linalg.norm(n, axis=1)[:, None]
        k = self.c.shape[1]
        self.vn = np.zeros_like(self.p)
        for j in range(k):  # vertex pseudo-normals (2D: the sum of the two segments')
            if k == 3:
                a, b = P[:, (j + 1) % 3] - P[:, j], P[:, (j + 2) % 3] - P[:, j]
                cos = np.sum(a * b, 1) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
                wgt = np.arccos(np.clip(cos, -1, 1))
            else:
                wgt = np.ones(len(P))
            np.add.at(self.vn, self.c[:, j], wgt[:, None] * self.n)
        edges = {}
        for t, cell in enumerate(self.c):
            for j in range(k if k == 3 else 2):
                key = tuple(sorted((cell[j], cell[(j + 1) % 3]))) if k == 3 else (cell[j],)
                edges.setdefault(key, []).append(t)
        self.en = {}
        for key, ts in edges.items():
            if len(ts) == 2:
                self.en[key] = self.n[ts[0]] + self.n[ts[1]]
            else:  # an open rim: its vertices have no pseudo-normal
                self.vn[list(key)] = 0.0
                self.en[key] = np.zeros(3)

    def _closest(self, x):
        """(distance, closest point, pseudo-normal) of one point."""
        P = self.p[self.c]
        best = (np.inf, None, None)
        segs = [(0, 1)] if self.c.shape[1] == 2 else [(0, 1), (1, 2), (2, 0)]
        if self.c.shape[1] == 3:  # the face interiors
            h = np.sum((x - P[:, 0]) * self.n, 1)
            q = x - h[:, None] * self.n
            inside = np.ones(len(P), bool)
            for a, b in segs:
                inside &= np.sum(np.cross(P[:, b] - P[:, a], q - P[:, a]) * self.n, 1) >= 0
            if inside.any():
                i = np.flatnonzero(inside)[np.argmin(np.abs(h[inside]))]
                best = (abs(h[i]), q[i], self.n[i])
        for a, b in segs:  # the edges and vertices
            A, B = P[:, a], P[:, b]
            e = B - A
            s = np.clip(np.sum((x - A) * e, 1) / np.sum(e * e, 1), 0, 1)
            q = A + s[:, None] * e
            d = np.linalg.norm(x - q, axis=1)
            i = int(np.argmin(d))
            if d[i] < best[0]:
                if s[i] <= 0 or s[i] >= 1:
                    pn = self.vn[self.c[i, a if s[i] <= 0 else b]]
                elif self.c.shape[1] == 3:
                    pn = self.en[tuple(sorted((self.c[i, a], self.c[i, b])))]
                else:
                    pn = self.n[i]
                best = (d[i], q[i], pn)
        return best

    def signed_distance(self, X):
        out = np.empty(len(X))
        for j, x in enumerate(np.asarray(X, dtype=float)):
            d, q, pn = self._closest(x)
            out[j] = -d if np.dot(x - q, pn) < 0 else d
        return out


def wall_distance(model, w, y, t):
    W = model.walls
    tw = t - W["start_time"][w]  # at rest at its t = 0 pose before its start_time
    T = time_function(int(W["motion"][w]), W["motion_parameters"][w], tw)[0] if tw >= 0 else 0.0
    theta = W["angular_velocity"][w] * T
    centre = W["centre"][w] + W["velocity"][w] * T
    point = centre + rotate(W["point"][w] - W["centre"][w], theta)
    shape = int(W["shape"][w])
    if shape == 0:
        return (y - point) @ rotate(W["normal"][w], theta)
    if shape == 3:  # in the wall's reference frame: X = c0 + R(-theta) (y - c(t))
        rel = np.asarray(y, dtype=float) - centre
        X = W["centre"][w] + np.array([rotate(r, -theta) for r in rel]) if np.any(theta) \
            else W["centre"][w] + rel
        return W["mesh"][w].signed_distance(X)
    r = np.linalg.norm(y - point, axis=1)
    return W["radius"][w] - r if shape == 1 else r - W["radius"][w]


# ---------------------------------------------------------------------------------------------
# frames

class Frames:
    def __init__(self, f):
        pn = f["particles/nodes"]
        self.pos = pn["position/value"]
        self.time = pn["position/time"][()]
        self.vel = pn["velocity/value"] if "velocity" in pn else None
        self.damage = pn["damage/value"] if "damage" in pn else None
        self.mass = pn["mass"][()]
        self.count = len(self.time)


def current_depth(model, y, nodes, depth, hot):
    """The depth of `nodes` below their body's boundary: the reference one (`depth`), or the
    distance to the nearest boundary node (or crack face) of the body where it is now if smaller.
    A grain pressed hard (a soft grain under a drum's bar: 45 % strain in its surface layer) is
    thinner there than in its reference: its reference depth would put a node that touches its
    surface 0.25 mm inside it (examples/attrition_sim1 on the surface law)."""
    out = depth.copy()
    for b in np.unique(model.body[nodes]):
        sl = model.body_nodes(b)
        m = model.bmask[sl] if hot is None else (model.bmask[sl] | hot[sl])
        if not m.any():
            continue
        sel = nodes[model.body[nodes] == b]
        out[sel] = np.minimum(depth[sel], cKDTree(y[sl][m]).query(y[sel])[0])
    return out


def polygon_depth(edges, y, pts):
    """Signed depth of points `pts` (2D) inside the region bounded by `edges` (segments of node
    ids into positions y; several loops, holes included: even-odd rule): the distance to the
    nearest segment, > 0 inside, < 0 outside."""
    A, B = y[edges[:, 0], :2], y[edges[:, 1], :2]
    X = pts[:, :2]
    inside = np.zeros(len(X), bool)
    for k in range(0, len(A), 256):  # ray casting along +x, in blocks of segments
        a, b = A[k:k + 256][None], B[k:k + 256][None]
        x, yy = X[:, None, 0], X[:, None, 1]
        cross = (a[..., 1] > yy) != (b[..., 1] > yy)
        with np.errstate(divide="ignore", invalid="ignore"):
            xs = a[..., 0] + (yy - a[..., 1]) * (b[..., 0] - a[..., 0]) / (b[..., 1] - a[..., 1])
        inside ^= (np.count_nonzero(cross & (x < xs), axis=1) % 2).astype(bool)
    e = B - A
    d = np.full(len(X), np.inf)
    for k in range(0, len(A), 256):
        a, ek = A[k:k + 256][None], e[k:k + 256][None]
        s = np.clip(np.sum((X[:, None] - a) * ek, -1) / np.maximum(np.sum(ek * ek, -1), 1e-300),
                    0, 1)
        d = np.minimum(d, np.linalg.norm(X[:, None] - (a + s[..., None] * ek), axis=-1).min(1))
    return np.where(inside, d, -d)


def exact_2d(model, y, a, bb, e, rc):
    """2D meshed bodies: the estimates e > 0 of node a inside body bb capped by the depth
    behind bb's boundary segments where it is now (polygon_depth) less rc. The pair estimate
    (a node near a node of reference depth D is D - dist inside) counts a grain's reference
    depth, which a hard-pressed soft grain does not keep: 0.25 mm claimed, 0.02 mm measured
    (examples/attrition_sim1)."""
    e = e.copy()
    for b in np.unique(bb[e > 0]):
        edges = model.boundary_edges(int(b))
        if edges is None:
            continue
        sel = np.flatnonzero((bb == b) & (e > 0))
        nodes, inv = np.unique(a[sel], return_inverse=True)
        # never above the estimate: it counts crack faces as boundary, the polygon does not
        e[sel] = np.minimum(e[sel], polygon_depth(edges, y, y[nodes])[inv] - rc[sel])
    return e


def check_penetration(model, fr):
    """no_interpenetration (grain into grain) and no_wall_body_penetration (into a fixed or
    meshed-wall body)."""
    wallish = (model.kind == 1) | (model.fixed == 1)
    r = 2.0 * float(model.h.max())
    # per class (False: into a grain, True: into a fixed or meshed-wall body): the worst ratio
    # e / (h_B / 2), its e, its bound h_B / 2 and where it happened
    worst = {False: (-np.inf, 0.0, 0.0, ""), True: (-np.inf, 0.0, 0.0, "")}
    pairs_exist = {False: False, True: False}
    gb = model.group[model.body]
    for k in range(fr.count):
        y = fr.pos[k]
        depth = model.depth if fr.damage is None else model.depth_with_cracks(fr.damage[k])
        hot = None if fr.damage is None else fr.damage[k] > DAMAGE_BOUNDARY
        pr = cKDTree(y).query_pairs(r, output_type="ndarray")
        if len(pr) == 0:
            continue
        i, j = pr[:, 0], pr[:, 1]
        bi, bj = model.body[i], model.body[j]
        keep = bi != bj
        i, j, bi, bj = i[keep], j[keep], bi[keep], bj[keep]
        rc = model.rc[gb[i], gb[j]]
        keep = np.isfinite(rc) & ~(wallish[bi] & wallish[bj])
        i, j, bi, bj, rc = i[keep], j[keep], bi[keep], bj[keep], rc[keep]
        if len(i) == 0:
            continue
        dist = np.linalg.norm(y[i] - y[j], axis=1)
        now = current_depth(model, y, np.union1d(i, j), depth, hot)
        # both directions: i inside body(j), j inside body(i)
        for a, b, ba, bb in ((i, j, bi, bj), (j, i, bj, bi)):
            e = exact_2d(model, y, a, bb, now[b] - dist - rc, rc)
            for w in (False, True):
                sel = wallish[bb] == w
                if not sel.any():
                    continue
                pairs_exist[w] = True
                half_h = 0.5 * model.h[bb[sel]]
                ratio = e[sel] / half_h
                m = int(np.argmax(ratio))
                if ratio[m] > worst[w][0]:
                    worst[w] = (float(ratio[m]), float(e[sel][m]), float(half_h[m]),
                                "t = %.4g s: node %d (body %d) %.3g m inside body %d, beyond "
                                "R_c = %.3g m (h = %.3g m)" % (
                                    fr.time[k], a[sel][m], ba[sel][m], e[sel][m] + rc[sel][m],
                                    bb[sel][m], rc[sel][m], model.h[bb[sel][m]]))
    out = []
    for w, name in ((False, "no_interpenetration"), (True, "no_wall_body_penetration")):
        if not pairs_exist[w]:
            out.append(Check(name, None, detail="no interacting pair ever within reach"
                             if (wallish.any() or not w) else "no meshed or fixed walls"))
            continue
        ratio, e, half_h, det = worst[w]
        out.append(Check(name, bool(ratio <= 1.0), e, half_h,
                         "max depth beyond R_c (m; surface law: R_c = 0) vs h/2 of the body "
                         "entered; " + det))
    return out


def check_rigid_walls(model, fr):
    if model.walls is None:
        return Check("no_node_below_rigid_wall", None, detail="no rigid walls")
    gb = model.group[model.body]
    hn = model.h[model.body]
    worst, det = np.inf, ""
    for w in range(len(model.walls["shape"])):
        act = np.isfinite(model.rc[gb, int(model.walls["group"][w])])
        act &= model.fixed[model.body] == 0
        if not act.any():
            continue
        for k in range(fr.count):
            if fr.time[k] < model.walls["start_time"][w]:
                continue  # the wall is not there yet
            d = wall_distance(model, w, fr.pos[k][act], fr.time[k]) / (0.5 * hn[act])
            m = int(np.argmin(d))
            if d[m] < worst:
                idx = np.flatnonzero(act)[m]
                worst = d[m]
                det = "t = %.4g s: node %d (body %d) at %.3g m from wall %d" % (
                    fr.time[k], idx, model.body[idx], d[m] * 0.5 * hn[idx], w)
    if not np.isfinite(worst):
        return Check("no_node_below_rigid_wall", None, detail="no node interacts with a wall")
    return Check("no_node_below_rigid_wall", bool(worst >= -1.0), float(worst), -1.0,
                 "min signed distance / (h/2); " + det)


def check_energy(f, strict, tol):
    obs = f["observables"]
    ke = obs["kinetic_energy/value"][()]
    el = obs["elastic_energy/value"][()]
    ce = obs["contact_energy/value"][()]
    w = obs["external_work/value"][()]
    e = ke + el + ce - w
    scale = float(np.max(ke + np.abs(el) + np.abs(ce) + np.abs(w)))
    scale = scale if scale > 0 else 1.0
    out = []
    kin = (ke - (e[0] + w)) / scale
    k = int(np.argmax(kin))
    out.append(Check("kinetic_energy_bound", bool(kin[k] <= tol), float(kin[k]), tol,
                     "max (KE - E0 - W)/S: at t = %.4g s KE %.4g J, E0 %.4g J, W %.4g J" % (
                         obs["kinetic_energy/time"][k], ke[k], e[0], w[k])))
    grow = float(np.max(e - e[0])) / scale
    k = int(np.argmax(e - e[0]))
    out.append(Check("energy_no_creation", bool(grow <= tol), grow, tol,
                     "max (KE+el+contact-W - E0)/S, S = %.4g J; at t = %.4g s: KE %.4g, el "
                     "%.4g, contact %.4g, W %.4g J (t=0: KE %.4g, el %.4g)" % (
                         scale, obs["kinetic_energy/time"][k], ke[k], el[k], ce[k], w[k],
                         ke[0], el[0])))
    neg = float(np.min(el)) / scale
    out.append(Check("elastic_energy_nonnegative", bool(neg >= -1e-9), neg, -1e-9,
                     "min elastic_energy / S (min %.4g J)" % np.min(el)))
    missing = [d for d in DISSIPATION if d not in obs]
    if missing:
        out.append(Check("energy_balance", False if strict else None,
                         detail="not checkable (observables missing: %s)" % ", ".join(missing)))
    else:
        dsum = sum(obs[d + "/value"][()] for d in DISSIPATION)
        bal = e + dsum
        drift = float(np.max(np.abs(bal - bal[0]))) / scale
        neg_d = min(float(np.min(obs[d + "/value"][()])) for d in DISSIPATION)
        ok = drift <= tol and neg_d >= -1e-9 * scale
        out.append(Check("energy_balance", bool(ok), drift, tol,
                         "max |E + D - E0 - D0| / S; dissipation: " + ", ".join(
                             "%s %.4g J" % (d, obs[d + "/value"][-1]) for d in DISSIPATION)))
    return out


def check_momentum(f, model, fr, tol=1e-4):
    free = (not np.any(model.gravity) and model.walls is None and not model.conditions
            and not np.any(model.fixed) and not np.any(model.kind) and model.viscous == 0)
    if not free:
        return Check("momentum", None, detail="external forces act")
    p = f["observables/momentum/value"][()]
    ke = f["observables/kinetic_energy/value"][()]
    P = math.sqrt(2 * fr.mass.sum() * ke.max())
    if P == 0:
        return Check("momentum", None, detail="nothing moves")
    drift = float(np.max(np.linalg.norm(p - p[0], axis=1))) / P
    return Check("momentum", bool(drift <= tol), drift, tol,
                 "max |p - p0| / sqrt(2 M KE_max), P = %.4g kg m/s" % P)


def speed_bound(model, fr):
    """The bound of the speed_bound check and its terms."""
    if fr.vel is not None:
        v0 = float(np.max(np.linalg.norm(fr.vel[0], axis=1)))
    else:
        v0 = 0.0
    v0 = max(v0, float(np.max(np.linalg.norm(model.init_velocity, axis=1), initial=0)))
    T = float(fr.time[-1])
    x0 = model.x0
    if model.walls is not None:
        W = model.walls
        extent = float(np.max(np.linalg.norm(x0[:, None, :] - W["centre"][None, :, :], axis=2)))
        for w in range(len(W["shape"])):
            _, rate = time_function(int(W["motion"][w]), W["motion_parameters"][w], T)
            v0 = max(v0, rate * (np.linalg.norm(W["velocity"][w])
                                 + np.linalg.norm(W["angular_velocity"][w]) * extent))
    for c in model.conditions:
        _, rate = time_function(c["tf"], c["p"], T)
        X = x0[c["nodes"]]
        p0 = c["p"][0]
        S = {0: 1.0, 1: abs(p0) * np.max(np.abs(X[:, 0]), initial=0),
             2: abs(p0) * np.max(np.abs(X[:, 1]), initial=0), 3: 1.0}.get(c["sf"], abs(p0) + 1)
        if c["tf"] == 4:
            S = float(np.max(np.linalg.norm(X - c["centre"], axis=1), initial=0))
        if c["kind"] == "displacement":
            v0 = max(v0, abs(c["a"]) * rate * S)
        else:
            rho = min(m["rho"] for m in model.mats.values())
            v0 = max(v0, abs(c["a"]) * S * T / rho)
    g = float(np.linalg.norm(model.gravity)) * T
    wave = 0.0
    for b in range(model.nb):
        if model.fixed[b]:
            continue  # not integrated: its nodes do not move
        m = model.mats[int(model.material[b])]
        c = math.sqrt(m["E"] / m["rho"])
        wave = max(wave, c * model.strain_scale(int(model.material[b]), model.delta[b]))
    return 2 * v0 + g + 2 * wave, (v0, g, wave)


def check_speed(model, fr):
    bound, (v0, g, wave) = speed_bound(model, fr)
    vmax, det = 0.0, ""
    for k in range(fr.count):
        if fr.vel is not None:
            s = np.linalg.norm(fr.vel[k], axis=1)
        elif k > 0 and fr.time[k] > fr.time[k - 1]:
            s = np.linalg.norm(fr.pos[k] - fr.pos[k - 1], axis=1) / (fr.time[k] - fr.time[k - 1])
        else:
            continue
        m = int(np.argmax(s))
        if s[m] > vmax:
            vmax = float(s[m])
            det = "t = %.4g s: node %d (body %d)" % (fr.time[k], m, model.body[m])
    return Check("speed_bound", bool(vmax <= bound), vmax, bound,
                 "max |v| (m/s) vs 2 V0 + g T + 2 c s = 2*%.3g + %.3g + 2*%.3g; %s" % (
                     v0, g, wave, det))


def check_file(path, strict=False, energy_tol=0.02):
    with h5py.File(path, "r") as f:
        if "particles" not in f or "observables" not in f:
            return [Check("has_frames", False, detail="no frames or observables in the file")]
        model = Model(f)
        fr = Frames(f)
        checks = []
        checks += check_penetration(model, fr)
        checks.append(check_rigid_walls(model, fr))
        checks += check_energy(f, strict, energy_tol)
        checks.append(check_momentum(f, model, fr))
        checks.append(check_speed(model, fr))
    return checks


def failed(checks, strict=False):
    return [c for c in checks if c.ok is False]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("--strict", action="store_true",
                    help="an energy balance that cannot be checked is a failure")
    ap.add_argument("--energy-tol", type=float, default=0.02)
    ap.add_argument("--json", action="store_true", help="print the checks as JSON")
    a = ap.parse_args(argv)
    checks = check_file(a.file, a.strict, a.energy_tol)
    if a.json:
        print(json.dumps([dataclasses.asdict(c) for c in checks], indent=1))
    else:
        for c in checks:
            print(c.line())
    bad = failed(checks)
    if not a.json:
        print("%s: %d check(s) failed" % (a.file, len(bad)) if bad else "%s: all checks pass"
              % a.file)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
