"""Meshes for the benchmarks (pvpython): the Kuhn-subdivided unit cube and
bulk numpy-to-VTK helpers, shared by bench_embedded_remesh.py and
bench_adapt_to_shocks.py."""
import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkUnstructuredGrid, VTK_TETRA


def points_and_cells(points, cells):
    """vtkPoints and a vtkCellArray from numpy arrays (cells: one row of ids
    per cell), built in bulk: a per-cell loop would dominate at 5e6 cells."""
    vp = vtkPoints()
    vp.SetData(numpy_to_vtk(points, deep=1))
    ca = vtkCellArray()
    k = cells.shape[1]
    ca.SetData(numpy_to_vtkIdTypeArray(np.arange(0, k * len(cells) + 1, k, dtype=np.int64), deep=1),
               numpy_to_vtkIdTypeArray(cells.ravel().astype(np.int64), deep=1))
    return vp, ca


def kuhn_cube(n):
    """The unit cube cut into n^3 cubes of 6 Kuhn tetrahedra each (positive volumes)."""
    g = np.arange(n + 1) / n
    z, y, x = np.meshgrid(g, g, g, indexing="ij")
    points = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    i, j, k = np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij")
    base = (i + (n + 1) * (j + (n + 1) * k)).ravel()
    dx, dy, dz = 1, n + 1, (n + 1) ** 2
    corner = lambda a, b, c: base + a * dx + b * dy + c * dz
    v000, v111 = corner(0, 0, 0), corner(1, 1, 1)
    tets = []
    # The six paths from (0,0,0) to (1,1,1) along the axes.
    for order in ([0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]):
        step = [0, 0, 0]
        path = [v000]
        for axis in order[:2]:
            step[axis] = 1
            path.append(corner(*step))
        path.append(v111)
        tets.append(np.column_stack(path))
    tets = np.vstack(tets)
    P = points[tets]
    vol = np.einsum("ij,ij->i", np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), P[:, 3] - P[:, 0])
    flip = vol < 0
    tets[flip, 1], tets[flip, 2] = tets[flip, 2].copy(), tets[flip, 1].copy()
    grid = vtkUnstructuredGrid()
    vp, cells = points_and_cells(points, tets)
    grid.SetPoints(vp)
    grid.SetCells(VTK_TETRA, cells)
    p = numpy_to_vtk(1.0 + 0.5 * np.tanh(40.0 * (points[:, 2] - 0.5 - 0.2 * (points[:, 0] - 0.5))), deep=1)
    p.SetName("p")
    grid.GetPointData().AddArray(p)
    return grid


def producer(data):
    """A PVTrivialProducer proxy holding `data`."""
    from paraview.simple import PVTrivialProducer
    tp = PVTrivialProducer()
    tp.GetClientSideObject().SetOutput(data)
    return tp
