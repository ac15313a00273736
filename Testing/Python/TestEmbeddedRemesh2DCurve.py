"""EmbeddedRemesh's 2-D mode on the OpenFOAM wedge (Data/wedge15Ma5.vtu)
with a curved open feature: a circular arc (centre (-0.05, 0), radius 0.1,
from 10 to 80 degrees, a curved shock's shape) extruded through the depth.
The curve must stay open: every node of the embedded surface lies on the
arc, the embedded faces form one chain whose ends are the arc's ends (its
last point kept), and the mesh is valid. (The curve's ends were compared
through one shared GetPoint buffer, so every curve of more than three points
was taken for a closed loop: its last point dropped and a chord from there
back to its start embedded, across the cavity.)
"""
import numpy as np
from paraview.simple import *
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkPoints, vtkStringOutputWindow
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.util.numpy_support import vtk_to_numpy

import artest
from artest import check

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)

CENTRE, RADIUS, A0, A1 = np.array([-0.05, 0.0]), 0.1, np.radians(10.0), np.radians(80.0)
wedge = XMLUnstructuredGridReader(FileName=[artest.data("wedge15Ma5.vtu")])

arc = vtkPolyData()
points = vtkPoints()
points.SetDataTypeToDouble()
angles = np.linspace(A0, A1, 71)
for z in (-0.01, 0.01):  # beyond the mesh's depth (+-0.005): the mid-plane cut is the arc
    for a in angles:
        points.InsertNextPoint(CENTRE[0] + RADIUS * np.cos(a), CENTRE[1] + RADIUS * np.sin(a), z)
quads = vtkCellArray()
n = len(angles)
for k in range(n - 1):
    quads.InsertNextCell(4, [k, k + 1, n + k + 1, n + k])
arc.SetPoints(points)
arc.SetPolys(quads)
source = PVTrivialProducer()
source.GetClientSideObject().SetOutput(arc)

er = EmbeddedRemesh(Input=wedge, Surfaces=[source])
before = len(messages.GetOutput())
out = artest.fetch(er)
text = messages.GetOutput()[before:]
emb = artest.fetch(er, 1)
check("ERROR" not in text and artest.field(out, "TwoDimensional")[0] == 1,
      "the arc is embedded in 2-D mode without an error (%s)" % text.strip()[:300])
P = np.asarray(emb.Points, dtype=np.float64)
polys = emb.VTKObject.GetPolys()
offsets, conn = vtk_to_numpy(polys.GetOffsetsArray()), vtk_to_numpy(polys.GetConnectivityArray())
cells = [conn[offsets[i]:offsets[i + 1]] for i in range(len(offsets) - 1)]
used = np.unique(conn)
r = np.hypot(P[used, 0] - CENTRE[0], P[used, 1] - CENTRE[1])
# (1e-5: the input arc is a polyline of 1-degree chords, 3.8e-6 off the circle at most.)
check(len(cells) > 20 and np.abs(r - RADIUS).max() < 1e-5,
      "all %d nodes of the %d embedded faces lie on the arc (largest |r - R| %.1e; a chord across the cavity "
      "would be %.3f off it)" % (len(used), len(cells), np.abs(r - RADIUS).max() if len(used) else np.nan,
                                 RADIUS * (1 - np.cos((A1 - A0) / 2))))
theta = np.arctan2(P[used, 1] - CENTRE[1], P[used, 0] - CENTRE[0])
# S is trimmed BoundaryMargin edge lengths back from the domain's boundary only: these ends are inside.
check(abs(theta.min() - A0) < 1e-6 and abs(theta.max() - A1) < 1e-6,
      "the chain runs from the arc's first point to its last (%.4f to %.4f deg; arc %.1f to %.1f)"
      % (np.degrees(theta.min()), np.degrees(theta.max()), np.degrees(A0), np.degrees(A1)))
artest.check_valid_mesh("arc, 2-D", artest.fetch(wedge), out, None)

artest.finish()
