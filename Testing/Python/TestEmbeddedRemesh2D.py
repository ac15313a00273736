"""EmbeddedRemesh's 2-D mode on the OpenFOAM wedge (Data/wedge15Ma5.vtu,
4800 hexahedra one cell deep between z = -0.005 and z = 0.005), through the
real chain WeightFunction -> FeatureCluster -> QuadricFit (Plane), as an
unstructured grid and as an OpenFOAM-reader multiblock. Asserts:
- the mode is detected (field TwoDimensional = 1) and the output holds only
  hexahedra and wedges, each spanning the full depth with one face on each
  plane (what a 2-D OpenFOAM case needs);
- every cell has positive corner Jacobians (hexahedra and wedges, VTK node
  order) and vtkCellValidator finds no wrongly oriented cell;
- conforming (every face, triangle or quad, in at most two cells) and
  watertight (the boundary off the planes is the input's, face for face;
  every boundary edge in exactly two boundary faces);
- the kept hexahedra are input cells, node for node; the volume (VTK's
  cell sizes) is conserved to 1e-9;
- every quad of the embedded surface (output 1) is a face between two cells
  and lies on the fitted plane; they form one chain along the shock from
  near the apex to near the outlet;
- p at the kept nodes equals the input's exactly; the new triangles'
  smallest angle is at least 10 degrees, and at most 2% are below the
  MinTriangleAngle bound (20 degrees; CGAL's mesher may not split the
  cavity's boundary or the curve, so the bound can fail next to them);
- the node counts in field data match the mesh;
- a second cycle on the first one's output (fine triangles at the shock, the
  long wall edges kept): valid, finer again, and the same angle bounds;
- multiblock: the frontAndBack patch is rebuilt and covers exactly the
  output's boundary faces on the planes, the other patches pass through
  unchanged;
- bad input (an empty curve, a curve outside, crossing curves) gives an
  error naming the problem and the input unchanged; TwoDimensional = Off
  keeps the old refusal.
"""
import numpy as np
from paraview.simple import *
from paraview import servermanager
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet
from vtkmodules.vtkFiltersGeneral import vtkCellValidator
from vtkmodules.vtkFiltersVerdict import vtkCellSizeFilter
from vtkmodules.vtkFiltersGeometry import vtkGeometryFilter
from vtkmodules.util.numpy_support import vtk_to_numpy

import artest
from artest import check

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)

HEX, WEDGE = 12, 13
# The faces of VTK's hexahedron and wedge (outward for a positive cell).
FACES = {HEX: [(0, 4, 7, 3), (1, 2, 6, 5), (0, 1, 5, 4), (3, 7, 6, 2), (0, 3, 2, 1), (4, 5, 6, 7)],
         WEDGE: [(0, 1, 2), (3, 5, 4), (0, 3, 4, 1), (1, 4, 5, 2), (2, 5, 3, 0)]}


def cells_of(ds):
    """[(type, point ids)] of a wrapped grid."""
    vtk = ds.VTKObject
    offsets = vtk_to_numpy(vtk.GetCells().GetOffsetsArray())
    conn = vtk_to_numpy(vtk.GetCells().GetConnectivityArray())
    types = vtk_to_numpy(vtk.GetCellTypesArray())
    return [(int(types[c]), conn[offsets[c]:offsets[c + 1]]) for c in range(len(types))]


def key(P, ids):
    return tuple(sorted(tuple(P[i]) for i in ids))


def face_counts(P, cells):
    counts = {}
    for t, ids in cells:
        for f in FACES[t]:
            k = key(P, ids[list(f)])
            counts[k] = counts.get(k, 0) + 1
    return counts


def corner_jacobians(P, t, ids):
    """Triple products of the three edges at each corner, signed so that a
    positively oriented VTK hexahedron or wedge has them all positive."""
    x = P[ids]
    n = 4 if t == HEX else 3
    out = []
    for k in range(n):
        for top in (0, 1):
            c = k + top * n
            nxt = (k + 1) % n + top * n
            prv = (k + n - 1) % n + top * n
            other = k + (1 - top) * n
            a, b, d = x[nxt] - x[c], x[prv] - x[c], x[other] - x[c]
            j = np.dot(np.cross(a, b), d) if t == HEX else np.dot(np.cross(b, a), d)
            out.append(j if top == 0 else -j)
    return out


def cell_volumes(grid):
    size = vtkCellSizeFilter()
    size.SetInputData(grid)
    size.Update()
    return vtk_to_numpy(size.GetOutput().GetCellData().GetArray("Volume"))


reader = XMLUnstructuredGridReader(FileName=[artest.data("wedge15Ma5.vtu")])
src = artest.fetch(reader)
P0 = np.asarray(src.Points, dtype=np.float64)
C0 = cells_of(src)
zlo, zhi = P0[:, 2].min(), P0[:, 2].max()
weight = WeightFunction(Input=reader, Variables=["rho", "rhoU", "rhoE"], ComputePointWeight=1)
clusters = FeatureCluster(Input=weight, SensorArray=["POINTS", "WeightFunction"], SensorRange=[1.5, 2.0])
fit = QuadricFit(Input=OutputPort(clusters, 1), Domain=reader, Template="Plane", ClusterId=0)
plane = artest.fetch(fit)
normal, origin = artest.field(plane, "Normal"), artest.field(plane, "Origin")

er = EmbeddedRemesh(Input=reader, Surfaces=[fit])
out = artest.fetch(er)
emb = artest.fetch(er, 1)
P1 = np.asarray(out.Points, dtype=np.float64)
C1 = cells_of(out)
region = np.asarray(out.CellData["Region"])
check(artest.field(out, "TwoDimensional")[0] == 1, "wedge: detected as one cell deep (TwoDimensional = 1)")
types = np.array([t for t, _ in C1])
check(set(types) == {HEX, WEDGE} and np.all(types[region == 0] == HEX) and np.all(types[region == 1] == WEDGE),
      "wedge: %d kept hexahedra, %d new wedges (input %d hexahedra)" % ((region == 0).sum(), (region == 1).sum(), len(C0)))

# ---- Every cell spans the full depth, one face on each plane.
spans = all(np.sum(P1[ids, 2] == zlo) == len(ids) // 2 and np.sum(P1[ids, 2] == zhi) == len(ids) // 2
            and any(np.all(P1[ids[list(f)], 2] == zlo) for f in FACES[t])
            and any(np.all(P1[ids[list(f)], 2] == zhi) for f in FACES[t]) for t, ids in C1)
check(spans, "every cell spans z = %.4f .. %.4f with a face on each plane" % (zlo, zhi))
vertical = all(np.array_equal(P1[ids[:len(ids) // 2], :2], P1[ids[len(ids) // 2:], :2]) for t, ids in C1 if t == WEDGE)
check(vertical, "every wedge is a right prism (its top triangle straight above its base)")

# ---- Positive volumes.
jac = np.array([min(corner_jacobians(P1, t, ids)) for t, ids in C1])
check(jac.min() > 0, "every corner Jacobian positive (min %.3e)" % jac.min())
validator = vtkCellValidator()
validator.SetInputData(out.VTKObject)
validator.Update()
states = vtk_to_numpy(validator.GetOutput().GetCellData().GetArray("ValidityState"))
# (Its convexity test also flags the input's own thin sheared hexahedra on
# the ramp; every other check - orientation, intersecting faces or edges -
# must pass.)
NONCONVEX = 16
check(np.all((states & ~NONCONVEX) == 0), "vtkCellValidator: no cell with wrong orientation or intersecting "
      "faces or edges (%d)" % np.sum((states & ~NONCONVEX) != 0))

# ---- Conforming and watertight; the boundary off the planes is the input's.
c0, c1 = face_counts(P0, C0), face_counts(P1, C1)
check(max(c1.values()) <= 2, "conforming: no face in more than two cells (%d faces)" % len(c1))
on_plane = lambda k: all(p[2] == zlo for p in k) or all(p[2] == zhi for p in k)
b0 = {k for k, n in c0.items() if n == 1 and not on_plane(k)}
b1 = {k for k, n in c1.items() if n == 1 and not on_plane(k)}
check(b0 == b1, "the boundary off the planes is the input's, face for face (%d faces)" % len(b0))
plane_faces = [k for k, n in c1.items() if n == 1 and on_plane(k)]
check(len(plane_faces) == 2 * len(C1), "the boundary on the planes: one face per cell on each (%d)" % len(plane_faces))
geometry = vtkGeometryFilter()
geometry.SetInputData(out.VTKObject)
geometry.Update()
skin = geometry.GetOutput()
SP = vtk_to_numpy(skin.GetPoints().GetData()).astype(np.float64)
so = vtk_to_numpy(skin.GetPolys().GetOffsetsArray())
sc = vtk_to_numpy(skin.GetPolys().GetConnectivityArray())
edge_count = {}
for f in range(len(so) - 1):
    ids = sc[so[f]:so[f + 1]]
    for i in range(len(ids)):
        e = key(SP, [ids[i], ids[(i + 1) % len(ids)]])
        edge_count[e] = edge_count.get(e, 0) + 1
check(set(edge_count.values()) == {2}, "watertight: every edge of the boundary in exactly two boundary faces")

# ---- Kept cells are input cells, node for node; volume conserved.
input_cells = {tuple(map(tuple, P0[ids])) for _, ids in C0}
check(all(tuple(map(tuple, P1[ids])) in input_cells for (t, ids), r in zip(C1, region) if r == 0),
      "the %d kept hexahedra are input cells, node for node" % (region == 0).sum())
v0, v1 = cell_volumes(src.VTKObject).sum(), cell_volumes(out.VTKObject).sum()
check(abs(v1 / v0 - 1) < 1e-9, "volume conserved: %.12g vs %.12g (%.1e)" % (v1, v0, v1 / v0 - 1))
check(abs(artest.field(out, "RelativeVolumeChange")[0]) < 1e-9, "RelativeVolumeChange %.1e" % artest.field(out, "RelativeVolumeChange")[0])

# ---- The embedded surface: quads, faces of the mesh, on the fitted plane, along the shock.
EP = np.asarray(emb.Points, dtype=np.float64)
Q = vtk_to_numpy(emb.VTKObject.GetPolys().GetConnectivityArray()).reshape(-1, 4)
check(len(Q) == artest.field(out, "SurfaceQuads")[0] and len(Q) > 40,
      "the embedded surface: %d quads (SurfaceQuads field)" % len(Q))
check(all(c1.get(key(EP, q), 0) == 2 for q in Q), "every embedded quad is a face between two cells")
used = EP[np.unique(Q)]
dist = np.abs((used - origin) @ normal)
check(dist.max() < 1e-7, "the embedded quads lie on the fitted plane (max distance %.1e)" % dist.max())
segments = [tuple(sorted((tuple(EP[q[0]][:2]), tuple(EP[q[1]][:2])))) for q in Q]
degree = {}
for a, b in segments:
    degree[a] = degree.get(a, 0) + 1
    degree[b] = degree.get(b, 0) + 1
check(sorted(degree.values()).count(1) == 2 and max(degree.values()) == 2,
      "the quads form one chain along the shock")
# The ends are trimmed by lengths of the input's cells (QuadricFit's trim at
# the domain, the cavity's margin), so they are measured in the input's size
# at the curve, h_S, not in the (finer) curve edges.
h = artest.field(out, "SurfaceEdgeLength")[0]
hS = artest.field(out, "InputSizeAtSurface")[0]
xmax = P0[:, 0].max()
check(used[:, 0].min() < 10 * hS and used[:, 0].max() > xmax - 4 * hS,
      "the layer runs from near the apex (x = %.4f, %.1f input cells) to near the outlet (x = %.4f, %.1f input cells short)"
      % (used[:, 0].min(), used[:, 0].min() / hS, used[:, 0].max(), (xmax - used[:, 0].max()) / hS))

# ---- p at kept nodes exact; quality of the new triangles; node counts.
index0 = {tuple(p): i for i, p in enumerate(P0)}
kept_nodes = [i for i, p in enumerate(P1) if tuple(p) in index0]
p0, p1 = np.asarray(src.PointData["p"]), np.asarray(out.PointData["p"])
diff = max(abs(p1[i] - p0[index0[tuple(P1[i])]]) for i in kept_nodes)
check(diff == 0.0, "p at the %d kept nodes equals the input's exactly" % len(kept_nodes))


def triangle_min_angle(x):
    worst = 180.0
    for k in range(3):
        a, b = x[(k + 1) % 3] - x[k], x[(k + 2) % 3] - x[k]
        worst = min(worst, artest.angle_deg(np.append(a, 0.0), np.append(b, 0.0)))
    return worst


angles = [triangle_min_angle(P1[ids[:3], :2]) for t, ids in C1 if t == WEDGE]
# CGAL's mesher never splits the cavity's boundary or the curve, so the
# MinTriangleAngle bound holds only where the refinement reaches; on this
# thin cavity nearly every triangle has an edge on one of them.
below = sum(a < 20.0 for a in angles)
check(min(angles) >= 10.0 and below <= 0.02 * len(angles),
      "every new triangle's smallest angle >= 10 deg (min %.2f, mean %.2f; field %.2f); %d of %d below the "
      "20 deg bound (at most 2%%)" % (min(angles), np.mean(angles), artest.field(out, "MinTriangleAngleNew")[0],
                                     below, len(angles)))
check(abs(min(angles) - artest.field(out, "MinDihedralAngleNew")[0]) < 1e-9 and
      np.allclose(np.asarray(out.CellData["MinDihedralAngle"])[region == 1], np.minimum(angles, 90.0)),
      "MinDihedralAngle of the wedges = min(triangle angle, 90)")
n_new = len(P1) - len(kept_nodes)
n_removed = len(P0) - len(kept_nodes)
counts = {n: artest.field(out, n)[0] for n in ("InputNodes", "OutputNodes", "NewNodes", "RemovedNodes")}
check(counts == {"InputNodes": len(P0), "OutputNodes": len(P1), "NewNodes": n_new, "RemovedNodes": n_removed},
      "node counts in field data %s match the mesh (%d in, %d out, %d new, %d removed)"
      % (counts, len(P0), len(P1), n_new, n_removed))
check(artest.field(out, "KeptCells")[0] == (region == 0).sum() and artest.field(out, "NewCells")[0] == (region == 1).sum(),
      "KeptCells and NewCells match")

# ---- Multiblock (OpenFOAM reader shape): internalMesh + named patches.
def wedge_patches(centre, b):
    names = np.full(len(centre), "obstacle", dtype=object)
    names[np.abs(centre[:, 1] - b[3]) < 1e-7] = "top"
    names[np.abs(centre[:, 0] - b[0]) < 1e-7] = "inlet"
    names[np.abs(centre[:, 0] - b[1]) < 1e-7] = "outlet"
    names[(np.abs(centre[:, 2] - zlo) < 1e-9) | (np.abs(centre[:, 2] - zhi) < 1e-9)] = "frontAndBack"
    return names


patches = ["inlet", "outlet", "top", "obstacle", "frontAndBack"]
volume = src.VTKObject
mb, names = artest.openfoam_multiblock(volume, wedge_patches, patches)
boundary = mb.GetBlock(1)
check(all((names == n).sum() > 0 for n in patches), "the wedge's boundary in 5 patches: %s"
      % {n: int((names == n).sum()) for n in patches})
source = PVTrivialProducer()
source.GetClientSideObject().SetOutput(mb)
adapted = EmbeddedRemesh(Input=source, Surfaces=[fit])
adapted.UpdatePipeline()
amb = servermanager.Fetch(adapted)
av = amb.GetBlock(0)
check(av.GetNumberOfCells() == out.GetNumberOfCells() and av.GetNumberOfPoints() == out.GetNumberOfPoints(),
      "multiblock: internalMesh remeshed as the grid (%d cells)" % av.GetNumberOfCells())
ab = amb.GetBlock(1)
for i, name in enumerate(patches[:-1]):
    same = np.array_equal(vtk_to_numpy(ab.GetBlock(i).GetPolys().GetConnectivityArray()),
                          vtk_to_numpy(boundary.GetBlock(i).GetPolys().GetConnectivityArray()))
    check(same and ab.GetMetaData(i).Get(vtkCompositeDataSet.NAME()) == name, "patch %s passes through unchanged" % name)
fb = ab.GetBlock(4)
FP = vtk_to_numpy(fb.GetPoints().GetData()).astype(np.float64)
fo = vtk_to_numpy(fb.GetPolys().GetOffsetsArray())
fc = vtk_to_numpy(fb.GetPolys().GetConnectivityArray())
fb_faces = [key(FP, fc[fo[f]:fo[f + 1]]) for f in range(len(fo) - 1)]
AP = vtk_to_numpy(av.GetPoints().GetData()).astype(np.float64)
acells = [(av.GetCellType(c), np.array([av.GetCell(c).GetPointId(k) for k in range(av.GetCell(c).GetNumberOfPoints())]))
          for c in range(av.GetNumberOfCells())]
ac = face_counts(AP, acells)
on_planes = {k for k, n in ac.items() if n == 1 and on_plane(k)}
check(len(fb_faces) == len(set(fb_faces)) and set(fb_faces) == on_planes,
      "frontAndBack rebuilt: its %d faces are exactly the new mesh's boundary faces on the planes (%d)"
      % (len(fb_faces), len(on_planes)))
fid = vtk_to_numpy(fb.GetCellData().GetArray("FaceId"))
front_ids = set(np.where(names == "frontAndBack")[0])
check(fb.GetNumberOfPoints() == len(np.unique(fc)) and set(fid) <= front_ids,
      "frontAndBack: no unused points; every face carries a FaceId of an input frontAndBack face")
offp = {k for k, n in ac.items() if n == 1 and not on_plane(k)}
others = set()
for i in range(4):
    pd = ab.GetBlock(i)
    po = vtk_to_numpy(pd.GetPolys().GetOffsetsArray())
    pc = vtk_to_numpy(pd.GetPolys().GetConnectivityArray())
    pp = vtk_to_numpy(pd.GetPoints().GetData()).astype(np.float64)
    others |= {key(pp, pc[po[f]:po[f + 1]]) for f in range(len(po) - 1)}
check(others == offp, "the other patches cover exactly the new mesh's other boundary faces (%d)" % len(offp))

# ---- Deterministic: a second run gives the same mesh, bit for bit.
again = artest.fetch(EmbeddedRemesh(Input=reader, Surfaces=[fit]))
check(np.array_equal(np.asarray(again.Points), np.asarray(out.Points)) and
      np.array_equal(vtk_to_numpy(again.VTKObject.GetCells().GetConnectivityArray()),
                     vtk_to_numpy(out.VTKObject.GetCells().GetConnectivityArray())),
      "deterministic: a second run gives the same points and cells")

# ---- An unstructured grid carrying patch faces (2-D cells with a PatchId):
# those on the planes are rebuilt, the others pass through.
ug = volume.NewInstance()
ug.DeepCopy(volume)
for name in [ug.GetCellData().GetArrayName(i) for i in range(ug.GetCellData().GetNumberOfArrays())]:
    ug.GetCellData().RemoveArray(name)
from vtkmodules.vtkCommonCore import vtkIntArray
pid = vtkIntArray()
pid.SetName("PatchId")
for _ in range(ug.GetNumberOfCells()):
    pid.InsertNextValue(-1)
n_plane_in = n_outlet = 0
for t, ids in C0:
    for f in FACES[t]:
        q = ids[list(f)]
        if np.all(P0[q, 2] == zlo) or np.all(P0[q, 2] == zhi):
            ug.InsertNextCell(9, 4, [int(v) for v in q])
            pid.InsertNextValue(0)
            n_plane_in += 1
        elif np.all(P0[q, 0] == xmax):
            ug.InsertNextCell(9, 4, [int(v) for v in q])
            pid.InsertNextValue(1)
            n_outlet += 1
ug.GetCellData().AddArray(pid)
patched = PVTrivialProducer()
patched.GetClientSideObject().SetOutput(ug)
pout = artest.fetch(EmbeddedRemesh(Input=patched, Surfaces=[fit]))
PP = np.asarray(pout.Points, dtype=np.float64)
pcells = cells_of(pout)
ppid = np.asarray(pout.CellData["PatchId"])
solid = [(t, ids) for t, ids in pcells if t in (HEX, WEDGE)]
plane_keys = [key(PP, ids) for (t, ids), p in zip(pcells, ppid) if p == 0]
pc = face_counts(PP, solid)
want = {k for k, n in pc.items() if n == 1 and on_plane(k)}
check(len(solid) == len(C1) and np.all(ppid[[t in (HEX, WEDGE) for t, _ in pcells]] == -1),
      "grid with patch cells: the volume is remeshed as before (%d cells)" % len(solid))
check(len(plane_keys) == len(set(plane_keys)) and set(plane_keys) == want,
      "grid with patch cells: the %d front/back patch cells (input %d) are exactly the boundary faces on the planes"
      % (len(plane_keys), n_plane_in))
check(int(np.sum(ppid == 1)) == n_outlet, "grid with patch cells: the %d outlet patch cells pass through" % n_outlet)

# ---- A second cycle: the first cycle's output (triangles five times finer
# than the wedge's cells at the shock, the wall's long edges kept) remeshed
# at the same plane. The curve must stay a kept edge's length off the wall
# (it trimmed at its own, finer, edge: fans of 1-degree needles between the
# curve and the unsplittable wall edges near the apex).
er2 = EmbeddedRemesh(Input=er, Surfaces=[fit])
out2 = artest.fetch(er2)
artest.check_valid_mesh("second cycle", out, out2, artest.fetch(er2, 1))
P2 = np.asarray(out2.Points, dtype=np.float64)
region2 = np.asarray(out2.CellData["Region"])
angles2 = [triangle_min_angle(P2[ids[:3], :2]) for (t, ids), r_ in zip(cells_of(out2), region2) if r_ == 1]
below2 = sum(a < 20.0 for a in angles2)
check(min(angles2) >= 10.0 and below2 <= 0.02 * len(angles2),
      "second cycle: every new triangle's smallest angle >= 10 deg (min %.2f); %d of %d below 20 deg"
      % (min(angles2), below2, len(angles2)))
from vtkmodules.vtkFiltersGeometry import vtkDataSetSurfaceFilter
skin = vtkDataSetSurfaceFilter()
skin.SetInputData(out.VTKObject)
skin.Update()
SP = vtk_to_numpy(skin.GetOutput().GetPoints().GetData()).astype(np.float64)
walls = []
for i in range(skin.GetOutput().GetNumberOfCells()):
    ids = [skin.GetOutput().GetCell(i).GetPointId(k) for k in range(skin.GetOutput().GetCell(i).GetNumberOfPoints())]
    low = [j for j in ids if abs(SP[j, 2] - zlo) < 1e-12]
    if len(low) == 2:  # a quad off the planes: its edge on the plane z = zlo
        walls.append(SP[low, :2])
walls = np.array(walls)
emb2 = artest.fetch(er2, 1)
used2 = np.unique(vtk_to_numpy(emb2.VTKObject.GetPolys().GetConnectivityArray()))
E2 = np.asarray(emb2.Points, dtype=np.float64)[used2, :2]
a, b = walls[:, 0][None], walls[:, 1][None]
t_ = np.clip(np.einsum("ijk,ijk->ij", E2[:, None] - a, b - a) / np.einsum("ijk,ijk->ij", b - a, b - a), 0, 1)
dist = np.linalg.norm(E2[:, None] - (a + t_[..., None] * (b - a)), axis=2)
nearest = np.argmin(dist, axis=1)
clear = dist[np.arange(len(E2)), nearest] / np.linalg.norm(walls[nearest, 1] - walls[nearest, 0], axis=1)
check(clear.min() >= 1.0 - 1e-9, "second cycle: the curve stays BoundaryMargin (1) x the nearest boundary edge off "
      "the boundary (min %.2f of it)" % clear.min())
check(artest.field(out2, "SurfaceSizeRatio")[0] <= 1.0 / 3.0 and len(P2) > len(P1),
      "second cycle: finer again at the shock (size ratio %.2f), %d -> %d nodes"
      % (artest.field(out2, "SurfaceSizeRatio")[0], len(P1), len(P2)))

# ---- FullDomain: the whole cross-section remeshed, still one cell deep.
full = artest.fetch(EmbeddedRemesh(Input=reader, Surfaces=[fit], Mode="FullDomain"))
FPo = np.asarray(full.Points, dtype=np.float64)
fcells = cells_of(full)
fcount = face_counts(FPo, fcells)
check(all(t == WEDGE for t, _ in fcells) and {k for k, n in fcount.items() if n == 1 and not on_plane(k)} == b0
      and abs(cell_volumes(full.VTKObject).sum() / v0 - 1) < 1e-9,
      "FullDomain: %d wedges, the boundary off the planes the input's, volume conserved" % len(fcells))

# ---- Bad input: an error naming the problem, the input unchanged.
def refused(surfaces, fragment, label, **props):
    before = len(messages.GetOutput())
    o = artest.fetch(EmbeddedRemesh(Input=reader, Surfaces=surfaces, **props))
    text = messages.GetOutput()[before:]
    check(fragment in text, "%s: error says '%s'" % (label, fragment))
    check(o.GetNumberOfCells() == len(C0) and "Region" not in o.CellData.keys(),
          "%s: the input passes through unchanged (%d cells)" % (label, o.GetNumberOfCells()))


lifted = Transform(Input=fit)
lifted.Transform.Translate = [0.0, 0.0, 1.0]
refused([lifted], "does not cross the mid-depth plane", "surface away from the mid-depth plane")
far = Transform(Input=fit)
far.Transform.Translate = [5.0, 0.0, 0.0]
refused([far], "outside the mesh", "curve outside the mesh")
crossing = Transform(Input=fit)
crossing.Transform.Rotate = [0.0, 0.0, 50.0]
crossing.Transform.Translate = [0.08, -0.02, 0.0]
refused([fit, crossing], "intersects itself", "two crossing curves")
refused([fit], "no tetrahedra", "TwoDimensional = Off", TwoDimensional="Off")

artest.finish()
