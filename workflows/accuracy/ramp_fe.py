#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Classical answer of the former wave2d criterion (a one-off check, not part of `make accuracy`):
plane-stress finite elements (Q4, 2 x 2 Gauss, lumped mass, central difference) of the strip
L x W (default 40 x 2 mm), left edge driven with u_x = RAMP t^2 / 2, speed of the point where the
section-mean axial velocity equals RAMP x 0.3 L / c0, between t = T/2 and T (T = 0.8 L / c0),
against c0 = sqrt(E / rho). Measured (RESULTS.md): -0.494 / -0.450 / -0.400 / -0.398 % at element
sizes 0.2 / 0.1 / 0.05 / 0.025 mm (0.3 / 3 / 23 / 141 CPU s): the criterion's own bias.

  /usr/bin/python3 workflows/accuracy/ramp_fe.py H [L]     (H, L in m)
"""
import math, sys, numpy as np
E, RHO, NU = 1e9, 1000.0, 1 / 3
C0 = math.sqrt(E / RHO)
RAMP = 1e4
L, W = float(sys.argv[2]) if len(sys.argv) > 2 else 40e-3, 2e-3
h = float(sys.argv[1])
nx, ny = int(round(L / h)), int(round(W / h))
# Q4 stiffness of a square element (plane stress), 2x2 Gauss
D = E / (1 - NU**2) * np.array([[1, NU, 0], [NU, 1, 0], [0, 0, (1 - NU) / 2]])
Ke = np.zeros((8, 8))
g = 1 / math.sqrt(3)
xi_n = [-1, 1, 1, -1]; et_n = [-1, -1, 1, 1]
for xi in (-g, g):
    for et in (-g, g):
        dN = np.array([[0.25 * xi_n[a] * (1 + et * et_n[a]), 0.25 * et_n[a] * (1 + xi * xi_n[a])]
                       for a in range(4)]) * (2 / h)
        B = np.zeros((3, 8))
        for a in range(4):
            B[0, 2 * a] = dN[a, 0]; B[1, 2 * a + 1] = dN[a, 1]
            B[2, 2 * a] = dN[a, 1]; B[2, 2 * a + 1] = dN[a, 0]
        Ke += B.T @ D @ B * (h / 2) ** 2
nid = lambda i, j: j * (nx + 1) + i
I, J = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
I, J = I.ravel(), J.ravel()
conn = np.stack([nid(I, J), nid(I + 1, J), nid(I + 1, J + 1), nid(I, J + 1)], 1)
dofs = np.stack([2 * conn, 2 * conn + 1], 2).reshape(-1, 8)
nn = (nx + 1) * (ny + 1)
mass = np.bincount(conn.ravel(), minlength=nn) * RHO * h * h / 4
M2 = np.repeat(mass, 2)
x = (np.arange(nn) % (nx + 1)) * h
left = np.nonzero(np.arange(nn) % (nx + 1) == 0)[0]
u = np.zeros(2 * nn); v = np.zeros(2 * nn)
cp = C0 / math.sqrt(1 - NU**2)
dt = 0.5 * h / (cp * math.sqrt(2))
T = 0.8 * L / C0
nsteps = int(math.ceil(T / dt)); dt = T / nsteps
level = RAMP * 0.3 * L / C0
def force(u):
    fe = u[dofs] @ Ke.T
    return -np.bincount(dofs.ravel(), weights=fe.ravel(), minlength=2 * nn)
def where(vx):
    col = np.arange(nn) % (nx + 1)
    mean = np.bincount(col, weights=vx) / np.bincount(col)
    i = np.nonzero(mean > level)[0].max()
    return x[i] + h * (mean[i] - level) / (mean[i] - mean[i + 1])
a = force(u) / M2
pos = {}
for n in range(1, nsteps + 1):
    t = n * dt
    v += 0.5 * dt * a
    u += dt * v
    u[2 * left] = 0.5 * RAMP * t * t
    v[2 * left] = RAMP * t
    a = force(u) / M2
    v += 0.5 * dt * a
    v[2 * left] = RAMP * t
    if n == nsteps // 2 or n == nsteps:
        pos[n] = (t, where(v[0::2]))
(t1, x1), (t2, x2) = pos[nsteps // 2], pos[nsteps]
c = (x2 - x1) / (t2 - t1)
print(f"FE h = {h:g}: L = {L:g}, steps {nsteps}, c / c0 - 1 = {100 * (c / C0 - 1):+.3f} %")
