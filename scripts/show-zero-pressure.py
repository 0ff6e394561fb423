# Render the imaged and the stress-free eye of a run side by side (the
# stress-free one coloured by how far each node moves to its imaged place),
# and their outlines in the symmetry plane z = 0 around the apex.
# Usage: xvfb-run -a pvbatch scripts/show-zero-pressure.py RUN_FOLDER OUT.png
# (needs ParaView: apt-get install paraview python3-paraview xvfb; the run
# must have zero_pressure.enabled = true and output.fields = true)
import os
import sys

from paraview.simple import (AssignViewToLayout, Clean, ColorBy, CreateLayout, CreateView,
                             FeatureEdges, GetColorTransferFunction, PythonCalculator,
                             SaveScreenshot, Show, Slice, Text, Transform, Xdmf3ReaderS)

run, png = os.path.abspath(sys.argv[1]), sys.argv[2]
imaged = Xdmf3ReaderS(FileName=[os.path.join(run, "geometry_imaged.xdmf")])
stress_free = Xdmf3ReaderS(FileName=[os.path.join(run, "geometry_stress_free.xdmf")])
# Both files hold the same mesh with other coordinates: nodes correspond.
offset = PythonCalculator(Input=[stress_free, imaged], ArrayName="to_imaged_mm",
                          Expression="mag(inputs[1].Points - inputs[0].Points)")

layout = CreateLayout("zero pressure")
layout.SplitHorizontal(0, 1.0 / 3)
layout.SplitHorizontal(2, 0.5)  # cells: 1 | 5 | 6


def view(title, cell):
    v = CreateView("RenderView")
    v.OrientationAxesVisibility = 1
    Show(Text(Text=title), v)
    AssignViewToLayout(view=v, layout=layout, hint=cell)
    return v


def eye_camera(v):
    v.CameraPosition = [28, 14, 30]
    v.CameraFocalPoint = [3, 3, 3]
    v.CameraViewUp = [0, 1, 0]
    v.ResetCamera()


v = view("imaged (the mesh, at the IOP)", 1)
d = Show(imaged, v)
d.Representation = "Surface With Edges"
d.ColorArrayName = ["POINTS", ""]
d.AmbientColor = d.DiffuseColor = [0.9, 0.6, 0.3]
eye_camera(v)

v = view("stress-free (found): distance to the imaged place [mm]", 5)
d = Show(offset, v)
d.Representation = "Surface With Edges"
ColorBy(d, ("POINTS", "to_imaged_mm"))
d.RescaleTransferFunctionToDataRange(True, False)
d.SetScalarBarVisibility(v, True)
GetColorTransferFunction("to_imaged_mm").ApplyPreset("Viridis (matplotlib)", True)
eye_camera(v)

v = view("z = 0 near the apex: imaged (orange), stress-free (blue)", 6)
for source, colour, z in [(stress_free, [0.1, 0.3, 0.9], 0.0), (imaged, [0.9, 0.5, 0.1], 0.1)]:
    cut = Slice(Input=source)
    cut.SliceType.Origin = [0, 0, 1e-4]  # just inside: the plane z = 0 is a face
    cut.SliceType.Normal = [0, 0, 1]
    outline = FeatureEdges(Input=Clean(Input=cut), BoundaryEdges=1, FeatureEdges=0,
                           NonManifoldEdges=0, ManifoldEdges=0)
    lifted = Transform(Input=outline)  # towards the camera: drawn on top
    lifted.Transform.Translate = [0, 0, z]
    d = Show(lifted, v)
    d.ColorArrayName = ["POINTS", ""]  # solid colour, not a scalar map
    d.AmbientColor = d.DiffuseColor = colour
    d.LineWidth = 3
v.CameraPosition = [1.0, 12.8, 30]
v.CameraFocalPoint = [1.0, 12.8, 0]
v.CameraViewUp = [0, 1, 0]
v.CameraParallelProjection = 1
v.CameraParallelScale = 0.7

layout.SetSize(1920, 600)
SaveScreenshot(png, layout, ImageResolution=[1920, 600])
print("wrote", png)
