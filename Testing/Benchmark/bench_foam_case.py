"""Benchmark of the OpenFOAM side of issue 13 (a benchmark, not a test):
the case writer on Kuhn-subdivided unit cubes (6 n^3 tetrahedra) carrying
the analytic oblique shock's fields, and adapt_case.py without --solve on
the same cube written as an OpenFOAM case (targets: 5e6 cells written in
under 15 s; adapt_case.py on 1e6 cells under 60 s end to end).

    pvpython Testing/Benchmark/bench_foam_case.py [--plugin PATH] [--work DIR] [n ...]

n: cubes per side, default 55 95 (998,250 and 5,144,250 tetrahedra).
Writer: SaveData('<dir>/bench.foam') of the cube with the fields p, U, T,
rho as cell data (volScalarField/volVectorField, ASCII), no Source Case,
wall-clock around the call, with the case's size on disk. adapt_case.py:
the written case gets the validation wedge's system/ and gas
(make_validation_case.py) and its fields as time 1, then
`pvbatch adapt_case.py CASE TARGET` (reading the case with ParaView's
OpenFOAM reader, AdaptToShocks with its defaults, writing the adapted case)
is timed as a child process (cubes up to --adapt-max tetrahedra); its
report's AdaptToShocks seconds are given beside it. Prints a Markdown table.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import time

import numpy as np
from paraview.simple import LoadPlugin, SaveData, Delete
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.abspath(os.path.join(here, "..", ".."))
sys.path.insert(0, here)
sys.path.insert(0, os.path.join(root, "Data"))
from analytic_shock import ObliqueShock  # noqa: E402
from bench_meshes import kuhn_cube, producer  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("--plugin", default=os.path.join(root, "build", "lib", "paraview-5.11", "plugins",
                                                      "AdaptiveRedistribution", "AdaptiveRedistribution.so"))
parser.add_argument("--work", default="/tmp/ar_bench_foam_case")
parser.add_argument("--adapt-max", type=int, default=1200000,
                    help="run adapt_case.py only on cubes of at most this many tetrahedra (default 1.2e6)")
parser.add_argument("sizes", nargs="*", type=int, default=[55, 95])
args = parser.parse_args()
LoadPlugin(args.plugin, ns=globals())



def say(text):
    sys.stdout.write(text + "\n")
    sys.stdout.flush()


def du_mb(path):
    return sum(os.path.getsize(os.path.join(d, f)) for d, _, fs in os.walk(path) for f in fs) / 1e6


def cube(n):
    grid = kuhn_cube(n)
    P = vtk_to_numpy(grid.GetPoints().GetData())
    shock = ObliqueShock(delta=3.0 / n)
    fields = shock.fields(P)
    # normalised as the validation cases: p, T ~ 1, a = 1 at T = 1
    scale = {"p": 1.0 / shock.p1, "T": 1.0 / shock.T1, "rho": 1.0 / shock.rho1}
    for name in ("p", "T", "rho", "U"):
        values = np.asarray(fields[name], dtype=np.float64) * scale.get(name, 1.0 / np.sqrt(1.4 * 287.0 * shock.T1))
        a = numpy_to_vtk(np.ascontiguousarray(values), deep=1)
        a.SetName(name)
        grid.GetPointData().AddArray(a)
    from vtkmodules.vtkFiltersCore import vtkPointDataToCellData
    f = vtkPointDataToCellData()
    f.SetInputData(grid)
    f.Update()
    out = f.GetOutput()
    for name in ("p", "T", "rho", "U"):
        out.GetPointData().RemoveArray(name)
    return out


def foam_case(case, time_name="1"):
    """The writer's case made runnable: its fields moved to time 1, and the
    validation wedge's system/ and gas (make_validation_case.py)."""
    import tempfile
    import make_validation_case as mvc
    shutil.move(os.path.join(case, "0"), os.path.join(case, time_name))
    tmp = tempfile.mkdtemp()
    mvc.write_case_files(tmp, mvc.CASES["wedge10Ma3"])
    shutil.copytree(os.path.join(tmp, "system"), os.path.join(case, "system"), dirs_exist_ok=True)
    shutil.copy(os.path.join(tmp, "constant", "thermophysicalProperties"), os.path.join(case, "constant"))
    shutil.rmtree(tmp)


rows = []
for n in args.sizes:
    grid = cube(n)
    src = producer(grid)
    src.UpdatePipeline()
    target = os.path.join(args.work, "cube%d" % n)
    shutil.rmtree(target, ignore_errors=True)
    os.makedirs(os.path.dirname(target), exist_ok=True)
    t = time.perf_counter()
    SaveData(os.path.join(target, "bench.foam"), proxy=src)
    t_write = time.perf_counter() - t
    ok = os.path.isfile(os.path.join(target, "constant", "polyMesh", "owner"))
    size = du_mb(target)
    Delete(src)
    del grid
    t_adapt = float("nan")
    t_ats = float("nan")
    if ok and 6 * n ** 3 <= args.adapt_max:
        foam_case(target)
        adapted = target + "_adapted"
        shutil.rmtree(adapted, ignore_errors=True)
        t = time.perf_counter()
        r = subprocess.run(["pvbatch", os.path.join(root, "Plugin", "Scripts", "adapt_case.py"), target, adapted,
                            "--plugin", args.plugin], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        t_adapt = time.perf_counter() - t
        if r.returncode != 0:
            say("adapt_case.py failed on %s:\n%s" % (target, r.stdout[-2000:]))
        else:
            m = re.search(r"AdaptToShocks in ([0-9.]+) s", open(os.path.join(adapted, "report.md")).read())
            t_ats = float(m.group(1)) if m else float("nan")
    rows.append((6 * n ** 3, t_write, size, ok, t_adapt, t_ats))
    shutil.rmtree(target, ignore_errors=True)
    shutil.rmtree(target + "_adapted", ignore_errors=True)

say("| tets | write s | case MB | written | adapt_case.py (no --solve) s | of which AdaptToShocks s |")
say("|---:|---:|---:|---|---:|---:|")
for r in rows:
    say("| %d | %.1f | %.0f | %s | %.1f | %.1f |" % r)
