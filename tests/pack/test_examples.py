# SPDX-License-Identifier: MIT
"""Every examples/<case>/scene*.json packs (exit 0) and has a README.md; the preview draws a
non-empty PNG (workflows/preview/preview.py directly and through pd-pack --preview)."""

import subprocess
import sys

import pytest

from conftest import REPO, run

EXAMPLES = sorted(REPO.glob("examples/*/scene*.json"))
PREVIEW = REPO / "workflows" / "preview" / "preview.py"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("scene", EXAMPLES, ids=[p.parent.name + p.stem[5:] for p in EXAMPLES])
def test_example_packs(pd_pack, tmp_path, scene):
    assert (scene.parent / "README.md").is_file()
    out = tmp_path / "out.h5"
    r = run(pd_pack, scene, "-o", out, "-q")
    assert r.returncode == 0, r.stderr
    assert out.stat().st_size > 0


def test_preview_png(pd_pack, tmp_path):
    out = tmp_path / "scene.h5"
    assert run(pd_pack, REPO / "examples/compressive_small/scene.json", "-o", out, "-q").returncode == 0
    png = tmp_path / "scene.png"
    r = subprocess.run([sys.executable, str(PREVIEW), str(out), "-o", str(png)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    data = png.read_bytes()
    assert data.startswith(PNG_MAGIC) and len(data) > 10_000


def test_pd_pack_preview_option(pd_pack, tmp_path):
    png = tmp_path / "walls.png"
    r = run(pd_pack, REPO / "examples/attrition_sim1/scene.json", "-o", tmp_path / "a.h5",
            "--preview", png, "-q")
    assert r.returncode == 0, r.stderr
    assert png.read_bytes().startswith(PNG_MAGIC) and png.stat().st_size > 10_000
