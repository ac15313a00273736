"""Adapt an OpenFOAM case to its shocks, and optionally run the solver on it.

    pvbatch Plugin/Scripts/adapt_case.py SOURCE_CASE TARGET_CASE
            [--cycles N] [--solve] [--np K] [--config FILE] [--plugin PATH]

SOURCE_CASE  an OpenFOAM case with a solution (its latest time is read, with
             every patch, by ParaView's OpenFOAM reader; no .foam file needed)
TARGET_CASE  a new (or empty) directory: cycle K's case is TARGET_CASE/cycleK,
             and TARGET_CASE/report.md says what each cycle did
--cycles N   adapt-solve cycles (default 1). Cycle K > 1 adapts the solution
             of cycle K-1, so every cycle but the last needs --solve. With
             prism layers (LayerType Prisms) cycle K re-places cycle K-1's
             layers where its cavity reaches them (EmbeddedRemesh releases
             layers that float inside the mesh: RemovedLayerCells)
--solve      run the case's own application (controlDict's `application`)
             to its endTime after writing it; without it the case is only
             written, ready to run
--np K       solve on K MPI ranks (decomposePar, method simple: K slabs
             along the longest side, as Debian's OpenFOAM has no scotch;
             mpirun -np K APP -parallel; reconstructPar); default 1, serial
--config F   a JSON object: {"AdaptToShocks": {property: value, ...},
             "controlDict": {keyword: value, ...}}; the first are AdaptToShocks'
             properties (its defaults otherwise), the second replace entries of
             the written cases' system/controlDict (e.g. endTime, writeInterval)
--plugin P   the plugin (default: $AR_PLUGIN, else the build tree's)

Each cycle: AdaptToShocks with its defaults (or the config's properties) on
the source's latest time (cycles after the first with SurfaceSizeFactor
0.75 unless the config sets SurfaceSizeFactor or SurfaceEdgeLength: they keep
the first cycle's refinement, as its longest edges measure it, and re-place
it on the sharper shock, instead of shrinking the cells, and the explicit
solver's time step, five-fold again); the OpenFOAM case writer (vtkOpenFOAMCaseWriter)
with the source as SourceCase, so patch names and types, the fields' boundary
conditions, constant/ and system/ come from it; controlDict starts at time 0
(startFrom startTime) and its deltaT is scaled by the ratio of the smallest
step length after and before (2V / sum of face areas, the length the
Courant number divides by; the front and back faces of one-cell-deep cases
left out), never raised, so the first step is stable on the new smallest
cell (adjustTimeStep then takes over where the case uses it). The report
gives per cycle: nodes and cells by type, the fitted surfaces, the size at
the shock, the new cells' smallest step length against the requested size's
(StepLengthRatioNew, StepLengthRatioLayerCells), the smallest-angle
histogram of the new cells, deltaT,
the shock's position and 10-90 % thickness along lines normal to each fitted
surface (shock_measure.py) on the input's solution and, with --solve, on the
adapted mesh's, the solver's wall time and exit status, and pictures of the
Mach number on a cut through the shock with the mesh (shock_pictures.py, in
TARGET_CASE/cycleK_*.png; on a private Xvfb when there is no $DISPLAY) and
the fitted surfaces (TARGET_CASE/cycleK_surfaces.vtp).

Exit status 0 when every cycle was written (and solved, with --solve); 1 with
a message naming the failure otherwise; the report holds what was done.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import time

import numpy as np

from paraview.simple import LoadPlugin, OpenFOAMReader, SaveData, servermanager, Delete

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import shock_measure  # noqa: E402

FOAM_BASHRC = os.environ.get("AR_OPENFOAM_BASHRC", "/usr/share/openfoam/etc/bashrc")
# Cycles after the first keep its size at the shock: the "input's size" is
# the longest edge at each node, and a mesh made with edge l at the shock
# measures about 1.3 l that way (1.31 on the validation wedge's cycle 1), so
# a factor of 1 would coarsen the band by a third each cycle.
KEEP_SIZE_FACTOR = 0.75
TYPE_NAMES = {10: "tetrahedra", 12: "hexahedra", 13: "prisms", 14: "pyramids", 11: "voxels", 42: "polyhedra"}


def fail(message):
    print("adapt_case.py: " + message, file=sys.stderr)
    sys.exit(1)


def latest_time(case):
    times = []
    for d in os.listdir(case):
        try:
            if os.path.isdir(os.path.join(case, d)):
                times.append((float(d), d))
        except ValueError:
            pass
    return max(times)[1] if times else None


def foam(cmd, cwd, log):
    """Runs an OpenFOAM command line in `cwd` with OpenFOAM's environment;
    its output goes to `log`. Returns (exit code, seconds)."""
    if not os.path.exists(FOAM_BASHRC):
        fail("OpenFOAM is not installed (%s missing): apt-get install openfoam (the README's set-up installs it)"
             % FOAM_BASHRC)
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "OPAL_", "PMI_", "HYDRA_"))}
    t = time.time()
    with open(log, "w") as out:
        r = subprocess.run(["bash", "-c", "source %s >/dev/null 2>&1; %s" % (FOAM_BASHRC, cmd)], cwd=cwd, env=env,
                           stdout=out, stderr=subprocess.STDOUT)
    return r.returncode, time.time() - t


def dict_entry(text, key):
    m = re.search(r"^\s*%s\s+([^;]+);" % re.escape(key), text, re.M)
    return m.group(1).strip() if m else None


def set_entry(text, key, value):
    pattern = re.compile(r"^(\s*%s\s+)([^;]+);" % re.escape(key), re.M)
    if pattern.search(text):
        return pattern.sub(lambda m: m.group(1) + str(value) + ";", text, count=1)
    return text.rstrip() + "\n%s %s;\n" % (key, value)


def blocks(data):
    """The leaves of a (multiblock) dataset."""
    if data.IsA("vtkMultiBlockDataSet"):
        out = []
        for i in range(data.GetNumberOfBlocks()):
            b = data.GetBlock(i)
            if b is not None:
                out += blocks(b)
        return out
    return [data]


def volume_of(data):
    """The 3-D cells' grid of a reader or AdaptToShocks output (block
    internalMesh, or the first leaf with 3-D cells)."""
    leaves = blocks(data)
    for leaf in leaves:
        if leaf.GetNumberOfCells() and leaf.GetCell(0).GetCellDimension() == 3:
            return leaf
    return None


def vtk_points(grid):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    return vtk_to_numpy(grid.GetPoints().GetData())


FACES = {10: [(0, 1, 2), (0, 1, 3), (1, 2, 3), (0, 2, 3)],
         13: [(0, 1, 2), (3, 4, 5), (0, 1, 4, 3), (1, 2, 5, 4), (2, 0, 3, 5)],
         14: [(0, 1, 2, 3), (0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)],
         12: [(0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]}


def step_scale(grid):
    """(the smallest step length 2V / sum of face areas over the 3-D cells,
    one-cell-deep): the length an explicit solver's Courant number divides
    by (OpenFOAM: Co = 0.5 dt sum |phi_f| / V), so the stable deltaT scales
    with it. On a one-cell-deep mesh the front and back faces (normal to the
    axis on which the points take two values) carry no flux and are left
    out. V: pyramids from the cell's centroid to its faces."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    P = vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64)
    depth = [k for k in range(3) if len(np.unique(P[:, k])) == 2]
    axis = depth[0] if depth else None
    types = vtk_to_numpy(grid.GetCellTypesArray())
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray())
    offsets = vtk_to_numpy(grid.GetCells().GetOffsetsArray())
    best = np.inf
    for t, faces in FACES.items():
        idx = np.nonzero(types == t)[0]
        if len(idx) == 0:
            continue
        n = len({k for f in faces for k in f})
        for chunk in range(0, len(idx), 200000):  # bounded memory on large meshes
            c = idx[chunk:chunk + 200000]
            X = P[conn[offsets[c][:, None] + np.arange(n)[None, :]]]
            centre = X.mean(axis=1)
            V, A = np.zeros(len(c)), np.zeros(len(c))
            for f in faces:
                Y = X[:, list(f)]
                a = 0.5 * sum(np.cross(Y[:, i], Y[:, (i + 1) % len(f)]) for i in range(len(f)))
                V += np.abs(np.einsum("ij,ij->i", a, Y.mean(axis=1) - centre)) / 3.0
                area = np.linalg.norm(a, axis=1)
                if axis is not None:
                    area = np.where(np.abs(a[:, axis]) > (1 - 1e-9) * area, 0.0, area)
                A += area
            ok = A > 0
            if np.any(ok):
                best = min(best, float((2.0 * V[ok] / A[ok]).min()))
    return best, axis is not None


def cell_types(grid):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    t = vtk_to_numpy(grid.GetCellTypesArray())
    return {TYPE_NAMES.get(int(k), str(k)): int((t == k).sum()) for k in np.unique(t)}


def field(data, name):
    a = data.GetFieldData().GetAbstractArray(name)
    if a is None:
        return None
    if a.IsA("vtkStringArray"):
        return [a.GetValue(i) for i in range(a.GetNumberOfValues())]
    return [a.GetTuple(i)[c] for i in range(a.GetNumberOfTuples()) for c in range(a.GetNumberOfComponents())]


def angle_histogram(grid):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    region = grid.GetCellData().GetArray("Region")
    angle = grid.GetCellData().GetArray("MinDihedralAngle")
    if region is None or angle is None:
        return None
    new = vtk_to_numpy(angle)[vtk_to_numpy(region) == 1]
    edges = [0, 10, 20, 30, 40, 50, 60, 90]
    counts, _ = np.histogram(new, bins=edges)
    return edges, counts, float(new.min()) if len(new) else float("nan")


def split_surfaces(polydata):
    """[(SurfaceId, vtkPolyData)] of AdaptToShocks' output port 1."""
    from vtkmodules.vtkFiltersCore import vtkThreshold
    from vtkmodules.vtkFiltersGeometry import vtkGeometryFilter
    from vtkmodules.util.numpy_support import vtk_to_numpy
    ids = polydata.GetCellData().GetArray("SurfaceId")
    if ids is None or polydata.GetNumberOfCells() == 0:
        return []
    out = []
    for sid in np.unique(vtk_to_numpy(ids)):
        t = vtkThreshold()
        t.SetInputData(polydata)
        t.SetInputArrayToProcess(0, 0, 0, 1, "SurfaceId")
        t.SetLowerThreshold(sid - 0.5)
        t.SetUpperThreshold(sid + 0.5)
        g = vtkGeometryFilter()
        g.SetInputConnection(t.GetOutputPort())
        g.Update()
        out.append((int(sid), g.GetOutput()))
    return out


def shock_stations(surfaces, h, depth_axis):
    """Per fitted surface: (id, points, normals, half length) of the lines the
    shock is measured on: up to 24 points spread over the surface, at least a
    line's half length (8 h, h the first cycle's input size at the surface)
    from its border (in the cross-section of a one-cell-deep case, at
    mid-depth). A surface narrower than that (the quarter cone's shock is
    bounded by its symmetry planes: no point of it was 8 h from both) takes
    its stations at half the margin, and so on down to h."""
    length = 8.0 * h
    out = []
    for sid, surf in surfaces:
        margin = length
        P, N = shock_measure.surface_stations(surf, count=24, margin=margin, depth_axis=depth_axis)
        while len(P) == 0 and margin > h:
            margin *= 0.5
            P, N = shock_measure.surface_stations(surf, count=24, margin=margin, depth_axis=depth_axis)
        out.append((sid, P, N, length))
    return out


def measure_shock(grid, stations):
    """shock_measure's summary per surface on `grid`'s point array p."""
    return [(sid, shock_measure.summary(shock_measure.measure(grid, P, N, half_length=L, clip=True)) if len(P) else
             dict(lines=0, valid=0)) for sid, P, N, L in stations]


def shock_rows(before, after, templates, h):
    """The report's table of the shock along each fitted surface."""
    rows = ["", "the shock along lines normal to each fitted surface (`shock_measure.py`: p's 10-90 %% rise; "
            "position = mean offset of its midpoint from the surface; h = %.3g, the input's size at the surface):"
            % h, "",
            "| surface | | lines | 10-90 % thickness | thickness / h | position |", "|---|---|---:|---:|---:|---:|"]
    for label, result in (("before", before), ("after", after)):
        if result is None:
            continue
        for sid, r in result:
            name = templates[sid] if sid < len(templates) else "?"
            if r["valid"] == 0:
                rows.append("| %d (%s) | %s | 0 of %d | - | - | - |" % (sid, name, label, r["lines"]))
            else:
                rows.append("| %d (%s) | %s | %d of %d | %.3g | %.2f | %+.2g |" % (
                    sid, name, label, r["valid"], r["lines"], r["thickness_median"], r["thickness_median"] / h,
                    r["offset_mean"]))
    return rows


def solver_failure(name, case, rc):
    """The message for a step of the solve that failed: where (the last time
    its log reached) and, for a floating-point exception, the likely cause:
    a Courant number over 1 (the time step), else unlimited gradients.
    rhoCentralFoam's Minmod/vanLeer limiters build their slope ratio from the
    gradient; on tetrahedra at a strong shock the unlimited one overshoots
    and a cell's T goes negative (the sphereMa3 validation case: a plain Gmsh
    mesh 1.2x finer than the source, and the adapted mesh, fail so with Gauss
    linear and run with cellLimited Gauss linear 1)."""
    log = os.path.join(case, "log." + name)
    text = open(log, errors="replace").read() if os.path.isfile(log) else ""
    times = re.findall(r"^Time = (\S+)", text, re.M)
    msg = "%s failed on %s (exit %d%s; see %s)" % (
        name, case, rc, ", after t = %s" % times[-1] if times else "", log)
    if "sigFpe::sigHandler" not in text:
        return msg
    msg += ": a floating-point exception"
    courant = [float(c) for c in re.findall(r"Courant Numbers? = \S+ (\S+)", text)]
    if courant and max(courant) > 1.0:
        return msg + (". The Courant number reached %.3g (over 1: the time step is too large for this mesh; "
                      "lower maxCo or deltaT in the config's controlDict)" % max(courant))
    schemes_path = os.path.join(case, "system", "fvSchemes")
    block = re.search(r"gradSchemes\s*\{([^}]*)\}", open(schemes_path).read()) \
        if os.path.isfile(schemes_path) else None
    grad = dict_entry(block.group(1), "default") if block else None
    if grad is not None and "limited" not in grad.lower():
        if courant:
            msg += ", the Courant number at most %.3g" % max(courant)
        msg += (". The case's gradients are unlimited (gradSchemes default %s): on tetrahedra at a strong shock "
                "the limiters' slope ratio then overshoots until T < 0; 'cellLimited Gauss linear 1' is the robust "
                "choice (set it in the source case's system/fvSchemes)" % grad)
    return msg


def gas_of(case):
    """(gamma, R) of a case's constant/thermophysicalProperties (hConst,
    perfectGas), or None."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Data"))
    import foam_case
    try:
        return tuple(foam_case.gas_properties(case)[:2])
    except (RuntimeError, OSError, ValueError, TypeError, AttributeError):
        return None


def mach_range(grid, gas):
    """(smallest, largest) Mach number of a solution, the pictures' colour scale."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    pd = grid.GetPointData()
    U, T = (vtk_to_numpy(pd.GetArray(n)) for n in ("U", "T"))
    m = np.linalg.norm(U, axis=1) / np.sqrt(gas[0] * gas[1] * T)
    return float(m.min()), float(m.max())


_display = []  # (Xvfb process, ":N") once started


def x_display():
    """$DISPLAY, or a private Xvfb on the first free display (-displayfd:
    it names the display once it accepts connections) that does not reset
    (-noreset). Returns (":N", None) or (None, why there is none)."""
    import atexit
    import select
    import shutil
    import signal
    if os.environ.get("DISPLAY"):
        return os.environ["DISPLAY"], None
    if _display:
        return _display[0][1], None
    xvfb = shutil.which("Xvfb")
    if xvfb is None:
        return None, "no X display and no Xvfb (apt-get install xvfb, or run under an X server)"
    rfd, wfd = os.pipe()
    # -noreset: Xvfb otherwise resets when its last client leaves and drops
    # one that connected meanwhile ("bad X server connection" in VTK)
    proc = subprocess.Popen([xvfb, "-displayfd", str(wfd), "-screen", "0", "1600x1200x24", "-nolisten", "tcp",
                             "-noreset"],
                            pass_fds=(wfd,), stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)
    os.close(wfd)
    text, end = b"", time.monotonic() + 20
    while not text.endswith(b"\n") and time.monotonic() < end:
        if select.select([rfd], [], [], 0.5)[0]:
            chunk = os.read(rfd, 64)
            if not chunk:
                break
            text += chunk
    os.close(rfd)
    if not text.strip().isdigit():
        os.killpg(proc.pid, signal.SIGKILL)
        return None, "Xvfb did not start (it printed %r)" % text
    atexit.register(lambda: os.killpg(proc.pid, signal.SIGKILL))
    _display.append((proc, ":" + text.decode().strip()))
    return _display[0][1], None


def pictures(jobs, surfaces_vtp, mach, gas):
    """shock_pictures.py for each (label, grid, png, title) of `jobs`: the
    picture's cut of the grid (a solution this script holds) made here
    (shock_pictures.write_cut: its plane, Mach and the cut, the child's own
    code) and written to a temporary .vtp of the cut alone (1.4 MB; on 1e6
    cells the stage took 14 s when the children read the whole solution, a
    61 MB .vtu with U and T, and cut it, 9 s this way), one
    child pvpython per picture, the children run side by side (on a private
    Xvfb without an X display; a pvbatch child of pvbatch could not open its
    window). Returns [(label, png, None or why there is no picture)]."""
    import shutil
    import shock_pictures
    if mach is None or gas is None:
        why = "no Mach number for the colour scale (the gas of constant/thermophysicalProperties, or U and T)"
        return [(label, png, why) for label, _, png, _ in jobs]
    display, why = x_display()
    if display is None:
        return [(label, png, why) for label, _, png, _ in jobs]
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "OPAL_", "PMI_", "HYDRA_"))}
    env["DISPLAY"] = display
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "shock_pictures.py")
    running = []
    for label, grid, png, title in jobs:
        cut = png[:-4] + ".tmp.vtp"
        try:
            shock_pictures.write_cut(grid, surfaces_vtp, gas, cut)
        except Exception as e:  # noqa: BLE001 (no picture, as when the child made the cut and failed)
            running.append((label, png, None, None, None, "the cut for shock_pictures.py failed: %s" % e))
            continue
        cmd = [shutil.which("pvpython") or "pvpython", script, cut, "0", surfaces_vtp, png, "--title", title,
               "--mach-range", "%.6g" % mach[0], "%.6g" % mach[1]]
        proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        running.append((label, png, cut, cmd, proc, None))
    out = []
    for label, png, cut, cmd, proc, why in running:
        if proc is None:
            out.append((label, png, why))
            continue
        text, _ = proc.communicate()
        try:
            if proc.returncode == 0 and os.path.isfile(png):
                why = None
            elif "bad X server connection" in text:
                why = _run_picture(cmd, png, env)  # again, one at a time
            else:
                why = _picture_failure(proc.returncode, text, display)
        finally:
            os.remove(cut)
        out.append((label, png, why))
    return out


def _picture_failure(code, text, display):
    lines = [re.sub(r"\x1b\[[0-9;]*m", "", l) for l in text.splitlines()]
    said = [l for l in lines if "ERR|" in l or "Error" in l or "shock_pictures.py:" in l] or lines[-1:]
    return "shock_pictures.py failed (exit %d, DISPLAY %s): %s" % (code, display, " / ".join(said[:3]))


def _run_picture(cmd, png, env):
    # An X server started without -noreset (a $DISPLAY given by the user)
    # drops a client that connects while it resets after its last client
    # left ("bad X server connection", 1 in 4 to 6 tries here): try again
    for attempt in range(5):
        time.sleep(1.0)
        r = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if r.returncode == 0 and os.path.isfile(png):
            return None
        if "bad X server connection" not in r.stdout:
            break
    return _picture_failure(r.returncode, r.stdout, env["DISPLAY"])


def picture_rows(pictures):
    rows = []
    for label, png, why in pictures:
        rows.append("%s: %s" % (label, "![%s](%s)" % (label, os.path.basename(png)) if why is None else
                                "no picture (%s)" % why))
    return rows + [""]


class Stages:
    """Wall-clock seconds per named stage of a cycle, in first-use order:
    `with stages("read"): ...` adds the block's time to "read"."""

    def __init__(self):
        self.seconds = {}

    def __call__(self, name):
        import contextlib

        @contextlib.contextmanager
        def timed():
            t = time.perf_counter()
            try:
                yield
            finally:
                self.seconds[name] = self.seconds.get(name, 0.0) + time.perf_counter() - t
        return timed()

    def row(self):
        return "seconds per stage: " + ", ".join("%s %.1f" % kv for kv in self.seconds.items()) + \
            " (%.1f in all)" % sum(self.seconds.values())


def read_solution(case, time_name):
    """The 3-D cells (with point data) of an OpenFOAM case at a time."""
    marker = os.path.join(case, "adapt_case.foam")
    reader = OpenFOAMReader(FileName=marker)
    reader.MeshRegions = ["internalMesh"]
    reader.CellArrays = reader.CellArrays.Available
    reader.UpdatePipeline(float(time_name))
    grid = volume_of(servermanager.Fetch(reader))
    Delete(reader)
    return grid


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("source")
    ap.add_argument("target")
    ap.add_argument("--cycles", type=int, default=1)
    ap.add_argument("--solve", action="store_true")
    ap.add_argument("--np", type=int, default=1)
    ap.add_argument("--config")
    ap.add_argument("--plugin")
    args = ap.parse_args()
    source, target = os.path.abspath(args.source), os.path.abspath(args.target)
    if args.cycles < 1:
        fail("--cycles is %d; it must be at least 1" % args.cycles)
    if args.np < 1:
        fail("--np is %d; it must be at least 1" % args.np)
    if args.cycles > 1 and not args.solve:
        fail("--cycles %d needs --solve: cycle 2 adapts the solution of cycle 1" % args.cycles)
    if not os.path.isfile(os.path.join(source, "system", "controlDict")) or \
            not os.path.isfile(os.path.join(source, "constant", "polyMesh", "boundary")):
        fail("%s is not an OpenFOAM case (system/controlDict or constant/polyMesh/boundary missing)" % source)
    if latest_time(source) is None:
        fail("%s has no time directory with a solution" % source)
    if os.path.exists(target) and os.listdir(target):
        fail("%s exists and is not empty; give a new directory" % target)
    config = {}
    if args.config:
        try:
            with open(args.config) as f:
                config = json.load(f)
        except (OSError, ValueError) as e:
            fail("cannot read the config %s: %s" % (args.config, e))
        unknown = set(config) - {"AdaptToShocks", "controlDict"}
        if not isinstance(config, dict) or unknown:
            fail("the config must be a JSON object with the keys AdaptToShocks and controlDict (found %s)"
                 % sorted(unknown))
    plugin = args.plugin or os.environ.get("AR_PLUGIN") or os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "..", "build", "lib", "paraview-5.11", "plugins",
        "AdaptiveRedistribution", "AdaptiveRedistribution.so")
    if not os.path.exists(plugin):
        fail("the plugin %s does not exist (build it, or give --plugin)" % plugin)
    LoadPlugin(plugin, remote=False, ns=globals())
    AdaptToShocks = globals()["AdaptToShocks"]
    os.makedirs(target, exist_ok=True)
    report = ["# adapt_case.py report", "",
              "source `%s`, %d cycle(s), %s" % (source, args.cycles,
                                                 "solved on %d rank(s)" % args.np if args.solve else "not solved"), ""]

    def write_report():
        with open(os.path.join(target, "report.md"), "w") as f:
            f.write("\n".join(report) + "\n")

    current = source
    h_first = None
    for k in range(1, args.cycles + 1):
        case = os.path.join(target, "cycle%d" % k)
        time_name = latest_time(current)
        report += ["## Cycle %d" % k, "", "adapted `%s` at time %s" % (current, time_name), ""]
        stages = Stages()
        with stages("read"):
            reader = OpenFOAMReader(FileName=os.path.join(current, "adapt_case.foam"))
            reader.MeshRegions = ["internalMesh"] + [r for r in reader.MeshRegions.Available
                                                     if r.startswith("patch/")]
            reader.CellArrays = reader.CellArrays.Available
            reader.UpdatePipeline(float(time_name))
            before = volume_of(servermanager.Fetch(reader))
        if before is None:
            report.append("**failed**: the OpenFOAM reader found no 3-D cells")
            write_report()
            fail("the OpenFOAM reader found no 3-D cells in %s" % current)
        adapt = AdaptToShocks(Input=reader)
        props = config.get("AdaptToShocks", {})
        if k > 1 and "SurfaceSizeFactor" not in props and "SurfaceEdgeLength" not in props:
            # Keep cycle 1's size at the shock and move it onto the sharper
            # shock: 0.2 again would shrink the cells (and the explicit
            # solver's time step) five-fold per cycle.
            adapt.SurfaceSizeFactor = KEEP_SIZE_FACTOR
            report += ["cycle %d keeps the size at the shock (SurfaceSizeFactor %g of the input's own, refined, "
                       "size there) and re-places the refined band on the re-fitted shock" % (k, KEEP_SIZE_FACTOR), ""]
        for prop, value in props.items():
            try:
                setattr(adapt, prop, value)
            except AttributeError:
                fail("AdaptToShocks has no property %s (config)" % prop)
        t = time.time()
        with stages("AdaptToShocks"):
            adapt.UpdatePipeline(float(time_name))
        seconds = time.time() - t
        with stages("fetch"):
            out = servermanager.Fetch(adapt)
            after = volume_of(out)
        if after is None or after.GetCellData().GetArray("Region") is None:
            report.append("**failed**: AdaptToShocks did not adapt the mesh (see its error above)")
            write_report()
            fail("AdaptToShocks did not adapt %s (its message is above)" % current)
        with stages("shock measurement"):
            surfaces = split_surfaces(servermanager.Fetch(adapt, None, None, 1))
            h_in = (field(out, "InputSizeAtSurface") or field(after, "InputSizeAtSurface") or [float("nan")])[0]
            P_in = vtk_points(before)
            depth = [a for a in range(3) if len(np.unique(P_in[:, a])) == 2]
            # lines 8 of the FIRST input's cells either side: later inputs are
            # finer at the shock than the shock they carry is thin
            if k == 1:
                h_first = h_in
            stations = shock_stations(surfaces, h_first, depth[0] if depth else None)
            shock_before = measure_shock(before, stations)
        from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter
        surfaces_vtp = os.path.join(target, "cycle%d_surfaces.vtp" % k)
        with stages("report"):
            w = vtkXMLPolyDataWriter()
            w.SetInputData(servermanager.Fetch(adapt, None, None, 1))
            w.SetFileName(surfaces_vtp)
            w.SetDataModeToBinary()
            w.Write()
            gas = gas_of(current)
            try:
                mach = mach_range(before, gas) if gas else None
            except (ValueError, TypeError, AttributeError):
                mach = None  # the pictures say why there are none
        with stages("write"):
            SaveData(os.path.join(case, "cycle%d.foam" % k), proxy=adapt, SourceCase=current, SourceTime=time_name,
                     StartTime="0")
        if not os.path.isfile(os.path.join(case, "constant", "polyMesh", "owner")):
            report.append("**failed**: the case writer wrote nothing (its error is above)")
            write_report()
            fail("the OpenFOAM case writer failed on %s (its message is above)" % case)
        # controlDict: start at 0 and a first step for the new smallest cell.
        cd_path = os.path.join(case, "system", "controlDict")
        with open(cd_path) as f:
            cd = f.read()
        with stages("report"):
            h0, two_d = step_scale(before)
            h1, _ = step_scale(after)
        dt0 = float(dict_entry(cd, "deltaT") or "nan")
        dt1 = dt0 * min(1.0, h1 / h0)
        cd = set_entry(set_entry(set_entry(cd, "startFrom", "startTime"), "startTime", "0"), "deltaT", "%.6g" % dt1)
        for key, value in config.get("controlDict", {}).items():
            cd = set_entry(cd, key, value)
        with open(cd_path, "w") as f:
            f.write(cd)
        fd = lambda n: field(out, n) or field(after, n)
        templates = fd("SurfaceTemplates") or []
        report += ["| | before | after |", "|---|---:|---:|",
                   "| nodes | %d | %d |" % (before.GetNumberOfPoints(), after.GetNumberOfPoints()),
                   "| cells | %d | %d |" % (before.GetNumberOfCells(), after.GetNumberOfCells())]
        with stages("report"):
            types0, types1 = cell_types(before), cell_types(after)
            hist = angle_histogram(after)
        for name in sorted(set(types0) | set(types1)):
            report.append("| %s | %d | %d |" % (name, types0.get(name, 0), types1.get(name, 0)))
        report += ["| smallest step length 2V/sum(A)%s | %.3g | %.3g |"
                   % (" (front and back left out)" if two_d else "", h0, h1),
                   "| deltaT | %.3g | %.3g |" % (dt0, dt1), ""]
        ratio_new, ratio_layers = (fd("StepLengthRatioNew") or [0.0])[0], (fd("StepLengthRatioLayerCells") or [0.0])[0]
        if ratio_new > 0 or ratio_layers > 0:
            parts = []
            if ratio_new > 0:
                parts.append("the new cells' %.2f of the regular cell's at S's edge (StepLengthRatioNew)" % ratio_new)
            if ratio_layers > 0:
                parts.append("the layer cells' %.2f of a prism one layer high (StepLengthRatioLayerCells)"
                             % ratio_layers)
            report.append("Smallest step length 2V/sum(A) against the requested size's: %s. An explicit solver's "
                          "time step follows the mesh's smallest." % "; ".join(parts))
            report.append("")
        report.append("AdaptToShocks in %.1f s: %d surface(s) (%s); new cells at the shock %.2f of the input's size "
                      "(SurfaceSizeRatio)" % (seconds, len(templates), ", ".join(templates),
                                              (fd("SurfaceSizeRatio") or [float("nan")])[0]))
        if (fd("RemovedLayerCells") or [0])[0] > 0:
            report.append("; the input's layers re-placed: %d of its prisms and pyramids remeshed (RemovedLayerCells)"
                          % fd("RemovedLayerCells")[0])
        if hist:
            edges, counts, worst = hist
            report += ["", "smallest dihedral angle of the new cells (degrees; min %.1f):" % worst, "",
                       "| " + " | ".join("%d-%d" % (a, b) for a, b in zip(edges[:-1], edges[1:])) + " |",
                       "|" + "---:|" * len(counts), "| " + " | ".join(str(int(c)) for c in counts) + " |"]
        report += shock_rows(shock_before, None, templates, h_in)
        report.append("")
        def job(label, grid, name, title):
            return label, grid, os.path.join(target, "cycle%d_%s.png" % (k, name)), title

        with stages("pictures"):
            jobs = [job("cycle %d, before (the input's solution)" % k, before, "before",
                        "cycle %d: the input's solution, its mesh" % k)]
            if not args.solve:
                jobs.append(job("cycle %d, the adapted mesh with the interpolated start field" % k, after,
                                "start", "cycle %d: adapted mesh, start field" % k))
            shown = pictures(jobs, surfaces_vtp, mach, gas)
        report += picture_rows(shown)
        report += [stages.row(), ""]
        write_report()
        for p in (reader, adapt):
            Delete(p)
        if args.solve:
            app = dict_entry(cd, "application")
            if not app:
                fail("%s has no application entry" % cd_path)
            steps = [(app, app)]
            if args.np > 1:
                # Debian's OpenFOAM has no scotch (a dummy library): "simple"
                # cuts the mesh into K slabs along its longest side.
                P = np.array(after.GetPoints().GetBounds()).reshape(3, 2)
                n = ["1", "1", "1"]
                n[int(np.argmax(P[:, 1] - P[:, 0]))] = str(args.np)
                with open(os.path.join(case, "system", "decomposeParDict"), "w") as f:
                    f.write("FoamFile { version 2.0; format ascii; class dictionary; object decomposeParDict; }\n"
                            "numberOfSubdomains %d;\nmethod simple;\nsimpleCoeffs { n (%s); delta 0.001; }\n"
                            % (args.np, " ".join(n)))
                steps = [("decomposePar -force", "decomposePar"),
                         ("mpirun --allow-run-as-root -np %d %s -parallel" % (args.np, app), app),
                         ("reconstructPar -latestTime", "reconstructPar")]
            total = 0.0
            for cmd, name in steps:
                rc, secs = foam(cmd, case, os.path.join(case, "log." + name))
                total += secs
                report.append("%s: exit %d in %.1f s (log `cycle%d/log.%s`)" % (name, rc, secs, k, name))
                if rc != 0:
                    why = solver_failure(name, case, rc)
                    report += ["", "**failed**: " + why, ""]
                    write_report()
                    fail(why)
            report += ["", "solved in %.1f s in all, latest time %s" % (total, latest_time(case))]
            solved = read_solution(case, latest_time(case))
            report += shock_rows(None, measure_shock(solved, stations), templates, h_in) + [""]
            report += picture_rows(pictures([job("cycle %d, after (solved on the adapted mesh)" % k, solved, "after",
                                                 "cycle %d: solved on the adapted mesh" % k)], surfaces_vtp, mach, gas))
            write_report()
            current = case
    write_report()
    print("adapt_case.py: %d cycle(s) in %s; report %s" % (args.cycles, target, os.path.join(target, "report.md")))


main()
