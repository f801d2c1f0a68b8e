#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""compressive_small from Python, in process (issue 30): scene.json packed and run step by step
with each body's centre and mean velocity read from the numpy views between chunks, then pd-post
on the same file (pdgrain.example). The example: Compressive test, small set (spec 8.4).

    PYTHONPATH=build/python /usr/bin/python3 examples/compressive_small/problem.py [--quick] [--steps N]

--quick: the first 200 steps (CI). README.md describes the example; scene.json is its scene.
"""
import pathlib
import sys

import pdgrain.example

sys.exit(pdgrain.example.main(__doc__, pathlib.Path(__file__).with_name("scene.json"),
                              quick_steps=200))
