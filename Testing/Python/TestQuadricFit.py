"""QuadricFit through paraview.simple on medial points whose surface is known
exactly: a tilted plane and a cone (apex outside the unit cube), built in
python as a vtkPolyData of vertices with ClusterId, LocalSize and Weight.
Checks the fitted geometry (field data), the mesh (edge length, triangle
quality away from the cut border, coverage of the cluster), trimming to the
unit cube of Data/oblique_shock_unstructured.vtu (nothing outside, the
surface reaches the boundary), the one-filter-per-cluster loop, and that bad
input gives an error naming the problem and an empty output.
"""
import numpy as np
from paraview.simple import *
from paraview import servermanager
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkPoints, vtkStringOutputWindow
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

import artest
from artest import check

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)
rng = np.random.default_rng(2024)

H = 0.04           # local mesh size of the medial points
PLANE_N = np.array([0.25, -0.15, 1.0]) / np.linalg.norm([0.25, -0.15, 1.0])
PLANE_O = np.array([0.5, 0.5, 0.5])
APEX = np.array([-0.3, 0.5, 0.5])
AXIS = np.array([1.0, 0.0, 0.0])
THETA = 30.0


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def plane_points(n, sigma):
    """Points of the plane over (x, y) in [0.05, 0.95]^2, noise along the normal."""
    xy = rng.uniform(0.05, 0.95, (n, 2))
    z = PLANE_O[2] - (PLANE_N[0] * (xy[:, 0] - 0.5) + PLANE_N[1] * (xy[:, 1] - 0.5)) / PLANE_N[2]
    return np.c_[xy, z] + rng.normal(0.0, sigma, (n, 1)) * PLANE_N


def cone_points(n, sigma):
    """Points of the cone inside [0.03, 0.97]^3, noise along its normal."""
    th = np.radians(THETA)
    e1, e2 = np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0])
    out = []
    while len(out) < n:
        s = rng.uniform(0.3, 1.6)
        phi = rng.uniform(-np.pi, np.pi)
        radial = np.cos(phi) * e1 + np.sin(phi) * e2
        p = APEX + s * (np.cos(th) * AXIS + np.sin(th) * radial)
        p += rng.normal(0.0, sigma) * (np.cos(th) * radial - np.sin(th) * AXIS)
        if np.all(p > 0.03) and np.all(p < 0.97):
            out.append(p)
    return np.array(out)


def medial_source(blocks, with_ids=True, with_weight=True):
    """A PVTrivialProducer holding vertices with ClusterId, LocalSize, Weight."""
    xyz = np.vstack([b[1] for b in blocks])
    ids = np.concatenate([np.full(len(b[1]), b[0], dtype=np.int32) for b in blocks])
    size = rng.uniform(0.9 * H, 1.1 * H, len(xyz))
    pd = vtkPolyData()
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(xyz), deep=1))
    pd.SetPoints(pts)
    verts = vtkCellArray()
    for i in range(len(xyz)):
        verts.InsertNextCell(1)
        verts.InsertCellPoint(i)
    pd.SetVerts(verts)
    arrays = [("LocalSize", size)]
    if with_ids:
        arrays.append(("ClusterId", ids))
    if with_weight:
        arrays.append(("Weight", 1.0 / size))
    for name, values in arrays:
        a = numpy_to_vtk(np.ascontiguousarray(values), deep=1)
        a.SetName(name)
        pd.GetPointData().AddArray(a)
    src = PVTrivialProducer()
    src.GetClientSideObject().SetOutput(pd)
    return src


def triangles(out):
    conn = vtk_to_numpy(out.VTKObject.GetPolys().GetConnectivityArray())
    offsets = vtk_to_numpy(out.VTKObject.GetPolys().GetOffsetsArray())
    assert np.all(np.diff(offsets) == 3), "not all triangles"
    return conn.reshape(-1, 3)


def quality(out):
    """(min angle over triangles away from the border, mean edge length, number of those triangles)."""
    x = np.asarray(out.Points)
    tri = triangles(out)
    edges = np.sort(np.vstack([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
    uniq, count = np.unique(edges, axis=0, return_counts=True)
    border = np.zeros(len(x), dtype=bool)
    border[uniq[count == 1].ravel()] = True
    inner = ~border[tri].any(axis=1)
    a, b, c = x[tri[:, 0]], x[tri[:, 1]], x[tri[:, 2]]

    def angle(p, q, r):
        return artest.angle_deg(q - p, r - p)

    angles = np.minimum(np.minimum(angle(a, b, c), angle(b, c, a)), angle(c, a, b))
    lengths = np.linalg.norm(np.vstack([b - a, c - b, a - c]), axis=1)
    return angles[inner].min(), lengths.mean(), inner.sum()


def area(out):
    x = np.asarray(out.Points)
    tri = triangles(out)
    return 0.5 * np.linalg.norm(np.cross(x[tri[:, 1]] - x[tri[:, 0]], x[tri[:, 2]] - x[tri[:, 0]]), axis=1).sum()


plane_xyz = plane_points(900, 0.004)
cone_xyz = cone_points(1500, 0.003)
medial = medial_source([(0, plane_xyz), (1, cone_xyz)])
domain = XMLUnstructuredGridReader(FileName=[artest.data("oblique_shock_unstructured.vtu")])

# ---------------------------------------------------------------- plane
fit = QuadricFit(Input=medial, Template='Plane', ClusterId=0)
out = artest.fetch(fit)
check(str(out.FieldData["Template"].GetValue(0)) == "Plane", "plane: Template field data is 'Plane'")
normal = artest.field(out, "Normal")
ang = artest.angle_between_planes(normal, PLANE_N)
check(ang < 0.2, "plane: normal within 0.2 deg of the exact one (%.4f deg)" % ang)
origin = artest.field(out, "Origin")
check(abs(np.dot(origin - PLANE_O, PLANE_N)) < 2e-3, "plane: Origin lies on the exact plane")
coeff = artest.field(out, "Coefficients")
check(len(coeff) == 4 and abs(np.dot(coeff[:3], PLANE_O) + coeff[3]) < 2e-3,
      "plane: Coefficients a b c d vanish at a point of the exact plane")
rms = artest.field(out, "RMSResidual")[0]
check(0.003 < rms < 0.005, "plane: RMSResidual %.5f near the noise 0.004" % rms)
check(artest.field(out, "NumberOfFitPoints")[0] == 900, "plane: only cluster 0's 900 points are fitted")
h = artest.field(out, "SurfaceEdgeLength")[0]
check(abs(h - H) < 0.05 * H, "plane: automatic edge length %.4f = median LocalSize" % h)
qmin, mean_edge, n_inner = quality(out)
check(n_inner > 500 and qmin > 20.0, "plane: min angle away from the border %.1f deg (> 20) over %d triangles" % (qmin, n_inner))
check(abs(mean_edge - h) < 0.1 * h, "plane: mean edge %.4f near the edge length" % mean_edge)
x = np.asarray(out.Points)
check(np.abs((x - origin) @ normal).max() < 1e-12, "plane: the mesh lies on the fitted plane")
# Trimmed to the cluster + margin (3 edge lengths): the points' (x, y)
# extent [0.05, 0.95] grows by about 3 h (along the plane).
lo, hi = x.min(axis=0), x.max(axis=0)
check(np.all(lo[:2] < 0.05 - 2.5 * h) and np.all(lo[:2] > 0.05 - 3.5 * h) and
      np.all(hi[:2] > 0.95 + 2.5 * h) and np.all(hi[:2] < 0.95 + 3.5 * h),
      "plane: extent = the cluster's + a 3-edge margin (x, y from %.3f to %.3f)" % (lo[:2].min(), hi[:2].max()))
wide = artest.fetch(QuadricFit(Input=medial, Template='Plane', Margin=6))
check(np.asarray(wide.Points)[:, :2].min() < 0.05 - 5.5 * h, "plane: Margin=6 reaches further")

# With the unit cube as the domain and a wide margin: cut exactly at x, y = 0 and 1.
clipped = artest.fetch(QuadricFit(Input=medial, Domain=domain, Template='Plane', Margin=10))
x = np.asarray(clipped.Points)
check(x.min() >= -1e-9 and x.max() <= 1 + 1e-9,
      "plane + domain: inside [0,1]^3 (%.2e .. 1 + %.2e)" % (x.min(), x.max() - 1))
b = clipped.GetBounds()
check(max(abs(b[0]), abs(b[2]), abs(b[1] - 1), abs(b[3] - 1)) < 1e-9,
      "plane + domain: reaches the faces x = 0, 1 and y = 0, 1 (bounds %s)" % (np.round(b, 12),))
exact_area = 1.0 / abs(PLANE_N[2])  # the unit square seen along z
check(abs(area(clipped) - exact_area) < 0.01 * exact_area,
      "plane + domain: area %.4f = the exact section's %.4f" % (area(clipped), exact_area))
qmin, _, n_inner = quality(clipped)
check(qmin > 20.0, "plane + domain: min angle away from the cut %.1f deg" % qmin)
check(np.abs((x - origin) @ normal).max() < 1e-9, "plane + domain: the cut points stay on the plane")

# ---------------------------------------------------------------- cone
for label, kwargs in (("automatic axis", {}),
                      ("user axis", dict(UseAutomaticAxis=0, AxisOrigin=[-0.3, 0.55, 0.48],
                                         AxisDirection=[1.0, 0.06, -0.03]))):
    cone = artest.fetch(QuadricFit(Input=medial, Template='Cone', ClusterId=1, **kwargs))
    check(str(cone.FieldData["Template"].GetValue(0)) == "Cone", "cone (%s): Template 'Cone'" % label)
    half = artest.field(cone, "HalfAngle")[0]
    check(abs(half - THETA) < 0.2, "cone (%s): half-angle %.4f within 0.2 deg of %g" % (label, half, THETA))
    apex = artest.field(cone, "Apex")
    check(np.linalg.norm(apex - APEX) < 0.01, "cone (%s): apex off by %.5f" % (label, np.linalg.norm(apex - APEX)))
    axis = artest.field(cone, "AxisDirection")
    check(artest.angle_deg(axis, AXIS) < 0.3, "cone (%s): axis along +x" % label)
    check(len(artest.field(cone, "Coefficients")) == 7, "cone (%s): 7 coefficients" % label)
    qmin, mean_edge, n_inner = quality(cone)
    check(n_inner > 500 and qmin > 20.0, "cone (%s): min angle away from the border %.1f deg over %d triangles" % (label, qmin, n_inner))
    check(abs(mean_edge - H) < 0.1 * H, "cone (%s): mean edge %.4f" % (label, mean_edge))
    x = np.asarray(cone.Points)
    v = x - apex
    hh = v @ unit(axis)
    rho = np.linalg.norm(v - np.outer(hh, unit(axis)), axis=1)
    dev = np.abs(rho * np.cos(np.radians(half)) - hh * np.sin(np.radians(half))).max()
    check(dev < 1e-9, "cone (%s): the mesh lies on the fitted cone (%.1e)" % (label, dev))

cone_cut = artest.fetch(QuadricFit(Input=medial, Domain=domain, Template='Cone', ClusterId=1, Margin=12))
x = np.asarray(cone_cut.Points)
check(x.min() >= -1e-9 and x.max() <= 1 + 1e-9,
      "cone + domain: inside [0,1]^3 (%.2e .. 1 + %.2e)" % (x.min(), x.max() - 1))
b = cone_cut.GetBounds()
check(max(abs(b[0]), abs(b[2]), abs(b[3] - 1), abs(b[4]), abs(b[5] - 1)) < 1e-9,
      "cone + domain: reaches the faces x = 0, y = 0, 1, z = 0, 1 (bounds %s)" % (np.round(b, 12),))
qmin, _, _ = quality(cone_cut)
check(qmin > 20.0, "cone + domain: min angle away from the cut %.1f deg" % qmin)

# ---------------------------------------------------------------- several clusters
ids = vtk_to_numpy(servermanager.Fetch(medial).GetPointData().GetArray("ClusterId"))
templates = {0: 'Plane', 1: 'Cone'}
fits = [QuadricFit(Input=medial, Domain=domain, ClusterId=int(i), Template=templates[int(i)])
        for i in sorted(set(ids))]
counts = [artest.fetch(f).GetNumberOfCells() for f in fits]
check(len(fits) == 2 and min(counts) > 100, "one QuadricFit per cluster id: %s triangles" % counts)

# ---------------------------------------------------------------- the whole pipeline
# On the analytic oblique shock (Gmsh tetrahedra, cell size ~0.1): weight
# function -> FeatureCluster's medial points -> plane. The shock plane is
# known exactly. With the axis along z (77 degrees from the shock normal)
# Eq. 4 alone is visibly off; the refinement is not.
src = artest.fetch(domain)
n_exact = artest.field(src, "ShockNormal")
x_exact = artest.field(src, "ShockOrigin")
wf = WeightFunction(Input=domain, Variables=["rho", "rhoU", "rhoE"], ComputePointWeight=1)
fc = FeatureCluster(Input=wf, SensorArray=["POINTS", "WeightFunction"], SensorRange=[1.5, 2.0], DilationRings=1)
for label, kwargs, limit in (("automatic axis", {}, 1.0),
                             ("axis z, Eq. 4 only", dict(UseAutomaticAxis=0, AxisDirection=[0, 0, 1], GeometricRefinement=0), None),
                             ("axis z, refined", dict(UseAutomaticAxis=0, AxisDirection=[0, 0, 1]), 1.0)):
    # ShockCentring off: the fit of the medial points themselves.
    shock = artest.fetch(QuadricFit(Input=OutputPort(fc, 1), Domain=domain, Template='Plane', ShockCentring=0, **kwargs))
    ang = artest.angle_between_planes(artest.field(shock, "Normal"), n_exact)
    offset = abs(np.dot(artest.field(shock, "Origin") - x_exact, n_exact))
    if limit is None:
        check(ang > 2.0, "oblique shock, %s: %.2f deg from the exact shock plane (biased)" % (label, ang))
    else:
        check(ang < limit and offset < 0.05,
              "oblique shock, %s: %.2f deg from the exact shock plane, offset %.4f" % (label, ang, offset))
        b = shock.GetBounds()
        check(min(b[2], b[4]) > -1e-9 and max(b[3], b[5]) < 1 + 1e-9 and b[2] < 1e-9 and b[3] > 1 - 1e-9,
              "oblique shock, %s: the surface spans the cube and stays inside it" % label)

# ---------------------------------------------------------------- shock centring
# The same analytic shock (p a tanh profile across the exact plane): the W band
# sits upstream of the shock, the NormalMach band downstream of its centre, so
# their medial points' fits are off the plane by 0.013 and 0.03 (0.57 and
# 1.6 degrees, 3 and 5.4 with Eq. 4 alone); moved to the half-jump of p along
# the first fit's normal, the points lie on the plane.
mn = FeatureCluster(Input=ShockSensor(Input=domain))
for band, clusters in (("W band", fc), ("NormalMach band", mn)):
    for label, kwargs in (("", {}), (", Eq. 4 only", dict(UseAutomaticAxis=0, AxisDirection=[0, 0, 1], GeometricRefinement=0))):
        plain = artest.fetch(QuadricFit(Input=OutputPort(clusters, 1), Domain=domain, Template='Plane', ShockCentring=0, **kwargs))
        shock = artest.fetch(QuadricFit(Input=OutputPort(clusters, 1), Domain=domain, Template='Plane', **kwargs))
        off0 = abs(np.dot(artest.field(plain, "Origin") - x_exact, n_exact))
        ang = artest.angle_between_planes(artest.field(shock, "Normal"), n_exact)
        offset = abs(np.dot(artest.field(shock, "Origin") - x_exact, n_exact))
        centred, fitted = artest.field(shock, "CentredPoints")[0], artest.field(shock, "NumberOfFitPoints")[0]
        check(ang < 0.1 and offset < 0.002 and off0 > 0.01 and centred >= 0.9 * fitted
              and shock.FieldData["CentringArrayUsed"].GetValue(0) == "p",
              "oblique shock, %s%s, centred on p's half-jump: %.3f deg from the exact plane, offset %.4f (uncentred "
              "%.4f); %d of %d points centred" % (band, label, ang, offset, off0, centred, fitted))
# The density jumps at the same place; a named array that is not there is a
# warning and the points are fitted where they are; no Domain, no centring.
shock = artest.fetch(QuadricFit(Input=OutputPort(fc, 1), Domain=domain, Template='Plane', CentringArray="rho"))
check(artest.angle_between_planes(artest.field(shock, "Normal"), n_exact) < 0.1
      and abs(np.dot(artest.field(shock, "Origin") - x_exact, n_exact)) < 0.002
      and shock.FieldData["CentringArrayUsed"].GetValue(0) == "rho",
      "oblique shock, centred on rho's half-jump: on the exact plane")
before = len(messages.GetOutput())
shock = artest.fetch(QuadricFit(Input=OutputPort(fc, 1), Domain=domain, Template='Plane', CentringArray="nothing"))
check("the Domain has no one-component array 'nothing'" in messages.GetOutput()[before:]
      and artest.field(shock, "CentredPoints")[0] == 0 and shock.FieldData["CentringArrayUsed"].GetValue(0) == "none"
      and shock.GetNumberOfCells() > 0,
      "a centring array that is not there: a warning naming it, the points fitted where they are")
shock = artest.fetch(QuadricFit(Input=OutputPort(fc, 1), Template='Plane'))
check(artest.field(shock, "CentredPoints")[0] == 0 and shock.GetNumberOfCells() > 0, "no Domain: no centring")

# ---------------------------------------------------------------- bad input
def refused(proxy, fragment, label):
    before = len(messages.GetOutput())
    out = artest.fetch(proxy)
    text = messages.GetOutput()[before:]
    check(fragment in text, "%s: error says '%s'" % (label, fragment))
    check(out.GetNumberOfPoints() == 0 and out.GetNumberOfCells() == 0, "%s: empty output" % label)


refused(QuadricFit(Input=medial, ClusterId=7), "No point has ClusterId 7 (the ids present run from 0 to 1)", "absent cluster")
few = medial_source([(0, plane_xyz[:5])])
refused(QuadricFit(Input=few, Template='Quadric'), "Too few points: the Quadric needs at least 6, there are 5", "too few points")
refused(QuadricFit(Input=few, Template='Quartic'), "needs at least 15", "too few points (quartic)")
refused(QuadricFit(Input=medial, UseAutomaticAxis=0, AxisDirection=[0, 0, 0]), "Degenerate axis", "zero axis")
flat = plane_points(200, 0.0)
refused(QuadricFit(Input=medial_source([(0, flat)]), Template='Cone'), "coplanar", "coplanar points, cone")
line = np.outer(np.linspace(0, 1, 30), [1.0, 0.5, 0.2])
refused(QuadricFit(Input=medial_source([(0, line)]), Template='Plane'), "collinear", "collinear points")
nan = plane_xyz[:50].copy()
nan[17, 1] = np.nan
refused(QuadricFit(Input=medial_source([(0, nan)])), "Point 17 has a NaN", "NaN coordinate")
wall = np.c_[np.linspace(0, 1, 40), np.linspace(0, 1, 40), rng.uniform(0, 1, 40)]
refused(QuadricFit(Input=medial_source([(0, wall)]), Template='Quadric', UseAutomaticAxis=0, AxisDirection=[0, 0, 1]),
        "Singular system", "singular system")
refused(QuadricFit(Input=medial_source([(0, plane_xyz)], with_ids=False)), "no point array 'ClusterId'", "no ClusterId array")
far = Transform(Input=domain)
far.Transform.Translate = [5.0, 0.0, 0.0]
refused(QuadricFit(Input=medial, Domain=far), "lies entirely outside the Domain", "surface outside the domain")
check(artest.fetch(QuadricFit(Input=medial_source([(0, plane_xyz)], with_ids=False), ClusterId=-1)).GetNumberOfCells() > 100,
      "ClusterId -1 fits all points without a ClusterId array")

# The same filters still work afterwards.
check(artest.fetch(fit).GetNumberOfCells() > 500, "good input afterwards: a surface")

artest.finish()
