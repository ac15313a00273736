"""MPI test driver (run with pvpython): QuadricFit under `mpiexec -np 2
pvbatch` equals the serial run.

    pvpython RunMPIQuadricFit.py <pvbatch> <mpiexec>

Splits Data/oblique_shock_unstructured.vtu (the unit cube) into a 2-piece
.pvtu (SplitIntoPieces.py), runs MPIQuadricFitPipeline.py serially on the
whole mesh and on 2 ranks on the pieces (with and without ghost cells), the
medial points dealt out over the ranks, and compares every surface with the
serial one: same triangles at the same places, same field data; rank 0 holds
the surface, rank 1 nothing.
"""
import os
import sys

import numpy as np

import artest
from artest import check

pvbatch, mpiexec = sys.argv[1], sys.argv[2]
pvpython = os.path.join(os.path.dirname(pvbatch), "pvpython")
here = os.path.dirname(os.path.abspath(__file__))
script = os.path.join(here, "MPIQuadricFitPipeline.py")
load = artest.load


def run(cmd):
    return artest.run(cmd)


def corners(d):
    """Each triangle's corners, sorted (so that their order in the cell does not matter): (n, 9)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    x = np.asarray(d.Points)
    conn = vtk_to_numpy(d.VTKObject.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    c = x[conn]
    key = np.round(c, 6)
    order = np.lexsort((key[:, :, 2], key[:, :, 1], key[:, :, 0]), axis=1)
    return np.take_along_axis(c, order[:, :, None], axis=1).reshape(-1, 9)


def triangle_mismatch(a, b):
    """Largest distance from a triangle of `a` to the nearest triangle of `b`
    (as 9-vectors of sorted corners)."""
    worst = 0.0
    for start in range(0, len(a), 500):
        chunk = a[start:start + 500]
        d = np.sqrt(((chunk[:, None, :] - b[None, :, :]) ** 2).sum(axis=2)).min(axis=1)
        worst = max(worst, d.max())
    return worst


out = artest.OUTPUT_DIR
pieces = os.path.join(out, "mpiqf_pieces.pvtu")
whole = os.path.join(out, "mpiqf_whole.vtu")
serial = os.path.join(out, "mpiqf_serial")
parallel = os.path.join(out, "mpiqf_np2")
rc, _ = run([pvpython, os.path.join(here, "SplitIntoPieces.py"), artest.data("oblique_shock_unstructured.vtu"), pieces, whole])
check(rc == 0 and os.path.exists(pieces), "split into a 2-piece .pvtu")
rc, _ = run([pvbatch, script, whole, serial])
check(rc == 0, "serial pvbatch run")
rc, text = run([mpiexec, "--allow-run-as-root", "--oversubscribe", "-np", "2", pvbatch, "--symmetric", script,
                pieces, parallel])
check(rc == 0, "mpiexec -np 2 pvbatch run")

for template in ("Plane", "Cone"):
    ref_path = "%s.whole.%s.vtp" % (serial, template)
    if not os.path.exists(ref_path):
        check(False, "%s: serial output written" % template)
        continue
    ref = load(ref_path)
    check(ref.GetNumberOfCells() > 100, "%s: serial surface (%d triangles)" % (template, ref.GetNumberOfCells()))
    for label in ("pieces", "ghosts"):
        check("rank 1 of 2: %s %s 0 cells" % (label, template) in text,
              "%s, %s: rank 1's output is empty" % (template, label))
        path = "%s.%s.%s.vtp" % (parallel, label, template)
        if not os.path.exists(path):
            check(False, "%s, %s: rank 0 wrote its surface" % (template, label))
            continue
        par = load(path)
        same = par.GetNumberOfCells() == ref.GetNumberOfCells()
        check(same, "%s, %s: %d triangles (serial %d)" % (template, label, par.GetNumberOfCells(), ref.GetNumberOfCells()))
        if same:
            diff = max(triangle_mismatch(corners(par), corners(ref)), triangle_mismatch(corners(ref), corners(par)))
            check(diff < 1e-9, "%s, %s: the same triangles at the same places (max diff %.1e)" % (template, label, diff))
        for name in ["Coefficients", "RMSResidual", "NumberOfFitPoints"] + (["Normal"] if template == "Plane" else ["Apex", "HalfAngle"]):
            a, b = artest.field(par, name), artest.field(ref, name)
            check(len(a) == len(b) and np.allclose(a, b, rtol=1e-9, atol=1e-12),
                  "%s, %s: field %s equal to the serial run" % (template, label, name))

# The chain from the mesh (sensor -> clusters -> fit, reader as Domain).
ref_path, par_path = "%s.chain.Plane.vtp" % serial, "%s.chain.Plane.vtp" % parallel
if os.path.exists(ref_path) and os.path.exists(par_path):
    ref, par = load(ref_path), load(par_path)
    check(ref.GetNumberOfCells() > 100 and par.GetNumberOfCells() == ref.GetNumberOfCells(),
          "chain: %d triangles on 2 ranks (serial %d)" % (par.GetNumberOfCells(), ref.GetNumberOfCells()))
    a, b = artest.field(par, "Normal"), artest.field(ref, "Normal")
    check(np.allclose(abs(np.dot(a, b)), 1.0, atol=1e-9), "chain: the same plane as the serial run")
else:
    check(False, "chain: both runs wrote their surface")
check("rank 1 of 2: chain Plane 0 cells" in text, "chain: rank 1's output is empty")

artest.finish()
