#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Run under mpirun: every rank opens FILE with h5py's MPI-IO driver and reads its share of
the frames of every field; rank 0 prints the sum of every field over all frames (JSON)."""
import json
import sys

import h5py
from mpi4py import MPI

comm = MPI.COMM_WORLD
assert h5py.get_config().mpi, "h5py without MPI (python3-h5py-mpi)"
sums = {}
with h5py.File(sys.argv[1], "r", driver="mpio", comm=comm) as h:
    nodes = h["particles/nodes"]
    for k in sorted(nodes):
        if not isinstance(nodes[k], h5py.Group) or "value" not in nodes[k]:
            continue
        v = nodes[k]["value"]
        mine = sum(float(v[f].sum()) for f in range(comm.rank, v.shape[0], comm.size))
        sums[k] = comm.allreduce(mine)
if comm.rank == 0:
    print(json.dumps(sums))
