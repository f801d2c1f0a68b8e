#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""circ_damp_diff_radius from Python, in process (issue 30): scene.json packed and run step by step
with each body's centre and mean velocity read from the numpy views between chunks, then pd-post
on the same file (pdgrain.example). The example: Two-disc impact, PeriDEM's
`circ_damp_diff_radius` (spec 8.1), with PeriDEM's parameters and parity switches (strict bond
cut-off, no surface correction, symplectic Euler).

    PYTHONPATH=build/python /usr/bin/python3 examples/circ_damp_diff_radius/problem.py [--quick] [--steps N]

--quick: the first 200 steps (CI). pd-solve --force-dt, as README.md says: PeriDEM's dt is
above pdgrain's estimate. README.md describes the example; scene.json is its scene.
"""
import pathlib
import sys

import pdgrain.example

sys.exit(pdgrain.example.main(__doc__, pathlib.Path(__file__).with_name("scene.json"),
                              quick_steps=200, force_dt=True))
