#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""n12 from Python, in process (issue 30): scene.json packed and run step by step with each body's
centre and mean velocity read from the numpy views between chunks, then pd-post on the same file
(pdgrain.example). The example: The small deck of PeriDEM's compressive family.

    PYTHONPATH=build/python /usr/bin/python3 examples/n12/problem.py [--quick] [--steps N]

--quick: the Makefile's quick run (the first 3 ms). README.md describes the example; scene.json is its scene.
"""
import pathlib
import sys

import pdgrain.example

sys.exit(pdgrain.example.main(__doc__, pathlib.Path(__file__).with_name("scene.json"),
                              quick=["solver.final_time=0.003"], quick_steps=None))
