#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""pack500 from Python, in process (issue 30): scene.json packed and run step by step with each
body's centre and mean velocity read from the numpy views between chunks, then pd-post on the
same file (pdgrain.example). The example: PeriDEM's compressive-test pack (spec 8.3): 500
circles and hexagons (R 0.9-1.1 mm, M1, LPS) packed at random in a 68.5 x 41 mm box with three
rigid walls, settling under gravity.

    PYTHONPATH=build/python /usr/bin/python3 examples/pack500/problem.py [--quick] [--steps N]

--quick: the first 200 steps (CI). README.md describes the example; scene.json is its scene.
"""
import pathlib
import sys

import pdgrain.example

sys.exit(pdgrain.example.main(__doc__, pathlib.Path(__file__).with_name("scene.json"),
                              quick_steps=200))
