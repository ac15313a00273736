"""EmbeddedRemesh (LocalCavity and FullDomain) through paraview.simple on
Gmsh tetrahedra with real feature surfaces:
- the analytic oblique shock with QuadricFit's plane, and the OpenFOAM cone
  with QuadricFit's cone: every cell of positive volume; conforming (no face
  in more than two cells); the boundary equal to the input's face for face;
  volume conserved to 1e-9; every triangle of the embedded surface a face
  between two cells; the kept cells identical to input cells; p at the kept
  points equal to the input's exactly; every new cell's smallest dihedral
  angle at least 10 degrees;
- bad input: no surface connected (one message), an empty surface, a surface outside the domain, two surfaces
  crossing, a TetGen failure, an inverted cell, a mesh without tetrahedra: an
  error naming the problem and the input passed through unchanged.
"""
import os

import numpy as np
from paraview.simple import *
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.util.numpy_support import vtk_to_numpy

import artest
from artest import check

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)

FACES = ((1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1))


def tets(ds):
    conn = vtk_to_numpy(ds.VTKObject.GetCells().GetConnectivityArray())
    types = vtk_to_numpy(ds.VTKObject.GetCellTypesArray())
    assert np.all(types == 10), "tetrahedra only"
    return conn.reshape(-1, 4)


def keys(P, tris):
    """Each triangle as its sorted, rounded corner coordinates (numbering-free)."""
    c = np.round(P[tris] * 1e9).astype(np.int64)
    order = np.lexsort((c[:, :, 2], c[:, :, 1], c[:, :, 0]), axis=1)
    return [tuple(r) for r in np.take_along_axis(c, order[:, :, None], axis=1).reshape(-1, 9)]


def face_counts(P, T):
    faces = np.concatenate([T[:, list(f)] for f in FACES])
    k = keys(P, faces)
    counts = {}
    for key in k:
        counts[key] = counts.get(key, 0) + 1
    return counts


def volumes(P, T):
    a, b, c, d = (P[T[:, i]] for i in range(4))
    return np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a)) / 6.0


def min_dihedral(P, T):
    """Smallest interior dihedral angle of each tetrahedron, degrees."""
    worst = np.full(len(T), 180.0)
    for f, g in ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)):
        # the dihedral angle at the edge opposite to faces f and g
        nf = np.cross(P[T[:, FACES[f][1]]] - P[T[:, FACES[f][0]]], P[T[:, FACES[f][2]]] - P[T[:, FACES[f][0]]])
        ng = np.cross(P[T[:, FACES[g][1]]] - P[T[:, FACES[g][0]]], P[T[:, FACES[g][2]]] - P[T[:, FACES[g][0]]])
        worst = np.minimum(worst, artest.angle_deg(-nf, ng))
    return worst


def validate(label, mesh_proxy, surface_proxy, mode):
    src = artest.fetch(mesh_proxy)
    er = EmbeddedRemesh(Input=mesh_proxy, Surfaces=[surface_proxy], Mode=mode)
    out = artest.fetch(er)
    emb = artest.fetch(er, 1)
    P0, T0 = np.asarray(src.Points, dtype=np.float64), tets(src)  # (the cone's points are float32)
    P1, T1 = np.asarray(out.Points, dtype=np.float64), tets(out)
    region = np.asarray(out.CellData["Region"])
    kept, new = int((region == 0).sum()), int((region == 1).sum())
    check(new > 0 and kept + new == out.GetNumberOfCells() and kept == artest.field(out, "KeptCells")[0],
          "%s: %d kept + %d new cells (input %d)" % (label, kept, new, len(T0)))
    v1 = volumes(P1, T1)
    check(v1.min() > 0, "%s: every cell has a positive volume (min %.3e)" % (label, v1.min()))
    check(abs(v1.sum() / volumes(P0, T0).sum() - 1) < 1e-9, "%s: volume conserved (%.1e relative)" % (label, v1.sum() / volumes(P0, T0).sum() - 1))
    c0, c1 = face_counts(P0, T0), face_counts(P1, T1)
    check(max(c1.values()) <= 2, "%s: conforming, no face in more than two cells" % label)
    check({k for k, n in c1.items() if n == 1} == {k for k, n in c0.items() if n == 1},
          "%s: the boundary is the input's, face for face (%d faces)" % (label, sum(1 for n in c0.values() if n == 1)))
    S = vtk_to_numpy(emb.VTKObject.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    on = [c1.get(k, 0) for k in keys(np.asarray(emb.Points), S)]
    check(len(S) > 50 and all(n == 2 for n in on),
          "%s: all %d triangles of the embedded surface are faces between two cells" % (label, len(S)))
    input_cells = set(tuple(sorted(k)) for k in keys(P0, T0[:, :3]))  # cheap fingerprint: 3 corners
    kept_cells = keys(P1, T1[region == 0][:, :3])
    check(all(tuple(sorted(k)) in input_cells for k in kept_cells), "%s: the kept cells are input cells" % label)
    # p at the kept points equals the input's exactly.
    index0 = {tuple(np.round(p * 1e9).astype(np.int64)): i for i, p in enumerate(P0)}
    p0, p1 = np.asarray(src.PointData["p"]), np.asarray(out.PointData["p"])
    same = [i for i, p in enumerate(P1) if tuple(np.round(p * 1e9).astype(np.int64)) in index0]
    diff = max(abs(p1[i] - p0[index0[tuple(np.round(P1[i] * 1e9).astype(np.int64))]]) for i in same)
    check(len(same) > 0 and diff == 0.0, "%s: p at the %d kept points equals the input's exactly" % (label, len(same)))
    # Quality: every new cell's smallest dihedral angle at least 10 degrees.
    a1 = min_dihedral(P1, T1)
    check(a1[region == 1].min() >= 10.0,
          "%s: every new cell's min dihedral >= 10 deg (min %.2f, mean %.2f; input min %.2f)"
          % (label, a1[region == 1].min(), a1[region == 1].mean(), min_dihedral(P0, T0).min()))
    check(abs(artest.field(out, "RelativeVolumeChange")[0]) < 1e-9, "%s: RelativeVolumeChange field %.1e" % (label, artest.field(out, "RelativeVolumeChange")[0]))
    return er, out


# ---- The analytic oblique shock with QuadricFit's plane.
oblique = XMLUnstructuredGridReader(FileName=[artest.data("oblique_shock_unstructured.vtu")])
weight = WeightFunction(Input=oblique, Variables=["p", "rho"], ComputePointWeight=1)
clusters = FeatureCluster(Input=weight, SensorArray=["POINTS", "WeightFunction"], SensorRange=[1.5, 2.0])
plane = QuadricFit(Input=OutputPort(clusters, 1), Domain=oblique, Template="Plane", ClusterId=0)
validate("oblique shock, LocalCavity", oblique, plane, "LocalCavity")
validate("oblique shock, FullDomain", oblique, plane, "FullDomain")

# ---- The OpenFOAM cone with QuadricFit's cone.
cone = XMLUnstructuredGridReader(FileName=[artest.data("cone20Ma2p5.vtu")])
cfit = artest.cone_shock_fit(cone)
validate("cone, LocalCavity", cone, cfit, "LocalCavity")


# ---- Bad input: an error naming the problem, the input unchanged.
def refused(mesh, surfaces, fragment, label, **props):
    before = len(messages.GetOutput())
    n_in = artest.fetch(mesh).GetNumberOfCells()
    out = artest.fetch(EmbeddedRemesh(Input=mesh, Surfaces=surfaces, **props))
    text = messages.GetOutput()[before:]
    check(fragment in text, "%s: error says '%s'" % (label, fragment))
    check(out.GetNumberOfCells() == n_in and "Region" not in out.CellData.keys(),
          "%s: the input passes through unchanged (%d cells)" % (label, out.GetNumberOfCells()))


# No surface connected at all: one clear message, not the pipeline's
# generic errors about a missing input connection.
before = len(messages.GetOutput())
bare = artest.fetch(EmbeddedRemesh(Input=oblique))
text = messages.GetOutput()[before:]
check(text.count("ERROR") == 1 and "no feature surface: connect one or more to Surfaces" in text
      and bare.GetNumberOfCells() == artest.fetch(oblique).GetNumberOfCells(),
      "no Surfaces connected: one error (%d) that says to connect one, the input passes through" % text.count("ERROR"))
empty = Contour(Input=weight, ContourBy=["POINTS", "WeightFunction"], Isosurfaces=[5.0])
refused(oblique, [empty], "feature surface is empty", "empty surface")
far = Transform(Input=plane)
far.Transform.Translate = [5.0, 0.0, 0.0]
refused(oblique, [far], "outside the volume mesh", "surface outside the domain")
crossing = Transform(Input=plane)
crossing.Transform.Rotate = [0.0, 0.0, 90.0]
crossing.Transform.Translate = [1.0, 0.0, 0.0]
refused(oblique, [plane, crossing], "intersects itself", "two surfaces crossing")
folded = AppendGeometry(Input=[plane, crossing])  # one surface that crosses itself
refused(oblique, [folded], "intersects itself", "a self-intersecting surface")
# Two copies of the plane 1e-11 apart: nothing crosses, but TetGen fails on
# them (it crashes while cleaning up; it runs in a child process, so the
# error is reported and ParaView lives on).
twin = Transform(Input=plane)
twin.Transform.Translate = [0.0, 0.0, 1e-11]
# (At the surfaces' default size, 0.2 h_S, the two remeshed sheets are
# already found to touch; at 0.25 h_S they are not, and TetGen is reached.)
refused(oblique, [plane, twin], "TetGen", "a TetGen failure (two sheets 1e-11 apart)", SurfaceSizeFactor=0.25)
# An inverted cell: the first tetrahedron's corners swapped, in a file.
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter
bad = artest.fetch(oblique).VTKObject.NewInstance()
bad.DeepCopy(artest.fetch(oblique).VTKObject)
conn = vtk_to_numpy(bad.GetCells().GetConnectivityArray())
conn[1], conn[2] = conn[2], conn[1]
bad.GetCells().GetConnectivityArray().Modified()
path = os.path.join(artest.OUTPUT_DIR, "inverted_cell.vtu")
w = vtkXMLUnstructuredGridWriter()
w.SetFileName(path)
w.SetInputData(bad)
w.SetDataModeToBinary()
w.Write()
refused(XMLUnstructuredGridReader(FileName=[path]), [plane], "is inverted or flat", "inverted cell")
wedge = XMLUnstructuredGridReader(FileName=[artest.data("wedge15Ma5.vtu")])
# (one cell deep: with TwoDimensional Off, as TestEmbeddedRemesh2D.py covers Auto)
refused(wedge, [plane], "no tetrahedra", "a mesh without tetrahedra", TwoDimensional="Off")

artest.finish()
