#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""grain_crushing from Python, in process (issue 30): scene.json (one disc, d = 0.8 mm, between
two rigid platens, the upper driven down at 0.2 m/s) packed and run step by step with the
grain's centre and mean velocity read from the numpy views between chunks, then pd-post on the
same file (pdgrain.example). The example: single-grain crushing (issue 31 item 3).

    PYTHONPATH=build/python /usr/bin/python3 examples/grain_crushing/problem.py [--quick] [--steps N]

--quick: the first 200 steps (CI). README.md describes the example; scene.json is its scene;
crush.py reads the platen force from the file (`crush.py out_grain_crushing/grain_crushing.h5`).
"""
import pathlib
import sys

import pdgrain.example

sys.exit(pdgrain.example.main(__doc__, pathlib.Path(__file__).with_name("scene.json"),
                              quick_steps=200))
