# The air puff at one time: the speed and the pressure on the symmetry
# plane z = 0 (the jet from the nozzle at the top onto the eye below),
# two PNGs. Usage:
#   xvfb-run -a pvbatch scripts/show-air.py RUN_FOLDER OUT_DIR [TIME_MS]
# (needs ParaView: apt-get install paraview python3-paraview xvfb; the run
# must be an air run with output.fields = true; TIME_MS defaults to the
# output time nearest the inlet's peak, 10 ms). In ParaView's GUI: open
# air_velocity.xdmf and air_pressure.xdmf, Slice (normal z), colour.
import os
import sys

from paraview.simple import (ColorBy, CreateView, GetColorTransferFunction, SaveScreenshot,
                             Show, Slice, Text, Xdmf3ReaderS)

run, out = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
wanted = float(sys.argv[3]) if len(sys.argv) > 3 else 10.0
os.makedirs(out, exist_ok=True)
for name, title, component, bounds in (
        ("air_velocity", "air speed [mm/ms = m/s]", "Magnitude", (0.0, 130.0)),
        ("air_pressure", "air pressure [MPa] (65 mmHg = 0.0087 MPa)", None, (-0.002, 0.01))):
    path = os.path.join(run, name + ".xdmf")
    if not os.path.exists(path):
        sys.exit(f"{path}: not found (an air run with output.fields = true?)")
    f = Xdmf3ReaderS(FileName=[path])
    f.UpdatePipelineInformation()
    time = min(f.TimestepValues, key=lambda t: abs(t - wanted))
    cut = Slice(Input=f)
    cut.SliceType.Origin = [0, 0, 1e-3]  # just inside: a cut on the boundary face is empty
    cut.SliceType.Normal = [0, 0, 1]
    v = CreateView("RenderView")
    v.ViewSize = [700, 900]
    v.ViewTime = time
    d = Show(cut, v)
    ColorBy(d, ("POINTS", name, component) if component else ("POINTS", name))
    lut = GetColorTransferFunction(name)
    lut.ApplyPreset("Turbo" if component else "Cool to Warm", True)
    lut.RescaleTransferFunction(*bounds)
    d.SetScalarBarVisibility(v, True)
    Show(Text(Text=f"{title}, t = {time:.2f} ms"), v)
    # From +z onto the plane z = 0: the axis vertical, the nozzle on top.
    v.CameraPosition = [4, 20, 60]
    v.CameraFocalPoint = [4, 20, 0]
    v.CameraViewUp = [0, 1, 0]
    v.CameraParallelProjection = 1
    v.CameraParallelScale = 10
    SaveScreenshot(os.path.join(out, f"{name}.png"), v)
    print(os.path.join(out, f"{name}.png"))
