"""The surface-editing filters through paraview.simple on sheets whose
answers are known exactly:
- RemoveSelectedCells: id, threshold and combined selections remove exactly
  the selected cells (checked by an id array), drop the unused points and
  keep the arrays; no selection or an empty one passes through with a warning;
- TrimSurface: a plane and a box keep only the points on the kept side, the
  area equals the analytic area, a linear point array is interpolated exactly;
- SmoothSurface: open edges stay put with BoundarySmoothing off (and move
  with it on), the roughness of a noised plane drops;
- ExtendToPlane: a tilted sheet whose edge is at distance d from an oblique
  plane: new boundary points on the plane, strip columns parallel to the
  normal, strip triangles orthogonal to the plane, rows no taller than the
  mean edge, exact area gained, arrays copied; trimming, the flipped normal,
  the gap, a non-manifold edge; bad input gives an error and an empty output.
"""
import numpy as np
from paraview.simple import *
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkPoints, vtkStringOutputWindow
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkFiltersCore import vtkTriangleFilter, vtkAppendPolyData
from vtkmodules.vtkFiltersSources import vtkPlaneSource
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

import artest
from artest import check

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)
# An exception's traceback would go to the captured output window: show it.
import sys
import traceback
sys.excepthook = lambda *e: (artest.say("".join(traceback.format_exception(*e))), sys.exit(3))
rng = np.random.default_rng(7)


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def grid_sheet(origin, p1, p2, nx, ny):
    """A triangulated parallelogram (vtkPlaneSource + vtkTriangleFilter)."""
    plane = vtkPlaneSource()
    plane.SetOrigin(*origin)
    plane.SetPoint1(*p1)
    plane.SetPoint2(*p2)
    plane.SetResolution(nx, ny)
    plane.SetOutputPointsPrecision(1)  # double
    tri = vtkTriangleFilter()
    tri.SetInputConnection(plane.GetOutputPort())
    tri.Update()
    pd = vtkPolyData()
    pd.ShallowCopy(tri.GetOutput())
    pd.GetPointData().Initialize()
    pd.GetCellData().Initialize()
    return pd


def add_array(pd, name, values, cells=False):
    a = numpy_to_vtk(np.ascontiguousarray(values), deep=1)
    a.SetName(name)
    (pd.GetCellData() if cells else pd.GetPointData()).AddArray(a)


def producer(pd):
    src = PVTrivialProducer()
    src.GetClientSideObject().SetOutput(pd)
    return src


def tris(out):
    conn = vtk_to_numpy(out.VTKObject.GetPolys().GetConnectivityArray())
    offsets = vtk_to_numpy(out.VTKObject.GetPolys().GetOffsetsArray())
    assert np.all(np.diff(offsets) == 3), "not all triangles"
    return conn.reshape(-1, 3)


def areas(x, t):
    return 0.5 * np.linalg.norm(np.cross(x[t[:, 1]] - x[t[:, 0]], x[t[:, 2]] - x[t[:, 0]]), axis=1)


def open_edges(t):
    e = np.sort(np.vstack([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
    uniq, count = np.unique(e, axis=0, return_counts=True)
    return uniq[count == 1]


seen = [0]


def new_messages():
    """The messages written since the last call."""
    text = messages.GetOutput()
    fresh = text[seen[0]:]
    seen[0] = len(text)
    return fresh


# ====================================================== RemoveSelectedCells
sheet = grid_sheet((0, 0, 0), (1, 0, 0.5), (0, 1, 0), 10, 8)
npts, ncells = sheet.GetNumberOfPoints(), sheet.GetNumberOfCells()
xyz0 = vtk_to_numpy(sheet.GetPoints().GetData()).copy()
add_array(sheet, "CellTag", np.arange(ncells, dtype=np.int64), cells=True)
add_array(sheet, "PointTag", np.arange(npts, dtype=np.int64))
add_array(sheet, "F", 2.0 * xyz0[:, 0] + 3.0 * xyz0[:, 1] - xyz0[:, 2])
src = producer(sheet)
conn0 = vtk_to_numpy(sheet.GetPolys().GetConnectivityArray()).reshape(-1, 3)


def check_removed(out, removed, label):
    removed = set(int(c) for c in removed)
    kept_expected = [c for c in range(ncells) if c not in removed]
    tags = np.asarray(out.CellData["CellTag"])
    check(list(tags) == kept_expected,
          "%s: the %d remaining cells are exactly the unselected ones, in order" % (label, len(kept_expected)))
    used = np.unique(conn0[kept_expected].ravel())
    ptags = np.asarray(out.PointData["PointTag"])
    check(out.GetNumberOfPoints() == len(used) and set(ptags) == set(used),
          "%s: %d points = those the remaining cells use (of %d)" % (label, out.GetNumberOfPoints(), npts))
    x = np.asarray(out.Points)
    check(np.array_equal(x, xyz0[ptags]) and np.array_equal(np.asarray(out.PointData["F"]), 2 * x[:, 0] + 3 * x[:, 1] - x[:, 2]),
          "%s: points and point arrays carried with their ids" % label)
    t = tris(out)
    check(np.array_equal(ptags[t], conn0[kept_expected]), "%s: the remaining cells keep their corners" % label)


chosen = sorted(rng.choice(ncells, 17, replace=False))
ids = IDSelectionSource(IDs=sum([[0, int(c)] for c in chosen], []), FieldType='CELL')
remove = RemoveSelectedCells(Input=src, Selection=ids)
check_removed(artest.fetch(remove), chosen, "RemoveSelectedCells ids")

# A cell threshold selection: CellTag in [30, 59].
thresh = ThresholdSelectionSource(ArrayName='CellTag', Thresholds=[30, 59], FieldType='CELL')
remove.Selection = thresh
check_removed(artest.fetch(remove), range(30, 60), "RemoveSelectedCells threshold")

# A combined selection (ids or threshold), as the GUI makes with Ctrl.
both = AppendSelections(Input=[ids, thresh], SelectionNames=['s0', 's1'], Expression='s0|s1')
remove.Selection = both
check_removed(artest.fetch(remove), set(chosen) | set(range(30, 60)), "RemoveSelectedCells s0|s1")

# Inputs that are not polydata: the sheet as an unstructured grid.
ug = AppendDatasets(Input=src)
remove_ug = RemoveSelectedCells(Input=ug, Selection=ids)
out = artest.fetch(remove_ug)
check(out.VTKObject.IsA("vtkPolyData") and out.GetNumberOfCells() == ncells - len(chosen),
      "RemoveSelectedCells on an unstructured grid: polydata with %d cells" % out.GetNumberOfCells())

new_messages()
none = RemoveSelectedCells(Input=src)
out = artest.fetch(none)
log = new_messages()
check(out.GetNumberOfCells() == ncells and "no selection" in log,
      "RemoveSelectedCells without a selection: pass-through with a warning")
empty_sel = IDSelectionSource(IDs=[0, ncells + 5], FieldType='CELL')
none.Selection = empty_sel
out = artest.fetch(none)
log = new_messages()
check(out.GetNumberOfCells() == ncells and "selects no cell" in log,
      "RemoveSelectedCells with a selection of no cell: pass-through with a warning")
empty_pd = producer(vtkPolyData())
bad = RemoveSelectedCells(Input=empty_pd, Selection=ids)
out = artest.fetch(bad)
log = new_messages()
check(out.GetNumberOfCells() == 0 and "no cells" in log, "RemoveSelectedCells on an empty input: error, empty output")

# ============================================================= TrimSurface
# The sheet z = x / 2 over [0, 1]^2 (area sqrt(1.25)); F = 2x + 3y - z is linear.
SLOPE = np.sqrt(1.25)


def check_trim(trim, side, exact_area, label):
    out = artest.fetch(trim)
    x = np.asarray(out.Points)
    t = tris(out)
    check(np.all(side(x) <= 1e-12), "%s: every point on the kept side (max %.1e)" % (label, side(x).max()))
    a = areas(x, t).sum()
    check(abs(a - exact_area) < 1e-12 * exact_area, "%s: area %.15f = analytic %.15f" % (label, a, exact_area))
    f = np.asarray(out.PointData["F"])
    check(np.abs(f - (2 * x[:, 0] + 3 * x[:, 1] - x[:, 2])).max() < 1e-12, "%s: point array interpolated exactly" % label)
    check(set(np.asarray(out.CellData["CellTag"])) <= set(range(ncells)), "%s: cell array kept" % label)


trim = TrimSurface(Input=src)
trim.TrimType = 'Plane'
trim.TrimType.Origin = [0.5, 0.5, 0.0]
trim.TrimType.Normal = [1.0, 1.0, 0.0]
# Invert (default): keep x + y < 1, half the square.
check_trim(trim, lambda x: x[:, 0] + x[:, 1] - 1.0, 0.5 * SLOPE, "TrimSurface plane")
trim.Invert = 0
trim.TrimType.Origin = [0.37, 0.0, 0.0]
trim.TrimType.Normal = [1.0, 0.0, 0.0]
check_trim(trim, lambda x: 0.37 - x[:, 0], 0.63 * SLOPE, "TrimSurface plane, Invert off")
trim.Invert = 1
trim.TrimType = 'Box'
trim.TrimType.Position = [0.23, 0.31, -1.0]
trim.TrimType.Length = [0.5, 0.45, 3.0]
box_side = lambda x: np.maximum.reduce([0.23 - x[:, 0], x[:, 0] - 0.73, 0.31 - x[:, 1], x[:, 1] - 0.76])
check_trim(trim, box_side, 0.5 * 0.45 * SLOPE, "TrimSurface box")
trim.Invert = 0
check_trim(trim, lambda x: -box_side(x), (1.0 - 0.5 * 0.45) * SLOPE, "TrimSurface outside the box")
out = artest.fetch(trim)
x = np.asarray(out.Points)
oe = open_edges(tris(out))
perimeter = np.linalg.norm(x[oe[:, 1]] - x[oe[:, 0]], axis=1).sum()
expected_perimeter = 2 * (SLOPE + 1.0) + 2 * (0.5 * SLOPE + 0.45)
check(abs(perimeter - expected_perimeter) < 1e-9, "TrimSurface outside the box: the pieces are merged (open edges %.12f = outline + hole %.12f)"
      % (perimeter, expected_perimeter))

# =========================================================== SmoothSurface
flat = grid_sheet((0, 0, 0), (1, 0, 0), (0, 1, 0), 30, 30)
xf = vtk_to_numpy(flat.GetPoints().GetData())
edge_pts = np.unique(open_edges(vtk_to_numpy(flat.GetPolys().GetConnectivityArray()).reshape(-1, 3)))
noisy = xf.copy()
noisy[:, 2] += rng.normal(0.0, 0.01, len(noisy))
flat.GetPoints().SetData(numpy_to_vtk(noisy, deep=1))
smooth = SmoothSurface(Input=producer(flat))
check(smooth.BoundarySmoothing == 0 and smooth.NormalizeCoordinates == 1, "SmoothSurface defaults: BoundarySmoothing off, NormalizeCoordinates on")
out = artest.fetch(smooth)
xs = np.asarray(out.Points)
inner = np.setdiff1d(np.arange(len(xs)), edge_pts)
moved = np.linalg.norm(xs[edge_pts] - noisy[edge_pts], axis=1).max()
check(moved < 1e-12, "SmoothSurface: %d boundary points stay put (moved %.1e)" % (len(edge_pts), moved))
before, after = np.sqrt(np.mean(noisy[inner, 2] ** 2)), np.sqrt(np.mean(xs[inner, 2] ** 2))
check(after < 0.5 * before, "SmoothSurface: interior roughness %.4f -> %.4f" % (before, after))
smooth.BoundarySmoothing = 1
xs = np.asarray(artest.fetch(smooth).Points)
check(np.linalg.norm(xs[edge_pts] - noisy[edge_pts], axis=1).max() > 1e-4, "SmoothSurface with BoundarySmoothing: boundary points move")

# =========================================================== ExtendToPlane
# An oblique plane; the sheet spans e1 (in the plane) and u (at ALPHA to the
# plane), its near edge at distance D.
N = unit([0.3, -0.2, 1.0])
O = np.array([0.1, 0.2, -0.3])
E1 = unit(np.cross(N, [1.0, 0.0, 0.0]))
E2 = np.cross(N, E1)
ALPHA = np.radians(60.0)
U = np.cos(ALPHA) * E2 + np.sin(ALPHA) * N
L, W, D, NX, NY = 1.0, 0.5, 0.13, 20, 10
corner = O + D * N
tilted = grid_sheet(corner, corner + L * E1, corner + W * U, NX, NY)
xt = vtk_to_numpy(tilted.GetPoints().GetData()).copy()
add_array(tilted, "PointTag", np.arange(tilted.GetNumberOfPoints(), dtype=np.int64))
add_array(tilted, "CellTag", np.arange(tilted.GetNumberOfCells(), dtype=np.int64), cells=True)
tsrc = producer(tilted)
sheet_area = L * W


def analyse(out):
    x = np.asarray(out.Points)
    t = tris(out)
    ext = np.asarray(out.CellData["Extended"])
    return x, t, ext


ext = ExtendToPlane(Input=tsrc, PlaneOrigin=list(O), PlaneNormal=list(N))
out = artest.fetch(ext)
x, t, flag = analyse(out)
s = (x - O) @ N
h = artest.field(out, "ExtendMeanEdgeLength")[0]
check(int(artest.field(out, "NumberOfExtendedEdges")[0]) == NX, "ExtendToPlane: the %d edges of the near side are extended" % NX)
a_sheet, a_strip = areas(x, t[flag == 0]).sum(), areas(x, t[flag == 1]).sum()
check(abs(a_sheet - sheet_area) < 1e-12 and abs(a_strip - L * D) < 1e-12 * L * D,
      "ExtendToPlane: area gained %.15f = L d = %.15f" % (a_strip, L * D))
bnd = np.unique(open_edges(t))
scale = np.abs(x).max()
on_plane = np.flatnonzero(np.abs(s) < 1e-9 * scale)
check(len(on_plane) == NX + 1 and np.all(np.isin(on_plane, bnd)) and np.all(s[bnd] > -1e-9 * scale),
      "ExtendToPlane: the %d new boundary points lie on the plane (max |s| %.1e)" % (len(on_plane), np.abs(s[on_plane]).max()))
# Strip triangles contain the normal direction (meet the plane orthogonally).
tn = np.cross(x[t[flag == 1, 1]] - x[t[flag == 1, 0]], x[t[flag == 1, 2]] - x[t[flag == 1, 0]])
tn /= np.linalg.norm(tn, axis=1)[:, None]
dev = np.abs(90.0 - artest.angle_deg(tn, np.broadcast_to(N, tn.shape))).max()
check(dev < 1e-6, "ExtendToPlane: strip triangles orthogonal to the plane (max deviation %.1e deg)" % dev)
# Columns: each strip point lies on the normal line of its boundary point.
tags = np.asarray(out.PointData["PointTag"])
new = np.arange(tilted.GetNumberOfPoints(), len(x))
src_x = xt[tags[new]]
d = x[new] - src_x
# The angle between d and -N, measured from the cross product (arccos of a
# cosine next to -1 cannot resolve 1e-6 degree).
ang = artest.angle_deg(d, np.broadcast_to(-N, d.shape))
check(len(new) > 0 and ang.max() < 1e-6,
      "ExtendToPlane: %d strip points on their boundary point's normal line, point arrays copied (max angle %.1e deg)"
      % (len(new), ang.max()))
rows = int(np.ceil(D / h))
check(len(new) == rows * (NX + 1), "ExtendToPlane: %d rows of height %.4f <= mean edge %.4f" % (rows, D / rows, h))
owner = np.asarray(out.CellData["CellTag"])[flag == 1]
check(set(owner) <= set(range(tilted.GetNumberOfCells())) and len(set(owner)) == NX,
      "ExtendToPlane: strip cells carry the cell arrays of the %d edge owners" % NX)
# Orientation: no edge is used twice in the same direction.
directed = np.vstack([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
check(len(np.unique(directed, axis=0)) == len(directed), "ExtendToPlane: strips oriented like the sheet")

# The flipped normal gives the same surface.
ext.PlaneNormal = list(-N)
out = artest.fetch(ext)
check(abs(areas(*analyse(out)[:2]).sum() - (sheet_area + L * D)) < 1e-12 and np.allclose(artest.field(out, "ExtendPlaneNormal"), N),
      "ExtendToPlane: a normal pointing away from the sheet is flipped, same result")

# Trimming: cut at T (inside the sheet), then extend from the cut.
T = D + 0.2
ext.PlaneNormal = list(N)
ext.TrimDistance = T
out = artest.fetch(ext)
x, t, flag = analyse(out)
s = (x - O) @ N
expected = L * (W - (T - D) / np.sin(ALPHA)) + L * T
got = areas(x, t).sum()
check(abs(got - expected) < 1e-12 * expected, "ExtendToPlane trim: area %.15f = analytic %.15f" % (got, expected))
check(np.all(s[np.unique(t[flag == 0])] >= T - 1e-12), "ExtendToPlane trim: the kept sheet lies beyond TrimDistance")
sb = s[np.unique(t[flag == 1])]
lowest = np.abs(sb) < 1e-9 * scale
check(np.all(lowest | (sb >= -1e-9)) and np.count_nonzero(lowest) >= NX + 1 and abs(sb[~lowest].max() - T) < 1e-9,
      "ExtendToPlane trim: the strips run from the cut (s = T) to the plane, %d edges" % artest.field(out, "NumberOfExtendedEdges")[0])

# A gap smaller than the distance: nothing extended, with a warning.
ext.TrimDistance = 0.0
ext.MaximumGap = 0.5 * D
new_messages()
out = artest.fetch(ext)
log = new_messages()
check(out.GetNumberOfCells() == tilted.GetNumberOfCells() and np.all(np.asarray(out.CellData["Extended"]) == 0)
      and "nothing was extended" in log, "ExtendToPlane: MaximumGap < d leaves the sheet alone, with a warning")
ext.MaximumGap = 0.0

# A non-manifold sheet: a fin shares an interior line of the sheet; that line
# is not open; the fin's own near edge is.
fin_base = corner + 0.5 * W * U
fin = grid_sheet(fin_base, fin_base + L * E1, fin_base + 0.3 * N + 0.2 * E2, NX, 3)
app = vtkAppendPolyData()
plain = grid_sheet(corner, corner + L * E1, corner + W * U, NX, NY)
app.AddInputData(plain)
app.AddInputData(fin)
app.Update()
nm = ExtendToPlane(Input=producer(app.GetOutput()), PlaneOrigin=list(O), PlaneNormal=list(N))
out = artest.fetch(nm)
check(int(artest.field(out, "NumberOfExtendedEdges")[0]) == NX,
      "ExtendToPlane non-manifold: only the %d near edges are extended, not the shared line" % NX)

# Bad input.
def bad_case(make, words, label):
    new_messages()
    out = artest.fetch(make())
    log = new_messages()
    check(out.GetNumberOfCells() == 0 and out.GetNumberOfPoints() == 0 and "ERROR" in log and words in log,
          "ExtendToPlane %s: error naming it ('%s'), empty output" % (label, words))


bad_case(lambda: ExtendToPlane(Input=tsrc, PlaneNormal=[0, 0, 0]), "PlaneNormal is zero", "zero normal")
bad_case(lambda: ExtendToPlane(Input=tsrc, PlaneOrigin=[float('nan'), 0, 0]), "not finite", "NaN origin")
bad_case(lambda: ExtendToPlane(Input=empty_pd), "no cells", "empty input")
nan_pd = vtkPolyData()
nan_pd.DeepCopy(tilted)
nan_pd.GetPoints().SetPoint(5, float('nan'), 0, 0)
bad_case(lambda: ExtendToPlane(Input=producer(nan_pd), PlaneOrigin=list(O), PlaneNormal=list(N)), "NaN or Inf", "NaN point")
verts = vtkPolyData()
vp = vtkPoints()
vc = vtkCellArray()
for i in range(4):
    vp.InsertNextPoint(i, 0, 0)
    vc.InsertNextCell(1)
    vc.InsertCellPoint(i)
verts.SetPoints(vp)
verts.SetVerts(vc)
bad_case(lambda: ExtendToPlane(Input=producer(verts)), "no polygons", "vertices only")
bad_case(lambda: ExtendToPlane(Input=tsrc, PlaneOrigin=list(O), PlaneNormal=list(N), TrimDistance=5.0),
         "nothing of the surface", "everything trimmed")

artest.finish()
