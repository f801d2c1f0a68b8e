# SPDX-License-Identifier: MIT
"""examples/compressive_n500/reaction.py's curve check on synthetic curves: the paper's curve
shifted by the settled pack's height passes bounds_full.json (counted from the onset); a curve
that keeps rising (the full run today) fails only on the plateau; an onset past the end of the
rise window fails cleanly instead of crashing."""
import importlib.util
import json
import pathlib

import numpy as np

EX = pathlib.Path(__file__).resolve().parents[2] / "examples" / "compressive_n500"


def load():
    spec = importlib.util.spec_from_file_location("n500_reaction", EX / "reaction.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def paper_like(shift, plateau=True):
    p = np.linspace(0, 6, 3001)
    q = p - shift  # after the onset at 0.5 mm + shift
    s = np.clip(60 * (q - 0.5), 0, None)
    if plateau:
        s = np.minimum(s, 89 + 3 * np.sin(8 * q))
    return p, s


def test_full_bounds_count_from_the_onset():
    r = load()
    bounds = json.loads((EX / "bounds_full.json").read_text())
    assert bounds["after_onset"]
    p, s = paper_like(1.8)
    assert r.check(p, s, bounds, broken=100)
    # the same curve judged from PeriDEM's height fails on the stress at 1.35 mm
    absolute = dict(bounds, after_onset=False)
    assert not r.check(p, s, absolute, broken=100)
    # still rising (no plateau) fails
    p, s = paper_like(1.8, plateau=False)
    assert not r.check(p, s, bounds, broken=100)
    # no broken bond fails
    p, s = paper_like(0.0)
    assert not r.check(p, s, bounds, broken=0)


def test_onset_after_the_rise_window_fails_without_crashing():
    r = load()
    p, s = paper_like(3.0)
    bounds = {"onset_mm": [0.2, 1.2], "rise_to_mm": 1.85}
    assert not r.check(p, s, bounds, broken=1)


def test_plateau_slope_bound():
    # plateau_max_slope: a level curve with force-chain noise passes, the same noise on a curve
    # that still climbs at 120 kPa/mm (the 14.2 mm quick box with the guard off) fails
    r = load()
    p = np.linspace(0, 4, 2001)
    noise = 40 * np.sin(9 * p)
    level = np.where(p < 1.35, 210 * p, 283) + noise
    rising = np.where(p < 1.35, 210 * p, 283 + 120 * (p - 1.35)) + noise
    bounds = {"plateau_mm": [1.35, 2.7], "plateau_kPa": [150, 450], "plateau_max_slope": 50}
    assert r.check(p, level, bounds, broken=1)
    assert not r.check(p, rising, bounds, broken=1)
    # without the slope bound the rising curve passes (mean and spread alone do not see it)
    loose = dict(bounds, plateau_spread=1.0)
    del loose["plateau_max_slope"]
    assert r.check(p, rising, loose, broken=1)
