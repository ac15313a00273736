"""Benchmark of the OpenFOAM side of issue 13 (a benchmark, not a test):
the case writer on Kuhn-subdivided unit cubes (6 n^3 tetrahedra) carrying
the analytic oblique shock's fields, and adapt_case.py without --solve on
the same cube written as an OpenFOAM case (targets: 5e6 cells written in
under 15 s; adapt_case.py on 1e6 cells under 60 s end to end).

    pvpython Testing/Benchmark/bench_foam_case.py [--plugin PATH] [--work DIR]
             [--formats ascii binary] [--adapt-max N] [n ...]

n: cubes per side, default 55 95 (998,250 and 5,144,250 tetrahedra).
Writer: SaveData('<dir>/bench.foam') of the cube with the fields p, U, T,
rho as cell data (volScalarField/volVectorField), no Source Case, in each
of --formats (the writer's Format; default ascii and binary), wall-clock
around the call, with the case's size on disk and the time ParaView's
OpenFOAM reader takes to read it back (internalMesh and every cell array,
UpdatePipeline). adapt_case.py: the ASCII
case (the writer reads a Source Case's fields as text) gets the validation wedge's system/ and gas
(make_validation_case.py) and its fields as time 1, then
`pvbatch adapt_case.py CASE TARGET` (reading the case with ParaView's
OpenFOAM reader, AdaptToShocks with its defaults, writing the adapted case)
is timed as a child process (cubes up to --adapt-max tetrahedra); its
report's seconds per stage are printed below the table. Prints a Markdown table.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import time

import numpy as np
from paraview.simple import LoadPlugin, SaveData, Delete, OpenFOAMReader
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
parser.add_argument("--formats", nargs="+", default=["ascii", "binary"], choices=["ascii", "binary"],
                    help="the writer's Format values timed (default both; ascii is the one adapt_case.py reads)")
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
stage_rows = []
for n in args.sizes:
    grid = cube(n)
    src = producer(grid)
    src.UpdatePipeline()
    target = os.path.join(args.work, "cube%d" % n)
    writes = []
    for fmt in args.formats:
        case = target if fmt == "ascii" else target + "_" + fmt
        shutil.rmtree(case, ignore_errors=True)
        os.makedirs(os.path.dirname(case), exist_ok=True)
        extra = {} if fmt == "ascii" else {"Format": fmt}  # the default: also for a plugin without Format
        t = time.perf_counter()
        SaveData(os.path.join(case, "bench.foam"), proxy=src, **extra)
        t_write = time.perf_counter() - t
        ok = os.path.isfile(os.path.join(case, "constant", "polyMesh", "owner"))
        t_read = float("nan")
        if ok:
            reader = OpenFOAMReader(FileName=os.path.join(case, "bench.foam"), SkipZeroTime=0)
            reader.Refresh()
            reader.UpdatePipelineInformation()
            reader.MeshRegions = ["internalMesh"]
            reader.CellArrays = reader.CellArrays.Available
            t = time.perf_counter()
            reader.UpdatePipeline(0.0)
            t_read = time.perf_counter() - t
            Delete(reader)
        writes.append((fmt, t_write, du_mb(case), ok, t_read))
        if fmt != "ascii":
            shutil.rmtree(case, ignore_errors=True)
    Delete(src)
    del grid
    t_adapt = float("nan")
    t_ats = float("nan")
    ascii_ok = any(w[0] == "ascii" and w[3] for w in writes)
    if ascii_ok and 6 * n ** 3 <= args.adapt_max:
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
            text = open(os.path.join(adapted, "report.md")).read()
            m = re.search(r"AdaptToShocks in ([0-9.]+) s", text)
            t_ats = float(m.group(1)) if m else float("nan")
            m = re.search(r"^seconds per stage: (.*)$", text, re.M)
            if m:
                stage_rows.append((6 * n ** 3, m.group(1)))
    for fmt, t_write, size, ok, t_read in writes:
        rows.append((6 * n ** 3, fmt, t_write, size, ok, t_read, t_adapt if fmt == "ascii" else float("nan"),
                     t_ats if fmt == "ascii" else float("nan")))
    shutil.rmtree(target, ignore_errors=True)
    shutil.rmtree(target + "_adapted", ignore_errors=True)

say("| tets | format | write s | case MB | written | read back s | adapt_case.py (no --solve) s | "
    "of which AdaptToShocks s |")
say("|---:|---|---:|---:|---|---:|---:|---:|")
for r in rows:
    say("| %d | %s | %.1f | %.0f | %s | %.1f | %.1f | %.1f |" % r)
for tets, text in stage_rows:
    say("")
    say("adapt_case.py on %d tets, %s" % (tets, text))
