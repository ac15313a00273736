"""Plugin/Scripts/adapt_case.py, the adapt-solve loop on an OpenFOAM case, as
a user runs it (pvbatch, a child process). The source is a real steady
solution made here: the first-order Mach 3 wedge of the validation matrix
(Data/make_validation_case.py wedge10Ma3o1 --keep: blockMesh, rhoCentralFoam,
~30 s), one cell deep. Asserts:
- write only: exit 0; the case checkMesh calls "Mesh OK"; its patches have
  the source's names and types; p, U and T are at time 0; controlDict starts
  at 0 with deltaT = the source's x (smallest step length 2V / sum of the
  side faces' areas after / before, at most 1), recomputed here from the two
  meshes' cross-sections; report.md has the cycle's node counts, the new
  cells' step length against the requested size's (StepLengthRatioNew),
  the input's shock measured along the fitted plane (10-90 % thickness of
  the first-order solution 0.015-0.035) and the Mach pictures (1200 x 900,
  a colour map on them);
- two cycles solved on two MPI ranks (decomposePar, mpirun, reconstructPar)
  to a bounded endTime (the config's controlDict entries): exit 0; each
  cycle's latest time is that endTime; cycle 2 adapted cycle 1's solution
  (another mesh) and kept its size at the shock (size ratio 0.75-1.33, where
  cycle 1's is at most 1/3); each cycle's shock measured after the solve, its
  picture; cycle 2's solution reads back in ParaView with finite,
  positive p and T on every cell;
- bad input, each exit 1 with a message naming it and no case written: a
  source that is no case, a target that is not empty, two cycles without
  --solve, a config naming a property AdaptToShocks does not have;
- a solve that blows up (maxCo 5): exit 1, the message names the
  floating-point exception, the time and the Courant number, and so does
  report.md; the case is kept;
- two cycles with prism layers on a 3-D mesh (a coarse cone made for it,
  solved to a bounded endTime): exit 0, both cycles solved, cycle 2 re-placed
  every prism and pyramid of cycle 1 (the report's RemovedLayerCells equal to
  cycle 1's count, read back from its case) and has layers of its own.
"""
import json
import os
import re
import shutil
import subprocess
import time

import numpy as np
from paraview.simple import *
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy

import artest
from artest import check
import foamcase

root = os.path.join(artest.OUTPUT_DIR, "adapt_case")
shutil.rmtree(root, ignore_errors=True)
os.makedirs(root)
source = os.path.join(root, "source")
script_dir = os.path.join(os.path.dirname(os.environ["AR_DATA_DIR"]), "Plugin", "Scripts")
rc, _ = artest.run([artest.require_program("python3", "python3"),
                    os.path.join(os.environ["AR_DATA_DIR"], "make_validation_case.py"), "wedge10Ma3o1",
                    os.path.join(root, "source.vtu"), "--keep", source])
check(rc == 0 and os.path.isdir(source), "the source case was made and solved (exit %d)" % rc)
pvbatch = artest.require_program("pvbatch", "paraview")


def adapt_case(*args):
    cmd = [pvbatch, os.path.join(script_dir, "adapt_case.py")] + list(args) + ["--plugin", os.environ["AR_PLUGIN"]]
    return artest.run(cmd)


def check_mesh(case):
    out = subprocess.run(["bash", "-c", "source %s >/dev/null 2>&1; checkMesh -case %s" % (foamcase.bashrc("checkMesh"), case)],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=artest.child_environment())
    return "Mesh OK." in out.stdout


def read_case(case, time=None):
    r = OpenFOAMReader(FileName=os.path.join(case, "read.foam"))
    r.MeshRegions = ["internalMesh"]
    r.CellArrays = r.CellArrays.Available
    r.UpdatePipeline(max(r.TimestepValues) if time is None else time)
    d = servermanager.Fetch(r).GetBlock(0)
    Delete(r)
    return d


def smallest(grid):
    """The smallest step length 2V / sum(A) with the front and back (z) left
    out, computed here from each cell's corners: a hexahedron's (area x
    depth) over its four side faces' area x depth, a wedge's likewise, so
    2 x area / perimeter of the cross-section."""
    P = vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64)
    types = vtk_to_numpy(grid.GetCellTypesArray())
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray())
    offsets = vtk_to_numpy(grid.GetCells().GetOffsetsArray())
    best = np.inf
    for c in range(len(types)):
        ids = conn[offsets[c]:offsets[c + 1]]
        X = P[ids]
        front = X[X[:, 2] == X[:, 2].min()][:, :2]  # the cross-section's corners
        centre = front.mean(axis=0)
        order = np.argsort(np.arctan2(front[:, 1] - centre[1], front[:, 0] - centre[0]))
        Q = front[order]
        area = 0.5 * abs(sum(Q[i, 0] * Q[(i + 1) % len(Q), 1] - Q[(i + 1) % len(Q), 0] * Q[i, 1] for i in range(len(Q))))
        perimeter = sum(np.linalg.norm(Q[(i + 1) % len(Q)] - Q[i]) for i in range(len(Q)))
        best = min(best, 2.0 * area / perimeter)
    return best


# ---- Write only.
t1 = os.path.join(root, "written")
started = time.time()
rc, text = adapt_case(source, t1)
wall1 = time.time() - started
case1 = os.path.join(t1, "cycle1")
check(rc == 0 and check_mesh(case1), "write only: exit %d, checkMesh says 'Mesh OK.'" % rc)
check(foamcase.patch_types(case1) == foamcase.patch_types(source) and len(foamcase.patch_types(source)) == 6,
      "write only: the patches' names and types are the source's (%s)" % foamcase.patch_types(case1))
check(all(os.path.isfile(os.path.join(case1, "0", n)) for n in ("p", "U", "T")), "write only: p, U, T at time 0")
cd0 = open(os.path.join(source, "system", "controlDict")).read()
cd1 = open(os.path.join(case1, "system", "controlDict")).read()
entry = lambda text, key: re.search(r"^\s*%s\s+([^;]+);" % key, text, re.M).group(1).strip()
h0, h1 = smallest(read_case(source)), smallest(read_case(case1, 0.0))
expected = float(entry(cd0, "deltaT")) * min(1.0, h1 / h0)
check(entry(cd1, "startFrom") == "startTime" and float(entry(cd1, "startTime")) == 0.0
      # (1e-4: the script measures its mesh in memory, this the case as
      # written and read back, whose points differ in the last digits; the
      # smallest cell's 2V/sum(A) is ~2e-4 at coordinates ~0.3)
      and abs(float(entry(cd1, "deltaT")) / expected - 1) < 1e-4,
      "write only: controlDict starts at 0, deltaT %s = %s x %.3f (smallest step length 2V/sum(A) %.2e -> %.2e)"
      % (entry(cd1, "deltaT"), entry(cd0, "deltaT"), h1 / h0, h0, h1))
report = open(os.path.join(t1, "report.md")).read()
check("## Cycle 1" in report and "| nodes | 14342 |" in report, "write only: report.md holds the cycle and its nodes")
m = re.search(r"the new cells' ([0-9.]+) of the regular cell's at S's edge \(StepLengthRatioNew\)", report)
check(m is not None and float(m.group(1)) >= 0.45,
      "write only: report.md states the new cells' step length against the requested size's (%s)"
      % (m.group(1) if m else "missing"))
# The shock along the fitted plane, measured on the source's solution: the
# first-order solution's 10-90 % rise is ~0.026 wide (make_validation_case.py).
row = re.search(r"^\| 0 \(Plane\) \| before \| (\d+) of (\d+) \| (\S+) \|", report, re.M)
check(row is not None and int(row.group(1)) >= 12 and 0.015 < float(row.group(3)) < 0.035,
      "write only: the report measures the input's shock on %s of %s lines, 10-90 %% thickness %s (0.015-0.035)"
      % (row.group(1), row.group(2), row.group(3)) if row else "write only: the report has no shock row")


def picture_ok(png):
    """A 1200 x 900 picture with a colour map on it, not a blank window."""
    from vtkmodules.vtkIOImage import vtkPNGReader
    if not os.path.isfile(png):
        return False
    r = vtkPNGReader()
    r.SetFileName(png)
    r.Update()
    img = r.GetOutput()
    rgb = vtk_to_numpy(img.GetPointData().GetScalars())[:, :3]
    return img.GetDimensions()[:2] == (1200, 900) and len(np.unique(rgb, axis=0)) > 100


check(all(picture_ok(os.path.join(t1, n)) for n in ("cycle1_before.png", "cycle1_start.png"))
      and "![cycle 1, before" in report,
      "write only: the Mach pictures before and on the adapted mesh are in the report")
# The report's seconds per stage: every stage, together within the run's wall
# time, AdaptToShocks' the report's own figure.
stages = re.search(r"^seconds per stage: (.*) \(([0-9.]+) in all\)$", report, re.M)
seconds = dict((k, float(v)) for k, v in re.findall(r"([A-Za-z][A-Za-z ]*?) ([0-9.]+)(?:, |$)", stages.group(1))) \
    if stages else {}
ats = re.search(r"AdaptToShocks in ([0-9.]+) s", report)
check(list(seconds) == ["read", "AdaptToShocks", "fetch", "shock measurement", "report", "write", "pictures"]
      and ats and abs(seconds["AdaptToShocks"] - float(ats.group(1))) <= 0.11
      and abs(sum(seconds.values()) - float(stages.group(2))) <= 0.05 * len(seconds)
      and sum(seconds.values()) <= wall1,
      "write only: the report's seconds per stage %s (AdaptToShocks as reported), in all %.1f <= the run's %.1f s"
      % (seconds, sum(seconds.values()), wall1))

# ---- Two cycles, solved on two ranks, to a bounded end time.
end = 0.0005
config = os.path.join(root, "config.json")
with open(config, "w") as f:
    json.dump({"controlDict": {"endTime": end, "writeInterval": end}}, f)
t2 = os.path.join(root, "cycles")
rc, text = adapt_case(source, t2, "--solve", "--cycles", "2", "--np", "2", "--config", config)
check(rc == 0, "two cycles on two ranks: exit %d" % rc)
times = [max((float(d) for d in os.listdir(os.path.join(t2, c)) if re.fullmatch(r"[0-9.e+-]+", d)), default=-1)
         for c in ("cycle1", "cycle2")]
check(all(abs(t - end) < 1e-12 for t in times), "both cycles ran to endTime %g (latest times %s)" % (end, times))
report = open(os.path.join(t2, "report.md")).read()
check("adapted `%s`" % os.path.join(t2, "cycle1") in report and report.count("rhoCentralFoam: exit 0") == 2,
      "cycle 2 adapted cycle 1's solution; the report has both solver runs")
check(len(re.findall(r"^\| 0 \(Plane\) \| after \| \d+ of", report, re.M)) == 2
      and all(picture_ok(os.path.join(t2, "cycle%d_after.png" % k)) for k in (1, 2)),
      "each cycle's report measures the shock on the solved mesh and shows its picture")
g1, g2 = read_case(os.path.join(t2, "cycle1"), 0.0), read_case(os.path.join(t2, "cycle2"))
p2 = vtk_to_numpy(g2.GetCellData().GetArray("p"))
T2 = vtk_to_numpy(g2.GetCellData().GetArray("T"))
check(g2.GetNumberOfPoints() != g1.GetNumberOfPoints() and np.isfinite(p2).all() and p2.min() > 0 and T2.min() > 0,
      "cycle 2's solution reads back: %d nodes (cycle 1: %d), p in [%.3f, %.3f], T > 0 on all %d cells"
      % (g2.GetNumberOfPoints(), g1.GetNumberOfPoints(), p2.min(), p2.max(), len(p2)))
# Cycle 2 keeps cycle 1's size at the shock (SurfaceSizeFactor 0.75 of the
# longest edges there) instead of shrinking it five-fold again.
ratios = [float(x) for x in re.findall(r"new cells at the shock ([0-9.]+) of the input's size", report)]
check(len(ratios) == 2 and ratios[0] <= 1.0 / 3.0 and 0.75 <= ratios[1] <= 1.33,
      "cycle 1 refines at the shock (size ratio %s), cycle 2 keeps that size (within a third)"
      % " and ".join("%.2f" % r for r in ratios))


# ---- Bad input.
def refused(args, fragment, label):
    target = args[1]
    rc, text = adapt_case(*args)
    check(rc == 1 and fragment in text and not os.path.exists(os.path.join(target, "cycle1", "constant")),
          "%s: exit %d, '%s', nothing written" % (label, rc, fragment))


refused([os.path.join(source, "system"), os.path.join(root, "bad1")], "is not an OpenFOAM case", "no case")
busy = os.path.join(root, "busy")
os.makedirs(busy)
open(os.path.join(busy, "notes.txt"), "w").write("a user's file\n")
refused([source, busy], "is not empty", "a target that is not empty")
check(os.listdir(busy) == ["notes.txt"], "a target that is not empty: left as it was")
refused([source, os.path.join(root, "bad3"), "--cycles", "2"], "needs --solve", "two cycles without --solve")
with open(config, "w") as f:
    json.dump({"AdaptToShocks": {"NoSuchProperty": 1}}, f)
refused([source, os.path.join(root, "bad4"), "--config", config], "no property NoSuchProperty", "a wrong property")

# A solve that blows up (maxCo 5: the explicit scheme is unstable): exit 1,
# the message names the floating-point exception, the time it got to and the
# Courant number as its cause, and so does the report; the written case stays.
with open(config, "w") as f:
    json.dump({"controlDict": {"maxCo": 5, "endTime": 0.05, "writeInterval": 0.05}}, f)
blown = os.path.join(root, "blown")
rc, text = adapt_case(source, blown, "--solve", "--config", config)
said = re.search(r"rhoCentralFoam failed on .*after t = ([0-9.e+-]+).*a floating-point exception\. "
                 r"The Courant number reached ([0-9.]+)", text)
check(rc == 1 and said and 0 < float(said.group(1)) < 0.05 and float(said.group(2)) > 1
      and os.path.isfile(os.path.join(blown, "report.md"))
      and "**failed**: rhoCentralFoam failed" in open(os.path.join(blown, "report.md")).read()
      and os.path.isdir(os.path.join(blown, "cycle1", "constant", "polyMesh")),
      "a solve that blows up: exit %d, the exception, its time and the Courant number named (%s); case and report kept"
      % (rc, said.group(0) if said else text.strip().splitlines()[-1:]))

# ---- Prism layers on a 3-D mesh, two cycles: cycle 2's cavity takes cycle
# 1's layers (they float inside the mesh) and builds its own. (A cone coarse
# enough to solve in a minute, fine enough for its layers; cycle 1 solved to
# a bounded end time, as the cycles above.)
cone = os.path.join(root, "cone")
rc, _ = artest.run([artest.require_program("python3", "python3"),
                    os.path.join(os.environ["AR_DATA_DIR"], "make_validation_case.py"), "cone15Ma3",
                    os.path.join(root, "cone.vtu"), "--keep", cone, "--refine", "0.8"])
check(rc == 0 and os.path.isdir(cone), "the 3-D cone case was made and solved (exit %d)" % rc)
with open(config, "w") as f:
    json.dump({"AdaptToShocks": {"LayerType": "Prisms"}, "controlDict": {"endTime": 0.002, "writeInterval": 0.002}}, f)
t3 = os.path.join(root, "cone_cycles")
rc, text = adapt_case(cone, t3, "--cycles", "2", "--solve", "--config", config)
report = open(os.path.join(t3, "report.md")).read() if os.path.exists(os.path.join(t3, "report.md")) else ""
replaced = [int(x) for x in re.findall(r"the input's layers re-placed: (\d+) of its prisms", report)]
c1, c2 = read_case(os.path.join(t3, "cycle1"), 0.0), read_case(os.path.join(t3, "cycle2"), 0.0)
layer_cells = lambda g: int(sum(1 for i in range(g.GetNumberOfCells()) if g.GetCellType(i) in (13, 14)))
n1, n2 = layer_cells(c1), layer_cells(c2)
check(rc == 0 and report.count("rhoCentralFoam: exit 0") == 2 and n1 > 0 and n2 > 0 and replaced == [n1],
      "two cycles with 3-D prism layers: exit %d, both solved; cycle 2 re-placed all %s of cycle 1's %d prisms and "
      "pyramids and has %d of its own" % (rc, replaced, n1, n2))
artest.finish()
