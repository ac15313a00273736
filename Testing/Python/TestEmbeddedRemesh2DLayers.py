"""EmbeddedRemesh's 2-D mode with LayerType Prisms (issue 13) on the OpenFOAM
wedge (Data/wedge15Ma5.vtu, one cell deep), the shock's plane from the real
chain WeightFunction -> FeatureCluster -> QuadricFit, as a grid and as an
OpenFOAM-reader multiblock. Asserts:
- layers of hexahedra on both sides of the curve (Region 2): LayerHexahedra
  = 2 NumberOfLayers (SurfaceQuads - 2), the two tapered end segments'
  layer cells wedges (Prisms = 2 NumberOfLayers 2), LayerCells their sum,
  and the field data says what the 3-D layers say (LayerStackHeight half the
  curve's edge by the automatic rule, FirstLayerThicknessUsed from it and
  GrowthRatio, LimitedColumns);
- aligned with the shock: every layer hexahedron's edges across the layer
  within 0.5 degrees of the fitted plane's normal; where its two columns
  are equally high (all but next to the ends, where the heights grade to
  0) its edges along the layer within 0.5 degrees of the plane; the full-height columns' layer-0 cells exactly
  FirstLayerThicknessUsed thick (1e-9 relative);
- artest.check_valid_mesh (positive corner Jacobians, conforming,
  watertight, the boundary off the planes the input's, volume conserved;
  the embedded quads faces between two cells), every cell spanning the two
  planes, the refill's triangles at least 10 degrees;
- point data: kept points copy the input's p exactly, new points (layer
  points included) equal vtkProbeFilter's interpolation of the input;
- an explicit stack (NumberOfLayers 3, TotalThickness): the stack height
  and first layer as asked;
- multiblock: frontAndBack rebuilt, its faces exactly the output's boundary
  faces on the planes (quads of the hexahedra included);
- bad layer properties refused by name, the input unchanged.
"""
import numpy as np
from paraview.simple import *
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkFiltersCore import vtkProbeFilter
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

import artest
from artest import check

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)
HEX, WEDGE = 12, 13

reader = XMLUnstructuredGridReader(FileName=[artest.data("wedge15Ma5.vtu")])
src = artest.fetch(reader)
P0 = np.asarray(src.Points, dtype=np.float64)
zlo, zhi = P0[:, 2].min(), P0[:, 2].max()
fit = artest.wedge_shock_plane(reader)
plane = artest.fetch(fit)
normal = np.asarray(artest.field(plane, "Normal"), dtype=np.float64)
normal /= np.linalg.norm(normal)

N = 5
er = EmbeddedRemesh(Input=reader, Surfaces=[fit], LayerType="Prisms", NumberOfLayers=N, GrowthRatio=1.2)
out = artest.fetch(er)
emb = artest.fetch(er, 1)
P1 = np.asarray(out.Points, dtype=np.float64)
types, cells = artest.cells_of(out)
region = np.asarray(out.CellData["Region"])
layer = np.asarray(out.CellData["Layer"])
side = np.asarray(out.CellData["LayerSide"])
f = lambda name: artest.field(out, name)[0]
check(f("TwoDimensional") == 1, "layers: 2-D mode (TwoDimensional = 1), no refusal")
quads = int(f("SurfaceQuads"))
nhex = int(((types == HEX) & (region == 2)).sum())
nwedge = int(((types == WEDGE) & (region == 2)).sum())
check(nhex == f("LayerHexahedra") == 2 * N * (quads - 2) and nwedge == f("Prisms") == 2 * N * 2
      and f("LayerCells") == nhex + nwedge,
      "layers: %d hexahedra = 2 x %d layers x (%d segments - 2 tapered ends), %d end wedges = 2 x %d x 2, "
      "LayerCells %d" % (nhex, N, quads, nwedge, N, f("LayerCells")))
check(set(types[region == 1]) == {WEDGE} and set(types[region == 0]) == {HEX},
      "layers: the refill is wedges (%d), the kept cells the input's hexahedra (%d)"
      % ((region == 1).sum(), (region == 0).sum()))
check(set(layer[region == 2]) == set(range(N)) and set(side[region == 2]) == {-1, 1}
      and np.all(layer[region != 2] == -1) and np.all(side[region != 2] == 0),
      "layers: Layer 0..%d and LayerSide +-1 on the layer cells, -1 and 0 elsewhere" % (N - 1))
edge = f("SurfaceEdgeLength")
Z = f("LayerStackHeight")
t0 = Z / sum(1.2 ** k for k in range(N))
check(abs(Z - 0.5 * edge) < 1e-12 * edge and abs(f("FirstLayerThicknessUsed") - t0) < 1e-12 * edge,
      "layers: the automatic stack half a curve edge high per side (%.4g of %.4g), first layer %.4g"
      % (Z, edge, f("FirstLayerThicknessUsed")))
check(f("LimitedColumns") >= 4, "layers: LimitedColumns %d (the tapered ends, 2 per end)" % f("LimitedColumns"))

# ---- Aligned with the shock: edges across the layer along the plane's
# normal, edges along it in the plane. A layer cell's front face is its
# first half of points; across = the two opposite edges of the quad that
# are shorter (the layers are thinner than the segments).
across_dev, along_dev, thick0 = [], [], []
parallel = 0  # cells between two columns of the same height: their edges along the layer lie in the plane
n2 = normal.copy()
n2[2] = 0.0
n2 /= np.linalg.norm(n2)
for c in np.nonzero((region == 2) & (types == HEX))[0]:
    q = P1[cells[c][:4]]
    e = [q[(k + 1) % 4] - q[k] for k in range(4)]
    l = [np.linalg.norm(v) for v in e]
    pair = (0, 2) if l[0] + l[2] < l[1] + l[3] else (1, 3)
    level = abs(l[pair[0]] - l[pair[1]]) < 1e-9 * l[pair[0]]
    parallel += level
    for k in range(4):
        cosine = abs(np.dot(e[k], n2)) / l[k]
        if k in pair:
            across_dev.append(np.degrees(np.arccos(min(1.0, cosine))))
        elif level:
            along_dev.append(np.degrees(np.arcsin(min(1.0, cosine))))
    if layer[c] == 0:
        thick0.append(min(l[pair[0]], l[pair[1]]))
across_dev, along_dev, thick0 = map(np.array, (across_dev, along_dev, thick0))
check(across_dev.max() < 0.5 and along_dev.max() < 0.5 and parallel >= 2 * N * (quads - 6),
      "layers: aligned with the shock: edges across the layer within %.2g deg of the plane's normal; in the %d "
      "hexahedra between columns of equal height (all but the ends' graded ones) the edges along it within %.2g "
      "deg of the plane" % (across_dev.max(), parallel, along_dev.max()))
exact = np.abs(thick0 - t0) < 1e-9 * t0
check(exact.sum() >= 2 * (quads - 4),
      "layers: %d of %d layer-0 hexahedra exactly FirstLayerThicknessUsed thick (all but the graded ends)"
      % (exact.sum(), len(thick0)))

# ---- Valid.
artest.check_valid_mesh("layers", src, out, emb)
spans = all(np.sum(P1[ids, 2] == zlo) == len(ids) // 2 and np.sum(P1[ids, 2] == zhi) == len(ids) // 2
            for ids in cells)
check(spans, "layers: every cell has half its points on each plane")
check(f("MinTriangleAngleNew") >= 10.0, "layers: the refill's smallest triangle angle %.1f deg" % f("MinTriangleAngleNew"))
ar = np.asarray(out.CellData["AspectRatio"])
artest.say("layer cells: aspect ratio (longest / shortest edge, depth included) max %.1f, median %.1f; "
           "in-plane segment / first layer %.1f" % (ar[region == 2].max(), np.median(ar[region == 2]), edge / t0))

# ---- Point data: kept points exact, new ones the input interpolated there.
p0, p1 = np.asarray(src.PointData["p"]), np.asarray(out.PointData["p"])
index = {tuple(x): i for i, x in enumerate(P0)}
kept = np.array([index.get(tuple(x), -1) for x in P1])
check(np.array_equal(p1[kept >= 0], p0[kept[kept >= 0]]), "layers: p at the %d kept points is the input's" % (kept >= 0).sum())
new = np.nonzero(kept < 0)[0]
pts = vtkPoints()
pts.SetData(numpy_to_vtk(np.ascontiguousarray(P1[new]), deep=1))
probe_in = vtkPolyData()
probe_in.SetPoints(pts)
probe = vtkProbeFilter()
probe.SetInputData(probe_in)
probe.SetSourceData(src.VTKObject)
probe.Update()
probed = vtk_to_numpy(probe.GetOutput().GetPointData().GetArray("p"))
valid = vtk_to_numpy(probe.GetOutput().GetPointData().GetArray("vtkValidPointMask")).astype(bool)
err = np.abs(p1[new] - probed)[valid].max() / np.abs(p0).max()
check(valid.mean() > 0.99 and err < 1e-9,
      "layers: p at the %d new points (layer points included) = the input interpolated there (%.1e)" % (len(new), err))

# ---- An explicit stack.
er3 = EmbeddedRemesh(Input=reader, Surfaces=[fit], LayerType="Prisms", NumberOfLayers=3, GrowthRatio=1.5,
                     TotalThickness=0.001)
o3 = artest.fetch(er3)
f3 = lambda name: artest.field(o3, name)[0]
check(abs(f3("LayerStackHeight") - 0.001) < 1e-15 and abs(f3("FirstLayerThicknessUsed") - 0.001 / 4.75) < 1e-15
      and f3("LayerHexahedra") == 2 * 3 * (f3("SurfaceQuads") - 2) and f3("NonPositiveJacobianCells") == 0,
      "explicit stack: 3 layers of ratio 1.5 in 0.001 (first %.4g), %d hexahedra"
      % (f3("FirstLayerThicknessUsed"), f3("LayerHexahedra")))

# ---- Multiblock: frontAndBack rebuilt with the hexahedra's quads.
source, _ = artest.wedge_multiblock(reader)
mer = EmbeddedRemesh(Input=source, Surfaces=[fit], LayerType="Prisms")
mb = servermanager.Fetch(mer)
vol = mb.GetBlock(0)
boundary = mb.GetBlock(1)
fb = boundary.GetBlock(artest.WEDGE_PATCHES.index("frontAndBack"))
from vtkmodules.numpy_interface import dataset_adapter as dsa
wv = dsa.WrapDataObject(vol)
VP = np.asarray(wv.Points, dtype=np.float64)
vtypes, vcells = artest.cells_of(wv)
counts, _ = artest.faces(VP, vtypes, vcells)
on_planes = {k for k, c in counts.items() if c == 1 and
             (np.all(np.frombuffer(k, dtype=np.int64).reshape(-1, 3)[:, 2] == np.round(zlo * 1e9))
              or np.all(np.frombuffer(k, dtype=np.int64).reshape(-1, 3)[:, 2] == np.round(zhi * 1e9)))}
wf = dsa.WrapDataObject(fb)
FP = np.asarray(wf.Points, dtype=np.float64)
off = vtk_to_numpy(fb.GetPolys().GetOffsetsArray())
conn = vtk_to_numpy(fb.GetPolys().GetConnectivityArray())
patch = [artest.coord_key(FP, conn[off[i]:off[i + 1]]) for i in range(len(off) - 1)]
sizes = np.diff(off)
check(set(patch) == on_planes and len(patch) == len(on_planes) and (sizes == 4).sum() > 0,
      "multiblock: frontAndBack is exactly the %d boundary faces on the planes (%d quads, %d triangles)"
      % (len(on_planes), (sizes == 4).sum(), (sizes == 3).sum()))
check(artest.field(wv, "LayerHexahedra")[0] == nhex, "multiblock: the same layers as the grid (%d hexahedra)" % nhex)


# ---- Bad layer properties: refused by name, the input passes through.
def refused(fragment, **props):
    before = len(messages.GetOutput())
    bad = EmbeddedRemesh(Input=reader, Surfaces=[fit], LayerType="Prisms", **props)
    o = artest.fetch(bad)
    text = messages.GetOutput()[before:]
    check(fragment in text and o.GetNumberOfCells() == src.GetNumberOfCells(),
          "refused: %s (%r)" % (fragment, text.strip()[-200:]))


refused("NumberOfLayers is 0", NumberOfLayers=0)
refused("GrowthRatio is -1", GrowthRatio=-1.0)
refused("TotalThickness is -1", TotalThickness=-1.0)
artest.finish()
