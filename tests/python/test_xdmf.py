# SPDX-License-Identifier: MIT
"""pd-post's ParaView products read by readers nobody here wrote: the XDMF sidecar and the .pvd
through ParaView's pvbatch (every time stepped through, every field's range compared with the
HDF5), every .vtu through meshio (damage and positions equal the file's)."""

import xml.etree.ElementTree as ET

import h5py
import meshio
import numpy as np
import pytest

from post_helpers import pvbatch_ranges, resting_disc, run

FIELDS = ("position", "velocity", "displacement", "force", "damage")


@pytest.fixture(scope="module")
def disc(tmp_path_factory, bin_dir):
    return resting_disc(tmp_path_factory, bin_dir)


@pytest.fixture(scope="module")
def frames(disc):
    with h5py.File(disc[0], "r") as f:
        pn = f["particles/nodes"]
        return {"time": pn["position/time"][()],
                "fields": {k: pn[k + "/value"][()] for k in FIELDS if k in pn},
                "body": f["nodes/body"][()], "volume": f["nodes/volume"][()]}


def expected_range(values):
    v = values.reshape(len(values), -1)
    return [[float(v[:, c].min()), float(v[:, c].max())] for c in range(v.shape[1])]


def check_paraview(result, frames):
    np.testing.assert_allclose(result["times"], frames["time"], rtol=1e-12)
    assert len(result["frames"]) == len(frames["time"])
    n = len(frames["body"])
    for k, fr in enumerate(result["frames"]):
        assert fr["points"] == n, "frame %d" % k
        for name, values in frames["fields"].items():
            got = fr["arrays"][name]
            assert got["components"] == (3 if values.ndim == 3 else 1)
            np.testing.assert_allclose(got["range"], expected_range(values[k]), rtol=1e-12,
                                       atol=1e-300, err_msg="%s, frame %d" % (name, k))
        pos = frames["fields"]["position"][k]
        np.testing.assert_allclose(fr["bounds"], np.ravel(
            [[pos[:, c].min(), pos[:, c].max()] for c in range(3)]), rtol=1e-12)


def test_xdmf_is_xdmf2_hyperslab(disc):
    h5, post = disc
    root = ET.parse(post / (h5.stem + ".xmf")).getroot()
    assert root.tag == "Xdmf" and root.get("Version") == "2.0"
    topo = root.find(".//Topology")
    assert topo.get("TopologyType") == "Polyvertex" and topo.get("NodesPerElement") == "1"
    slabs = root.findall(".//DataItem[@ItemType='HyperSlab']")
    assert slabs
    # The heavy data is referenced, not copied: relative path to the HDF5 file.
    ref = slabs[0].findall("DataItem")[1].text
    assert ref == "../%s:/particles/nodes/position/value" % h5.name


def test_xdmf_in_paraview(disc, frames):
    h5, post = disc
    result = pvbatch_ranges(post / (h5.stem + ".xmf"))
    check_paraview(result, frames)
    for fr in result["frames"]:
        assert fr["arrays"]["body"]["range"] == [[0.0, 0.0]]
        np.testing.assert_allclose(fr["arrays"]["volume"]["range"],
                                   [[frames["volume"].min(), frames["volume"].max()]], rtol=1e-12)


def test_pvd_in_paraview(disc, frames):
    h5, post = disc
    check_paraview(pvbatch_ranges(post / (h5.stem + ".pvd")), frames)


def test_vtu_damage_equals_file(disc, frames):
    h5, post = disc
    for k in range(len(frames["time"])):
        m = meshio.read(post / ("%s_%06d.vtu" % (h5.stem, k)))
        np.testing.assert_array_equal(m.points, frames["fields"]["position"][k])
        np.testing.assert_array_equal(np.ravel(m.point_data["damage"]),
                                      frames["fields"]["damage"][k])


def test_xdmf_beside_moved_pair(synthetic_file, pd_post, tmp_path):
    """The .xmf names the HDF5 file relative to itself: the pair opens after a move."""
    out = tmp_path / "out"
    r = run(pd_post, synthetic_file, "-o", out, "--no-vtu", "--no-csv", "--no-grains")
    assert r.returncode == 0, r.stderr
    text = (out / "synthetic.xmf").read_text()
    assert "../synthetic.h5:/particles/nodes/damage/value" in text
    assert text.count("<Grid Name=\"frame_") == 3
