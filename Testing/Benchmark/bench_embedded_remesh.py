"""Benchmark of EmbeddedRemesh (a benchmark, not a test): the stages of the
filter on Kuhn-subdivided unit cubes (6 n^3 tetrahedra) with a planar
feature surface, LocalCavity beside FullDomain. Prints a Markdown table.

    pvpython Testing/Benchmark/bench_embedded_remesh.py [--plugin PATH] [n ...]

n: cubes per side, default 55 95 (998,250 and 5,144,250 tetrahedra). Two
surfaces: "wide", the plane z = 0.5 + 0.2 (x - 0.5) over [0.1, 0.9]^2 (its
cavity is about a fifth of the cube), and "local", the same plane over
[0.3, 0.7]^2 (a shock that covers a smaller part of the domain). The stage
times are the filter's own (its Seconds* field data); peak memory is this
process's and, separately, TetGen's (it runs in a child process).
"""
import argparse
import os
import resource
import sys
import time

import numpy as np
from paraview.simple import *
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData, vtkUnstructuredGrid, VTK_TETRA

parser = argparse.ArgumentParser()
parser.add_argument("--plugin", default=None)
parser.add_argument("sizes", nargs="*", type=int, default=[55, 95])
args = parser.parse_args()
plugin = args.plugin or os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "build", "lib",
                                     "paraview-5.11", "plugins", "AdaptiveRedistribution", "AdaptiveRedistribution.so")
LoadPlugin(plugin, ns=globals())


def say(text):
    sys.stdout.write(text + "\n")
    sys.stdout.flush()


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


def plane(lo, hi, h):
    m = max(2, int(round((hi - lo) / h)))
    g = lo + (hi - lo) * np.arange(m + 1) / m
    y, x = np.meshgrid(g, g, indexing="ij")
    pts = np.column_stack([x.ravel(), y.ravel(), 0.5 + 0.2 * (x.ravel() - 0.5)])
    a = (np.arange(m)[None, :] + (m + 1) * np.arange(m)[:, None]).ravel()
    tris = np.vstack([np.column_stack([a, a + 1, a + m + 2]), np.column_stack([a, a + m + 2, a + m + 1])])
    poly = vtkPolyData()
    vp, cells = points_and_cells(pts, tris)
    poly.SetPoints(vp)
    poly.SetPolys(cells)
    return poly


def producer(data):
    tp = PVTrivialProducer()
    tp.GetClientSideObject().SetOutput(data)
    return tp


stages = ["Input", "SurfaceMeshing", "Setup", "Removal", "Cavity", "Layers", "Refill", "Assembly", "Output", "Interpolation", "Quality"]
say("| mesh tets | surface | mode | total s | " + " | ".join(stages) + " | new cells | layer cells | kept cells | peak RSS MB | TetGen peak MB |")
say("|---:|---|---|---:|" + "---:|" * len(stages) + "---:|---:|---:|---:|---:|")
for n in args.sizes:
    grid = kuhn_cube(n)
    mesh = producer(grid)
    for name, lo, hi in (("wide", 0.1, 0.9), ("local", 0.3, 0.7)):
        surface = producer(plane(lo, hi, 1.0 / n))
        for mode, layers in (("LocalCavity", "Tetrahedra"), ("LocalCavity", "Prisms"), ("FullDomain", "Tetrahedra")):
            if name == "local" and (mode == "FullDomain" or layers == "Prisms"):
                continue  # FullDomain remeshes everything whatever the surface
            er = EmbeddedRemesh(Input=mesh, Surfaces=[surface], Mode=mode, LayerType=layers, NumberOfLayers=5)
            t0 = time.time()
            er.UpdatePipeline()
            total = time.time() - t0
            out = er.GetClientSideObject().GetOutputDataObject(0)
            fd = out.GetFieldData()
            value = lambda key: fd.GetArray(key).GetValue(0) if fd.GetArray(key) else float("nan")
            say("| %d | %s | %s | %.2f | %s | %d | %d | %d | %.0f | %.0f |" % (
                grid.GetNumberOfCells(), name, mode + (" + prisms" if layers == "Prisms" else ""), total,
                " | ".join("%.2f" % value("Seconds" + s) for s in stages),
                value("NewCells"), value("LayerCells"), value("KeptCells"),
                resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
                resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0))
            Delete(er)
            del er
