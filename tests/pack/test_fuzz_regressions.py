# SPDX-License-Identifier: MIT
"""Scenes that once crashed pd-pack or the scene fuzz harness (tests/fuzz/regressions/scene,
issue 13; `make fuzz` replays the same files through the harness). Each must now give exit 2
with the culprit key in the message and no output file. Every file there needs an entry here."""

import pathlib

import pytest

from conftest import REPO, run

DIR = REPO / "tests" / "fuzz" / "regressions" / "scene"

# file -> words the message must contain (exit 2 always)
EXPECTED = {
    # [[0], [x1, y1]]: corners[0][1] was read past the end of the array (heap-buffer-overflow,
    # valgrind: invalid read in parse_shape)
    "rectangle_corner_of_one_number.json": ["shapes.r.corners", "[[x0, y0], [x1, y1]]"],
    # a vertex [x]: vertices[k][1] read past the end of the array
    "polygon_vertex_of_one_number.json": ["shapes.r.vertices", "[[x, y], ...]"],
    # 1e300 cast to int32 (undefined; x86 gave -2147483648 in the message): clamped first
    "dimension_1e300.json": ["dimension", "1000000000: expected 2 or 3"],
    "particle_group_1e300.json": ["particles[1].group", "must be in [0, 1000]"],
    "contact_pair_groups_1e300.json": ["contact.pairs[0].groups", "in group 1000000000 or 0"],
    # a negative seed was cast to uint64 (undefined) and the lattice packed with exit 0
    "lattice_seed_negative.json": ["particles[0].seed", "from 0 to 2^53"],
    # issue 27, bounded work (the fuzz_scene timeouts' kinds): a lattice of a shape that is not
    # defined counted 0 nodes a grain and generated 1e10 grains; a count of 1e300 was cast to
    # size_t (undefined); a 1e9 m x 1e-9 m rectangle has 1 node of area and 2e9 along its
    # boundary (gmsh); horizon_factor 300 multiplies the bonds (81 s, then bad_alloc); 65
    # nested arrays (a deep scene's dump grew quadratically).
    "lattice_undefined_shape_1e10_grains.json": ["particles[0].counts", "--max-nodes"],
    "lattice_count_1e300.json": ["particles[0].counts[0]", "whole number"],
    "thin_rectangle_long_boundary.json": ["shapes.thin", "--max-nodes"],
    "horizon_factor_300_bonds.json": ["discretization.horizon_factor", "bonds"],
    "nesting_65_levels.json": ["nested more than 64 levels"],
}


def test_every_regression_file_has_an_expectation():
    files = sorted(p.name for p in DIR.glob("*.json"))
    assert files == sorted(EXPECTED), "add new tests/fuzz/regressions/scene files to EXPECTED"


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_regression_refused(pd_pack, tmp_path, name):
    out = tmp_path / "out.h5"
    r = run(pd_pack, DIR / name, "-o", out, "--max-nodes", "4000")
    assert r.returncode == 2, (r.returncode, r.stderr)
    for w in EXPECTED[name]:
        assert w in r.stderr, (w, r.stderr)
    assert "-2147483648" not in r.stderr, r.stderr
    assert not out.exists()


def test_well_formed_corners_and_vertices_still_pack(pd_pack, tmp_path):
    """The checks refuse only malformed values: the same scenes with two numbers per point, or a
    seed >= 0, pack."""
    for name, good in [("rectangle_corner_of_one_number.json", ("[[0], ", "[[0, 0], ")),
                       ("polygon_vertex_of_one_number.json", ("[1e-3]", "[1e-3, 0]")),
                       ("lattice_seed_negative.json", ('"seed": -1', '"seed": 7'))]:
        text = (DIR / name).read_text()
        assert good[0] in text
        path = tmp_path / name
        path.write_text(text.replace(*good))
        r = run(pd_pack, path, "-o", tmp_path / (name + ".h5"), "-q")
        assert r.returncode == 0, (name, r.stderr)
