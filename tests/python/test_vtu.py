# SPDX-License-Identifier: MIT
"""(b) pd-post's ParaView output: every frame's .vtu, read back with meshio, holds one vertex per
node at the frame's positions and the frame's fields bit for bit, then each grain's outline (issue
28: the boundary edges of its reference mesh, 2D lines, so ParaView shows the grains' shapes);
the .pvd lists every frame with the times of /particles/nodes/position/time."""
import collections

import pathlib
import xml.etree.ElementTree as ET

import h5py
import meshio
import numpy as np
import pytest

FIELDS = ("position", "velocity", "displacement", "force", "damage")

@pytest.fixture(scope="module")
def frames(h5file):
    with h5py.File(h5file, "r") as f:
        pn = f["particles/nodes"]
        return {
            "n": f["nodes/volume"].shape[0],
            "time": pn["position/time"][()],
            "step": pn["position/step"][()],
            "fields": {k: pn[k + "/value"][()] for k in FIELDS if k in pn},
            "body": f["nodes/body"][()],
            "volume": f["nodes/volume"][()],
        }


@pytest.fixture(scope="module")
def outline(h5file):
    """The boundary facets of every body's reference mesh (2D: edges of one cell), global ids."""
    with h5py.File(h5file, "r") as f:
        assert int(f.attrs.get("dimension", 2)) == 2
        off, ref = f["bodies/node_offsets"][()], f["bodies/ref_mesh"][()]
        cells = {int(k.split("_")[1]): f["reference_meshes"][k]["cells"][()]
                 for k in f["reference_meshes"]}
    edges = set()
    for b in range(len(off) - 1):
        count = collections.Counter()
        for c in cells[int(ref[b])]:
            for k in range(len(c)):
                count[tuple(sorted((off[b] + c[k], off[b] + c[(k + 1) % len(c)])))] += 1
        edges |= {e for e, n in count.items() if n == 1}
    return edges


@pytest.fixture(scope="module")
def pvd(post_dir, h5file):
    path = post_dir / (h5file.stem + ".pvd")
    assert path.is_file(), "%s missing" % path
    root = ET.parse(path).getroot()
    assert root.tag == "VTKFile" and root.get("type") == "Collection"
    return [(float(d.get("timestep")), post_dir / d.get("file"))
            for d in root.iter("DataSet")]


def test_pvd_lists_every_frame(pvd, frames):
    assert len(pvd) == len(frames["time"])
    np.testing.assert_array_equal([t for t, _ in pvd], frames["time"])
    for _, path in pvd:
        assert path.is_file(), path


def test_vtu_matches_frames(pvd, frames, outline):
    fields = frames["fields"]
    assert {"position", "velocity", "damage"} <= set(fields)
    assert len(outline) > 0
    for k, (_, path) in enumerate(pvd):
        m = meshio.read(path)
        assert m.points.shape == (frames["n"], 3)
        assert [c.type for c in m.cells] == ["vertex", "line"]
        assert len(m.cells[0].data) == frames["n"]
        lines = {tuple(sorted(e)) for e in m.cells[1].data.tolist()}
        assert len(lines) == len(m.cells[1].data) and lines == outline
        np.testing.assert_array_equal(m.points, fields["position"][k])
        for name, values in fields.items():
            got = np.asarray(m.point_data[name]).reshape(values[k].shape)
            np.testing.assert_array_equal(got, values[k], err_msg="%s, frame %d" % (name, k))
        np.testing.assert_array_equal(m.point_data["body"], frames["body"])
        np.testing.assert_array_equal(m.point_data["volume"], frames["volume"])


def test_no_stale_vtu(pvd, post_dir, h5file):
    listed = {p.name for _, p in pvd}
    on_disk = {p.name for p in pathlib.Path(post_dir).glob(h5file.stem + "_*.vtu")}
    assert on_disk == listed


def test_vtk_reader_reads_vtu(pvd, frames, outline):
    """VTK's own XML reader (what ParaView uses) reads the last frame: VTK_VERTEX cells, then the
    outline's VTK_LINE cells, fields."""
    vtk = pytest.importorskip("vtk")
    from vtk.util.numpy_support import vtk_to_numpy

    k = len(pvd) - 1
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(str(pvd[k][1]))
    r.Update()
    g = r.GetOutput()
    assert g.GetNumberOfPoints() == frames["n"]
    assert g.GetNumberOfCells() == frames["n"] + len(outline)
    types = [g.GetCellType(i) for i in range(g.GetNumberOfCells())]
    assert set(types[:frames["n"]]) == {vtk.VTK_VERTEX} and set(types[frames["n"]:]) == {vtk.VTK_LINE}
    np.testing.assert_array_equal(vtk_to_numpy(g.GetPoints().GetData()),
                                  frames["fields"]["position"][k])
    np.testing.assert_array_equal(vtk_to_numpy(g.GetPointData().GetArray("damage")),
                                  frames["fields"]["damage"][k])
