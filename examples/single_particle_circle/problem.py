#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""single_particle_circle from Python, in process (issue 30): scene.json packed and run step by
step with each body's centre and mean velocity read from the numpy views between chunks, then
pd-post on the same file (pdgrain.example). The example: Single particle, circle (spec 8.6); no
contact.

    PYTHONPATH=build/python /usr/bin/python3 examples/single_particle_circle/problem.py [--quick] [--steps N]

--quick: the first 200 steps (CI). README.md describes the example; scene.json is its scene.
"""
import pathlib
import sys

import pdgrain.example

sys.exit(pdgrain.example.main(__doc__, pathlib.Path(__file__).with_name("scene.json"),
                              quick_steps=200))
