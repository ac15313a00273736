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
from vtkmodules.vtkCommonDataModel import vtkPolyData

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_meshes import kuhn_cube, points_and_cells, producer  # noqa: E402

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
