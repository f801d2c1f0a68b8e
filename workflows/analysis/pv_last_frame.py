#!/usr/bin/pvbatch
# SPDX-License-Identifier: MIT
"""The last frame of a pd-post .pvd as a PNG, nodes coloured by a point field (ParaView 5.11).

    xvfb-run -a -s "-screen 0 1280x1024x24" pvbatch pv_last_frame.py post/run.pvd last.png [damage]

pvbatch needs Debian's paraview package and python3-paraview's modules on PYTHONPATH (`make deps`
unpacks them into .deps/paraview-python; README "ParaView"); rendering needs an X display
(xvfb-run gives a virtual one; its default 8-bit screen cannot render: pass -s as above)."""
import sys

from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetAnimationScene, PVDReader,
                             Render, SaveScreenshot, Show)

pvd, png = sys.argv[1], sys.argv[2]
field = sys.argv[3] if len(sys.argv) > 3 else "damage"
reader = PVDReader(FileName=pvd)
scene = GetAnimationScene()
scene.UpdateAnimationUsingDataTimeSteps()
scene.AnimationTime = reader.TimestepValues[-1]
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [800, 600]
view.Background = [1, 1, 1]
view.OrientationAxesVisibility = 0
display = Show(reader, view)
display.PointSize = 4
ColorBy(display, ("POINTS", field))
display.RescaleTransferFunctionToDataRange(True)
display.SetScalarBarVisibility(view, True)
view.ResetCamera()
Render(view)
SaveScreenshot(png, view, ImageResolution=[800, 600])
print("wrote %s: %s at t = %g s" % (png, field, reader.TimestepValues[-1]))
