"""FeatureCluster on fields whose answer is known exactly:
- slabs of even and odd thickness (in node layers) on the structured mesh:
  the medial points are the middle layer(s), whose mean is the mid-plane;
- the analytic oblique shock: the medial points of W lie on the exact shock
  plane (weighted plane fit within 1 degree, offset within a cell);
- two separate bands give two clusters, ordered by size;
- a cell-array sensor; bad input (no node in range, a missing, a
  3-component or a non-finite sensor) gives a clear message and no crash.
"""
import numpy as np
from paraview.simple import *
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow

import artest
from artest import check

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)

mesh = XMLUnstructuredGridReader(FileName=[artest.data("oblique_shock_structured.vtu")])
h = 1.0 / 16


def cluster(source, array, lo, hi, rings=0, association="POINTS", minimum=10):
    fc = FeatureCluster(Input=source, SensorArray=[association, array], SensorRange=[lo, hi],
                        DilationRings=rings, MinimumClusterSize=minimum)
    return fc, artest.fetch(fc, 0), artest.fetch(fc, 1)


# ---- Slabs of 4 (even) and 5 (odd) node layers, x = 4h .. 7h / 8h.
for layers, expected in ((4, [5 * h, 6 * h]), (5, [6 * h])):
    top = (4 + layers - 1) * h
    slab = PythonCalculator(Input=mesh, ArrayName="slab",
                            Expression="1.0 * ((points[:,0] > %r) & (points[:,0] < %r))" % (4 * h - 1e-9, top + 1e-9))
    fc, out, med = cluster(slab, "slab", 0.5, 1.5)
    x = np.asarray(med.Points)[:, 0]
    check(set(np.round(x / h).astype(int)) == set(np.round(np.array(expected) / h).astype(int)),
          "%d-layer slab: medial points on layers %s (got %s)" % (layers, expected, sorted(set(np.round(x / h, 6)))))
    check(abs(x.mean() - (4 * h + top) / 2) < 1e-12,
          "%d-layer slab: medial points centred on the mid-plane x = %.5f (mean %.12f)" % (layers, (4 * h + top) / 2, x.mean()))
    check(len(x) == len(expected) * 17 * 17, "%d-layer slab: %d medial points (expected %d)" % (layers, len(x), len(expected) * 17 * 17))
    dist = np.asarray(out.PointData["BoundaryDistance"])
    check(dist.max() == (layers - 1) // 2, "%d-layer slab: largest boundary distance %d" % (layers, dist.max()))
    sizes = np.asarray(med.FieldData["ClusterSizes"])
    check(list(sizes) == [layers * 17 * 17], "%d-layer slab: one cluster of %d nodes (%s)" % (layers, layers * 17 * 17, list(sizes)))
    Delete(fc)

# ---- The analytic oblique shock: medial points of W on the shock plane.
src = artest.fetch(mesh)
n = artest.field(src, "ShockNormal")
x0 = artest.field(src, "ShockOrigin")
for assoc in ("POINTS", "CELLS"):
    wf = WeightFunction(Input=mesh, Variables=["rho", "rhoU", "rhoE"], ComputePointWeight=1)
    fc, out, med = cluster(wf, "WeightFunction", 1.5, 2.0, rings=1, association=assoc)
    pts = np.asarray(med.Points)
    weight = np.asarray(med.PointData["Weight"])
    cid = np.asarray(med.PointData["ClusterId"])
    sizes = np.asarray(med.FieldData["ClusterSizes"])
    check(len(sizes) == 1 and np.all(cid == 0), "oblique shock (%s sensor): one cluster (%s)" % (assoc, list(sizes)))
    normal, centre = artest.fit_plane(pts, weight)
    angle = artest.angle_between_planes(normal, n)
    offset = abs(np.dot(centre - x0, n))
    check(angle < 1.0, "oblique shock (%s sensor): medial plane within 1 deg of the exact one (%.3f deg)" % (assoc, angle))
    check(offset < h, "oblique shock (%s sensor): medial plane offset %.4f < one cell %.4f" % (assoc, offset, h))
    size = np.asarray(med.PointData["LocalSize"])
    check(np.allclose(weight * size, 1.0) and size.min() >= h - 1e-12 and size.max() <= np.sqrt(3) * h + 1e-12,
          "oblique shock (%s sensor): LocalSize is the longest edge (%.4f .. %.4f), Weight its inverse" % (assoc, size.min(), size.max()))
    mask = np.asarray(out.PointData["FeatureMask"])
    medial_flag = np.asarray(out.PointData["MedialPoint"])
    check(medial_flag.sum() == len(pts) and np.all(mask[medial_flag == 1] == 1),
          "oblique shock (%s sensor): port 0 marks the %d medial points inside the mask" % (assoc, len(pts)))
    Delete(fc)
    Delete(wf)

# ---- Two bands of different strength: two clusters, the wider first.
two = PythonCalculator(Input=mesh, ArrayName="bands",
                       Expression="exp(-((points[:,0]-0.25)/0.08)**2) + 0.7*exp(-((points[:,0]-0.75)/0.08)**2)")
fc, out, med = cluster(two, "bands", 0.5, 2.0)
sizes = np.asarray(med.FieldData["ClusterSizes"])
pts = np.asarray(med.Points)
cid = np.asarray(med.PointData["ClusterId"])
check(len(sizes) == 2 and sizes[0] > sizes[1], "two bands: two clusters, by decreasing size (%s)" % list(sizes))
if len(sizes) == 2:
    check(abs(pts[cid == 0, 0].mean() - 0.25) < 1e-9 and abs(pts[cid == 1, 0].mean() - 0.75) < 1e-9,
          "two bands: cluster 0 at x = 0.25, cluster 1 at x = 0.75 (%.4f, %.4f)"
          % (pts[cid == 0, 0].mean(), pts[cid == 1, 0].mean()))
Delete(fc)

# ---- Bad input.
def message_of(proxy, port=0):
    before = len(messages.GetOutput())
    out = artest.fetch(proxy, port)
    return out, messages.GetOutput()[before:]


fc = FeatureCluster(Input=two, SensorArray=["POINTS", "bands"], SensorRange=[5.0, 6.0])
out, text = message_of(fc, 1)
check("No cluster" in text and out.GetNumberOfPoints() == 0, "no node in range: a warning and no medial point")
check(np.asarray(artest.fetch(fc, 0).PointData["FeatureMask"]).sum() == 0, "no node in range: an empty mask")
out, text = message_of(FeatureCluster(Input=mesh, SensorArray=["POINTS", "nothing"], SensorRange=[0, 1]))
check("sensor array 'nothing' is not a point or cell array" in text and "FeatureMask" not in out.PointData.keys(),
      "missing sensor: error, input passed through")
out, text = message_of(FeatureCluster(Input=mesh, SensorArray=["POINTS", "U"], SensorRange=[0, 1]))
check("has 3 components; it needs 1" in text, "3-component sensor: error")
inf = PythonCalculator(Input=mesh, ArrayName="bad", Expression="1.0 / (points[:,0] > 0.5)")
out, text = message_of(FeatureCluster(Input=inf, SensorArray=["POINTS", "bad"], SensorRange=[0, 2]))
check("holds NaN or Inf" in text, "non-finite sensor: error")
out, text = message_of(FeatureCluster(Input=mesh, SensorArray=["POINTS", "p"], SensorRange=[2, 1]))
check("is empty" in text, "empty range: error")

artest.finish()
