# The puff as an animation: the eye warped by its displacement, coloured
# by the displacement's magnitude, seen from the side (the horizontal
# section z = 0 faces the camera), one PNG per output time from the start
# of the puff.
# Usage: xvfb-run -a pvbatch scripts/show-puff.py RUN_FOLDER OUT_DIR
# (needs ParaView: apt-get install paraview python3-paraview xvfb; the run
# must have a puff and output.fields = true). ParaView's GUI plays the
# same: open displacement.xdmf, Warp By Vector, press Play.
import os
import sys

from paraview.simple import (ColorBy, CreateView, GetColorTransferFunction, SaveScreenshot,
                             Show, Text, WarpByVector, Xdmf3ReaderS)

run, out = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
os.makedirs(out, exist_ok=True)
u = Xdmf3ReaderS(FileName=[os.path.join(run, "displacement.xdmf")])
u.UpdatePipelineInformation()
times = [t for t in u.TimestepValues if t >= 0]  # the puff
if not times:
    sys.exit(f"{run}: displacement.xdmf holds no time from the start of a puff on")
warped = WarpByVector(Input=u, Vectors=["POINTS", "displacement"], ScaleFactor=1.0)

v = CreateView("RenderView")
v.ViewSize = [900, 500]
v.OrientationAxesVisibility = 1
d = Show(warped, v)
ColorBy(d, ("POINTS", "displacement", "Magnitude"))
lut = GetColorTransferFunction("displacement")
lut.ApplyPreset("Viridis (matplotlib)", True)
lut.RescaleTransferFunction(0.0, 1.2)
d.SetScalarBarVisibility(v, True)
label = Text(Text="")
Show(label, v)
# From -z onto the section z = 0 (x grows to the left), the cornea at the top.
v.CameraPosition = [3, 8.5, -40]
v.CameraFocalPoint = [3, 8.5, 0]
v.CameraViewUp = [0, 1, 0]
v.CameraParallelProjection = 1
v.CameraParallelScale = 6.5
for k, t in enumerate(times):
    v.ViewTime = t
    label.Text = "t = %.1f ms from the start of the puff" % t
    SaveScreenshot(os.path.join(out, "puff.%04d.png" % k), v, ImageResolution=[900, 500])
print("wrote %d frames (t = %g to %g ms) to %s" % (len(times), times[0], times[-1], out))
