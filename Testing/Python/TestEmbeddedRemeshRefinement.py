"""EmbeddedRemesh refines at the feature surface with its defaults (the
paper's clustering: "elements around the shock are replaced with finer
elements"), checked against sizes computed here, independently of the
filter:
- the OpenFOAM cone (Gmsh tetrahedra) with QuadricFit's cone, and the
  OpenFOAM wedge (one cell deep, 2-D mode) with QuadricFit's plane, every
  property at its default:
  - the input's size at S, h_S (the median over the fitted surface's points
    of the longest edge at the nearest input node), equals the field data's
    InputSizeAtSurface; S's edge length is 0.21 h_S in 3-D, 0.2 h_S in 2-D
    (the automatic SurfaceSizeFactor);
  - the output's size at the embedded surface (the median longest edge at
    its nodes, the same measure) equals OutputSizeAtSurface, and is at most
    a third of the input's (SurfaceSizeRatio their ratio: the issue's
    "at least 3x smaller across the shock");
  - across the shock (cells whose centroid lies within h_S / 2 of the fitted
    surface, measured analytically from its Apex/HalfAngle or Normal/Origin)
    the mean edge of the output's cells is below 0.55 of the input's, and
    there are at least 3 times as many cells (2-D: 2.5 times as many);
  - InputNodes, OutputNodes, NewNodes are the grids' node counts, and the
    output has more nodes than the input;
- an absolute SurfaceEdgeLength overrides the factor (SurfaceSizeFactor in
  the field data is then edge / h_S); an explicit SurfaceSizeFactor is used
  as given; with prism layers the automatic factor is 1 (the layers refine
  across S);
- the new cells allow an explicit solver the time step of the requested
  size: the smallest step length 2V / (sum of face areas) of the new cells
  (computed here from the corners, the front and back faces left out in
  2-D) equals StepLengthNew, StepLengthRatioNew is it over the regular
  tetrahedron's (2-D: the equilateral triangle's) at S's edge, and that
  ratio is at least 0.45 ("no smaller than about half the requested size");
  with prism layers StepLengthLayerCells and StepLengthRatioLayerCells
  likewise for the layer cells, against the right prism one layer high;
- SurfaceSizeFactor -1, 11 or NaN is refused with an error naming it, and
  the input passes through unchanged.
"""
import numpy as np
from paraview.simple import *
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow

import artest
from artest import VTK_HEXAHEDRON, VTK_PYRAMID, VTK_TETRA, VTK_WEDGE, check

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)

# The documented automatic SurfaceSizeFactor with tetrahedra, by dimension.
FACTOR = {3: 0.21, 2: 0.2}


def edges_of(t):
    """The edges of a cell type as pairs of local node ids."""
    return {VTK_TETRA: [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)],
            VTK_WEDGE: [(0, 1), (1, 2), (2, 0), (3, 4), (4, 5), (5, 3), (0, 3), (1, 4), (2, 5)],
            VTK_HEXAHEDRON: [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)]}[t]


def cell_edges(ds, in_plane_axis=None):
    """Per cell: its centroid and mean edge length, and per node the longest
    edge at it. With in_plane_axis (the 2-D mode's depth axis) only the
    edges normal to that axis count (the cross-section's edges)."""
    P = np.asarray(ds.Points, dtype=np.float64)
    types, cells = artest.cells_of(ds)
    centroid = np.zeros((len(types), 3))
    mean = np.zeros(len(types))
    longest = np.zeros(len(P))
    for t in (VTK_TETRA, VTK_WEDGE, VTK_HEXAHEDRON):
        idx, C = artest.by_type(types, cells, t)
        if len(idx) == 0:
            continue
        centroid[idx] = P[C].mean(axis=1)
        total, count = np.zeros(len(idx)), np.zeros(len(idx))
        for a, b in edges_of(t):
            d = P[C[:, a]] - P[C[:, b]]
            use = np.ones(len(idx), dtype=bool)
            if in_plane_axis is not None:  # a depth edge spans the planes: left out
                depth = np.abs(d[:, in_plane_axis])
                d = d.copy()
                d[:, in_plane_axis] = 0.0
                use = depth < 0.5 * np.linalg.norm(d, axis=1)
            length = np.where(use, np.linalg.norm(d, axis=1), 0.0)
            total += length
            count += use
            np.maximum.at(longest, C[:, a], length)
            np.maximum.at(longest, C[:, b], length)
        mean[idx] = total / np.maximum(count, 1)
    return P, centroid, mean, longest


FACES = {VTK_TETRA: [(0, 1, 2), (0, 1, 3), (1, 2, 3), (0, 2, 3)],
         VTK_WEDGE: [(0, 1, 2), (3, 4, 5), (0, 1, 4, 3), (1, 2, 5, 4), (2, 0, 3, 5)],
         VTK_PYRAMID: [(0, 1, 2, 3), (0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)],
         VTK_HEXAHEDRON: [(0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]}


def step_lengths(ds, region, depth_axis=None):
    """The smallest 2V / (sum of face areas) over the 3-D cells of a Region:
    V summed over pyramids from the cell's centroid to its faces (a face's
    area vector: half the sum of its corners' cross products), faces normal
    to depth_axis left out of the areas."""
    P = np.asarray(ds.Points, dtype=np.float64)
    types, cells = artest.cells_of(ds)
    reg = np.asarray(ds.CellData["Region"])
    best = np.inf
    for t, faces in FACES.items():
        idx, C = artest.by_type(types, cells, t)
        keep = reg[idx] == region if len(idx) else []
        if not np.any(keep):
            continue
        X = P[C[keep]]
        centre = X.mean(axis=1)
        V, A = np.zeros(len(X)), np.zeros(len(X))
        for f in faces:
            Y = X[:, list(f)]
            a = 0.5 * sum(np.cross(Y[:, i], Y[:, (i + 1) % len(f)]) for i in range(len(f)))
            V += np.abs(np.einsum("ij,ij->i", a, Y.mean(axis=1) - centre)) / 3.0
            area = np.linalg.norm(a, axis=1)
            if depth_axis is not None:
                area = np.where(np.abs(a[:, depth_axis]) > (1 - 1e-9) * area, 0.0, area)
            A += area
        best = min(best, (2.0 * V / A).min())
    return best


def check_steps(label, out, depth_axis=None):
    """StepLengthNew and its ratio against the corners, and the ratio at least 0.45."""
    f = lambda name: artest.field(out, name)[0]
    mine = step_lengths(out, 1, depth_axis)
    edge = f("SurfaceEdgeLength")
    ideal = edge / (2 * np.sqrt(3)) if depth_axis is not None else edge / (3 * np.sqrt(6))
    check(abs(f("StepLengthNew") - mine) <= 1e-9 * mine and abs(f("StepLengthRatioNew") - mine / ideal) < 1e-9
          and f("StepLengthRatioNew") >= 0.45,
          "%s: the smallest new cell's step length 2V/sum(A) %.3g (here %.3g) is %.2f of the %s at S's edge "
          "(StepLengthRatioNew; at least 0.45)" % (label, f("StepLengthNew"), mine, f("StepLengthRatioNew"),
                                                   "equilateral triangle's" if depth_axis is not None
                                                   else "regular tetrahedron's"))
    check(f("StepLengthLayerCells") == 0 and f("StepLengthRatioLayerCells") == 0,
          "%s: no layer cells, no layer step length" % label)


def upper_median(values):
    """The median as the filter takes it: the element at n / 2 in sorted order."""
    v = np.sort(np.asarray(values))
    return v[len(v) // 2]


def nearest_nodes(P, X):
    """For each row of X, the index of the nearest row of P (brute force in chunks)."""
    out = np.empty(len(X), dtype=np.int64)
    for s in range(0, len(X), 256):
        d = ((X[s:s + 256, None, :] - P[None, :, :]) ** 2).sum(axis=2)
        out[s:s + 256] = d.argmin(axis=1)
    return out


def check_refinement(label, source, fit, distance, cells_factor, depth_axis=None):
    """The defaults' refinement at S, against sizes computed here."""
    src = artest.fetch(source)
    er = EmbeddedRemesh(Input=source, Surfaces=[fit])
    out = artest.fetch(er)
    emb = artest.fetch(er, 1)
    f = lambda name: artest.field(out, name)[0]
    P0, c0, m0, l0 = cell_edges(src, depth_axis)
    P1, c1, m1, l1 = cell_edges(out, depth_axis)
    # h_S from the fitted surface's points (in 2-D: its cut at mid-depth,
    # taken here as the surface points nearest the mid-depth plane's nodes).
    S = np.asarray(artest.fetch(fit).Points, dtype=np.float64)
    if depth_axis is not None:
        S = S.copy()
        S[:, depth_axis] = P0[:, depth_axis].min()  # the cross-section's nodes: those on the front plane
    near = nearest_nodes(P0, S)
    hS = f("InputSizeAtSurface")
    mine = upper_median(l0[near])
    check(abs(mine - hS) <= 0.05 * hS,
          "%s: the input's size at S h_S = %.5f (here: median longest edge at the nodes nearest the fitted "
          "surface, %.5f)" % (label, hS, mine))
    factor = FACTOR[2 if depth_axis is not None else 3]  # one cell deep: the 2-D mode
    check(abs(f("SurfaceEdgeLength") - factor * hS) <= 1e-12 * hS and abs(f("SurfaceSizeFactor") - factor) < 1e-12,
          "%s: S's edge %.5f = %.2f h_S (SurfaceSizeFactor %.3f)" % (label, f("SurfaceEdgeLength"), factor,
                                                                   f("SurfaceSizeFactor")))
    # The output's size at the embedded surface, the same measure.
    from vtkmodules.util.numpy_support import vtk_to_numpy
    on_s = np.unique(vtk_to_numpy(emb.VTKObject.GetPolys().GetConnectivityArray()))
    out_size = upper_median(l1[on_s])
    check(abs(out_size - f("OutputSizeAtSurface")) <= 1e-9 * out_size,
          "%s: the output's size at S %.5f = OutputSizeAtSurface %.5f (the median longest edge at its %d nodes)"
          % (label, out_size, f("OutputSizeAtSurface"), len(on_s)))
    check(f("SurfaceSizeRatio") <= 1.0 / 3.0 and abs(f("SurfaceSizeRatio") - out_size / hS) < 1e-9,
          "%s: the new cells at S are %.2f of the input's size there (SurfaceSizeRatio <= 1/3)"
          % (label, f("SurfaceSizeRatio")))
    # Across the shock: within h_S / 2 of the fitted surface.
    band0 = np.abs(distance(c0)) < 0.5 * hS
    band1 = np.abs(distance(c1)) < 0.5 * hS
    e0, e1 = m0[band0].mean(), m1[band1].mean()
    check(e1 < 0.55 * e0 and band1.sum() >= cells_factor * band0.sum(),
          "%s: across the shock (within h_S / 2 of the surface) %d -> %d cells, mean edge %.4f -> %.4f (%.2f)"
          % (label, band0.sum(), band1.sum(), e0, e1, e1 / e0))
    check(f("InputNodes") == src.GetNumberOfPoints() and f("OutputNodes") == out.GetNumberOfPoints()
          and f("OutputNodes") > f("InputNodes") and f("NewNodes") > 0,
          "%s: nodes %d -> %d (%d new)" % (label, f("InputNodes"), f("OutputNodes"), f("NewNodes")))
    return out, hS


def props_run(source, fit, **props):
    out = artest.fetch(EmbeddedRemesh(Input=source, Surfaces=[fit], **props))
    return out, (lambda name: artest.field(out, name)[0])


# ---- The OpenFOAM cone, Gmsh tetrahedra, QuadricFit's cone.
cone = XMLUnstructuredGridReader(FileName=[artest.data("cone20Ma2p5.vtu")])
cfit = artest.cone_shock_fit(cone)
C = artest.fetch(cfit)
apex, axis = artest.field(C, "Apex"), artest.field(C, "AxisDirection")
theta = np.radians(artest.field(C, "HalfAngle")[0])


def to_cone(x):
    v = x - apex
    along = v @ axis
    radius = np.linalg.norm(v - np.outer(along, axis), axis=1)
    return radius * np.cos(theta) - along * np.sin(theta)


out, hS = check_refinement("cone", cone, cfit, to_cone, 3.0)
check_steps("cone", out)
check(artest.field(out, "MinDihedralAngleNew")[0] >= 10.0,
      "cone: the new tetrahedra stay above 10 deg (min %.2f)" % artest.field(out, "MinDihedralAngleNew")[0])

# An absolute edge overrides the factor; an explicit factor is used as given;
# prism layers refine across S, so their automatic factor is 1.
_, f = props_run(cone, cfit, SurfaceEdgeLength=0.8 * hS)
check(abs(f("SurfaceEdgeLength") - 0.8 * hS) < 1e-12 * hS and abs(f("SurfaceSizeFactor") - 0.8) < 1e-9,
      "cone: SurfaceEdgeLength %.5f overrides the factor (SurfaceSizeFactor %.3f)" % (0.8 * hS, f("SurfaceSizeFactor")))
_, f = props_run(cone, cfit, SurfaceSizeFactor=0.5)
check(abs(f("SurfaceEdgeLength") - 0.5 * hS) < 1e-12 * hS and f("SurfaceSizeRatio") < 1.0,
      "cone: SurfaceSizeFactor 0.5 gives S's edge 0.5 h_S (%.5f), SurfaceSizeRatio %.2f"
      % (f("SurfaceEdgeLength"), f("SurfaceSizeRatio")))
layered, f = props_run(cone, cfit, LayerType="Prisms", NumberOfLayers=3)
check(abs(f("SurfaceSizeFactor") - 1.0) < 1e-12 and f("FirstLayerThicknessUsed") < 0.25 * hS,
      "cone, prism layers: automatic factor 1 along S, first layer %.5f = %.3f h_S across it"
      % (f("FirstLayerThicknessUsed"), f("FirstLayerThicknessUsed") / hS))
# The layer cells' step against the corners, and against the right prism
# over the equilateral triangle of S's edge e, one layer t high:
# 2V / sum(A) = t / (1 + 2 sqrt(3) t / e).
mine = step_lengths(layered, 2)
e, t = f("SurfaceEdgeLength"), f("FirstLayerThicknessUsed")
check(abs(f("StepLengthLayerCells") - mine) <= 1e-6 * mine
      and abs(f("StepLengthRatioLayerCells") - mine / (t / (1 + 2 * np.sqrt(3) * t / e))) < 1e-6
      and 0 < f("StepLengthRatioLayerCells") < 1,
      "cone, prism layers: the smallest layer cell's step length %.3g (here %.3g) is %.2f of a layer's prism "
      "(StepLengthRatioLayerCells; the stack's closure cells are thinner by design)"
      % (f("StepLengthLayerCells"), mine, f("StepLengthRatioLayerCells")))

# ---- The OpenFOAM wedge, one cell deep (2-D mode), QuadricFit's plane.
wedge = XMLUnstructuredGridReader(FileName=[artest.data("wedge15Ma5.vtu")])
weight = WeightFunction(Input=wedge, Variables=["rho", "rhoU", "rhoE"], ComputePointWeight=1)
clusters = FeatureCluster(Input=weight, SensorArray=["POINTS", "WeightFunction"], SensorRange=[1.5, 2.0])
pfit = QuadricFit(Input=OutputPort(clusters, 1), Domain=wedge, Template="Plane", ClusterId=0)
Q = artest.fetch(pfit)
normal, origin = artest.field(Q, "Normal"), artest.field(Q, "Origin")
out2, _ = check_refinement("wedge (2-D)", wedge, pfit, lambda x: (x - origin) @ normal, 2.5, depth_axis=2)
check(artest.field(out2, "TwoDimensional")[0] == 1, "wedge: the 2-D mode ran")
check_steps("wedge (2-D)", out2, depth_axis=2)


# ---- Bad factors: refused by name, the input unchanged.
def refused(value):
    before = len(messages.GetOutput())
    out = artest.fetch(EmbeddedRemesh(Input=cone, Surfaces=[cfit], SurfaceSizeFactor=value))
    text = messages.GetOutput()[before:]
    check("SurfaceSizeFactor is" in text and "[0, 10]" in text and "passes through unchanged" in text,
          "SurfaceSizeFactor %s: refused by name" % value)
    check(out.GetNumberOfCells() == artest.fetch(cone).GetNumberOfCells() and "Region" not in out.CellData.keys(),
          "SurfaceSizeFactor %s: the input passes through unchanged" % value)


for value in (-1.0, 11.0, float("nan")):
    refused(value)

artest.finish()
