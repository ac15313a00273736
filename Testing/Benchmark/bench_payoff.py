"""The payoff benchmark (issue 13): is the shock sharper on the adapted mesh
than on a uniformly refined mesh of the same node count, after the solver
ran on both, and what does it cost?

    pvpython Testing/Benchmark/bench_payoff.py [--case NAME] [--work DIR]
             [--refine F1,F2,...] [--cycles N] [--layers | --layers-only]
             [--adapted-end T]
             [--lts] [--steady-tol F]

--case      a case of Data/make_validation_case.py (default wedge10Ma3, the
            2-D Mach 3 wedge; cone15Ma3 is the 3-D cone)
--work      where the cases are made and kept (default /tmp/ar_payoff/NAME,
            with --lts /tmp/ar_payoff/NAME_lts);
            a case already there and solved is reused, so a second run only
            measures
--refine    the uniform meshes: the case's mesh refined by each factor
            (make_validation_case.py --refine; default 1,1.1,1.25,1.5,1.75,2);
            factor 1 is the original mesh and the source of the adaptation
--cycles    adapt-solve cycles (default 2): Plugin/Scripts/adapt_case.py
            --solve on the original solution
--layers    also the adapted mesh with layers (LayerType Prisms: prism
            layers in 3-D, layers of hexahedra along the shock in 2-D)
--layers-only  the adapted mesh with layers only, not the tetrahedral one
--adapted-end  endTime of the adapted cases' solves (default half the case's:
            they start from the interpolated solution; with --lts iterations,
            default the uniform meshes' number: the shock, where the cells
            are small, settles in no fewer iterations than there)
--lts       local time stepping, rhoCentralFoam's steady mode, on every mesh:
            ddtSchemes localEuler, maxCo half the case's, rDeltaTSmoothingCoeff,
            deltaT 1 (the time is the iteration count), a fixed number of
            iterations written at a fixed interval (make_validation_case.LTS,
            lts_control; make_validation_case.py --lts for the uniform
            meshes, the same controlDict entries in adapt_case.py's config
            for the adapted cycles, which inherit the source's fvSchemes).
            Every solver log must say "Using LTS"; a --work holding cases
            of the other time scheme is refused
--steady-tol  p's rms change between writes, as a fraction of its range,
            under which the solution counts as steady (default 1e-3,
            make_validation_case.STEADY_RMS)

Every mesh is solved by rhoCentralFoam with the case's settings (Tadmor
flux, Minmod limiters, adjustTimeStep at the case's maxCo, serial; with
--lts every cell's own step at half that maxCo).  On each
solution the shock is measured along lines normal to the EXACT shock
(theta-beta-Mach plane through the wedge's tip; the Taylor-Maccoll cone on
the 45-degree meridian of the quarter cone) at 12 stations from 0.35 (the
cone: 0.5) to 0.85 of its length, with Plugin/Scripts/shock_measure.py (p's 10-90 % rise,
linear on the point data; for the cone, whose p keeps rising behind the
shock, of the exact jump from p1 = 1 to Taylor-Maccoll's p2): the thickness (median over the stations) and the
shock angle (mean over the stations of the angle of the rise's midpoint
seen from the tip) against theory.  The cost: the solver's CPU seconds
(ExecutionTime) until the solution is steady, i.e. from the first write
after which p's rms change between writes stays under 0.1 % of its range
(--steady-tol)
(make_validation_case.steady_time), and in all.

The table compares each adapted mesh with the uniform meshes interpolated
(log-log in the node count) to its node count: thickness ratio (target at
most 0.5), CPU-to-steady ratio (target at most 2), angle error (target
within 0.5 deg); and gives the uniform mesh as sharp as it (nodes and CPU
to steady interpolated log-log in the thickness).  It is printed and written to WORK/payoff.md.
"""
import argparse
import json
import math
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "Data"))
sys.path.insert(0, os.path.join(ROOT, "Plugin", "Scripts"))
import make_validation_case as mvc  # noqa: E402
import shock_measure  # noqa: E402


def read_latest(case):
    """The internalMesh (point and cell data) at the case's latest time."""
    from vtkmodules.vtkIOGeometry import vtkOpenFOAMReader
    r = vtkOpenFOAMReader()
    r.SetFileName(os.path.join(case, "bench.foam"))
    r.UpdateInformation()
    r.DisableAllPatchArrays()
    r.SetPatchArrayStatus("internalMesh", 1)
    r.EnableAllCellArrays()
    times = r.GetTimeValues()
    t = times.GetValue(times.GetNumberOfTuples() - 1)
    r.UpdateTimeStep(t)
    g = r.GetOutput()
    while g.IsA("vtkMultiBlockDataSet"):
        g = g.GetBlock(0)
    return g, t


def exact_lines(c, grid):
    """(origins, normals, half length, the exact shock angle, a function
    giving the shock angle of a rise's midpoint seen from the tip) of the
    lines normal to the exact shock."""
    beta, _, _ = mvc.theory(c)
    b = math.radians(beta)
    P = np.array(grid.GetPoints().GetData())
    if c["kind"] == "wedge":
        length = c["x1"] / math.cos(b)
        z = 0.5 * (P[:, 2].min() + P[:, 2].max())
        along = np.array([math.cos(b), math.sin(b), 0.0])
        normal = np.array([math.sin(b), -math.cos(b), 0.0])
        s = np.linspace(0.35, 0.85, 12) * length
        origins = s[:, None] * along + np.array([0.0, 0.0, z])
        normals = np.tile(normal, (len(s), 1))
        angle = lambda x: math.degrees(math.atan2(x[1], x[0]))
        half = 0.06 * length
    else:
        length = c["x1"] / math.cos(b)
        e = np.array([0.0, 1.0, 1.0]) / math.sqrt(2.0)  # the 45-degree meridian
        along = math.cos(b) * np.array([1.0, 0.0, 0.0]) + math.sin(b) * e
        normal = -math.sin(b) * np.array([1.0, 0.0, 0.0]) + math.cos(b) * e
        # the coarse meshes smear the cone's shock over ~0.05: longer lines,
        # from 0.5 of the length on, where they stay clear of the cone
        s = np.linspace(0.5, 0.85, 12) * length
        origins = s[:, None] * along
        normals = np.tile(normal, (len(s), 1))
        angle = lambda x: math.degrees(math.atan2(math.hypot(x[1], x[2]), x[0]))
        half = 0.07 * length
    return origins, normals, half, beta, angle


def measure(case, c, lts, tol=mvc.STEADY_RMS):
    if not solved(case, lts):
        sys.exit("bench_payoff.py: %s was not solved to its end" % case)
    grid, t = read_latest(case)
    origins, normals, half, beta, angle = exact_lines(c, grid)
    # a cone's p keeps rising behind the shock (Taylor-Maccoll): the exact
    # jump (p1 = 1, the normalised free stream) is the reference there
    states = (1.0, mvc.theory(c)[1]) if c["kind"] == "cone" else None
    r = shock_measure.measure(grid, origins, normals, half_length=half, states=states)
    summ = shock_measure.summary(r)
    angles = [angle(x) for x, ok in zip(r["points"], r["valid"]) if ok]
    settled, cpu, clock, _ = mvc.steady_time(case, tol)
    hist = mvc.solver_history(case)
    steps = len([h for h in hist if h[0] <= settled * (1 + 1e-9)]) if settled is not None else None
    from vtkmodules.util.numpy_support import vtk_to_numpy
    types = vtk_to_numpy(grid.GetCellTypesArray())
    return dict(case=case, nodes=grid.GetNumberOfPoints(), cells=grid.GetNumberOfCells(),
                kinds={int(k): int((types == k).sum()) for k in np.unique(types)},
                thickness=summ.get("thickness_median", float("nan")), lines=summ["valid"],
                angle_error=(float(np.mean(angles)) - beta) if angles else float("nan"),
                steady_time=settled, cpu_steady=cpu, clock_steady=clock,
                cpu_total=hist[-1][1] if hist else float("nan"), steps=len(hist), steps_steady=steps,
                end_time=t)


def run(cmd, log):
    with open(log, "w") as f:
        r = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT)
    if r.returncode != 0:
        sys.exit("bench_payoff.py: %s failed (exit %d), see %s" % (" ".join(cmd[:3]), r.returncode, log))


def solved(case, lts):
    """Whether the case was solved to its end; exits if it was, with the
    other time scheme than `lts` asks for."""
    log = os.path.join(case, "log.rhoCentralFoam")
    if not (os.path.isfile(log) and "\nEnd" in open(log).read()):
        return False
    if ("\nUsing LTS" in open(log).read()) != lts:
        sys.exit("bench_payoff.py: %s was solved %s local time stepping: use another --work"
                 % (case, "with" if not lts else "without"))
    return True


def interp(nodes, xs, ys):
    """log-log interpolation (linear extrapolation past the ends)."""
    xs, ys = np.log(np.asarray(xs, float)), np.log(np.asarray(ys, float))
    o = np.argsort(xs)
    xs, ys = xs[o], ys[o]
    x = math.log(nodes)
    i = int(np.clip(np.searchsorted(xs, x) - 1, 0, len(xs) - 2))
    return float(np.exp(ys[i] + (ys[i + 1] - ys[i]) * (x - xs[i]) / (xs[i + 1] - xs[i])))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--case", default="wedge10Ma3", choices=list(mvc.CASES))
    ap.add_argument("--work")
    ap.add_argument("--refine", default="1,1.1,1.25,1.5,1.75,2")
    ap.add_argument("--cycles", type=int, default=2)
    ap.add_argument("--layers", action="store_true")
    ap.add_argument("--layers-only", action="store_true")
    ap.add_argument("--adapted-end", type=float)
    ap.add_argument("--lts", action="store_true")
    ap.add_argument("--steady-tol", type=float, default=mvc.STEADY_RMS)
    ap.add_argument("--plugin", default=os.environ.get("AR_PLUGIN", os.path.join(
        ROOT, "build", "lib", "paraview-5.11", "plugins", "AdaptiveRedistribution", "AdaptiveRedistribution.so")))
    a = ap.parse_args()
    c = mvc.CASES[a.case]
    work = os.path.abspath(a.work or os.path.join("/tmp/ar_payoff", a.case + ("_lts" if a.lts else "")))
    os.makedirs(work, exist_ok=True)
    factors = sorted(float(f) for f in a.refine.split(","))
    if 1.0 not in factors:
        sys.exit("--refine must include 1 (the original mesh, the adaptation's source)")
    rows = []
    for f in factors:
        case = os.path.join(work, "uniform_%g" % f)
        if not solved(case, a.lts):
            lts = ["--lts"] if a.lts else []
            print("[payoff] uniform mesh x%g: make_validation_case.py --refine %g %s" % (f, f, " ".join(lts)),
                  flush=True)
            run(["python3", os.path.join(ROOT, "Data", "make_validation_case.py"), a.case, case + ".vtu",
                 "--keep", case, "--refine", "%g" % f] + lts, case + ".log")
        rows.append(("uniform x%g" % f, measure(case, c, a.lts, a.steady_tol)))
    if a.lts:
        end = int(a.adapted_end or mvc.LTS["iterations"])
        control = mvc.lts_control(c, end)
    else:
        end = a.adapted_end or 0.5 * c["end"]
        control = {"endTime": end}
    variants = [("tetrahedra" if c["kind"] == "cone" else "triangles", "adapted", {})]
    if a.layers_only:
        variants = []
    if a.layers or a.layers_only:
        variants.append(("layers", "layers", {"LayerType": "Prisms"}))
    for label, name, props in variants:
        target = os.path.join(work, name)
        last = os.path.join(target, "cycle%d" % a.cycles)
        if not solved(last, a.lts):
            cfg = os.path.join(work, name + ".json")
            with open(cfg, "w") as fcfg:
                json.dump({"AdaptToShocks": props, "controlDict": control}, fcfg)
            if os.path.isdir(target):
                import shutil
                shutil.rmtree(target)
            print("[payoff] adapted (%s): adapt_case.py --cycles %d --solve" % (label, a.cycles), flush=True)
            run(["pvbatch", os.path.join(ROOT, "Plugin", "Scripts", "adapt_case.py"),
                 os.path.join(work, "uniform_1"), target, "--cycles", str(a.cycles), "--solve", "--config", cfg,
                 "--plugin", a.plugin], target + ".log")
        for k in range(1, a.cycles + 1):
            rows.append(("adapted %s, cycle %d" % (label, k),
                         measure(os.path.join(target, "cycle%d" % k), c, a.lts, a.steady_tol)))
    uniform = [r for n, r in rows if n.startswith("uniform")]
    un, ut = [r["nodes"] for r in uniform], [r["thickness"] for r in uniform]
    uc = [r["cpu_steady"] for r in uniform]
    beta = mvc.theory(c)[0]
    scheme = ("local time stepping (localEuler, maxCo %(maxCo)s, rDeltaTSmoothingCoeff %(rDeltaTSmoothingCoeff)s; "
              "t is the iteration)" % mvc.lts_control(c) if a.lts
              else "Euler in time, adjustTimeStep at maxCo %g" % c["maxco"])
    out = ["# Payoff: %s (%s, theory %.3f deg; %s)" % (a.case, c["kind"], beta, scheme), "",
           "| mesh | nodes | cells | 10-90 % thickness | vs uniform at equal nodes | angle - theory (deg) "
           "| steady at t | steps to steady | CPU s to steady | vs uniform at equal nodes "
           "| uniform at equal thickness: nodes, CPU s to steady | CPU s in all (to t) |",
           "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for name, r in rows:
        adapted = not name.startswith("uniform")
        tr = r["thickness"] / interp(r["nodes"], un, ut) if adapted else None
        cr = (r["cpu_steady"] / interp(r["nodes"], un, uc)) if adapted and r["cpu_steady"] else None
        same = ""
        if adapted:
            # the uniform mesh that would be as sharp: nodes and cost, log-log
            # in the thickness (extrapolated past the finest uniform mesh)
            same = "%d, %.0f%s" % (interp(r["thickness"], ut, un), interp(r["thickness"], ut, uc),
                                   " (extrapolated)" if r["thickness"] < min(ut) else "")
        out.append("| %s | %d | %d | %.4g (%d lines) | %s | %+.2f | %s | %s | %s | %s | %s | %.0f (%g) |" % (
            name, r["nodes"], r["cells"], r["thickness"], r["lines"], "%.2f" % tr if tr else "",
            r["angle_error"], "%g" % r["steady_time"] if r["steady_time"] is not None else "not steady",
            "%d" % r["steps_steady"] if r["steps_steady"] is not None else "-",
            "%.0f" % r["cpu_steady"] if r["cpu_steady"] is not None else "-", "%.2f" % cr if cr else "",
            same, r["cpu_total"], r["end_time"]))
    out += ["", "Steady: p's rms change between writes under %g of its range from then on. " % a.steady_tol
            + "Targets at equal node count: thickness ratio <= 0.5, CPU-to-steady ratio <= 2, "
            "angle within 0.5 deg. Adapted solves start from the interpolated solution (endTime %g); "
            "the uniform ones from the free stream (endTime %g)." % (end, mvc.LTS["iterations"] if a.lts else c["end"])]
    text = "\n".join(out)
    print(text)
    with open(os.path.join(work, "payoff.md"), "w") as f:
        f.write(text + "\n")


main()
