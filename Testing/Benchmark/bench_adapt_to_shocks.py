"""Benchmark of AdaptToShocks (a benchmark, not a test): the whole step on
Kuhn-subdivided unit cubes (6 n^3 tetrahedra) carrying the analytic oblique
shock of Data/analytic_shock.py (Mach 2.5, 15 degree deflection, smeared over
about three cells, rotated to a generic orientation), against its parts run
separately with the same defaults (ShockSensor, FeatureCluster, QuadricFit of
cluster 0, EmbeddedRemesh). Prints a Markdown table.

    pvpython Testing/Benchmark/bench_adapt_to_shocks.py [--plugin PATH] [n ...]

n: cubes per side, default 55 95 (998,250 and 5,144,250 tetrahedra). The
parts' times are wall-clock around each filter's update (the pipeline
upstream already up to date); the one step's stages are its own field data
(SecondsSensor, SecondsClusters, SecondsFit, SecondsRemesh). Peak memory is
this process's (TetGen runs in a child process: its peak is EmbeddedRemesh's
business, see bench_embedded_remesh.py).
"""
import argparse
import os
import resource
import sys
import time

import numpy as np
from paraview.simple import *
from vtkmodules.util.numpy_support import numpy_to_vtk

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
sys.path.insert(0, os.path.join(here, "..", "..", "Data"))
from analytic_shock import ObliqueShock  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("--plugin", default=None)
parser.add_argument("sizes", nargs="*", type=int, default=[55, 95])
args = parser.parse_args()
plugin = args.plugin or os.path.join(here, "..", "..", "build", "lib", "paraview-5.11", "plugins",
                                     "AdaptiveRedistribution", "AdaptiveRedistribution.so")
LoadPlugin(plugin, ns=globals())
from bench_meshes import kuhn_cube, producer  # noqa: E402


def say(text):
    sys.stdout.write(text + "\n")
    sys.stdout.flush()


def solution(n):
    grid = kuhn_cube(n)
    from vtkmodules.util.numpy_support import vtk_to_numpy
    P = vtk_to_numpy(grid.GetPoints().GetData())
    shock = ObliqueShock(delta=3.0 / n)  # smeared over about three cells, as a captured shock
    for name, values in shock.fields(P).items():
        a = numpy_to_vtk(np.ascontiguousarray(values, dtype=np.float64), deep=1)
        a.SetName(name)
        grid.GetPointData().AddArray(a)
    return grid, shock


def peak_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def timed(proxy):
    t = time.perf_counter()
    proxy.UpdatePipeline()
    return time.perf_counter() - t


rows = []
for n in args.sizes:
    grid, shock = solution(n)
    src = producer(grid)
    src.UpdatePipeline()
    # The parts, one after the other.
    sensor = ShockSensor(Input=src)
    t_sensor = timed(sensor)
    clusters = FeatureCluster(Input=sensor)
    t_clusters = timed(clusters)
    fit = QuadricFit(Input=OutputPort(clusters, 1), Domain=src, ClusterId=0)
    t_fit = timed(fit)
    remesh = EmbeddedRemesh(Input=src, Surfaces=[fit])
    t_remesh = timed(remesh)
    parts = t_sensor + t_clusters + t_fit + t_remesh
    separate = servermanager.Fetch(remesh)
    for p in (remesh, fit, clusters, sensor):
        Delete(p)
    # The one step.
    adapt = AdaptToShocks(Input=src)
    t_all = timed(adapt)
    out = servermanager.Fetch(adapt)
    fd = out.GetFieldData()
    v = lambda name: fd.GetArray(name).GetValue(0)
    rows.append((grid.GetNumberOfCells(), t_sensor, v("SecondsSensor"), t_clusters, v("SecondsClusters"), t_fit,
                 v("SecondsFit"), t_remesh, v("SecondsRemesh"), parts, t_all, t_all / parts,
                 int(v("InputNodes")), int(v("OutputNodes")), v("SurfaceSizeRatio"), int(v("RefillPieces")),
                 v("MinDihedralAngleNew"), out.GetNumberOfPoints() == separate.GetNumberOfPoints(), peak_mb()))
    Delete(adapt)
    Delete(src)
    del grid, out, separate

say("| tets | sensor (parts / step) s | clusters s | fit s | remesh s | sum of parts s | AdaptToShocks s | step / parts "
    "| nodes in -> out | size ratio at S | refill pieces | smallest new angle | same mesh | peak RSS MB |")
say("|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---|---:|")
for r in rows:
    say("| %d | %.2f / %.2f | %.2f / %.2f | %.2f / %.2f | %.2f / %.2f | %.2f | %.2f | %.2f | %d -> %d | %.2f | %d | %.2f | %s | %.0f |" % r)
