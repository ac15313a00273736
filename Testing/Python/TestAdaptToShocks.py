"""AdaptToShocks: a solution in, the adapted mesh out, in one call with no
property set.
- The OpenFOAM cone as loaded: the same mesh as the separate filters with
  their defaults (ShockSensor -> FeatureCluster -> QuadricFit of cluster 0
  -> EmbeddedRemesh): node and cell counts, the embedded triangles, p at the
  nodes; port 1 one surface, SurfaceId 0, its template Cone, within 0.5
  degree of Taylor-Maccoll; refined at the shock (SurfaceSizeRatio <= 1/3),
  new tetrahedra at least 10 degrees; the stage times in the field data.
- The OpenFOAM wedge (one cell deep): a plane within 0.5 degree of
  theta-beta-Mach, still one cell deep (2-D mode); the small cluster split
  off at the shock's foot is a piece of the same shock: one plane fits both
  clusters' centred points as well as each alone, so they are joined into
  one surface (SurfaceClusters "0+1"). Given a template of its own
  (ClusterTemplates), the piece stays alone, and as its surface crosses the
  main one it is left out with a warning. A second cycle with layers on the
  layered output (no solve between): one surface, new triangles >= 10 deg.
- The cone as the OpenFOAM reader gives it (a multiblock of internalMesh
  and patches): a multiblock out, the patches' face counts unchanged.
- ClusterTemplates [0, Plane] overrides the automatic choice.
- A shock cut by every boundary (the analytic oblique shock turned so that
  its plane cuts all six faces of the cube): one plane within 0.5 degree of
  the exact one and one cell of its Mn = 1 plane, reaching all six faces;
  the mesh refined (size ratio <= 1/3), new tetrahedra >= 10 degrees, valid
  (artest.check_valid_mesh).
- Prism layers sized from the shock: the stack spans the captured shock's
  thickness (QuadricFit's ShockThickness, within a quarter of a cell of the
  analytic profile's 10-90 % width), the first layer a fraction of the input's size,
  new tetrahedra >= 10 degrees (the analytic shock and the cone).
- Bad and borderline input, each an error naming the cause and the input
  passed through: a uniform flow (no shock), no flow arrays, Mode 3,
  MinimumClusterFraction 0.
"""
import numpy as np
from paraview.simple import *
from paraview import servermanager
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid

import artest
from artest import check

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)

from vtkmodules.vtkCommonCore import vtkSMPTools
backend = vtkSMPTools.GetBackend()  # Sequential in Debian's ParaView, unless the user chose one
cone = XMLUnstructuredGridReader(FileName=[artest.data("cone20Ma2p5.vtu")])
src = artest.fetch(cone)
f = lambda d, n: artest.field(d, n)[0]

# ---- The cone in one call, against the separate filters.
adapt = AdaptToShocks(Input=cone)
out, surf = artest.fetch(adapt), artest.fetch(adapt, 1)
clusters = FeatureCluster(Input=ShockSensor(Input=cone))
fit = QuadricFit(Input=OutputPort(clusters, 1), Domain=cone, ClusterId=0)
separate = EmbeddedRemesh(Input=cone, Surfaces=[fit])
ref = artest.fetch(separate)
check(out.GetNumberOfPoints() == ref.GetNumberOfPoints() and out.GetNumberOfCells() == ref.GetNumberOfCells()
      and f(out, "SurfaceTriangles") == f(ref, "SurfaceTriangles"),
      "cone: %d nodes, %d cells, %d embedded triangles, as the separate filters (%d, %d, %d)"
      % (out.GetNumberOfPoints(), out.GetNumberOfCells(), f(out, "SurfaceTriangles"), ref.GetNumberOfPoints(),
         ref.GetNumberOfCells(), f(ref, "SurfaceTriangles")))
check(np.array_equal(np.asarray(out.Points), np.asarray(ref.Points))
      and np.array_equal(np.asarray(out.PointData["p"]), np.asarray(ref.PointData["p"])),
      "cone: the same points and interpolated p as the separate filters")
templates = out.FieldData["SurfaceTemplates"]
half = f(artest.fetch(fit), "HalfAngle")
theory = f(src, "ShockAngleTaylorMaccoll")
check(f(out, "NumberOfSurfaces") == 1 and templates.GetValue(0) == "Cone" and abs(half - theory) < 0.5,
      "cone: one surface, a cone of %.2f deg (Taylor-Maccoll %.2f)" % (half, theory))
ids = np.asarray(surf.CellData["SurfaceId"])
check(surf.GetNumberOfCells() == artest.fetch(fit).GetNumberOfCells() and set(ids) == {0},
      "cone: port 1 holds the fitted surface (%d triangles), SurfaceId 0" % surf.GetNumberOfCells())
check(f(out, "SurfaceSizeRatio") <= 1.0 / 3.0 and f(out, "MinDihedralAngleNew") >= 10.0
      and f(out, "OutputNodes") > f(out, "InputNodes"),
      "cone: refined at the shock (size ratio %.2f), new tetrahedra >= %.1f deg, %d -> %d nodes"
      % (f(out, "SurfaceSizeRatio"), f(out, "MinDihedralAngleNew"), f(out, "InputNodes"), f(out, "OutputNodes")))
check(all(n in out.FieldData.keys() for n in ("SecondsSensor", "SecondsClusters", "SecondsFit", "SecondsRemesh")),
      "cone: the stage times are in the field data (sensor %.2f, clusters %.2f, fit %.2f, remesh %.2f s)"
      % tuple(f(out, n) for n in ("SecondsSensor", "SecondsClusters", "SecondsFit", "SecondsRemesh")))

# ---- The wedge, one cell deep.
wedge = XMLUnstructuredGridReader(FileName=[artest.data("wedge15Ma5.vtu")])
before = len(messages.GetOutput())
adapt_w = AdaptToShocks(Input=wedge)
out_w, surf_w = artest.fetch(adapt_w), artest.fetch(adapt_w, 1)
text = messages.GetOutput()[before:]
W = artest.fetch(wedge)
n = artest.field(artest.fetch(QuadricFit(Input=OutputPort(FeatureCluster(Input=ShockSensor(Input=wedge)), 1),
                                         Domain=wedge, ClusterId=0)), "Normal")
beta = np.degrees(np.arctan2(abs(n[0]), abs(n[1])))
check(out_w.FieldData["SurfaceTemplates"].GetValue(0) == "Plane" and f(out_w, "NumberOfSurfaces") == 1
      and abs(beta - f(W, "ShockAngleThetaBetaMach")) < 0.5,
      "wedge: one plane at %.2f deg (theta-beta-Mach %.2f)" % (beta, f(W, "ShockAngleThetaBetaMach")))
members = out_w.FieldData["SurfaceClusters"]
check(f(out_w, "TwoDimensional") == 1 and members.GetNumberOfValues() == 1 and members.GetValue(0) == "0+1"
      and "left out" not in text,
      "wedge: 2-D mode; the shock foot's piece (cluster 1) joined to the main one (SurfaceClusters %s)"
      % [members.GetValue(i) for i in range(members.GetNumberOfValues())])
before = len(messages.GetOutput())
alone = artest.fetch(AdaptToShocks(Input=wedge, ClusterTemplates=[1, 0]))
text = messages.GetOutput()[before:]
check(f(alone, "NumberOfSurfaces") == 1 and alone.FieldData["SurfaceClusters"].GetValue(0) == "0"
      and "crosses the surface of cluster 0 and is left out" in text,
      "wedge, cluster 1 given its own template: not joined; its surface crosses the main one and is left out "
      "with a warning")

# A second cycle on the layered 2-D output without a solve in between (its
# fields interpolated): the band of the shock in the thin layers used to fall
# into overlapping pieces 0.0005 apart, fitted as three planes with 1.35-degree
# triangles between them; centred and joined, it is one surface again.
layered = AdaptToShocks(Input=wedge, LayerType=1)
again = artest.fetch(AdaptToShocks(Input=layered, LayerType=1))
members = again.FieldData["SurfaceClusters"] if "SurfaceClusters" in again.FieldData.keys() else None
check(members is not None and members.GetNumberOfValues() == 1 and f(again, "MinTriangleAngleNew") >= 10.0,
      "wedge, layers, a second cycle without a solve: one surface (%s), new triangles >= %.1f deg"
      % ([members.GetValue(i) for i in range(members.GetNumberOfValues())] if members else None,
         f(again, "MinTriangleAngleNew") if "MinTriangleAngleNew" in again.FieldData.keys() else float("nan")))

# ---- The OpenFOAM reader's multiblock.
patches = artest.CONE_PATCHES
mb, names = artest.openfoam_multiblock(src.VTKObject, artest.cone_patches, patches)
source = PVTrivialProducer()
source.GetClientSideObject().SetOutput(mb)
adapt_mb = AdaptToShocks(Input=source)
adapt_mb.UpdatePipeline()
out_mb = servermanager.Fetch(adapt_mb)
faces = {patches[i]: out_mb.GetBlock(1).GetBlock(i).GetNumberOfCells() for i in range(len(patches))}
check(out_mb.IsA("vtkMultiBlockDataSet") and out_mb.GetBlock(0).GetNumberOfPoints() == out.GetNumberOfPoints()
      and faces == {p: int((names == p).sum()) for p in patches},
      "multiblock: adapted internalMesh (%d nodes), patches unchanged %s" % (out_mb.GetBlock(0).GetNumberOfPoints(), faces))

# ---- A template named per cluster.
over = artest.fetch(AdaptToShocks(Input=cone, ClusterTemplates=[0, 0]))
check(over.FieldData["SurfaceTemplates"].GetValue(0) == "Plane",
      "ClusterTemplates [0, 0]: cluster 0 gets a plane")


# ---- A shock cut by every boundary: the analytic oblique shock
# (Data/analytic_shock.py, smeared over delta = 1/16) on the Gmsh cube of
# Data/oblique_shock_unstructured.vtu, turned so that its plane through the
# centre cuts all six faces (a hexagon). One plane within 0.5 degree of the
# exact normal and within one cell of the exact Mn = 1 plane, trimmed to the
# domain on all six faces; the mesh refined and valid.
from analytic_shock import ObliqueShock
from vtkmodules.util.numpy_support import numpy_to_vtk
cube = artest.fetch(XMLUnstructuredGridReader(FileName=[artest.data("oblique_shock_unstructured.vtu")]))
shock = ObliqueShock(rotation_deg=(-10.0, -60.0, -60.0))
n_exact = shock.normal
check(min(abs(n_exact[(i + 1) % 3]) + abs(n_exact[(i + 2) % 3]) - abs(n_exact[i]) for i in range(3)) > 0.3,
      "the turned shock plane cuts all six faces of the cube (normal %s)" % np.round(n_exact, 3))
g = vtkUnstructuredGrid()
g.CopyStructure(cube.VTKObject)
for name, values in shock.fields(np.asarray(cube.Points)).items():
    if name in ("U", "p", "rho", "T"):
        a = numpy_to_vtk(np.ascontiguousarray(values, dtype=np.float64), deep=1)
        a.SetName(name)
        g.GetPointData().AddArray(a)
turned = PVTrivialProducer()
turned.GetClientSideObject().SetOutput(g)
a6 = AdaptToShocks(Input=turned)
o6, s6 = artest.fetch(a6), artest.fetch(a6, 1)
check("Region" in o6.CellData.keys() and f(o6, "NumberOfSurfaces") == 1
      and s6.FieldData["Template"].GetValue(0) == "Plane",
      "cut by every boundary: adapted, one surface, a plane")
n6 = artest.field(s6, "Normal")
offset = (artest.field(s6, "Origin") - shock.origin) @ n_exact
h6 = f(o6, "InputSizeAtSurface")
check(artest.angle_between_planes(n6, n_exact) < 0.5 and abs(offset - shock.normal_mach_unity_offset()) < h6,
      "cut by every boundary: the plane is %.2f deg from the exact one, %.4f from the Mn = 1 plane (one cell: %.4f)"
      % (artest.angle_between_planes(n6, n_exact), abs(offset - shock.normal_mach_unity_offset()), h6))
P6 = np.asarray(s6.Points)
touched = [int((np.abs(P6[:, k] - v) < 1e-6).sum() > 0) for k in range(3) for v in (0.0, 1.0)]
check(sum(touched) == 6, "cut by every boundary: the trimmed surface reaches all six faces (%s)" % touched)
check(f(o6, "SurfaceSizeRatio") <= 1.0 / 3.0 and f(o6, "MinDihedralAngleNew") >= 10.0,
      "cut by every boundary: size ratio %.2f, new tetrahedra >= %.1f deg"
      % (f(o6, "SurfaceSizeRatio"), f(o6, "MinDihedralAngleNew")))
artest.check_valid_mesh("cut by every boundary", cube, o6)

# ---- Prism layers sized from the shock itself: on the analytic shock p
# rises as tanh(d / delta), whose 10-90 % width is 2 atanh(0.8) delta = 0.137;
# the measured ShockThickness within a quarter of the input's cell at S (0.11
# here: the mesh's linear interpolation of the profile over cells that size
# widens it, to 0.159), the stack a quarter of it per side (the two sides
# span half the captured shock), its 5 layers uniform (GrowthRatio 1), the
# first layer a fraction of the input's cell size, every new tetrahedron at
# least 10 degrees, and the mesh valid. On the OpenFOAM cone, the same rule
# and the same angle bound.
exact_width = 2.0 * np.arctanh(0.8) * shock.delta
for label, source, reference in (("analytic shock", turned, cube), ("cone", cone, src)):
    lay = artest.fetch(AdaptToShocks(Input=source, LayerType=1))
    width, stack = f(lay, "ShockThickness"), f(lay, "LayerStackHeight")
    good = width > 0 and abs(stack - 0.25 * width) <= 1e-12 * width and f(lay, "MinDihedralAngleNew") >= 10.0 \
        and abs(f(lay, "FirstLayerThicknessUsed") - stack / 5) <= 1e-12 * stack \
        and f(lay, "Prisms") > 0 and f(lay, "FirstLayerThicknessUsed") < 0.3 * f(lay, "InputSizeAtSurface")
    if label == "analytic shock":
        good = good and abs(width - exact_width) <= 0.25 * f(lay, "InputSizeAtSurface")
    check(good, "%s, prism layers: the shock measured %.4f thick%s, the stack %.4f per side, the first layer %.4f "
          "(%.2f of the input's size at S), %d prisms, new tetrahedra >= %.1f deg"
          % (label, width, " (exact 10-90 %%: %.4f)" % exact_width if label == "analytic shock" else "", stack,
             f(lay, "FirstLayerThicknessUsed"), f(lay, "FirstLayerThicknessUsed") / f(lay, "InputSizeAtSurface"),
             f(lay, "Prisms"), f(lay, "MinDihedralAngleNew")))
    artest.check_valid_mesh(label + ", prism layers", reference, lay)

# GrowthRatio reaches EmbeddedRemesh: layer k is first * 1.5^k, the 5 of them
# summing to the stack.
lay = artest.fetch(AdaptToShocks(Input=cone, LayerType=1, GrowthRatio=1.5))
stack, first = f(lay, "LayerStackHeight"), f(lay, "FirstLayerThicknessUsed")
check(abs(first - stack * 0.5 / (1.5 ** 5 - 1)) <= 1e-12 * stack,
      "GrowthRatio 1.5: the first layer %.5f of the stack %.5f (expected %.5f)"
      % (first, stack, stack * 0.5 / (1.5 ** 5 - 1)))


# ---- Bad and borderline input.
def refused(proxy, fragments, label):
    before = len(messages.GetOutput())
    o = artest.fetch(proxy)
    text = messages.GetOutput()[before:]
    s = artest.fetch(proxy, 1)
    check(all(x in text for x in fragments) and "Region" not in o.CellData.keys() and s.GetNumberOfCells() == 0
          and o.GetNumberOfCells() == src.GetNumberOfCells(),
          "%s: refused (%s), the input passes through, no surface" % (label, " / ".join(fragments)))


def uniform_flow():
    g = vtkUnstructuredGrid()
    g.DeepCopy(src.VTKObject)
    for name in ("U", "p", "rho", "T", "rhoU", "rhoE"):
        a = g.GetPointData().GetArray(name)
        for c in range(a.GetNumberOfComponents()):
            a.FillComponent(c, a.GetComponent(0, c))
        g.GetCellData().RemoveArray(name)
    p = PVTrivialProducer()
    p.GetClientSideObject().SetOutput(g)
    return p


def bare_mesh():
    g = vtkUnstructuredGrid()
    g.CopyStructure(src.VTKObject)
    p = PVTrivialProducer()
    p.GetClientSideObject().SetOutput(g)
    return p


refused(AdaptToShocks(Input=uniform_flow()), ["No shock found"], "a uniform flow")
refused(AdaptToShocks(Input=bare_mesh()), ["No complete flow state", "the shock sensor could not run"], "no flow arrays")
refused(AdaptToShocks(Input=cone, Mode=3), ["Mode is 3"], "Mode 3")
refused(AdaptToShocks(Input=cone, MinimumClusterFraction=0.0), ["MinimumClusterFraction is 0"], "MinimumClusterFraction 0")

# The filters run their own work on threads in a vtkSMPTools::LocalScope:
# the process's backend, which every other filter of the session uses, is
# what it was (a filter used to switch it to STDThread for good).
check(vtkSMPTools.GetBackend() == backend,
      "the process's SMP backend is unchanged by the filters (%s, was %s)" % (vtkSMPTools.GetBackend(), backend))
artest.finish()
