"""MedialAxisDelaunay through paraview.simple, on isosurfaces made the way a
user makes them (Contour with normals):
- analytic: the sheet of the slab |z| < 2 is the plane z = 0, the sheet of
  the shell 4.5 < r < 7.5 is the sphere r = 6, each within one surface edge
  length, with Radius the half thickness; a Domain clips the sheet;
- OpenFOAM wedge15Ma5 (one cell deep, front and back planes as symmetry
  planes): the sheet of the WeightFunction isosurface lies within 2 cells of
  the plane QuadricFit fits, spans the shock from near the apex to the
  outlet, and is empty without the symmetry planes (every contour point is
  then on the convex hull);
- OpenFOAM cone20Ma2p5 (3-D, half model): the sheet of the W isosurface is
  one sheet within 2 cells of the cone QuadricFit fits to the shock sensor,
  covering it, and stands orthogonally on the symmetry plane z = 0;
- bad input: empty surface, quadrilaterals, coincident points, a flat point
  set, NaN coordinates: an error naming the problem and an empty output.
"""
import numpy as np
from paraview.simple import *
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow

import artest
from artest import check

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)


def edge_lengths(surface):
    """Lengths of the edges of a triangulated vtkPolyData (numpy wrapper)."""
    P = np.asarray(surface.Points)
    polys = np.asarray(surface.VTKObject.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    return np.concatenate([np.linalg.norm(P[polys[:, a]] - P[polys[:, b]], axis=1) for a, b in ((0, 1), (1, 2), (2, 0))])


# ---- Analytic slab |z| < 2 in the box [-10, 10]^3 (open at the box's sides).
grid = Wavelet(WholeExtent=[-20, 20, -20, 20, -20, 20])  # spacing 1, scaled to 0.5
grid = Transform(Input=grid)
grid.Transform.Scale = [0.5, 0.5, 0.5]
slab_field = Calculator(Input=grid, ResultArrayName="f", Function="-abs(coordsZ)")
slab_iso = Contour(Input=slab_field, ContourBy=["POINTS", "f"], Isosurfaces=[-2.0], ComputeNormals=1)
iso = artest.fetch(slab_iso)
h = edge_lengths(iso).max()
medial = MedialAxisDelaunay(Input=slab_iso, Smoothing="None")
sheet = artest.fetch(medial)
P = np.asarray(sheet.Points)
check(sheet.GetNumberOfCells() > 100, "slab: %d sheet triangles" % sheet.GetNumberOfCells())
inner = (abs(P[:, 0]) < 8) & (abs(P[:, 1]) < 8)
check(inner.sum() > 100 and abs(P[inner, 2]).max() <= h,
      "slab: %d points inside, all within one edge length (%.3f) of z = 0 (max |z| %.2e)" % (inner.sum(), h, abs(P[inner, 2]).max()))
R = np.asarray(sheet.PointData["Radius"])
check(abs(R[inner] - 2.0).max() <= h, "slab: Radius is the half thickness 2 within %.3f (max error %.3f)" % (h, abs(R[inner] - 2.0).max()))
areas = np.asarray(sheet.FieldData["SheetAreas"])
check(len(areas) == 1 and areas[0] > 0.9 * 18.0 ** 2, "slab: one sheet of area %.1f (the plane inside the box's sides: about %.0f)" % (areas[0], 20.0 ** 2))

# A Domain: the sheet stops at its boundary (a box ending at x = 3).
domain = Clip(Input=grid, ClipType="Plane", Crinkleclip=1)
domain.ClipType.Origin = [3.0, 0, 0]
domain.ClipType.Normal = [1.0, 0, 0]
clipped = artest.fetch(MedialAxisDelaunay(Input=slab_iso, Domain=domain, Smoothing="None"))
dbounds = artest.fetch(domain).VTKObject.GetBounds()
xmax = np.asarray(clipped.Points)[:, 0].max()
check(dbounds[1] - h <= xmax <= dbounds[1] + 1e-9, "domain: the sheet ends at the domain's x = %.2f (x max %.3f)" % (dbounds[1], xmax))

# ---- Analytic spherical shell 4.5 < r < 7.5.
shell_field = Calculator(Input=grid, ResultArrayName="f", Function="-abs(sqrt(coordsX^2+coordsY^2+coordsZ^2) - 6)")
shell_iso = Contour(Input=shell_field, ContourBy=["POINTS", "f"], Isosurfaces=[-1.5], ComputeNormals=1)
h = edge_lengths(artest.fetch(shell_iso)).max()
for smoothing in ("None", "Windowed Sinc"):
    sheet = artest.fetch(MedialAxisDelaunay(Input=shell_iso, Smoothing=smoothing))
    P = np.asarray(sheet.Points)
    r = np.linalg.norm(P, axis=1)
    check(len(r) > 100 and abs(r - 6.0).max() <= h,
          "shell (%s): %d points within one edge length (%.3f) of r = 6 (max error %.3f)" % (smoothing, len(r), h, abs(r - 6.0).max()))
    area = np.asarray(sheet.FieldData["SheetAreas"]).sum()
    check(abs(area / (4 * np.pi * 36) - 1) < 0.1, "shell (%s): area %.1f vs the sphere's %.1f" % (smoothing, area, 4 * np.pi * 36))

# FeatureRegion: the other side of the shell's surface is the hollow and the
# outside; its medial points are the centre and far away, not r = 6.
outside = artest.fetch(MedialAxisDelaunay(Input=shell_iso, Smoothing="None", FeatureRegion="Below Iso-Value"))
r = np.linalg.norm(np.asarray(outside.Points), axis=1) if outside.GetNumberOfPoints() else np.array([0.0])
check(abs(r - 6.0).min() > 1.0, "shell, region below the iso-value: no sheet point near r = 6 (closest %.2f)" % abs(r - 6.0).min())

# ---- The OpenFOAM wedge: one cell deep, symmetry planes front and back.
reader = XMLUnstructuredGridReader(FileName=[artest.data("wedge15Ma5.vtu")])
mesh = artest.fetch(reader)
zlo, zhi = mesh.VTKObject.GetBounds()[4:6]
weight = WeightFunction(Input=reader, Variables=["rho", "rhoU", "rhoE"], ComputePointWeight=1)
clusters = FeatureCluster(Input=weight, SensorArray=["POINTS", "WeightFunction"], SensorRange=[1.5, 2.0])
fit = artest.fetch(QuadricFit(Input=OutputPort(clusters, 1), Domain=reader, Template="Plane", ClusterId=0))
normal, origin = artest.field(fit, "Normal"), artest.field(fit, "Origin")
volumes = np.asarray(artest.fetch(CellSize(Input=reader, ComputeVolume=1)).CellData["Volume"])
cell = np.median(np.sqrt(volumes / (zhi - zlo)))  # in-plane cell size
contour = Contour(Input=weight, ContourBy=["POINTS", "WeightFunction"], Isosurfaces=[1.5], ComputeNormals=1)
planes = [0, 0, zlo, 0, 0, 1, 0, 0, zhi, 0, 0, 1]
sheet = artest.fetch(MedialAxisDelaunay(Input=contour, Domain=reader, SymmetryPlanes=planes))
P = np.asarray(sheet.Points)
d = abs((P - origin) @ normal) / cell
check(len(P) > 100 and d.max() <= 2.0,
      "wedge: %d sheet points, all within 2 cells of the fitted plane (max %.2f cells, mean %.2f; cell %.4f)" % (len(P), d.max(), d.mean(), cell))
check(P[:, 2].min() >= zlo - 1e-9 and P[:, 2].max() <= zhi + 1e-9 and P[:, 2].max() - P[:, 2].min() > 0.99 * (zhi - zlo),
      "wedge: the sheet spans the depth between the symmetry planes, z in [%.4f, %.4f]" % (P[:, 2].min(), P[:, 2].max()))
xmax = mesh.VTKObject.GetBounds()[1]
check(P[:, 0].min() < 0.07 and P[:, 0].max() > xmax - 2 * cell,
      "wedge: the sheet spans the shock from x = %.3f (apex at 0) to x = %.3f (outlet at %.3f)" % (P[:, 0].min(), P[:, 0].max(), xmax))
check(len(sheet.FieldData["SheetAreas"]) == 1, "wedge: one sheet")
def triangle_normals(surface):
    P = np.asarray(surface.Points)
    t = np.asarray(surface.VTKObject.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    n = np.cross(P[t[:, 1]] - P[t[:, 0]], P[t[:, 2]] - P[t[:, 0]])
    area = 0.5 * np.linalg.norm(n, axis=1)
    return n / np.maximum(2 * area, 1e-300)[:, None], area


n, area = triangle_normals(sheet)
tilt = 90.0 - artest.angle_between_planes(n, np.broadcast_to([0.0, 0.0, 1.0], n.shape))
check(np.average(tilt, weights=area) < 5.0,
      "wedge: the sheet stands orthogonal to the symmetry planes (area-weighted mean tilt %.2f deg)" % np.average(tilt, weights=area))
# A trim distance: the sheet is cut 0.002 short of each plane and extended
# back onto it by strips that are exactly orthogonal to it.
trimmed = artest.fetch(MedialAxisDelaunay(Input=contour, Domain=reader, SymmetryPlanes=planes, SymmetryTrimDistance=0.002))
strips = np.asarray(trimmed.CellData["Extended"]) == 1
n, area = triangle_normals(trimmed)
Pz = np.asarray(trimmed.Points)[:, 2]
check(strips.sum() > 20 and abs(n[strips, 2]).max() < 1e-6 and Pz.min() <= zlo + 1e-9 and Pz.max() >= zhi - 1e-9,
      "wedge, trim 0.002: %d strip triangles, exactly orthogonal to the planes (max |n_z| %.1e), reaching both" % (strips.sum(), abs(n[strips, 2]).max()))
t = np.asarray(trimmed.VTKObject.GetPolys().GetConnectivityArray()).reshape(-1, 3)
zs = Pz[t[strips]]
in_band = np.all(zs <= zlo + 0.002 + 1e-9, axis=1) | np.all(zs >= zhi - 0.002 - 1e-9, axis=1)
check(in_band.all(), "wedge, trim 0.002: every strip lies within 0.002 of its own plane (none folds across the sheet "
      "to the other plane, %d outside)" % (~in_band).sum())
bare = artest.fetch(MedialAxisDelaunay(Input=contour, Domain=reader))
check(bare.GetNumberOfCells() == 0, "wedge without symmetry planes: no interior facet (%d triangles)" % bare.GetNumberOfCells())

# ---- The OpenFOAM cone (Mach 2.5, 20 deg; Gmsh tetrahedra, half model with
# the symmetry plane z = 0): the sheet of the W isosurface against the cone
# that QuadricFit fits to the shock sensor's clusters (itself within 0.2 deg
# of Taylor-Maccoll, PyFeatureSurfacesReal).
cone = XMLUnstructuredGridReader(FileName=[artest.data("cone20Ma2p5.vtu")])
csrc = artest.fetch(cone)
sensor = ShockSensor(Input=cone, Velocity=["POINTS", "U"], Pressure=["POINTS", "p"], Density=["POINTS", "rho"],
                     Gamma=artest.field(csrc, "Gamma")[0])
cweight = WeightFunction(Input=sensor, Variables=["rho", "rhoU", "rhoE"], ComputePointWeight=1)
cclusters = FeatureCluster(Input=cweight, SensorArray=["POINTS", "NormalMach"], SensorRange=[0.8, 1.2])
cfit = artest.fetch(QuadricFit(Input=OutputPort(cclusters, 1), Domain=cone, Template="Cone", ClusterId=0))
apex, axis = artest.field(cfit, "Apex"), artest.field(cfit, "AxisDirection")
half = np.radians(artest.field(cfit, "HalfAngle")[0])
volumes = np.asarray(artest.fetch(CellSize(Input=cone, ComputeVolume=1)).CellData["Volume"])
cell = np.median(np.cbrt(6 * np.sqrt(2) * volumes))  # edge of the regular tetrahedron of that volume
ccontour = Contour(Input=cweight, ContourBy=["POINTS", "WeightFunction"], Isosurfaces=[1.5], ComputeNormals=1)
csheet = artest.fetch(MedialAxisDelaunay(Input=ccontour, Domain=cone, SymmetryPlanes=[0, 0, 0, 0, 0, 1]))
P = np.asarray(csheet.Points)
v = P - apex
along = v @ axis
dist = np.linalg.norm(v - np.outer(along, axis), axis=1) * np.cos(half) - along * np.sin(half)
check(len(P) > 1000 and abs(dist).max() <= 2.0 * cell,
      "cone: %d sheet points, all within 2 cells of the fitted cone (max %.2f, mean %.2f cells; cell %.4f)"
      % (len(P), abs(dist).max() / cell, abs(dist).mean() / cell, cell))
check(len(csheet.FieldData["SheetAreas"]) == 1, "cone: one sheet")
_, fit_area = triangle_normals(cfit)
check(artest.field(csheet, "SheetAreas")[0] > 0.8 * fit_area.sum(),
      "cone: the sheet's area %.3f covers the fitted cone's %.3f in the domain" % (artest.field(csheet, "SheetAreas")[0], fit_area.sum()))
n, area = triangle_normals(csheet)
P3 = np.asarray(csheet.Points)
t = np.asarray(csheet.VTKObject.GetPolys().GetConnectivityArray()).reshape(-1, 3)
near = P3[t][:, :, 2].min(axis=1) < 1e-9
tilt = 90.0 - artest.angle_between_planes(n[near], np.broadcast_to([0.0, 0.0, 1.0], n[near].shape))
check(near.sum() > 10 and np.average(tilt, weights=area[near]) < 10.0,
      "cone: %d triangles reach the symmetry plane, standing on it at %.1f deg from orthogonal (area-weighted mean)"
      % (near.sum(), np.average(tilt, weights=area[near])))

# ---- Symmetry planes picked from the domains' planar boundary patches: the
# wedge's front and back (not its outlet, walls or inlet), the cone's z = 0.
def picked(proxy):
    out = artest.fetch(proxy)
    return np.asarray(out.FieldData["SymmetryPlanesUsed"]).reshape(-1, 6), out


planes_w, auto_w = picked(MedialAxisDelaunay(Input=contour, Domain=reader, SymmetryPlanesFromDomain=1))
expected = np.array([[0, 0, zlo, 0, 0, 1], [0, 0, zhi, 0, 0, 1]])
found = len(planes_w) == 2 and all(np.abs(planes_w - e).max(axis=1).min() < 1e-6 for e in expected)
check(found and len(auto_w.FieldData["SheetAreas"]) == 1,
      "wedge: SymmetryPlanesFromDomain picks the front and back planes only (%s), one sheet" % planes_w.round(4).tolist())
planes_c, _ = picked(MedialAxisDelaunay(Input=ccontour, Domain=cone, SymmetryPlanesFromDomain=1))
check(len(planes_c) == 1 and abs(planes_c[0, 2]) < 1e-9 and abs(abs(planes_c[0, 5]) - 1) < 1e-9,
      "cone: SymmetryPlanesFromDomain picks the plane z = 0 only (%s)" % planes_c.round(4).tolist())

# ---- Bad input.
def refused(proxy, fragment, label):
    before = len(messages.GetOutput())
    out = artest.fetch(proxy)
    text = messages.GetOutput()[before:]
    check(fragment in text, "%s: error says '%s'" % (label, fragment))
    check(out.GetNumberOfCells() == 0 and out.GetNumberOfPoints() == 0, "%s: empty output" % label)


refused(MedialAxisDelaunay(Input=Contour(Input=slab_field, ContourBy=["POINTS", "f"], Isosurfaces=[5.0])),
        "The input surface is empty", "empty surface")
box = Box(XLength=4, YLength=4, ZLength=1)
refused(MedialAxisDelaunay(Input=Clean(Input=box)), "is a quadrilateral with 4 points", "quadrilaterals")
refused(MedialAxisDelaunay(Input=Triangulate(Input=box), Smoothing="None"), "coincide with other points", "coincident points")
refused(MedialAxisDelaunay(Input=Triangulate(Input=Plane(XResolution=4, YResolution=4))), "coplanar", "flat point set")
nan = Transform(Input=slab_iso)
nan.Transform.Scale = [float("nan"), 1.0, 1.0]
refused(MedialAxisDelaunay(Input=nan), "non-finite coordinate", "NaN coordinates")
fixed = LoopSubdivision(Input=Triangulate(Input=Clean(Input=box)), NumberofSubdivisions=3)
good = artest.fetch(MedialAxisDelaunay(Input=fixed))
check(good.GetNumberOfCells() > 0, "the same box, cleaned and triangulated: a sheet of %d triangles" % good.GetNumberOfCells())

artest.finish()
