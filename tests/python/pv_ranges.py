# SPDX-License-Identifier: MIT
"""Run by ParaView's pvbatch (not by pytest): opens an .xmf (legacy XDMFReader, XDMF 2) or a .pvd
with ParaView's own readers, steps through every time and prints, as one JSON line, the number of
points and the range of every point array (per component and magnitude) at each time.
Usage: pvbatch pv_ranges.py FILE.xmf|FILE.pvd"""

import json
import sys

from paraview import servermanager
from paraview.simple import PVDReader, UpdatePipeline, XDMFReader

path = sys.argv[1]
reader = XDMFReader(FileNames=[path]) if path.endswith(".xmf") else PVDReader(FileName=path)
reader.UpdatePipelineInformation()
times = list(reader.TimestepValues) if reader.TimestepValues else [0.0]
out = {"times": times, "frames": []}
for t in times:
    UpdatePipeline(time=t, proxy=reader)
    data = servermanager.Fetch(reader)
    if data.IsA("vtkMultiBlockDataSet"):  # flatten a one-block composite
        data = data.GetBlock(0)
    pd = data.GetPointData()
    frame = {"time": t, "points": data.GetNumberOfPoints(), "arrays": {}}
    pts = data.GetPoints()
    if pts is not None:
        frame["bounds"] = list(data.GetBounds())
    for i in range(pd.GetNumberOfArrays()):
        a = pd.GetArray(i)
        nc = a.GetNumberOfComponents()
        frame["arrays"][a.GetName()] = {
            "components": nc,
            "range": [list(a.GetRange(c)) for c in range(nc)],
        }
    out["frames"].append(frame)
print("PV_RANGES " + json.dumps(out))
