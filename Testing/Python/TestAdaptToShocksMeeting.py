"""AdaptToShocks on two plane shocks that meet (issue 12's "two shocks that
meet"): a clear error naming the cause, and the input passed through.

The case (Data/analytic_shock.py, MeetingShocks): two smeared oblique shocks
of the same freestream (Mach 2.5, 15 degrees, delta = 1/16) through the
centre of the Gmsh cube of Data/oblique_shock_unstructured.vtu, the second
turned 45 degrees about the freestream, so that the shock sheet is two
half-planes 35.6 degrees apart meeting at a line through the cube. The
sensor marks one connected cluster; every template fits it badly, yet
before this check the cone was chosen and embedded without a word.
- Refused: "two shocks meet in cluster 0", the two families' angle in the
  message within 3 degrees of the exact 35.6, the input passed through (same
  cells, no Region, no surface on port 1).
- At 16 degrees apart (turn 20) still refused, the angle within 3 degrees.
- The control, on the same mesh and smearing: a single plane shock is not
  refused (adapted, one plane surface). The bundled cone and wedge (and the
  validation solutions) are TestAdaptToShocks' and TestValidationCase's
  cases, which fail if the check fires there.
"""
import re

import numpy as np
from paraview.simple import *
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid
from vtkmodules.util.numpy_support import numpy_to_vtk

import artest
from artest import check
from analytic_shock import MeetingShocks, ObliqueShock

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)
cube = artest.fetch(XMLUnstructuredGridReader(FileName=[artest.data("oblique_shock_unstructured.vtu")]))


def solution(shock):
    g = vtkUnstructuredGrid()
    g.CopyStructure(cube.VTKObject)
    for name, values in shock.fields(np.asarray(cube.Points)).items():
        if name in ("U", "p", "rho", "T"):
            a = numpy_to_vtk(np.ascontiguousarray(values, dtype=np.float64), deep=1)
            a.SetName(name)
            g.GetPointData().AddArray(a)
    source = PVTrivialProducer()
    source.GetClientSideObject().SetOutput(g)
    return source


def adapt(shock):
    before = len(messages.GetOutput())
    proxy = AdaptToShocks(Input=solution(shock))
    out, surf = artest.fetch(proxy), artest.fetch(proxy, 1)
    return out, surf, messages.GetOutput()[before:]


for turn in (45.0, 20.0):
    shock = MeetingShocks(turn_deg=turn)
    # the exact case: both half-planes cross the cube, the line inside it
    foot = shock.origin + shock.normal_mach_unity_offset() * (shock.normals[0] + shock.normals[1]) / (
        1.0 + shock.normals[0] @ shock.normals[1])
    side = np.asarray(shock.fields(np.asarray(cube.Points))["Side"])
    check(np.all(np.abs(foot - 0.5) < 0.1) and 0.3 < side.mean() < 0.7,
          "turn %g: two half-planes %.1f deg apart meeting at a line through (%.2f, %.2f, %.2f), %.0f%% of the nodes "
          "on the second shock's side" % ((turn, shock.angle_deg) + tuple(foot) + (100 * side.mean(),)))
    out, surf, text = adapt(shock)
    found = re.search(r"two shocks meet in cluster 0 \(\d+ nodes\): .* form two families ([0-9.]+) degrees apart", text)
    angle = float(found.group(1)) if found else float("nan")
    check(found is not None and "passes through unchanged" in text and abs(angle - shock.angle_deg) < 3.0,
          "turn %g: refused, two shocks meet in cluster 0, the families %.1f deg apart (exact %.1f)"
          % (turn, angle, shock.angle_deg))
    check(out.GetNumberOfCells() == cube.GetNumberOfCells() and out.GetNumberOfPoints() == cube.GetNumberOfPoints()
          and "Region" not in out.CellData.keys() and surf.GetNumberOfCells() == 0,
          "turn %g: the input passes through (%d cells), no surface" % (turn, out.GetNumberOfCells()))

# ---- The control: one plane shock on the same mesh is adapted.
out, surf, text = adapt(ObliqueShock())
check("two shocks meet" not in text and "Region" in out.CellData.keys()
      and artest.field(out, "NumberOfSurfaces")[0] == 1 and surf.FieldData["Template"].GetValue(0) == "Plane",
      "one plane shock on the same mesh: not refused, adapted with one plane")

artest.finish()
