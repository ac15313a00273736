"""AdaptToShocks with its defaults on one case of the validation matrix: a
small steady rhoCentralFoam solution the plugin was never tuned on, made
here from nothing by Data/make_validation_case.py (Gmsh or blockMesh,
rhoCentralFoam, the conversion to .vtu; 30-150 s on one core).

Usage: pvpython TestValidationCase.py CASE   (a name of `make_validation_case.py --list`)

Asserts, on the adapted mesh and the first fitted surface (port 1):
- the template is the shock's (Plane for the wedges, Cone for the cones) and
  its angle is within ANGLE_TOLERANCE (the issue's 0.5 degree) of theory
  (theta-beta-Mach or Taylor-Maccoll, in the case's field data). QuadricFit
  centres the medial points on the half-jump of p before the final fit
  (ShockCentring); without it these coarse solutions' fits were -0.3 to +1.3
  degrees off. A cone's angle is that of the fitted surface about the cone's
  own tip and axis (ConeTip, ConeAxis): a line through the tip fitted to its
  points at 0.4-0.95 of the domain's length (cone_angles). The free cone's
  HalfAngle is printed, not checked: a quarter of a nappe fixes its axis
  poorly (cone10Ma4's tilts 3.7 degrees and opens 3.6 degrees wider, with
  the surface on the shock). The surface must also lie on the solution's own
  shock, within ANGLE_TOLERANCE of where p is half-way from the free
  stream's value to the value behind an oblique shock at the solution's own
  angle (own_jump_angle: Taylor-Maccoll's p2 placed a first-order shock 0.31
  degree outside its own half-jump), measured the same way on the meridians
  0, 45 and 90 degrees: until the centring read the
  Rankine-Hugoniot jump, the cones' surfaces were 0.9-1.2 degrees inside
  it while their HalfAngles passed. A wedge's plane likewise lies within
  ANGLE_TOLERANCE of its solution's own shock (wedge_own_shock: the same
  crossings on lines along +y at mid-span);
- the 2-D bow shock (cylinderMa3): the fitted surfaces cross the stagnation
  line (y = 0, at mid-depth) within one input cell (that cell's extent along
  x) of where p in the solution is half-way from the free stream's value to
  the normal shock's; the automatic template there is the quartic extruded
  along the depth (a parabola through the whole shock misses the vertex by
  about 1.6 cells, a plane, a chord, by as much);
- the 3-D bow shock (sphereMa3, a quarter domain): the first fitted
  surface's own formula (a quadric or quartic z = f(x, y) in its frame)
  crosses the stagnation line (the axis, where the two symmetry planes
  meet) within one input cell of where p on it is half-way from the free
  stream's to the normal shock's value (the embedded surface itself stops
  short of the symmetry planes). The automatic quadric in the points'
  principal frame missed it by 1.4 cells; QuadricFit also fits it about the
  free stream (ar::SurfaceFitOptions::GraphAxis): 0.3;
- across the shock the new cells are at least 3x finer than the input's
  (SurfaceSizeRatio <= 1/3);
- every new tetrahedron's smallest dihedral angle (in 2-D: every new
  triangle's smallest angle) at least 10 degrees;
- the new cells within two requested sizes of the surface at least half
  the requested size (SurfaceEdgeLength; a cell's size: the edge of the
  regular tetrahedron or equilateral triangle of its volume), so the
  explicit solver's time step follows the refinement asked for: every
  one (the smallest 0.57-0.67 of it on the 3-D cases, TetGen's, and
  0.81-0.87 in 2-D; this was 99 % of them and every one a quarter while
  CGAL's refinement left a rosette of triangles down to 0.34 around the
  2-D curve's end, before the open curve kept its last point);
- the usual validity (artest.check_valid_mesh): positive corner Jacobians,
  conforming, the boundary the input's face for face, watertight, volume to
  1e-9;
- the node counts in the field data, printed;
- in 3-D, with prism layers (AdaptToShocks with LayerType Prisms, the other
  properties at their defaults): prisms built, every new tetrahedron at
  least 10 degrees, TetGen's and the closure's (the tetrahedra at S's border
  points between a column of layers and its apices, LayerSide +-1), the mesh
  valid (artest.check_valid_mesh: the prisms' and pyramids' corner
  Jacobians positive). Not on wedge12Ma6tet: its domain is 0.06 deep, and
  with layers S is trimmed two of its edges (the input's size, about 0.02)
  back from the boundary, so nothing of it is left (AdaptToShocks refuses
  and passes the input through). Nor on wedge20Ma2p5tet, 0.12 deep on cells
  of 0.007-0.02: the same refusal ("nothing of the feature surface is left
  after trimming"), checked: its message names the extra edge of trim the
  stack's closure needs and tetrahedra as the way out, and the input passes
  through. The closure tetrahedra are 10.5-13.7 degrees (TetGen's 10.1-14.5)
  since the apices stand nearer the layers (ARPrismLayers.h); they were
  5.2-7.7 with the apices half a border edge out, as thin as their layer
  over 0.7 of an edge, and were asked only 5. On cone15Ma3 also a thinner
  stack of eight layers (THIN_STACKS): TetGen's tetrahedra at least 10
  degrees, the closure's at least THIN_CLOSURE_FLOOR.
"""
import os
import sys

import numpy as np
from paraview.simple import *

import artest
from artest import check

sys.path.insert(0, os.environ["AR_DATA_DIR"])
from make_validation_case import last_crossing  # noqa: E402

ANGLE_TOLERANCE = 0.5  # degrees, the target
# Every case meets it since wedge15Ma3tet's mesh is 1.25x finer (33,693
# tetrahedra: its solution's own shock +0.36 off theory, the fit +0.41; on
# 18,061 they were +0.51 and +0.53, and the case had 0.7). wedge12Ma6tet's
# fit (+0.49) follows its shock, which its coarse tetrahedra bend near the tip;
# on a mesh 1.15x finer (28,990) the fit is the same 20.04 degrees.
# The surfaces against the solution's own shock: ANGLE_TOLERANCE for every
# case. (cone15Ma3o1 had 0.8 while its own shock was measured at
# Taylor-Maccoll's half-jump: 0.65 degree outside its surface; at its own
# jump, own_jump_angle, 0.34.)
# The prism-layer variant: the 3-D cases with room for the stack.
NO_PRISM_CASES = {"wedge12Ma6tet", "wedge20Ma2p5tet"}
# The closure tetrahedra's floor is 10 degrees (the issue's) on every case.
# (The 3-D bow shock had 9.5 while the wedges' arc points stood at the
# apices' offsets: 9.95 and, on a solution with limited gradients, 7.6.)
CLOSURE_FLOOR = 10.0
# A thinner stack by hand (the payoff's eight layers on 0.03 per side, 0.51x
# the uniform mesh's shock thickness): a row of apices per side, joined by a
# band of triangles between the rows. A band quad folded towards the void
# left TetGen the flat tetrahedron of four apices (2.4 degrees);
# ARPrismLayers now folds each band quad convexly. With N layers under one
# apex the closure tetrahedra are bound to about 1/N radians (ARPrismLayers.h:
# 6.6 degrees with 8), so they are asked THIN_CLOSURE_FLOOR, TetGen's 10.
THIN_STACKS = {"cone15Ma3": (0.03, 8)}
THIN_CLOSURE_FLOOR = 6.0


def closure_angle(out):
    """The smallest dihedral angle of the layer stack's closure tetrahedra
    (tetrahedra with a LayerSide), degrees; 0 where there are none."""
    types = np.asarray(out.CellTypes)
    closure = (types == artest.VTK_TETRA) & (np.asarray(out.CellData["LayerSide"]) != 0)
    return float(np.asarray(out.CellData["MinDihedralAngle"])[closure].min()) if closure.any() else 0.0


def tip_line_angle(xs, rs, least=1):
    """Degrees: the line r = x tan b through the tip fitted (least squares) to
    the points (x, r); NaN with fewer than `least` points."""
    xs, rs = np.asarray(xs, dtype=np.float64), np.asarray(rs, dtype=np.float64)
    return np.degrees(np.arctan((xs @ rs) / (xs @ xs))) if len(xs) >= max(least, 1) else np.nan


def own_shock_angle(src, tip, along, across, r0_slope, r_end, p2_p1, lo, hi, stations):
    """The solution's own shock angle (degrees): the line through the tip fitted
    to the outermost crossings of p = (p1 + p2) / 2 (p1 upstream, p2 = p2_p1 p1)
    on the lines tip + x along + r d, d in `across`, r from x r0_slope to
    r_end, at `stations` stations x over lo..hi of the domain's length along
    `along` (last_crossing of make_validation_case.py, which measures the
    solution's shock the same way)."""
    P = np.asarray(src.Points, dtype=np.float64) - tip
    t = P @ along
    length = t.max()
    p1 = np.asarray(src.PointData["p"])[np.argmin(t)]
    p_mid = 0.5 * p1 * (1.0 + p2_p1)
    xs, rs = [], []
    for d in across:
        for x in np.linspace(lo, hi, stations) * length:
            r = last_crossing(src.VTKObject, tip + x * along, d, x * r0_slope, r_end, p_mid)
            if r is not None:
                xs.append(x)
                rs.append(r)
    return tip_line_angle(xs, rs, least=5)


def own_jump_angle(src, measure, beta0):
    """The solution's own shock angle (degrees) at its own jump: measure(p2_p1)
    is the angle of the crossings of p's half-way level for a jump p2 / p1;
    the level is the oblique-shock (Rankine-Hugoniot) jump at the angle it
    gives, p2 / p1 = 1 + 2 gamma / (gamma + 1) (M^2 sin^2 beta - 1) with the
    free stream's M ahead of the shock (a cone's and a wedge's alike), found
    by a damped fixed-point iteration from theory's angle beta0. Theory's p2
    put the level of a shock wider than theory's too low: on the first-order
    cone15Ma3o1, whose shock is 0.14 wide (nine cells) and 0.70 degree wide
    of Taylor-Maccoll, the crossings of Taylor-Maccoll's half-jump lie 0.31
    degree outside those of its own (p2 / p1 1.745 against 1.800)."""
    mach, gamma = f(src, "UpstreamMach"), f(src, "Gamma")
    beta = beta0
    for _ in range(20):
        sin = np.sin(np.radians(beta))
        measured = measure(1.0 + 2.0 * gamma / (gamma + 1.0) * ((mach * sin) ** 2 - 1.0))
        if not np.isfinite(measured):
            return measured
        step = 0.5 * (measured - beta)
        beta += step
        if abs(step) < 0.002:
            break
    return beta


def cone_angles(src, surf, lo=0.4, hi=0.95, stations=8):
    """(the fitted surface's angle, the solution's own shock angle, points
    used), degrees, about the cone's tip and axis (field data ConeTip,
    ConeAxis): a line through the tip fitted to the surface's points at
    lo..hi of the domain's length along the axis, and to the solution's
    shock (own_shock_angle at its own jump, own_jump_angle) on the
    meridians 0, 45 and 90 degrees at `stations` stations over the same
    range."""
    tip, axis = np.asarray(artest.field(src, "ConeTip")), np.asarray(artest.field(src, "ConeAxis"))
    axis = axis / np.linalg.norm(axis)
    P = np.asarray(src.Points, dtype=np.float64) - tip
    t = P @ axis
    length = t.max()
    rmax = 0.995 * np.linalg.norm(P - t[:, None] * axis, axis=1).max()
    S = np.asarray(surf.Points, dtype=np.float64) - tip
    ts = S @ axis
    rs = np.linalg.norm(S - ts[:, None] * axis, axis=1)
    sel = (ts >= lo * length) & (ts <= hi * length)
    surface = tip_line_angle(ts[sel], rs[sel])
    # probed about the inflow direction (+x, within 0.01 degree of the axis,
    # make_validation_case.py checks): the meridians 0 and 90 degrees lie
    # exactly in the symmetry planes, where an axis off by 1e-9 would not
    flow = np.asarray(artest.field(src, "FlowDirection"))
    meridians = [np.array([0.0, np.cos(psi), np.sin(psi)]) for psi in np.radians([0.0, 45.0, 90.0])]
    slope = 1.001 * np.tan(np.radians(f(src, "ConeHalfAngle")))
    own = own_jump_angle(src, lambda p2_p1: own_shock_angle(src, tip, flow, meridians, slope, rmax, p2_p1, lo, hi,
                                                            stations), f(src, "ShockAngleTaylorMaccoll"))
    return surface, own, int(sel.sum())


def wedge_own_shock(src, lo=0.4, hi=0.95, stations=12):
    """The solution's own shock angle (degrees) over a wedge (own_shock_angle
    at its own jump, own_jump_angle): on lines along +y at mid-span
    (WedgeTip's z) at `stations` stations over lo..hi of the domain's length
    behind the tip."""
    tip = np.asarray(artest.field(src, "WedgeTip"))
    P = np.asarray(src.Points, dtype=np.float64)
    top = P[:, 1].max() - tip[1] - 1e-9 * np.ptp(P[:, 0])
    slope = 1.001 * np.tan(np.radians(f(src, "WedgeAngle")))
    return own_jump_angle(src, lambda p2_p1: own_shock_angle(src, tip, np.array([1.0, 0.0, 0.0]),
                                                             [np.array([0.0, 1.0, 0.0])], slope, top, p2_p1,
                                                             lo, hi, stations), f(src, "ShockAngleThetaBetaMach"))


def stagnation_half_jump(src, reader, x0, x1, y, z):
    """On the stagnation line (x0 .. x1 at y, z): where p is half-way from the
    free stream's value to the normal shock's (NormalShockPressureRatio), and
    the extent along x of the input cell holding that point."""
    from vtkmodules.vtkCommonDataModel import vtkCellLocator
    xs = np.linspace(x0, x1, 4001)
    line = PlotOverLine(Input=reader)
    line.Point1, line.Point2, line.Resolution = [xs[0], y, z], [xs[-1], y, z], len(xs) - 1
    sampled = artest.fetch(line)
    valid = np.asarray(sampled.PointData["vtkValidPointMask"]) == 1
    x_line = np.asarray(sampled.Points)[:, 0][valid]
    p_line = np.asarray(sampled.PointData["p"])[valid]
    p_half = p_line[0] * (1.0 + f(src, "NormalShockPressureRatio")) / 2.0
    k = int(np.argmax(p_line >= p_half))
    x_shock = x_line[k - 1] + (p_half - p_line[k - 1]) / (p_line[k] - p_line[k - 1]) * (x_line[k] - x_line[k - 1])
    cells = vtkCellLocator()
    cells.SetDataSet(src.VTKObject)
    cells.BuildLocator()
    held = cells.FindCell([x_shock, y, z])
    b = src.VTKObject.GetCell(held).GetBounds() if held >= 0 else [np.nan] * 6
    return x_shock, b[1] - b[0]


f = lambda d, n: artest.field(d, n)[0]
case = sys.argv[1]
artest.load_plugin(globals())
out_dir = os.path.join(artest.OUTPUT_DIR, "validation")
os.makedirs(out_dir, exist_ok=True)
solution = os.path.join(out_dir, case + ".vtu")
script = os.path.join(os.environ["AR_DATA_DIR"], "make_validation_case.py")
rc, _ = artest.run([artest.require_program("python3", "python3"), script, case, solution])
check(rc == 0 and os.path.exists(solution), "%s: the solution was made (make_validation_case.py exit %d)" % (case, rc))
if rc != 0:
    artest.finish()

reader = XMLUnstructuredGridReader(FileName=[solution])
src = artest.fetch(reader)
adapt = AdaptToShocks(Input=reader)
out, surf = artest.fetch(adapt), artest.fetch(adapt, 1)
check("Region" in out.CellData.keys() and surf.GetNumberOfCells() > 0,
      "%s: adapted (%d surfaces: %s)" % (case, f(out, "NumberOfSurfaces") if "NumberOfSurfaces" in out.FieldData.keys()
                                        else 0, out.FieldData["SurfaceTemplates"].GetValue(0)
                                        if "SurfaceTemplates" in out.FieldData.keys() else "none"))
template = surf.FieldData["Template"].GetValue(0)
if "SphereRadius" in src.FieldData.keys():
    # The 3-D bow shock: where the first fitted surface (a quadric or quartic
    # z = f(x, y) in its frame, evaluated exactly) crosses the stagnation
    # line (the axis, where the two symmetry planes meet) against where p on
    # it is half-way from the free stream's to the normal shock's value,
    # within one input cell (the extent along x of the input cell there).
    # The embedded surface itself stops BoundaryMargin of its edges short of
    # the symmetry planes, so the surface's own formula is what is measured.
    centre, radius = artest.field(src, "SphereCentre"), f(src, "SphereRadius")
    P0 = np.asarray(src.Points, dtype=np.float64)
    tiny = 1e-7 * np.ptp(P0[:, 0])
    x0, x1 = P0[:, 0].min(), centre[0] - radius
    x_shock, cell_dx = stagnation_half_jump(src, reader, x0, x1, tiny, tiny)
    x_vertex = np.nan
    if template in ("Quadric", "Quartic"):
        coef = artest.field(surf, "Coefficients")
        origin = artest.field(surf, "FrameOrigin")
        axes = artest.field(surf, "FrameAxes").reshape(3, 3)
        fine = np.linspace(x0, x1, 20001)
        local = (np.c_[fine, np.zeros((len(fine), 2))] - origin) @ axes.T
        u, v = local[:, 0], local[:, 1]
        monomials = [np.ones_like(u), u, v, u * u, u * v, v * v, u ** 3, u * u * v, u * v * v, v ** 3,
                     u ** 4, u ** 3 * v, u * u * v * v, u * v ** 3, v ** 4][:len(coef)]
        g = local[:, 2] - sum(c * m for c, m in zip(coef, monomials))
        roots = np.where(np.sign(g[:-1]) != np.sign(g[1:]))[0]
        if len(roots):
            j = roots[np.argmin(np.abs(fine[roots] - x_shock))]
            x_vertex = fine[j] - g[j] * (fine[j + 1] - fine[j]) / (g[j + 1] - g[j])
    check(abs(x_vertex - x_shock) <= cell_dx,
          "%s: the %s crosses the stagnation line at x = %.4f, the solution's half-jump of p at %.4f (%+.4f, %.2f "
          "input cells of %.4f; at most one)"
          % (case, template, x_vertex, x_shock, x_vertex - x_shock, abs(x_vertex - x_shock) / cell_dx, cell_dx))
elif "CylinderRadius" in src.FieldData.keys():
    # The 2-D bow shock: where the fitted surfaces cross the stagnation line
    # (the symmetry plane y = 0 in front of the body, at mid-depth) against
    # where p in the solution is half-way from the free stream's to the
    # normal shock's value there, within one input cell (the extent along x
    # of the input cell holding that point).
    from vtkmodules.vtkCommonDataModel import vtkPlane
    from vtkmodules.vtkFiltersCore import vtkCutter
    centre, radius = artest.field(src, "CylinderCentre"), f(src, "CylinderRadius")
    P0 = np.asarray(src.Points, dtype=np.float64)
    zmid, tiny = centre[2], 1e-7 * np.ptp(P0[:, 0])
    x_shock, cell_dx = stagnation_half_jump(src, reader, P0[:, 0].min(), centre[0] - radius, tiny, zmid)
    plane = vtkPlane()
    plane.SetOrigin(0.0, 0.0, zmid)
    plane.SetNormal(0.0, 0.0, 1.0)
    cut = vtkCutter()
    cut.SetInputData(surf.VTKObject)
    cut.SetCutFunction(plane)
    cut.Update()
    C = np.array([cut.GetOutput().GetPoint(i) for i in range(cut.GetOutput().GetNumberOfPoints())])
    near = C[np.argmin(C[:, 1])] if len(C) else np.array([np.nan] * 3)
    check(len(C) > 0 and near[1] <= cell_dx,
          "%s: the fitted surfaces reach the stagnation line at mid-depth (lowest point y = %.4f, a cell %.4f)"
          % (case, near[1] if len(C) else np.nan, cell_dx))
    fd = out.VTKObject.GetFieldData()
    listed = lambda name: ", ".join(fd.GetAbstractArray(name).GetValue(i)
                                    for i in range(fd.GetAbstractArray(name).GetNumberOfValues())) \
        if fd.GetAbstractArray(name) else "?"
    templates = "%s (clusters %s)" % (listed("SurfaceTemplates"), listed("SurfaceClusters"))
    check(abs(near[0] - x_shock) <= cell_dx,
          "%s: the bow shock's vertex at x = %.4f, the solution's half-jump of p at %.4f (%+.4f, %.2f input cells of "
          "%.4f; at most one); surfaces %s"
          % (case, near[0], x_shock, near[0] - x_shock, abs(near[0] - x_shock) / cell_dx, cell_dx, templates))
elif "ShockAngleThetaBetaMach" in src.FieldData.keys():
    theory = f(src, "ShockAngleThetaBetaMach")
    n = artest.field(surf, "Normal") if template == "Plane" else None
    # the shock angle to the free stream (+x) in the x-y plane: the normal's angle to +y
    angle = np.degrees(np.arctan2(abs(n[0]), abs(n[1]))) if n is not None else np.nan
    expected = "Plane"
    own = wedge_own_shock(src)
    check(template == expected and abs(angle - own) <= ANGLE_TOLERANCE,
          "%s: the fitted plane at %.2f deg, the solution's own shock at %.2f (%+.2f; at most %.1f)"
          % (case, angle, own, angle - own, ANGLE_TOLERANCE))
else:
    theory = f(src, "ShockAngleTaylorMaccoll")
    angle, own, used = cone_angles(src, surf) if template == "Cone" else (np.nan, np.nan, 0)
    expected = "Cone"
    check(template == expected and abs(angle - own) <= ANGLE_TOLERANCE,
          "%s: the fitted surface (%d points) at %.2f deg about the cone's axis, the solution's own shock at %.2f "
          "(%+.2f; at most %.1f); the free cone's HalfAngle %.2f (theory %.2f)"
          % (case, used, angle, own, angle - own, ANGLE_TOLERANCE,
             f(surf, "HalfAngle") if template == "Cone" else np.nan, theory))
if "CylinderRadius" not in src.FieldData.keys() and "SphereRadius" not in src.FieldData.keys():
    check(template == expected and abs(angle - theory) <= ANGLE_TOLERANCE,
          "%s: the first surface is a %s at %.2f deg, theory %.2f (%+.2f; at most %.1f)"
          % (case, template, angle, theory, angle - theory, ANGLE_TOLERANCE))
check(f(out, "SurfaceSizeRatio") <= 1.0 / 3.0,
      "%s: the new cells at the shock are %.2f of the input's size there (at most 1/3)"
      % (case, f(out, "SurfaceSizeRatio")))
two_d = f(out, "TwoDimensional") == 1
worst = f(out, "MinTriangleAngleNew") if two_d else f(out, "MinDihedralAngleNew")
check(worst >= 10.0, "%s: the smallest angle of the new %s is %.1f deg (at least 10)"
      % (case, "triangles" if two_d else "tetrahedra", worst))
# The new cells near the shock are no smaller than about half the requested
# size (SurfaceEdgeLength), so the explicit solver's time step follows the
# refinement asked for, not a stray small cell: each new cell within two
# requested sizes of the fitted surface, as the edge of the regular
# tetrahedron (in 2-D: equilateral triangle) of its volume.
from vtkmodules.vtkCommonDataModel import vtkCellLocator, vtkCellTypes
from vtkmodules.vtkFiltersCore import vtkCellCenters
from vtkmodules.vtkFiltersVerdict import vtkCellSizeFilter
from vtkmodules.util.numpy_support import vtk_to_numpy
import vtk
size = vtkCellSizeFilter()
size.SetInputData(out.VTKObject)
size.Update()
volume = vtk_to_numpy(size.GetOutput().GetCellData().GetArray("Volume"))
centres = vtkCellCenters()
centres.SetInputData(out.VTKObject)
centres.Update()
C = vtk_to_numpy(centres.GetOutput().GetPoints().GetData())
locator = vtkCellLocator()
locator.SetDataSet(surf.VTKObject)
locator.BuildLocator()
requested = f(out, "SurfaceEdgeLength")
P1 = np.asarray(out.Points, dtype=np.float64)
depth = np.ptp(P1[:, 2]) if two_d else None
ratios = []
for c in np.where(np.asarray(out.CellData["Region"]) == 1)[0]:
    closest, cell, sub, d2 = [0.0, 0.0, 0.0], vtk.reference(0), vtk.reference(0), vtk.reference(0.0)
    locator.FindClosestPoint(C[c], closest, cell, sub, d2)
    if d2.get() <= (2 * requested) ** 2:
        edge = np.sqrt(4 * volume[c] / depth / np.sqrt(3)) if two_d else (6 * np.sqrt(2) * volume[c]) ** (1 / 3)
        ratios.append(edge / requested)
check(len(ratios) > 0 and min(ratios) >= 0.5,
      "%s: every one of the %d new cells near the shock is at least half the requested size %.4g "
      "(1%% %.2f, min %.2f, median %.2f of it)"
      % (case, len(ratios), requested, np.percentile(ratios, 1), min(ratios), np.median(ratios)))
artest.check_valid_mesh(case, src, out)
if not two_d and case in NO_PRISM_CASES:
    # The refusal names the cause (the trim the stack's closure needs) and the
    # way out, and the input passes through.
    from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
    previous, messages = vtkOutputWindow.GetInstance(), vtkStringOutputWindow()
    vtkOutputWindow.SetInstance(messages)
    refused = artest.fetch(AdaptToShocks(Input=reader, LayerType="Prisms"))
    vtkOutputWindow.SetInstance(previous)
    text = messages.GetOutput()
    check("BoundaryMargin + 1" in text and "thin slab" in text and "Tetrahedra (no layers)" in text
          and refused.GetNumberOfCells() == src.GetNumberOfCells(),
          "%s, prism layers: refused, the input passed through (%d cells), the message naming the trim the "
          "closure needs and tetrahedra as the way out" % (case, refused.GetNumberOfCells()))
if not two_d and case not in NO_PRISM_CASES:
    layered = artest.fetch(AdaptToShocks(Input=reader, LayerType="Prisms"))
    built = "Prisms" in layered.FieldData.keys() and f(layered, "Prisms") > 0
    check(built, "%s, prism layers: %d prisms, %d pyramids, %d closure tetrahedra"
          % (case, f(layered, "Prisms") if built else 0, f(layered, "Pyramids") if built else 0,
             f(layered, "LayerClosureTetrahedra") if built else 0))
    if built:
        closure = closure_angle(layered)
        check(f(layered, "MinDihedralAngleNew") >= 10.0 and closure >= CLOSURE_FLOOR,
              "%s, prism layers: the smallest angle of TetGen's tetrahedra is %.2f deg (at least 10), of the "
              "closure's %.2f (at least %.1f; the layer cells' %.2f)"
              % (case, f(layered, "MinDihedralAngleNew"), closure, CLOSURE_FLOOR,
                 f(layered, "MinDihedralAngleLayerCells")))
        artest.check_valid_mesh(case + ", prism layers", src, layered)
    if case in THIN_STACKS:
        total, layers = THIN_STACKS[case]
        thin = artest.fetch(AdaptToShocks(Input=reader, LayerType="Prisms", TotalThickness=total,
                                          NumberOfLayers=layers))
        thin_closure = closure_angle(thin)
        check(f(thin, "Prisms") > 0 and f(thin, "MinDihedralAngleNew") >= 10.0
              and thin_closure >= THIN_CLOSURE_FLOOR,
              "%s, %d prism layers on %g per side: the smallest angle of TetGen's tetrahedra is %.1f deg (at "
              "least 10), of the closure's %.1f (at least %.1f)"
              % (case, layers, total, f(thin, "MinDihedralAngleNew"), thin_closure, THIN_CLOSURE_FLOOR))
        artest.check_valid_mesh("%s, %d prism layers" % (case, layers), src, thin)
artest.say("%s: nodes %d -> %d (%d new, %d removed), cells %d -> %d"
           % (case, f(out, "InputNodes"), f(out, "OutputNodes"), f(out, "NewNodes"), f(out, "RemovedNodes"),
              src.GetNumberOfCells(), out.GetNumberOfCells()))
artest.finish()
