"""EmbeddedRemesh with LayerType = Prisms through paraview.simple (paper
sections 4.1, 4.2: prism layers on both sides of the shock surface S, closed
at S's open border by pyramids and thin closure tetrahedra, the rest of the
cavity refilled by TetGen). Every geometric check is the test's own (numpy,
Testing/Python/artest.py), independent of the filter's quality arrays.

Every case (validate):
- validity: every corner Jacobian of every cell of every type positive;
  conforming (every face, triangle or quad, keyed by its coordinates, in
  two cells unless it is on the boundary) and the boundary the input's face
  for face, watertight; the Region 0 cells the input's cells bit for bit; the
  total volume (the divergence theorem over every cell's faces, quads split
  at their centroid) conserved to 1e-9; p at the kept points equal to the
  input's;
- the stack: the embedded triangles (output 1) are exactly the faces between
  two layer-0 prisms of opposite sides; 2 x NumberOfLayers prisms on each,
  one per side and layer (each prism's column followed down its lateral
  edges to S); each column (S point, side) at most LayerStackHeight high,
  and the ones lower than that are LimitedColumns;
- the cell arrays and field data: Region, Layer, LayerSide; LayerCells,
  Prisms, Pyramids, LayerClosureTetrahedra, KeptCells, NewCells (Region 1
  and 2) match the cells; MinDihedralAngleNew / MeanDihedralAngleNew (Region
  1 only), MinDihedralAngleLayerCells, MaxAspectRatioLayerCells equal the
  test's own dihedral angles and edge ratios;
- quality: no new (Region 1) tetrahedron under 10 degrees, apart from those
  sharing a face with a kept cell of a worse angle (not required, only
  reported, for two surfaces closer than their stacks).

a. Planar S, the analytic oblique shock with QuadricFit's plane: S on the
   plane; every prism right (its three lateral edges within 5 degrees of the
   plane's normal); LayerSide +1 on the side the embedded triangles' normal
   points to; every column farther than (BoundaryMargin + 2) SurfaceEdgeLength
   + LayerStackHeight / MaxHeightGradient from the domain boundary of full
   height (S's border lies about (BoundaryMargin + 1) edges from the
   boundary, jagged by up to one more; there the columns taper to half a
   border edge, and the grading carries that inward at most that far); in every prism of a full-height
   column, layer k FirstLayerThickness x GrowthRatio^k thick (along the
   normal) within 1% and its bottom at the sum of the layers below.
b. Curved S, the OpenFOAM cone with QuadricFit's cone (FirstLayerThickness
   automatic: each side's stack half a SurfaceEdgeLength high): no folded layer: every lateral edge
   of every prism points to the side of its S triangle that its LayerSide
   says, and every prism's top triangle is within 60 degrees of its S
   triangle's normal (a cheap proxy for caps that do not overlap; that no
   two cells overlap at all follows from the validity checks: positive
   corners, conforming faces, the input's boundary and the conserved
   volume); the stack covers S: every point of the fitted cone farther than
   (BoundaryMargin + 2) longest S edges from the domain boundary is on an
   embedded triangle (within 5% of an edge: the two triangulations of the
   cone differ by their chords). With layers EmbeddedRemesh trims S one edge
   further back than without ((BoundaryMargin + 1) edges), and the border is
   one triangle jagged: hence the + 2.
c. Bad input: NumberOfLayers 0 or negative, a negative FirstLayerThickness
   or TotalThickness, GrowthRatio 0 or negative (set through
   paraview.simple; the XML range domains do not clamp values set from
   Python): an error naming the property, the input passed through
   unchanged. Two parallel copies of the plane 0.15 apart, with stacks of
   0.107 per side: the columns facing the other piece are lowered to
   GapFraction (0.35) of the gap (LimitedColumns > 0), and the mesh is valid.
"""
import numpy as np
from paraview.simple import *
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkFiltersCore import vtkFeatureEdges

import artest
from artest import (FACES, VTK_PYRAMID, VTK_TETRA, VTK_WEDGE, TYPE_NAMES, by_type, cell_volumes, cells_of, check,
                    coord_key, corner_jacobians, dihedral_angles, distance, edge_ratio, face_cells, locator_of, skin)

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)

LAYERS = 4            # NumberOfLayers (per side)
FIRST = 0.01          # FirstLayerThickness
GROWTH = 1.2          # GrowthRatio
MARGIN = 1.0          # EmbeddedRemesh's BoundaryMargin (default)
EDGE = 0.05           # SurfaceEdgeLength on the planes (the mesh's edges are about 0.1)
GAP_FRACTION = 0.35   # ar::PrismLayerOptions defaults (not exposed by the filter)
MAX_HEIGHT_GRADIENT = 0.5


def layer_bounds(first, growth, n):
    """z_0 = 0 .. z_n: the requested distance of each layer boundary from S."""
    return np.concatenate([[0.0], np.cumsum(first * growth ** np.arange(n))])


def point_index(P):
    """Output point id of each coordinate (rounded to 1e-9)."""
    return {tuple(np.round(p * 1e9).astype(np.int64)): i for i, p in enumerate(P)}


def embedded_triangles(emb, index):
    """Port 1's triangles as output point ids, and their (unnormalised) normals."""
    PS = np.asarray(emb.Points, dtype=np.float64)
    S = vtk_to_numpy(emb.VTKObject.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    ids = np.array([[index.get(tuple(np.round(PS[i] * 1e9).astype(np.int64)), -1) for i in t] for t in S])
    normals = np.cross(PS[S[:, 1]] - PS[S[:, 0]], PS[S[:, 2]] - PS[S[:, 0]])
    return ids.reshape(-1, 3), normals


def column_roots(P, W, nlayers):
    """Per output point: the S point at the foot of its column (following the
    prisms' lateral edges p3 -> p0, p4 -> p1, p5 -> p2 down to layer 0);
    points of no column are their own root."""
    below = np.arange(len(P))
    below[W[:, 3:].ravel()] = W[:, :3].ravel()
    root = below.copy()
    for _ in range(nlayers + 1):
        root = below[root]
    return root


def run(mesh, surfaces, **props):
    er = EmbeddedRemesh(Input=mesh, Surfaces=surfaces, LayerType="Prisms", **props)
    return er, artest.fetch(er), artest.fetch(er, 1)


def validate(label, mesh, er, out, emb, nlayers, quality=True):
    """The checks every prism-layer result must pass (with `quality`, also
    the new tetrahedra's 10 degrees); returns what the case-specific checks
    need."""
    f = lambda name: artest.field(out, name)[0]
    src = artest.fetch(mesh)
    P0, P1 = np.asarray(src.Points, dtype=np.float64), np.asarray(out.Points, dtype=np.float64)
    types0, cells0 = cells_of(src)
    types1, cells1 = cells_of(out)
    region = np.asarray(out.CellData["Region"])
    layer = np.asarray(out.CellData["Layer"])
    side = np.asarray(out.CellData["LayerSide"])
    counts = {t: int((types1 == t).sum()) for t in (VTK_TETRA, VTK_PYRAMID, VTK_WEDGE)}
    stack = region == 2
    artest.say("%s: %d cells: %d kept, %d new tetrahedra, %d layer cells (%d prisms, %d pyramids, %d closure "
               "tetrahedra); %d limited columns" % (label, len(types1), int((region == 0).sum()), int((region == 1).sum()),
                                                    int(stack.sum()), counts[VTK_WEDGE], counts[VTK_PYRAMID],
                                                    int((stack & (types1 == VTK_TETRA)).sum()), f("LimitedColumns")))

    # ---- Every corner of every cell positive.
    for t in (VTK_TETRA, VTK_PYRAMID, VTK_WEDGE):
        idx, C = by_type(types1, cells1, t)
        j = corner_jacobians(P1, C, t)
        check(len(idx) > 0 and j.min() > 0, "%s: every corner Jacobian of the %d %s is positive (min %.2e)"
              % (label, len(idx), TYPE_NAMES[t], j.min()))
    check(set(np.unique(types1)) <= {VTK_TETRA, VTK_PYRAMID, VTK_WEDGE},
          "%s: the output has tetrahedra, pyramids and prisms only" % label)

    # ---- Conforming, the input's boundary, watertight.
    owners0, _ = face_cells(P0, types0, cells0)
    owners1, corners1 = face_cells(P1, types1, cells1)
    check(max(len(c) for c in owners1.values()) <= 2,
          "%s: conforming: no face (triangle or quad) in more than two cells" % label)
    b0 = {k for k, c in owners0.items() if len(c) == 1}
    b1 = {k for k, c in owners1.items() if len(c) == 1}
    check(b0 == b1, "%s: every interior face is in two cells, and the boundary is the input's face for face "
          "(%d faces; %d faces in one cell that are not the input's boundary)" % (label, len(b0), len(b1 - b0)))
    edges = artest.boundary_edges(corners1, b1)
    check(set(edges.values()) == {2}, "%s: watertight: each of the %d boundary edges is in two boundary faces"
          % (label, len(edges)))

    # ---- Kept cells: the input's, bit for bit; p at the kept points exact.
    index0 = {P0[i].tobytes(): i for i in range(len(P0))}
    input_cell = {(int(t), tuple(ids)): c for c, (t, ids) in enumerate(zip(types0, cells0))}
    kept = np.nonzero(region == 0)[0]
    match = [input_cell.get((int(types1[c]), tuple(index0.get(P1[i].tobytes(), -1) for i in cells1[c])), -1)
             for c in kept]
    check(len(kept) == f("KeptCells") and min(match) >= 0 and len(set(match)) == len(match),
          "%s: the %d Region 0 cells are distinct input cells, the same corners bit for bit in the same order"
          % (label, len(kept)))
    shared = [i for i in range(len(P1)) if P1[i].tobytes() in index0]
    p0, p1 = np.asarray(src.PointData["p"]), np.asarray(out.PointData["p"])
    diff = np.abs(p1[shared] - p0[[index0[P1[i].tobytes()] for i in shared]]).max()
    check(diff == 0.0, "%s: p at the %d kept points equals the input's exactly" % (label, len(shared)))

    # ---- Volume.
    v0, v1 = cell_volumes(P0, types0, cells0), cell_volumes(P1, types1, cells1)
    rel = v1.sum() / v0.sum() - 1
    check(v1.min() > 0 and abs(rel) < 1e-9, "%s: every cell's volume positive (min %.2e), the total conserved "
          "(%.1e relative)" % (label, v1.min(), rel))

    # ---- The layer cells, their arrays and counts.
    layer_types = types1[stack]
    check(stack.sum() == f("LayerCells") and counts[VTK_WEDGE] == f("Prisms") and counts[VTK_PYRAMID] == f("Pyramids")
          and int((layer_types == VTK_TETRA).sum()) == f("LayerClosureTetrahedra")
          and int((region != 0).sum()) == f("NewCells") and (layer_types != VTK_TETRA).sum() + f("LayerClosureTetrahedra")
          == stack.sum() and (types1[region != 2] == VTK_TETRA).all(),
          "%s: field data LayerCells %d = Prisms %d + Pyramids %d + LayerClosureTetrahedra %d, NewCells %d (Region 1 "
          "and 2), KeptCells %d match the cells; every prism and pyramid is a layer cell"
          % (label, f("LayerCells"), f("Prisms"), f("Pyramids"), f("LayerClosureTetrahedra"), f("NewCells"),
             f("KeptCells")))
    check(((layer[stack] >= 0) & (layer[stack] < nlayers)).all() and np.isin(side[stack], (-1, 1)).all()
          and (layer[~stack] == -1).all() and (side[~stack] == 0).all(),
          "%s: Layer in [0, %d) and LayerSide +-1 on the layer cells, -1 and 0 on the others" % (label, nlayers))

    # ---- Quality: the test's own dihedral angles and aspect ratios.
    mind = np.zeros(len(types1))
    aspect = np.zeros(len(types1))
    for t in (VTK_TETRA, VTK_PYRAMID, VTK_WEDGE):
        idx, C = by_type(types1, cells1, t)
        mind[idx] = dihedral_angles(P1, C, t).min(axis=1)
        aspect[idx] = edge_ratio(P1, C, t)
    new = np.nonzero(region == 1)[0]
    err = max(abs(f("MinDihedralAngleNew") - mind[new].min()), abs(f("MeanDihedralAngleNew") - mind[new].mean()),
              abs(f("MinDihedralAngleLayerCells") - mind[stack].min()),
              abs(f("MaxAspectRatioLayerCells") / aspect[stack].max() - 1))
    check(err < 1e-6, "%s: MinDihedralAngleNew %.2f, MeanDihedralAngleNew %.2f (Region 1 only), "
          "MinDihedralAngleLayerCells %.2f, MaxAspectRatioLayerCells %.1f are the cells' own (error %.1e)"
          % (label, mind[new].min(), mind[new].mean(), mind[stack].min(), aspect[stack].max(), err))
    for t in (VTK_WEDGE, VTK_PYRAMID, VTK_TETRA):
        sel = stack & (types1 == t)
        artest.say("    layer %s: min dihedral %.2f deg, max aspect ratio %.1f"
                   % (TYPE_NAMES[t], mind[sel].min(), aspect[sel].max()))
    # A new tetrahedron under 10 degrees only next to a kept cell with a worse angle.
    excused, bad = 0, []
    for c in new[mind[new] < 10.0]:
        near = [d for fc in FACES[VTK_TETRA] for d in owners1[coord_key(P1, cells1[c][list(fc)])] if d != c]
        if any(region[d] == 0 and mind[d] <= mind[c] for d in near):
            excused += 1
        else:
            bad.append(c)
    check(not bad or not quality, "%s: %severy new tetrahedron's min dihedral >= 10 deg (min %.2f, mean %.2f; %d excused next to a "
          "worse kept cell; %d not: min %.2f, next to %s)"
          % (label, "" if quality else "(not required) ", mind[new].min(), mind[new].mean(), excused, len(bad), mind[bad].min() if bad else 0,
             sorted(set(int(region[d]) for c in bad for fc in FACES[VTK_TETRA]
                        for d in owners1[coord_key(P1, cells1[c][list(fc)])] if d != c))))

    # ---- The prisms stand on the embedded triangles, 2 N per triangle.
    pidx, W = by_type(types1, cells1, VTK_WEDGE)
    S, Snormal = embedded_triangles(emb, point_index(P1))
    check(len(S) > 50 and S.min() >= 0, "%s: the %d embedded triangles' corners are output points" % (label, len(S)))
    between = 0
    for tri in S:
        cs = owners1.get(coord_key(P1, tri), [])
        if (len(cs) == 2 and (types1[cs] == VTK_WEDGE).all() and (layer[cs] == 0).all()
                and sorted(side[cs]) == [-1, 1]):
            between += 1
    layer0 = pidx[layer[pidx] == 0]
    check(between == len(S) and len(layer0) == 2 * len(S),
          "%s: every embedded triangle is a face between two layer-0 prisms of opposite sides (%d of %d), and "
          "there are no other layer-0 prisms" % (label, between, len(S)))
    check(len(pidx) == 2 * nlayers * len(S), "%s: %d prisms = 2 x %d layers x %d embedded triangles"
          % (label, len(pidx), nlayers, len(S)))
    root = column_roots(P1, W, nlayers)
    tri_of = {tuple(sorted(t)): k for k, t in enumerate(S)}
    ptri = np.array([tri_of.get(tuple(sorted(root[w[:3]])), -1) for w in W])
    slots = set(zip(ptri, side[pidx], layer[pidx]))
    check(ptri.min() >= 0 and len(slots) == len(pidx) == 2 * nlayers * len(S),
          "%s: every prism's column stands on an embedded triangle, which carries one prism per side and layer"
          % label)
    # Columns (S point, side): straight (the layer points are foot + z_k x
    # direction), so the height is the distance from the foot to the top.
    top = layer[pidx] == nlayers - 1
    height = {}
    for w, sd in zip(W[top], side[pidx][top]):
        for i in range(3):
            height[(int(root[w[3 + i]]), int(sd))] = np.linalg.norm(P1[w[3 + i]] - P1[root[w[3 + i]]])
    h = np.array(list(height.values()))
    zN = f("LayerStackHeight")
    limited = {c for c, v in height.items() if v < zN * (1 - 1e-9)}
    check(len(height) == 2 * len(np.unique(S)) and h.max() <= zN * (1 + 1e-9) and len(limited) == f("LimitedColumns"),
          "%s: %d columns (2 per S point), none above LayerStackHeight %.4f; %d lower than it (lowest %.4f) = "
          "LimitedColumns %d" % (label, len(height), zN, len(limited), h.min(), f("LimitedColumns")))
    return dict(P=P1, types=types1, cells=cells1, region=region, layer=layer, side=side, pidx=pidx, W=W,
                root=root, S=S, Snormal=Snormal, ptri=ptri, src=src, field=f, limited=limited)


# ================================================ a. planar S, oblique shock
oblique = XMLUnstructuredGridReader(FileName=[artest.data("oblique_shock_unstructured.vtu")])
weight = WeightFunction(Input=oblique, Variables=["p", "rho"], ComputePointWeight=1)
clusters = FeatureCluster(Input=weight, SensorArray=["POINTS", "WeightFunction"], SensorRange=[1.5, 2.0])
plane = QuadricFit(Input=OutputPort(clusters, 1), Domain=oblique, Template="Plane", ClusterId=0)
fit = artest.fetch(plane)
n = artest.field(fit, "Normal")
o = artest.field(fit, "Origin")
er, out, emb = run(oblique, [plane], NumberOfLayers=LAYERS, FirstLayerThickness=FIRST, GrowthRatio=GROWTH,
                   SurfaceEdgeLength=EDGE)
check("Region" in out.CellData.keys() and "Layer" in out.CellData.keys() and not messages.GetOutput().strip(),
      "planar: EmbeddedRemesh (Prisms) ran without an error or warning %r" % messages.GetOutput()[-300:].strip())
r = validate("planar", oblique, er, out, emb, LAYERS)
P, W, pidx, layer, side, root, f = r["P"], r["W"], r["pidx"], r["layer"], r["side"], r["root"], r["field"]
z = layer_bounds(FIRST, GROWTH, LAYERS)
check(abs(f("FirstLayerThicknessUsed") - FIRST) < 1e-15 and abs(f("LayerStackHeight") / z[-1] - 1) < 1e-12,
      "planar: FirstLayerThicknessUsed %.4f, LayerStackHeight %.5f = sum of %.2f x %.1f^k, k < %d"
      % (f("FirstLayerThicknessUsed"), f("LayerStackHeight"), FIRST, GROWTH, LAYERS))

# S on the plane; every prism right.
Sp = np.unique(r["S"])
dplane = np.abs((P[Sp] - o) @ n).max()
check(dplane < 1e-9, "planar: the embedded surface lies on the fitted plane (%.1e)" % dplane)
lateral = np.stack([P[W[:, 3 + i]] - P[W[:, i]] for i in range(3)], axis=1)  # (m, 3 edges, xyz)
tilt = artest.angle_between_planes(lateral, np.broadcast_to(n, lateral.shape)).max()
check(tilt < 5.0, "planar: every prism is right: its lateral edges within 5 deg of the plane's normal (max %.2e deg)"
      % tilt)

# LayerSide +1 is where the embedded triangles' normal points.
plus = np.sign(r["Snormal"] @ n)
centre = (P[W].mean(axis=1) - o) @ n
check(abs(plus.sum()) == len(plus) and (np.sign(centre) == side[pidx] * plus[0]).all(),
      "planar: the embedded triangles all face one way, and every prism lies on the side of the plane its "
      "LayerSide says (+1: where the triangles' normal points)")

# Full-height columns away from the border; thicknesses.
limited = r["limited"]
domain = locator_of(skin(r["src"].VTKObject))
l_s = f("SurfaceEdgeLength")
# (the trim leaves S's border jagged by up to an edge, and from that border
# the columns taper: BorderHeight x the border edge there, then graded inward)
inner = (MARGIN + 2) * l_s + z[-1] / MAX_HEIGHT_GRADIENT
dist = {s: distance(domain, P[s]) for s in Sp}
deep_limited = [c for c in limited if dist[c[0]] > inner]
check(not deep_limited and sum(1 for s in Sp if dist[s] > inner) > 50,
      "planar: every column farther than %.3f from the domain boundary ((BoundaryMargin + 2) x %.4f + "
      "LayerStackHeight / %.1f) has the full height (%d S points that far; the lowered ones are at most %.3f from "
      "the boundary)" % (inner, l_s, MAX_HEIGHT_GRADIENT, sum(1 for s in Sp if dist[s] > inner),
                         max([dist[c[0]] for c in limited], default=0)))
full = np.array([all((int(root[w[i]]), int(s)) not in limited for i in range(3)) for w, s in zip(W, side[pidx])])
thick = np.abs(lateral @ n)                       # (m, 3): each lateral edge along the normal
base = np.abs((P[W[:, :3]] - o) @ n)              # the bottom corners' distance from the plane
want = FIRST * GROWTH ** layer[pidx]
err_t = np.abs(thick[full] / want[full][:, None] - 1).max()
err_b = np.abs(base[full] - z[layer[pidx][full]][:, None]).max() / FIRST
check(full.sum() > 0.5 * len(W) and err_t < 0.01 and err_b < 0.01,
      "planar: in the %d prisms of full-height columns (of %d; the others stand on a lowered column) layer k is "
      "%.2f x %.1f^k thick within 1%% (max error %.1e) and starts at z_k (max error %.1e of the first layer)"
      % (full.sum(), len(W), FIRST, GROWTH, err_t, err_b))
for k in range(LAYERS):
    sel = full & (layer[pidx] == k)
    artest.say("    layer %d: %d prisms, thickness %.5f (requested %.5f)" % (k, sel.sum(), thick[sel].mean(), want[sel][0]))

# ================================================== b. curved S, the cone
cone = XMLUnstructuredGridReader(FileName=[artest.data("cone20Ma2p5.vtu")])
cfit = artest.cone_shock_fit(cone)
before = len(messages.GetOutput())
cer, cout, cemb = run(cone, [cfit], NumberOfLayers=LAYERS)
check("Layer" in cout.CellData.keys(), "cone: EmbeddedRemesh (Prisms) ran %r" % messages.GetOutput()[before:][-300:])
r = validate("cone", cone, cer, cout, cemb, LAYERS)
P, W, pidx, layer, side, ptri, f = r["P"], r["W"], r["pidx"], r["layer"], r["side"], r["ptri"], r["field"]
l_s = f("SurfaceEdgeLength")
artest.say("cone: SurfaceEdgeLength %.4f, FirstLayerThicknessUsed %.5f, LayerStackHeight %.4f"
           % (l_s, f("FirstLayerThicknessUsed"), f("LayerStackHeight")))
check(abs(f("LayerStackHeight") / (0.5 * l_s) - 1) < 1e-12 and
      abs(f("FirstLayerThicknessUsed") * sum(1.2 ** k for k in range(LAYERS)) / f("LayerStackHeight") - 1) < 1e-12,
      "cone: FirstLayerThickness 0 (automatic): each side's stack is half a surface edge high")
# No folded layer: each lateral edge towards its LayerSide of its S triangle.
nS = r["Snormal"][ptri]
nS /= np.linalg.norm(nS, axis=1)[:, None]
lateral = np.stack([P[W[:, 3 + i]] - P[W[:, i]] for i in range(3)], axis=1)
along = np.einsum("mij,mj->mi", lateral, nS) / np.linalg.norm(lateral, axis=2) * side[pidx][:, None]
check(along.min() > 0, "cone: every lateral edge of the %d prisms points to its LayerSide of its S triangle "
      "(smallest cosine with the triangle's normal %.3f)" % (len(W), along.min()))
ntop = np.cross(P[W[:, 4]] - P[W[:, 3]], P[W[:, 5]] - P[W[:, 3]])
nbase = np.cross(P[r["root"][W[:, 1]]] - P[r["root"][W[:, 0]]], P[r["root"][W[:, 2]]] - P[r["root"][W[:, 0]]])
turn = artest.angle_deg(ntop, nbase)
check(turn.max() < 60.0, "cone: every prism's top triangle within 60 deg of its S triangle's normal (max %.1f deg, "
      "layer %d)" % (turn.max(), layer[pidx][np.argmax(turn)]))
# Coverage of the fitted cone away from the domain boundary.
cone_fit = artest.fetch(cfit)
domain = locator_of(skin(r["src"].VTKObject))
surface = locator_of(cemb.VTKObject)
CP = np.asarray(cone_fit.Points, dtype=np.float64)
CT = vtk_to_numpy(cone_fit.VTKObject.GetPolys().GetConnectivityArray()).reshape(-1, 3)
samples = np.concatenate([CP[np.unique(CT)], CP[CT].mean(axis=1)])
# With layers EmbeddedRemesh trims S (BoundaryMargin + 1) x its local longest
# edge from the domain boundary (one edge more than without: room for the
# closure's apices), and drops a triangle when one corner is nearer than
# that: S's border lies at most one triangle inside that line.
ES = r["S"]
longest = max(np.linalg.norm(P[ES[:, k]] - P[ES[:, (k + 1) % 3]], axis=1).max() for k in range(3))
band = (MARGIN + 2) * longest
samples = [x for x in samples if distance(domain, x) > band]
gap = max(distance(surface, x) for x in samples)
check(len(samples) > 100 and gap < 0.05 * l_s,
      "cone: the embedded surface covers all %d sample points of the fitted cone farther than %.3f ((BoundaryMargin "
      "+ 2) x the longest S edge %.4f) from the boundary (largest gap %.1e = %.3f edge lengths)"
      % (len(samples), band, longest, gap, gap / l_s))

# ================================================================ c. bad input
def refused(mesh, surfaces, fragment, label, **props):
    before = len(messages.GetOutput())
    n_in = artest.fetch(mesh).GetNumberOfCells()
    out = artest.fetch(EmbeddedRemesh(Input=mesh, Surfaces=surfaces, LayerType="Prisms", **props))
    text = messages.GetOutput()[before:]
    check(fragment in text, "%s: the error names %s: %r" % (label, fragment, text.strip().split("\n")[-1][-160:]))
    check(out.GetNumberOfCells() == n_in and "Region" not in out.CellData.keys(),
          "%s: the input passes through unchanged (%d cells)" % (label, out.GetNumberOfCells()))


refused(oblique, [plane], "NumberOfLayers", "NumberOfLayers 0", NumberOfLayers=0)
refused(oblique, [plane], "NumberOfLayers", "NumberOfLayers -2", NumberOfLayers=-2)
refused(oblique, [plane], "FirstLayerThickness", "FirstLayerThickness -0.01", FirstLayerThickness=-0.01)
refused(oblique, [plane], "GrowthRatio", "GrowthRatio 0", GrowthRatio=0.0)
refused(oblique, [plane], "GrowthRatio", "GrowthRatio -1.2", GrowthRatio=-1.2)
refused(oblique, [plane], "TotalThickness", "TotalThickness -0.1", TotalThickness=-0.1)

# Two parallel copies of the plane, GAP apart, with stacks of 2 x 0.107.
GAP = 0.15
twin = Transform(Input=plane)
twin.Transform.Translate = list(GAP * n)
before = len(messages.GetOutput())
ter, tout, temb = run(oblique, [plane, twin], NumberOfLayers=LAYERS, FirstLayerThickness=2 * FIRST,
                      GrowthRatio=GROWTH, SurfaceEdgeLength=EDGE)
check("Layer" in tout.CellData.keys(), "two planes %.2f apart: EmbeddedRemesh (Prisms) ran %r"
      % (GAP, messages.GetOutput()[before:][-300:]))
r = validate("two planes", oblique, ter, tout, temb, LAYERS, quality=False)
P, W, pidx, layer, side, root, f = r["P"], r["W"], r["pidx"], r["layer"], r["side"], r["root"], r["field"]
zt = layer_bounds(2 * FIRST, GROWTH, LAYERS)
# The columns of the two pieces that face each other (their foot moved
# across the gap lands on the other piece, not on its border: a ray that
# grazes the border may miss it) take at most GapFraction of it.
ES = r["S"]
lower = np.abs((P[ES].mean(axis=1) - o) @ n) < 0.5 * GAP
pieces, borders = [], []
for sel in (lower, ~lower):
    piece = skin(artest.grid_of(P, [(5, t) for t in ES[sel]]))
    edges = vtkFeatureEdges()
    edges.SetInputData(piece)
    edges.BoundaryEdgesOn()
    edges.FeatureEdgesOff()
    edges.NonManifoldEdgesOff()
    edges.ManifoldEdgesOff()
    edges.Update()
    pieces.append(locator_of(piece))
    borders.append(locator_of(edges.GetOutput()))
top = layer[pidx] == LAYERS - 1
tops = P[W[top][:, 3:]].reshape(-1, 3)
feet = P[root[W[top][:, 3:]]].reshape(-1, 3)
d_top, d_feet = (tops - o) @ n, (feet - o) @ n
towards = np.where(d_feet < 0.5 * GAP, 1.0, -1.0)
facing = np.array([(d_top[i] - d_feet[i]) * towards[i] > 0
                   and distance(pieces[1 if towards[i] > 0 else 0], feet[i] + towards[i] * GAP * n) < 1e-9
                   and distance(borders[1 if towards[i] > 0 else 0], feet[i] + towards[i] * GAP * n) > 1e-6
                   for i in range(len(feet))])
reach = np.abs(d_top - d_feet)[facing]
columns = len(np.unique(W[top][:, 3:].ravel()[facing]))
check(f("LimitedColumns") > 0 and facing.sum() > 0 and reach.max() <= GAP_FRACTION * GAP * (1 + 1e-9) < zt[-1],
      "two planes %.2f apart, stacks of %.3f: LimitedColumns %d; the %d columns facing the other plane reach at "
      "most %.4f (GapFraction x gap = %.4f) from their plane" % (GAP, zt[-1], f("LimitedColumns"), columns,
                                                                 reach.max(), GAP_FRACTION * GAP))

artest.finish()
