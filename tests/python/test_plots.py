# SPDX-License-Identifier: MIT
"""The workflows/analysis scripts run (as a user would: /usr/bin/python3 SCRIPT FILE) on a resting
disc made with the real tools and on a synthetic running crack, and write non-empty PNGs."""

import subprocess
import sys

import pytest

from post_helpers import ANALYSIS, meshed_floor, resting_disc
from test_crack import make_plate

PNG = b"\x89PNG\r\n\x1a\n"


def script(name, *args, cwd):
    r = subprocess.run([sys.executable, str(ANALYSIS / name), *map(str, args)], cwd=cwd,
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    return r


def check_png(path):
    data = path.read_bytes()
    assert data[:8] == PNG and len(data) > 10_000, path


@pytest.mark.parametrize("name, args", [
    ("plot_wall_reaction.py", ["--length", "2e-3"]),
    ("plot_energies.py", []),
    ("plot_damage_maps.py", []),
    ("plot_psd.py", ["--length", "2e-3", "--csv", "psd_table.csv"]),
])
def test_disc_plots(tmp_path_factory, bin_dir, tmp_path, name, args):
    h5, _ = resting_disc(tmp_path_factory, bin_dir)
    out = tmp_path / (name[:-3] + ".png")
    script(name, h5, "-o", out, *args, cwd=tmp_path)
    check_png(out)


def test_meshed_wall_reaction_plot(tmp_path_factory, bin_dir, tmp_path):
    h5, _ = meshed_floor(tmp_path_factory, bin_dir)
    for args in (["--body", "0", "--axis", "y"], ["--body", "2"], []):
        out = tmp_path / "reaction.png"
        r = script("plot_wall_reaction.py", h5, "-o", out, *args, cwd=tmp_path)
        check_png(out)
        out.unlink()
    # A body without reactions, a rigid wall the file does not have, a fixed body without an
    # axis: a message and exit 2, no traceback.
    for args, words in ((["--body", "1"], "bodies 0, 2 only"), (["--wall", "0"], "no rigid walls"),
                        (["--body", "0"], "give --axis")):
        r = subprocess.run([sys.executable, str(ANALYSIS / "plot_wall_reaction.py"), str(h5),
                            *args], cwd=tmp_path, capture_output=True, text=True, timeout=120)
        assert r.returncode == 2 and words in r.stderr and "Traceback" not in r.stderr, r.stderr


def test_crack_speed_plot(tmp_path):
    path = tmp_path / "plate.h5"
    origin, d, _, _ = make_plate(str(path))
    out = tmp_path / "crack_speed.png"
    script("plot_crack_speed.py", path, "--origin", "%r,%r" % tuple(origin[:2]),
           "--direction", "%r,%r" % tuple(d[:2]), "--band", "1e-4", "-o", out, cwd=tmp_path)
    check_png(out)
    out = tmp_path / "damage_maps.png"
    script("plot_damage_maps.py", path, "--frames", "0,-1", "-o", out, cwd=tmp_path)
    check_png(out)
