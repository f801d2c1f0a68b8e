#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""attrition_sim1 from Python, in process (issue 30): scene.json packed and run step by step with
each body's centre and mean velocity read from the numpy views between chunks, then pd-post on
the same file (pdgrain.example). The example: PeriDEM's attrition drum sim1 (spec 8.5), **with
its protrusion**: the drum (R_in = 20 mm, ...).

    PYTHONPATH=build/python /usr/bin/python3 examples/attrition_sim1/problem.py [--quick] [--steps N]

--quick: the Makefile's quick run (the first 5 ms). README.md describes the example; scene.json is its scene.
"""
import pathlib
import sys

import pdgrain.example

sys.exit(pdgrain.example.main(__doc__, pathlib.Path(__file__).with_name("scene.json"),
                              quick=["solver.final_time=0.005"], quick_steps=None))
