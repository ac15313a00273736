"""EmbeddedRemesh's field transfer (LocalCavity and FullDomain) on a
Kuhn-subdivided cube (every new point that falls on a face or an edge of
the input's tetrahedra is a tie between cells) with a planar feature
surface, and fields whose right values are known:
- reproducible: the run on 1 thread and the run on 5 threads (separate
  pvpython processes, VTK_SMP_MAX_THREADS) give bit-identical points, cells
  and point and cell arrays;
- the output has the input's point and cell arrays, same names, types and
  components (plus the filter's own);
- a linear point field p = 2x - 3y + 0.5z + 1 is the input's exactly at the
  kept points and within 1e-12 at the new points (linear interpolation in
  the containing tetrahedron); a float32 vector field within 1e-6; an
  integer point field stays integer;
- the kept cells' arrays are their input cell's exactly (cell found by its
  copied id), every new cell's are those of an input cell that contains the
  new cell's centre (barycentric coordinates >= -1e-9).

    pvpython TestEmbeddedRemeshFields.py <pvpython>
"""
import os
import subprocess
import sys

import numpy as np


def cube(n):
    """The unit cube in n^3 cubes of 6 Kuhn tetrahedra, with its fields."""
    from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkUnstructuredGrid, VTK_TETRA
    g = np.arange(n + 1) / n
    z, y, x = np.meshgrid(g, g, g, indexing="ij")
    P = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    i, j, k = np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij")
    base = (i + (n + 1) * (j + (n + 1) * k)).ravel()
    step = (1, n + 1, (n + 1) ** 2)
    T = []
    for order in ([0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]):
        path, at = [base], base.copy()
        for axis in order:
            at = at + step[axis]
            path.append(at)
        T.append(np.column_stack(path))
    T = np.vstack(T)
    vol = np.einsum("ij,ij->i", np.cross(P[T[:, 1]] - P[T[:, 0]], P[T[:, 2]] - P[T[:, 0]]), P[T[:, 3]] - P[T[:, 0]])
    T[vol < 0, 1], T[vol < 0, 2] = T[vol < 0, 2].copy(), T[vol < 0, 1].copy()
    grid = vtkUnstructuredGrid()
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(P, deep=1))
    grid.SetPoints(pts)
    cells = vtkCellArray()
    cells.SetData(numpy_to_vtkIdTypeArray(np.arange(0, 4 * len(T) + 1, 4, dtype=np.int64), deep=1),
                  numpy_to_vtkIdTypeArray(T.ravel().astype(np.int64), deep=1))
    grid.SetCells(VTK_TETRA, cells)
    arrays = [(grid.GetPointData(), "p", linear(P)),
              (grid.GetPointData(), "velocity", P.astype(np.float32) * np.float32(3.0) + np.float32(1.0)),
              (grid.GetPointData(), "tag", np.arange(len(P), dtype=np.int32)),
              (grid.GetCellData(), "cellId", np.arange(len(T), dtype=np.int64)),
              (grid.GetCellData(), "centreX", P[T].mean(axis=1)[:, 0])]
    for data, name, values in arrays:
        a = numpy_to_vtk(values, deep=1)
        a.SetName(name)
        data.AddArray(a)
    return grid


def linear(P):
    return 2.0 * P[:, 0] - 3.0 * P[:, 1] + 0.5 * P[:, 2] + 1.0


def plane_surface(n):
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
    m = n
    g = 0.1 + 0.8 * np.arange(m + 1) / m
    y, x = np.meshgrid(g, g, indexing="ij")
    pts = vtkPoints()
    for px, py in zip(x.ravel(), y.ravel()):
        pts.InsertNextPoint(px, py, 0.5 + 0.2 * (px - 0.5))
    polys = vtkCellArray()
    for r in range(m):
        for c in range(m):
            a = c + (m + 1) * r
            polys.InsertNextCell(3, (a, a + 1, a + m + 2))
            polys.InsertNextCell(3, (a, a + m + 2, a + m + 1))
    poly = vtkPolyData()
    poly.SetPoints(pts)
    poly.SetPolys(polys)
    return poly


N = 12

if len(sys.argv) > 2 and sys.argv[1] == "--worker":
    # A worker: one run, its output written to a file.
    mode, path = sys.argv[2], sys.argv[3]
    import artest
    from paraview.simple import *
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter
    artest.load_plugin(globals())
    mesh, surface = PVTrivialProducer(), PVTrivialProducer()
    mesh.GetClientSideObject().SetOutput(cube(N))
    surface.GetClientSideObject().SetOutput(plane_surface(N))
    er = EmbeddedRemesh(Input=mesh, Surfaces=[surface], Mode=mode)
    er.UpdatePipeline()
    w = vtkXMLUnstructuredGridWriter()
    w.SetInputData(er.GetClientSideObject().GetOutputDataObject(0))
    w.SetFileName(path)
    # Inline binary (base64, as exact), not appended: with Debian's current
    # libexpat (2.5.0-1+deb12u5) VTK 9.1's XML reader reads no cells from
    # appended data beyond a few kilobytes, raw or compressed (a 3^3 cell
    # block already fails raw, 10^3 zlib). This file's appended raw data had
    # passed until the StepLength* field arrays lengthened its header.
    w.SetDataModeToBinary()
    w.SetCompressorTypeToNone()
    w.Write()
    sys.exit(0)

import artest
from artest import check
from vtkmodules.numpy_interface import dataset_adapter as dsa
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

pvpython = sys.argv[1]
source = dsa.WrapDataObject(cube(N))
P0 = np.asarray(source.Points)
T0 = vtk_to_numpy(source.VTKObject.GetCells().GetConnectivityArray()).reshape(-1, 4)


def run(mode, threads):
    path = os.path.join(artest.OUTPUT_DIR, "erfields_%s_%d.vtu" % (mode, threads))
    if os.path.exists(path):
        os.remove(path)
    env = dict(os.environ, VTK_SMP_BACKEND_IN_USE="STDThread", VTK_SMP_MAX_THREADS=str(threads))
    subprocess.run([pvpython, os.path.abspath(__file__), "--worker", mode, path], env=env, check=True)
    r = vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    return dsa.WrapDataObject(r.GetOutput())


def arrays(data):
    return {data.GetArrayName(k): data.GetAbstractArray(k) for k in range(data.GetNumberOfArrays())}


def barycentric(x, cell):
    """x's barycentric coordinates in each input tetrahedron `cell`."""
    p = P0[T0[cell]]
    A = np.transpose(p[:, 1:] - p[:, :1], (0, 2, 1))
    lam = np.linalg.solve(A, (x - p[:, 0])[:, :, None])[:, :, 0]
    return np.column_stack([1.0 - lam.sum(axis=1), lam])


for mode in ("LocalCavity", "FullDomain"):
    one, five = run(mode, 1), run(mode, 5)
    # ---- Reproducible whatever the threads.
    same = np.array_equal(np.asarray(one.Points), np.asarray(five.Points)) and np.array_equal(
        vtk_to_numpy(one.VTKObject.GetCells().GetConnectivityArray()),
        vtk_to_numpy(five.VTKObject.GetCells().GetConnectivityArray()))
    check(same, "%s: 1 and 5 threads give the same points and cells (%d cells)" % (mode, one.GetNumberOfCells()))
    for kind in ("PointData", "CellData"):
        a1, a5 = arrays(getattr(one.VTKObject, "Get" + kind)()), arrays(getattr(five.VTKObject, "Get" + kind)())
        differ = [n for n in a1 if n not in a5 or not np.array_equal(vtk_to_numpy(a1[n]), vtk_to_numpy(a5[n]))]
        check(same and set(a1) == set(a5) and not differ,
              "%s: 1 and 5 threads give bit-identical %s arrays %s (differ: %s)" % (mode, kind, sorted(a1), differ))
    out = one
    P1 = np.asarray(out.Points)
    region = np.asarray(out.CellData["Region"])
    # ---- The input's arrays, same names, types and components.
    for kind in ("PointData", "CellData"):
        ain, aout = arrays(getattr(source.VTKObject, "Get" + kind)()), arrays(getattr(out.VTKObject, "Get" + kind)())
        kept = all(n in aout and aout[n].GetDataType() == a.GetDataType()
                   and aout[n].GetNumberOfComponents() == a.GetNumberOfComponents() for n, a in ain.items())
        check(kept, "%s: the output has the input's %s arrays %s with their types" % (mode, kind, sorted(ain)))
    # ---- Point data: kept points exact, new points the linear field to 1e-12.
    index0 = {tuple(p): i for i, p in enumerate(P0)}
    src = np.array([index0.get(tuple(p), -1) for p in P1])
    keptp, newp = src >= 0, src < 0
    p1 = np.asarray(out.PointData["p"])
    check(keptp.sum() > 0 and np.array_equal(p1[keptp], np.asarray(source.PointData["p"])[src[keptp]])
          and np.array_equal(np.asarray(out.PointData["tag"])[keptp], src[keptp]),
          "%s: p and tag at the %d kept points are the input's exactly" % (mode, keptp.sum()))
    err = np.abs(p1[newp] - linear(P1[newp])).max()
    check(newp.sum() > 100 and err < 1e-12, "%s: linear p at the %d new points exact to %.1e" % (mode, newp.sum(), err))
    v1 = np.asarray(out.PointData["velocity"])
    verr = np.abs(v1[newp] - (3.0 * P1[newp] + 1.0)).max()
    check(v1.dtype == np.float32 and verr < 1e-6, "%s: the float32 vector at the new points to %.1e" % (mode, verr))
    tag = np.asarray(out.PointData["tag"])
    check(tag.dtype == np.int32 and tag[newp].min() >= 0 and tag[newp].max() < len(P0),
          "%s: the integer point array stays int32 and in range at the new points" % mode)
    # ---- Cell data: kept cells their own, new cells the containing input cell's.
    cid = np.asarray(out.CellData["cellId"])
    cx = np.asarray(out.CellData["centreX"])
    cx0 = np.asarray(source.CellData["centreX"])
    keptc = region == 0
    check((keptc.sum() > 0 or mode == "FullDomain") and np.array_equal(cx[keptc], cx0[cid[keptc]]),
          "%s: the %d kept cells' arrays are their input cell's" % (mode, keptc.sum()))
    conn = vtk_to_numpy(out.VTKObject.GetCells().GetConnectivityArray())
    offsets = vtk_to_numpy(out.VTKObject.GetCells().GetOffsetsArray())
    newc = np.nonzero(~keptc)[0]
    centres = np.array([P1[conn[offsets[k]:offsets[k + 1]]].mean(axis=0) for k in newc])
    b = barycentric(centres, cid[newc])
    check(len(newc) > 100 and b.min() >= -1e-9 and np.array_equal(cx[newc], cx0[cid[newc]]),
          "%s: each of the %d new cells has the arrays of an input cell containing its centre (min coordinate %.1e)"
          % (mode, len(newc), b.min()))

artest.finish()
