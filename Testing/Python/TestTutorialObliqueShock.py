"""adapt_case.py on OpenFOAM's own obliqueShock tutorial, as shipped: a case
nobody here prepared, with two shocks that meet. The tutorial
(compressible/rhoCentralFoam/obliqueShock of openfoam-examples: 60 x 30
hexahedra one cell deep, 4.1 x 1; Mach 2.9 from the inlet; the top wall
imposes the flow turned 10.94 degrees, so a shock leaves its corner (0, 1)
and reflects off the bottom symmetry plane) is meshed with blockMesh and
solved with rhoCentralFoam to its own endTime (10, about 7 s), then
`adapt_case.py SOURCE TARGET` (write only, every default). Asserts:
- exit 0, and the report names two plane surfaces;
- the reflected shock (the surface downstream of the reflection) lies within
  0.5 degree of theta-beta-Mach (23.28 degrees to the wall: the incident
  shock's 29.00 at Mach 2.9, then 10.94 degrees back from Mach 2.38);
- the incident shock lies within 0.5 degree of the solution's own (a line
  through p's half-jump crossings on 11 horizontal lines, y = 0.35 .. 0.85;
  the tutorial's coarse cells put it at 29.7, 0.7 degree steeper than
  theory, and the fitted plane follows the solution);
- both surfaces meet the bottom plane within one input cell (4.1 / 60) of
  the exact reflection point x = 1 / tan(29.00 deg) = 1.804;
- the new cells at the shock are at most a third of the input's size
  (the report's SurfaceSizeRatio);
- the written case: checkMesh "Mesh OK", the tutorial's patches with their
  types, p, U and T at time 0.
"""
import math
import os
import re
import shutil
import sys

import numpy as np
from paraview.simple import *
from paraview import servermanager
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
from vtkmodules.util.numpy_support import vtk_to_numpy

import artest
from artest import check
import foamcase

sys.path.insert(0, os.environ["AR_DATA_DIR"])
import theta_beta_mach  # noqa: E402
from convert_cone20Ma2p5 import probe_p  # noqa: E402
from make_validation_case import last_crossing  # noqa: E402

GAMMA = 1.4
MACH = 2.9
U_TOP = (2.61933, -0.50632)  # the tutorial's 0/U on the top wall
CELL = 4.1 / 60.0            # the tutorial's cells along x
TOLERANCE = 0.5              # degrees

deflection = math.degrees(math.atan2(-U_TOP[1], U_TOP[0]))
beta1 = theta_beta_mach.shock_angle(MACH, deflection, GAMMA)
mach2 = theta_beta_mach.oblique_shock_jump(MACH, beta1, GAMMA).M2
reflected = theta_beta_mach.shock_angle(mach2, deflection, GAMMA) - deflection
x_reflection = 1.0 / math.tan(math.radians(beta1))
artest.say("theory: incident shock %.3f deg, reflected %.3f deg to the wall, reflection at x = %.4f"
           % (beta1, reflected, x_reflection))

root = os.path.join(artest.OUTPUT_DIR, "tutorial_oblique_shock")
shutil.rmtree(root, ignore_errors=True)
os.makedirs(root)
source, target = os.path.join(root, "source"), os.path.join(root, "target")
bashrc = foamcase.bashrc("the obliqueShock tutorial")
if not foamcase.solved_tutorial(bashrc, foamcase.tutorial("compressible/rhoCentralFoam/obliqueShock"), source,
                                10, 1, check):
    artest.finish()

script = os.path.join(os.path.dirname(os.environ["AR_DATA_DIR"]), "Plugin", "Scripts", "adapt_case.py")
rc, _ = artest.run([artest.require_program("pvbatch", "paraview"), script, source, target,
                      "--plugin", os.environ["AR_PLUGIN"]])
report = open(os.path.join(target, "report.md")).read() if os.path.exists(os.path.join(target, "report.md")) else ""
m = re.search(r"(\d+) surface\(s\) \(([^)]*)\)", report)
check(rc == 0 and m is not None and m.group(1) == "2" and m.group(2) == "Plane, Plane",
      "adapt_case.py exits 0 (%d) and fits two planes (report: %s)" % (rc, m.group(0) if m else "no surfaces"))
if rc != 0 or m is None:
    artest.finish()

# each fitted surface as a line in the x-y plane: the plane through its points
r = vtkXMLPolyDataReader()
r.SetFileName(os.path.join(target, "cycle1_surfaces.vtp"))
r.Update()
surf = r.GetOutput()
P = vtk_to_numpy(surf.GetPoints().GetData()).astype(np.float64)
ids = vtk_to_numpy(surf.GetCellData().GetArray("SurfaceId"))
lines = []
for sid in np.unique(ids):
    used = set()
    for c in np.where(ids == sid)[0]:
        cp = surf.GetCell(int(c)).GetPointIds()
        used.update(cp.GetId(k) for k in range(cp.GetNumberOfIds()))
    n, centre = artest.fit_plane(P[sorted(used)])
    # the line's angle to +x is the normal's to +y; it meets y = 0 where
    # n . (x - centre) = 0
    lines.append(dict(mean_x=centre[0], angle=math.degrees(math.atan(abs(n[0] / n[1]))),
                      x0=centre[0] + centre[1] * n[1] / n[0]))
lines.sort(key=lambda s: s["mean_x"])
incident, downstream = lines[0], lines[-1]

# the solution's own incident shock: p's half-jump on horizontal lines
# between the inlet and the reflected shock (last_crossing, as the
# validation cases measure theirs)
open(os.path.join(source, "read.foam"), "w").close()
reader = OpenFOAMReader(FileName=os.path.join(source, "read.foam"))
reader.MeshRegions = ["internalMesh"]
reader.UpdatePipeline(10.0)
grid = servermanager.Fetch(MergeBlocks(Input=reader))
heights, crossings = np.linspace(0.35, 0.85, 11), []
for y in heights:
    x_end = x_reflection + y / math.tan(math.radians(reflected)) - 6 * CELL
    origin = np.array([0.0, y, 0.05])
    ends = origin + np.r_[np.linspace(0.0, 0.01 * x_end, 20), np.linspace(0.99 * x_end, x_end, 20)][:, None] * [1, 0, 0]
    p_ends, inside = probe_p(grid, ends)
    half = 0.5 * (p_ends[:20][inside[:20]].mean() + p_ends[20:][inside[20:]].mean())
    crossings.append(last_crossing(grid, origin, np.array([1.0, 0.0, 0.0]), 0.0, x_end, half))
own = (math.degrees(math.atan(1.0 / abs(np.polyfit(heights, crossings, 1)[0]))) if None not in crossings
       else float("nan"))  # a line without a crossing fails the check below

check(abs(downstream["angle"] - reflected) <= TOLERANCE,
      "the reflected shock's plane at %.2f deg to the wall, theory %.2f (%+.2f; at most %.1f)"
      % (downstream["angle"], reflected, downstream["angle"] - reflected, TOLERANCE))
check(abs(incident["angle"] - own) <= TOLERANCE,
      "the incident shock's plane at %.2f deg, the solution's own shock at %.2f (%+.2f; at most %.1f; theory %.2f)"
      % (incident["angle"], own, incident["angle"] - own, TOLERANCE, beta1))
for name, s in (("incident", incident), ("reflected", downstream)):
    check(abs(s["x0"] - x_reflection) <= CELL,
          "the %s shock's plane meets the bottom plane at x = %.4f, the exact reflection at %.4f (%+.4f; at most "
          "one input cell, %.4f)" % (name, s["x0"], x_reflection, s["x0"] - x_reflection, CELL))
ratio = re.search(r"new cells at the shock ([0-9.]+) of the input's size", report)
check(ratio is not None and float(ratio.group(1)) <= 1.0 / 3.0,
      "the new cells at the shock are %s of the input's size (at most 1/3)" % (ratio.group(1) if ratio else "?"))

# the written case
case = os.path.join(target, "cycle1")
check("Mesh OK." in foamcase.run(bashrc, case, "checkMesh")[1], "checkMesh on the adapted case: Mesh OK")
types = foamcase.patch_types(case)
want = {"top": "wall", "inlet": "patch", "outlet": "patch", "bottom": "symmetryPlane", "frontAndBack": "empty"}
check(types == want, "the tutorial's patches and types are kept: %s" % types)
check(all(os.path.exists(os.path.join(case, "0", f)) for f in ("p", "U", "T")), "p, U and T are at time 0")
artest.finish()
