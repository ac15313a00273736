"""Plugin/Scripts/shock_measure.py, the shock position and 10-90 % thickness
that adapt_case.py reports and the payoff benchmark compares. Asserts:
- a tanh profile sampled finely: the position and the exact 10-90 %
  thickness 2 delta atanh(0.8), rising or falling along the line (the line is
  turned, the position keeps its sign); a line with no jump, a line whose
  ends are not plateaus: rejected;
- the analytic oblique shock (Data/oblique_shock_*.vtu, delta = 1/16, the
  fields linear in each tetrahedron of size h = 1/16) on lines normal to the
  exact plane: every line valid, the thickness at least 2 delta atanh(0.8) =
  0.1373 (linear interpolation can only widen tanh's rise: it lies above the
  convex part, below the concave one) and at most 8 % more on the Kuhn-split
  cube, 25 % on Gmsh's tetrahedra (edges up to ~1.5 h, crossed obliquely);
  the position within h / 4 of the plane; lines that leave the cube: rejected,
  and with clip measured on their piece inside as the short line is;
- a rise behind the shock (a cone's): rejected unless only the upstream
  plateau is asked for;
- surface_stations on a square: the requested count, each at least the margin
  from the boundary, unit normals along the square's normal;
- the bundled wedge (a real rhoCentralFoam solution) on lines normal to the
  exact theta-beta-Mach plane: the position within 2 cells of it and the
  thickness 1-8 cells (the solver captures a shock in 2-5 cells).
"""
import math
import os
import sys

import numpy as np
from paraview.simple import XMLUnstructuredGridReader

import artest
from artest import check

sys.path.insert(0, os.path.join(os.path.dirname(os.environ["AR_DATA_DIR"]), "Plugin", "Scripts"))
import shock_measure as sm  # noqa: E402

EXACT = 2.0 * math.atanh(0.8)  # 10-90 % thickness of 0.5 (1 + tanh(d / delta)), over delta

# ---- the profile on its own
s = np.linspace(-0.1, 0.1, 2001)
delta, c = 0.01, 0.013
for label, q in (("rising", 2.0 + 3.0 * 0.5 * (1 + np.tanh((s - c) / delta))),
                 ("falling", 2.0 + 3.0 * 0.5 * (1 - np.tanh((s - c) / delta)))):
    pos, thick, q1, q2 = sm.profile(s, q)
    check(abs(pos - c) < 1e-5, "%s tanh: position %.6f, exact %.6f" % (label, pos, c))
    check(abs(thick / (EXACT * delta) - 1) < 1e-3,
          "%s tanh: thickness %.6f, exact %.6f" % (label, thick, EXACT * delta))
    check(abs(q1 - 2.0) < 1e-4 and abs(q2 - 5.0) < 1e-4, "%s tanh: states %.4f, %.4f (2, 5)" % (label, q1, q2))
check(sm.profile(s, np.full_like(s, 3.0)) is None, "no jump: rejected")
check(sm.profile(s, 2.0 + s) is None, "a linear ramp (ends not plateaus): rejected")
# behind a cone's shock p keeps rising: a downstream ramp of 0.3 of the jump
cone_like = 2.0 + 3.0 * 0.5 * (1 + np.tanh((s - c) / delta)) + np.where(s > c + 5 * delta, 9.0 * (s - c - 5 * delta), 0.0)
res = sm.profile(s, cone_like, downstream_plateau=False)
check(sm.profile(s, cone_like) is None and res is not None and abs(res[0] - c) < delta,
      "a rise behind the shock: rejected with both plateaus asked, measured with the upstream one only "
      "(position %s, exact %.4f)" % (None if res is None else "%.4f" % res[0], c))

# ---- the analytic oblique shock
for name in ("oblique_shock_unstructured.vtu", "oblique_shock_structured.vtu"):
    reader = XMLUnstructuredGridReader(FileName=[artest.data(name)])
    grid = artest.fetch(reader).VTKObject
    n = artest.field(artest.fetch(reader), "ShockNormal")
    o = artest.field(artest.fetch(reader), "ShockOrigin")
    d = float(artest.field(artest.fetch(reader), "SmearingWidth")[0])
    t1 = np.cross(n, [0.0, 0.0, 1.0])
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(n, t1)
    origins = np.array([o + a * t1 + b * t2 for a in (-0.12, 0.0, 0.12) for b in (-0.12, 0.0, 0.12)])
    r = sm.measure(grid, origins, np.tile(n, (len(origins), 1)), half_length=0.3)
    summ = sm.summary(r)
    check(r["valid"].all(), "%s: %d of %d lines valid" % (name, r["valid"].sum(), len(origins)))
    tol = 0.08 if "structured" in name and "unstructured" not in name else 0.25
    ratio = r["thickness"] / (EXACT * d)
    check(ratio.min() >= 1 - 1e-9 and ratio.max() <= 1 + tol,
          "%s: thickness %.4f-%.4f, exact %.4f (at most +%d%%)"
          % (name, summ["thickness_min"], summ["thickness_max"], EXACT * d, 100 * tol))
    check(np.abs(r["offset"]).max() < 0.25 / 16,
          "%s: position off the plane at most %.4f (h / 4 = %.4f)" % (name, np.abs(r["offset"]).max(), 0.25 / 16))
    far = sm.measure(grid, [o + 0.45 * t1], [n], half_length=0.3)
    check(not far["valid"][0], "%s: a line leaving the cube is rejected" % name)
    # clip: a line longer than the cube is measured on its piece inside
    # (adapt_case.py: a cone's shock is nearer the body than its lines are long)
    long = sm.measure(grid, origins[4:5], n[None, :], half_length=0.9)
    cut = sm.measure(grid, origins[4:5], n[None, :], half_length=0.9, clip=True)
    check(not long["valid"][0] and cut["valid"][0] and abs(cut["thickness"][0] / r["thickness"][4] - 1) < 0.02
          and abs(cut["offset"][0] - r["offset"][4]) < 0.25 / 16,
          "%s: a line leaving the cube at both ends: rejected, clipped to the cube measured as the short line "
          "(thickness %.4f vs %.4f)" % (name, cut["thickness"][0], r["thickness"][4]))

# ---- stations on a surface
from vtkmodules.vtkFiltersSources import vtkPlaneSource  # noqa: E402
plane = vtkPlaneSource()
plane.SetOrigin(0, 0, 0)
plane.SetPoint1(1, 0, 0)
plane.SetPoint2(0, 2, 0)
plane.SetResolution(20, 40)
plane.Update()
P, N = sm.surface_stations(plane.GetOutput(), count=12, margin=0.2)
check(len(P) == 12, "square: %d stations (12 asked)" % len(P))
edge = np.minimum.reduce([P[:, 0], 1 - P[:, 0], P[:, 1], 2 - P[:, 1]])
check(edge.min() >= 0.2 - 1e-12, "square: every station at least 0.2 from the boundary (min %.3f)" % edge.min())
check(np.allclose(np.abs(N[:, 2]), 1.0), "square: normals along z")

# ---- the bundled wedge, a real solution, along the exact plane
reader = XMLUnstructuredGridReader(FileName=[artest.data("wedge15Ma5.vtu")])
ds = artest.fetch(reader)
grid = ds.VTKObject
sys.path.insert(0, os.environ["AR_DATA_DIR"])
from theta_beta_mach import shock_angle  # noqa: E402
beta = math.radians(shock_angle(5.0, 15.0))
along = np.array([math.cos(beta), math.sin(beta), 0.0])
normal = np.array([math.sin(beta), -math.cos(beta), 0.0])
h = 0.15242 / 40  # the tutorial's cell upstream of the ramp
origins = [r_ * along for r_ in np.linspace(0.2, 0.3, 10)]  # the lines reach the ramp before r = 0.19
r = sm.measure(grid, origins, [normal] * len(origins), half_length=0.03)
summ = sm.summary(r)
check(summ["valid"] == len(origins), "wedge15Ma5: %d of %d lines valid" % (summ["valid"], len(origins)))
check(summ["offset_max_abs"] < 2 * h, "wedge15Ma5: shock within %.4f of theta-beta-Mach (2 cells %.4f)"
      % (summ["offset_max_abs"], 2 * h))
check(h <= summ["thickness_median"] <= 8 * h, "wedge15Ma5: thickness %.4f = %.1f cells (1-8)"
      % (summ["thickness_median"], summ["thickness_median"] / h))
artest.finish()
