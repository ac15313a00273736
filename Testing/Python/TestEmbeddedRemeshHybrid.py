"""EmbeddedRemesh on a hybrid mesh with near-wall layers (paper Fig. 4):
Data/hybrid_wall.vtu (Data/make_hybrid_wall.py: the unit cube, five layers of
prisms and hexahedra on the wall z = 0 up to z = 0.1, pyramids on the
hexahedra, tetrahedra above) and the analytic oblique shock's plane as S,
which crosses the wall and the layers.
- every layer cell (prism, hexahedron, pyramid) of the input is in the
  output bit for bit: the same points, the same connectivity up to the point
  renumbering, the same cell data; the fields at their points too;
- S is trimmed at the layer region's edge: no vertex of the embedded surface
  is within BoundaryMargin times its longest edge of a layer cell, and no
  embedded triangle reaches into one; the embedded surface lies on the plane
  and still covers every point of the plane that is a margin and one S
  triangle away from the domain boundary and the layers;
- validity as TestEmbeddedRemesh: every corner Jacobian of every cell
  positive (tetrahedra, prisms, hexahedra, pyramids; no NonPositiveJacobian
  cells reported), conforming (no triangle or quad face in more than two
  cells), the boundary equal to the input's face for face (triangles and
  quads) and watertight (every boundary edge in two boundary faces), volume
  conserved to 1e-9, every embedded triangle a face between two cells;
- quality: the new tetrahedra's smallest dihedral angle >= 10 degrees, apart
  from those next to a kept cell with a worse angle; the cell arrays
  MinDihedralAngle / MaxDihedralAngle / AspectRatio are right for every cell
  type (the layer cells are right prisms over the wall's triangles and
  quads: their dihedral angles are the wall polygons' angles and 90);
- kept polyhedra: the same mesh with its hexahedra given as polyhedra (their
  six faces) gives the same points and cells, each polyhedron kept with its
  face stream in the output's point ids.
"""
import numpy as np
from paraview.simple import *
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkCommonDataModel import VTK_HEXAHEDRON, VTK_PYRAMID, VTK_TETRA, VTK_WEDGE
from vtkmodules.vtkFiltersExtraction import vtkExtractCellsByType

import artest
from artest import (FACES, by_type, cell_sizes, cells_of, check, coord_key, corner_jacobians, distance, edge_ratio,
                    face_cells, faces, locator_of, polygon_angles, skin)

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)

LAYER_TYPES = (VTK_WEDGE, VTK_HEXAHEDRON, VTK_PYRAMID)
MARGIN = 1.0        # EmbeddedRemesh's BoundaryMargin (default)
EDGE = 0.05         # SurfaceEdgeLength: S finer than the mesh (h = 0.1)


# ---- Input and run.
mesh = XMLUnstructuredGridReader(FileName=[artest.data("hybrid_wall.vtu")])
src = artest.fetch(mesh)
n = artest.field(src, "ShockNormal")
o = artest.field(src, "ShockOrigin")
u = np.cross(n, [0.0, 0.0, 1.0])
u /= np.linalg.norm(u)
v = np.cross(n, u)
plane = Plane(XResolution=20, YResolution=20)  # the shock plane, 3 x 3 about the cube's centre
plane.Origin = list(o - 1.5 * u - 1.5 * v)
plane.Point1 = list(o + 1.5 * u - 1.5 * v)
plane.Point2 = list(o - 1.5 * u + 1.5 * v)
er = EmbeddedRemesh(Input=mesh, Surfaces=[plane], SurfaceEdgeLength=EDGE, BoundaryMargin=MARGIN)
out = artest.fetch(er)
emb = artest.fetch(er, 1)
check("Region" in out.CellData.keys() and not messages.GetOutput().strip(),
      "EmbeddedRemesh ran without an error or warning %r" % messages.GetOutput()[-300:].strip())

P0, P1 = np.asarray(src.Points, dtype=np.float64), np.asarray(out.Points, dtype=np.float64)
types0, cells0 = cells_of(src)
types1, cells1 = cells_of(out)
region = np.asarray(out.CellData["Region"])
layer0 = np.isin(types0, LAYER_TYPES)
artest.say("input: %d tetrahedra, %d prisms, %d hexahedra, %d pyramids; output %d cells (%d new)"
           % tuple([int((types0 == t).sum()) for t in (VTK_TETRA, VTK_WEDGE, VTK_HEXAHEDRON, VTK_PYRAMID)]
                   + [len(types1), int((region == 1).sum())]))

# ---- Every layer cell kept bit for bit.
index1 = {P1[i].tobytes(): i for i in range(len(P1))}
cell_of = {(int(t), tuple(ids)): c for c, (t, ids) in enumerate(zip(types1, cells1)) if t != VTK_TETRA}
match = []
for c in np.nonzero(layer0)[0]:
    mapped = tuple(index1.get(P0[i].tobytes(), -1) for i in cells0[c])
    match.append(cell_of.get((int(types0[c]), mapped), -1))
match = np.array(match)
check(len(match) == 1054 and (match >= 0).all(),
      "all %d layer cells (640 prisms, 345 hexahedra, 69 pyramids) are in the output with the same "
      "points (bit for bit) in the same order (%d missing)" % (len(match), int((match < 0).sum())))
check(int(np.isin(types1, LAYER_TYPES).sum()) == len(match) and (region[match[match >= 0]] == 0).all(),
      "and no other non-tetrahedral cell; they are all Region 0")
same = all(np.array_equal(np.asarray(src.CellData[a])[layer0][match >= 0], np.asarray(out.CellData[a])[match[match >= 0]])
           for a in src.CellData.keys())
check(same, "their cell data (%s) equal the input's exactly" % ", ".join(src.CellData.keys()))
layer_points = np.unique(np.concatenate([cells0[c] for c in np.nonzero(layer0)[0]]))
out_points = np.array([index1[P0[i].tobytes()] for i in layer_points])
same = all(np.array_equal(np.asarray(src.PointData[a])[layer_points], np.asarray(out.PointData[a])[out_points])
           for a in src.PointData.keys())
check(same, "the point data at their %d points equal the input's exactly" % len(layer_points))

# ---- Validity.
for t, name in ((VTK_TETRA, "tetrahedra"), (VTK_WEDGE, "prisms"), (VTK_HEXAHEDRON, "hexahedra"),
                (VTK_PYRAMID, "pyramids")):
    idx, cells = by_type(types1, cells1, t)
    j = corner_jacobians(P1, cells, t)
    check(len(idx) > 0 and j.min() > 0, "every corner Jacobian of the %d %s is positive (min %.3e)"
          % (len(idx), name, j.min()))
check(artest.field(out, "NonPositiveJacobianCells")[0] == 0, "NonPositiveJacobianCells is 0")
vol0, vol1 = cell_sizes(mesh), cell_sizes(er)
check(vol1.min() > 0 and abs(vol1.sum() / vol0.sum() - 1) < 1e-9,
      "every cell has a positive volume, the total is conserved (%.1e relative)" % (vol1.sum() / vol0.sum() - 1))
count0, _ = faces(P0, types0, cells0)
count1, corners1 = faces(P1, types1, cells1)
check(max(count1.values()) <= 2, "conforming: no triangle or quad face in more than two cells")
b0 = {k for k, c in count0.items() if c == 1}
b1 = {k for k, c in count1.items() if c == 1}
nquads = sum(1 for k in b0 if len(k) == 4)
check(b0 == b1, "the boundary is the input's, face for face (%d faces, %d of them quads)" % (len(b0), nquads))
edges = artest.boundary_edges(corners1, b1)
check(set(edges.values()) == {2}, "watertight: each of the %d boundary edges is in two boundary faces" % len(edges))
S = vtk_to_numpy(emb.VTKObject.GetPolys().GetConnectivityArray()).reshape(-1, 3)
PS = np.asarray(emb.Points, dtype=np.float64)
on = [count1.get(coord_key(PS, tri), 0) for tri in S]
check(len(S) > 100 and all(c == 2 for c in on),
      "all %d triangles of the embedded surface are faces between two cells" % len(S))

# ---- S trimmed at the layer region's edge; the rest of S covered.
used = np.unique(S)
dplane = np.abs((PS[used] - o) @ n)
# (the Plane source's points are single precision: S is the plane to ~1e-8)
check(dplane.max() < 1e-6, "the embedded surface lies on the plane (%.1e)" % dplane.max())
extract = vtkExtractCellsByType()
extract.SetInputData(src.VTKObject)
for t in LAYER_TYPES:
    extract.AddCellType(t)
extract.Update()
layers = locator_of(skin(extract.GetOutput()))
domain = locator_of(skin(src.VTKObject))
longest = np.zeros(len(PS))
for k in range(3):
    a, b = S[:, k], S[:, (k + 1) % 3]
    L = np.linalg.norm(PS[a] - PS[b], axis=1)
    np.maximum.at(longest, a, L)
    np.maximum.at(longest, b, L)
slack = np.array([distance(layers, PS[i]) - MARGIN * longest[i] for i in used])
check(slack.min() >= -1e-12, "no embedded vertex within BoundaryMargin x its longest edge of a layer cell "
      "(closest: %.4f above the margin)" % slack.min())
centroids = PS[S].mean(axis=1)
check(min(distance(layers, x) for x in centroids) > 0 and PS[used, 2].min() > 0.1,
      "no embedded triangle reaches into the layers (lowest vertex z = %.3f, layer top 0.1)" % PS[used, 2].min())
check(artest.field(out, "SurfaceTrianglesAtLockedCells")[0] > 0,
      "S triangles were dropped at the layers (%d)" % artest.field(out, "SurfaceTrianglesAtLockedCells")[0])
# Every point of the plane at least (margin + 1) S edges (CGAL's isotropic
# remeshing keeps edges below 4/3 of the target) from the domain boundary and
# from the layers lies in an S triangle all of whose corners survive the trim.
# From the domain boundary, and from the tetrahedra's faces against the
# layers (V's boundary too: V holds only the tetrahedra), S keeps
# BoundaryMargin x max(its edge, the nearest boundary face's longest edge)
# (room for the refill to grade to the kept faces); from the layers'
# region itself BoundaryMargin x its edge.
outer = skin(src.VTKObject)
from vtkmodules.util.numpy_support import vtk_to_numpy as _v2n
_P = _v2n(outer.GetPoints().GetData()).astype(np.float64)
_off, _con = _v2n(outer.GetPolys().GetOffsetsArray()), _v2n(outer.GetPolys().GetConnectivityArray())
# (a face's diameter: the core fans quads into triangles, whose longest edge is a diagonal)
face_edge = max(np.linalg.norm(_P[_con[_off[f]:_off[f + 1]]][:, None] - _P[_con[_off[f]:_off[f + 1]]][None], axis=2).max()
                for f in range(len(_off) - 1))
band_domain = MARGIN * max(4.0 / 3.0 * EDGE, longest.max(), face_edge) + max(4.0 / 3.0 * EDGE, longest.max())
g = np.linspace(-1.0, 1.0, 81)
samples = [o + a * u + b * v for a in g for b in g]
samples = [x for x in samples if np.all(x > 0) and np.all(x < 1)
           and distance(domain, x) > band_domain and distance(layers, x) > band_domain]
surface = locator_of(emb.VTKObject)
gap = max(distance(surface, x) for x in samples)
check(len(samples) > 100 and gap < 1e-6,
      "the embedded surface covers all %d sample points of the plane farther than %.3f from the boundary and "
      "from the layers (largest gap %.1e)" % (len(samples), band_domain, gap))

# ---- Quality arrays for every cell type; new tetrahedra >= 10 degrees.
mind, maxd = np.asarray(out.CellData["MinDihedralAngle"]), np.asarray(out.CellData["MaxDihedralAngle"])
aspect = np.asarray(out.CellData["AspectRatio"])
check(mind.min() > 0 and (maxd >= mind).all() and aspect.min() >= 1,
      "MinDihedralAngle, MaxDihedralAngle, AspectRatio are set for every cell of every type")
for t, name, poly in ((VTK_WEDGE, "prisms", [0, 1, 2]), (VTK_HEXAHEDRON, "hexahedra", [0, 1, 2, 3])):
    idx, cells = by_type(types1, cells1, t)
    wall = polygon_angles(P1, cells[:, poly])  # the wall polygon: the right prism's angles are these and 90
    want_min, want_max = np.minimum(wall.min(axis=1), 90.0), np.maximum(wall.max(axis=1), 90.0)
    err = max(np.abs(mind[idx] - want_min).max(), np.abs(maxd[idx] - want_max).max())
    check(err < 1e-6, "%d %s: the dihedral angles are the wall polygon's angles and 90 (error %.1e)"
          % (len(idx), name, err))
    check(np.abs(aspect[idx] - edge_ratio(P1, cells, t)).max() < 1e-9,
          "%s: AspectRatio is the longest / shortest edge (max %.1f, MaxAspectRatioLayerCells %.1f)"
          % (name, aspect[idx].max(), artest.field(out, "MaxAspectRatioLayerCells")[0]))
new = np.nonzero(region == 1)[0]
check(len(new) > 0 and (types1[new] == VTK_TETRA).all(), "the %d new cells are tetrahedra" % len(new))
# A new tetrahedron under 10 degrees is allowed only next to a kept cell with a worse angle.
neighbours, _ = face_cells(P1, types1, cells1)
excused = 0
bad = []
for c in new[mind[new] < 10.0]:
    near = [d for f in FACES[VTK_TETRA] for d in neighbours[coord_key(P1, cells1[c][list(f)])] if d != c]
    if any(region[d] == 0 and mind[d] <= mind[c] for d in near):
        excused += 1
    else:
        bad.append(c)
check(not bad, "every new tetrahedron's min dihedral >= 10 deg (min %.2f, mean %.2f; %d excused next to a "
      "worse kept cell)" % (mind[new].min(), mind[new].mean(), excused))
check(abs(artest.field(out, "MinDihedralAngleNew")[0] - mind[new].min()) < 1e-12,
      "MinDihedralAngleNew is the new cells' minimum")

# ---- Kept polyhedra: the same mesh with its hexahedra as polyhedra (their six
# faces) gives the same output, each polyhedron kept with its face stream.
from vtkmodules.vtkCommonCore import vtkIdList
from vtkmodules.vtkCommonDataModel import VTK_POLYHEDRON, vtkUnstructuredGrid

HEX_FACES = ((0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7))
poly_in = vtkUnstructuredGrid()
poly_in.SetPoints(src.VTKObject.GetPoints())
poly_in.Allocate(len(types0))
streams = {}
for c, (t, ids) in enumerate(zip(types0, cells0)):
    if t == VTK_HEXAHEDRON:
        stream = [6] + [x for f in HEX_FACES for x in [4] + [int(ids[k]) for k in f]]
        streams[c] = stream
        faces_list = vtkIdList()
        for x in stream:
            faces_list.InsertNextId(x)
        poly_in.InsertNextCell(VTK_POLYHEDRON, faces_list)
    else:
        poly_in.InsertNextCell(int(t), len(ids), [int(i) for i in ids])
for target, source in ((poly_in.GetPointData(), src.VTKObject.GetPointData()),
                       (poly_in.GetCellData(), src.VTKObject.GetCellData()),
                       (poly_in.GetFieldData(), src.VTKObject.GetFieldData())):
    target.ShallowCopy(source)
producer = TrivialProducer()
producer.GetClientSideObject().SetOutput(poly_in)
er_poly = EmbeddedRemesh(Input=producer, Surfaces=[plane], SurfaceEdgeLength=EDGE, BoundaryMargin=MARGIN)
outp = artest.fetch(er_poly)
types2 = np.array([outp.VTKObject.GetCellType(c) for c in range(outp.GetNumberOfCells())])
expected = np.where(types1 == VTK_HEXAHEDRON, VTK_POLYHEDRON, types1)
P2 = np.asarray(outp.Points, dtype=np.float64)
check(np.array_equal(P2, P1) and np.array_equal(types2, expected),
      "with the %d hexahedra as polyhedra: the same points and cells, each hexahedron a polyhedron (%d)"
      % (len(streams), int((types2 == VTK_POLYHEDRON).sum())))
bad = 0
out_of_input = {i: index1[P0[i].tobytes()] for i in np.unique(np.concatenate([cells0[c] for c in streams]))}
kept = {}
for c in np.nonzero(types2 == VTK_POLYHEDRON)[0]:
    stream = vtkIdList()
    outp.VTKObject.GetFaceStream(int(c), stream)
    kept[tuple(stream.GetId(k) for k in range(stream.GetNumberOfIds()))] = c
for c, stream in streams.items():
    mapped, pos = [stream[0]], 1
    for f in range(stream[0]):
        n = stream[pos]
        mapped += [n] + [out_of_input[i] for i in stream[pos + 1:pos + 1 + n]]
        pos += n + 1
    bad += tuple(mapped) not in kept
check(bad == 0, "every polyhedron is kept with its face stream, in the output's point ids (%d differ)" % bad)
other = np.nonzero(types1 != VTK_HEXAHEDRON)[0]
_, cells2 = cells_of(outp)
check(all(np.array_equal(cells2[c], cells1[c]) for c in other) and
      np.array_equal(np.asarray(outp.CellData["Region"]), region),
      "the other %d cells and Region are the hexahedral run's" % len(other))

artest.finish()
