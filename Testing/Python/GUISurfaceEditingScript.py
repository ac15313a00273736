"""Run inside the real ParaView GUI (paraview --script=... --exit) by
RunGUISurfaceEditing.py: the wedge's shock surface, hand-edited (selected
cells removed, trimmed with a plane, extended to the back plane z = -0.005),
shown over the mesh; a screenshot is saved to AR_GUI_SCREENSHOT. The surface
is QuadricFit's plane, or with AR_GUI_SOURCE=medial the medial sheet of the
WeightFunction isosurface (MedialAxisDelaunay with the front and back planes
as symmetry planes)."""
import os

import numpy as np
from paraview.simple import *
from paraview import servermanager

LoadPlugin(os.environ["AR_PLUGIN"], remote=False, ns=globals())
out_png = os.environ["AR_GUI_SCREENSHOT"]
stage = os.environ.get("AR_GUI_STAGE", "extend")

reader = XMLUnstructuredGridReader(FileName=[os.path.join(os.environ["AR_DATA_DIR"], "wedge15Ma5.vtu")])
weight = WeightFunction(Input=reader, Variables=["rho", "rhoU", "rhoE"], ComputePointWeight=1)
clusters = FeatureCluster(Input=weight, SensorArray=["POINTS", "WeightFunction"], SensorRange=[1.5, 2.0])
if os.environ.get("AR_GUI_SOURCE", "fit") == "medial":
    contour = Contour(Input=weight, ContourBy=["POINTS", "WeightFunction"], Isosurfaces=[1.5], ComputeNormals=1)
    fit = MedialAxisDelaunay(Input=contour, Domain=reader,
                             SymmetryPlanes=[0, 0, -0.005, 0, 0, 1, 0, 0, 0.005, 0, 0, 1])
else:
    fit = QuadricFit(Input=OutputPort(clusters, 1), Domain=reader, Template="Plane", ClusterId=0)
fit.UpdatePipeline()
surface = servermanager.Fetch(fit)
bounds = surface.GetBounds()

# Select the cells of the upper third of the shock surface, as the Select
# Cells tool would, and hand the active selection to RemoveSelectedCells
# (what Copy Active Selection does).
from vtkmodules.numpy_interface import dataset_adapter as dsa
from vtkmodules.vtkFiltersCore import vtkCellCenters
centers = vtkCellCenters()
centers.SetInputData(surface)
centers.Update()
c = dsa.WrapDataObject(centers.GetOutput()).Points
ytop = bounds[2] + 0.7 * (bounds[3] - bounds[2])
chosen = np.flatnonzero((c[:, 1] > ytop) & (c[:, 2] > 0.0))
SelectIDs(IDs=sum([[0, int(i)] for i in chosen], []), FieldType='CELL', Source=fit)
selection = fit.GetSelectionInput(0)
remove = RemoveSelectedCells(Input=fit, Selection=selection)
trim = TrimSurface(Input=remove)
trim.TrimType = 'Plane'
trim.TrimType.Origin = [0.0, 0.0, -0.002]
trim.TrimType.Normal = [0.0, 0.0, 1.0]
trim.Invert = 0
extend = ExtendToPlane(Input=trim, PlaneOrigin=[0.0, 0.0, -0.005], PlaneNormal=[0.0, 0.0, 1.0])
last = {"fit": fit, "remove": remove, "trim": trim, "extend": extend}[stage]

view = GetActiveViewOrCreate('RenderView')
size = [int(v) for v in os.environ.get("AR_GUI_SIZE", "800x600").split("x")]
view.ViewSize = size
view.OrientationAxesVisibility = 1
mesh = Show(reader, view)
mesh.Representation = 'Wireframe'
mesh.Opacity = 0.25
mesh.ColorArrayName = ['POINTS', '']
mesh.AmbientColor = mesh.DiffuseColor = [0.5, 0.5, 0.5]
shown = Show(last, view)
# The medial sheet's Voronoi triangles are small: edges drawn would hide the colours.
shown.Representation = 'Surface' if os.environ.get("AR_GUI_SOURCE") == "medial" else 'Surface With Edges'
if stage == "extend":
    ColorBy(shown, ('CELLS', 'Extended'))
    lut = GetColorTransferFunction('Extended')
    lut.ApplyPreset('Cool to Warm', True)
    lut.RescaleTransferFunction(0.0, 1.0)
    shown.SetScalarBarVisibility(view, True)
else:
    shown.ColorArrayName = ['POINTS', '']
    shown.DiffuseColor = [0.9, 0.4, 0.1]
# The wedge is thin in z (0.01 against 0.5): stretch z so the edits show.
for d in (mesh, shown):
    d.Scale = [1.0, 1.0, 20.0]
SetActiveSource(reader)  # no widget drawn over the picture
view.CameraPosition = [0.5 * (bounds[0] + bounds[1]) - 0.4, 0.5 * (bounds[2] + bounds[3]) + 0.5, 0.8]
view.CameraFocalPoint = [0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), 0.0]
view.CameraViewUp = [0.0, 1.0, 0.0]
view.ResetCamera()
Render(view)
SaveScreenshot(out_png, view, ImageResolution=size)
ext = servermanager.Fetch(extend)
with open(out_png + ".txt", "w") as f:
    f.write("selected %d removed %d trim %d extend %d extended_edges %d\n" % (
        len(chosen), surface.GetNumberOfCells() - servermanager.Fetch(remove).GetNumberOfCells(),
        servermanager.Fetch(trim).GetNumberOfCells(), ext.GetNumberOfCells(),
        ext.GetFieldData().GetArray("NumberOfExtendedEdges").GetValue(0)))
