"""MPI test driver (run with pvpython): MedialAxisDelaunay under `mpiexec -np 2
pvbatch` equals the serial run.

    pvpython RunMPIMedialAxis.py <pvbatch> <mpiexec>

Splits Data/oblique_shock_unstructured.vtu into a 2-piece .pvtu, runs
MPIMedialAxisPipeline.py serially on the whole mesh and on 2 ranks on the
pieces, and compares: the isosurface pieces and the domain boundary are
gathered to rank 0, which must produce the serial sheet (same triangles at
the same places, same Radius, same field data); rank 1 holds nothing.
"""
import os
import sys

import numpy as np

import artest
from artest import check

pvbatch, mpiexec = sys.argv[1], sys.argv[2]
pvpython = os.path.join(os.path.dirname(pvbatch), "pvpython")
here = os.path.dirname(os.path.abspath(__file__))
script = os.path.join(here, "MPIMedialAxisPipeline.py")

out = artest.OUTPUT_DIR
pieces = os.path.join(out, "mpima_pieces.pvtu")
whole = os.path.join(out, "mpima_whole.vtu")
serial = os.path.join(out, "mpima_serial")
parallel = os.path.join(out, "mpima_np2")
rc, _ = artest.run([pvpython, os.path.join(here, "SplitIntoPieces.py"), artest.data("oblique_shock_unstructured.vtu"), pieces, whole])
check(rc == 0 and os.path.exists(pieces), "split into a 2-piece .pvtu")
rc, _ = artest.run([pvbatch, script, whole, serial])
check(rc == 0 and os.path.exists(serial + ".vtp"), "serial pvbatch run")
rc, text = artest.run([mpiexec, "--allow-run-as-root", "--oversubscribe", "-np", "2", pvbatch, "--symmetric", script,
                       pieces, parallel])
check(rc == 0 and os.path.exists(parallel + ".vtp"), "mpiexec -np 2 pvbatch run")
check("rank 1 of 2: sheet 0 cells" in text, "rank 1's output is empty")


def keyed(d):
    """Points (rounded) with their Radius, sorted."""
    P = np.round(np.asarray(d.Points), 9)
    R = np.asarray(d.PointData["Radius"])
    order = np.lexsort((P[:, 2], P[:, 1], P[:, 0]))
    return P[order], R[order]


if os.path.exists(serial + ".vtp") and os.path.exists(parallel + ".vtp"):
    ref, par = artest.load(serial + ".vtp"), artest.load(parallel + ".vtp")
    check(ref.GetNumberOfCells() > 100, "serial sheet: %d triangles" % ref.GetNumberOfCells())
    check(par.GetNumberOfCells() == ref.GetNumberOfCells() and par.GetNumberOfPoints() == ref.GetNumberOfPoints(),
          "2 ranks: %d triangles, %d points (serial %d, %d)" % (par.GetNumberOfCells(), par.GetNumberOfPoints(),
                                                               ref.GetNumberOfCells(), ref.GetNumberOfPoints()))
    if par.GetNumberOfPoints() == ref.GetNumberOfPoints():
        (Pa, Ra), (Pb, Rb) = keyed(par), keyed(ref)
        check(np.abs(Pa - Pb).max() < 1e-8 and np.abs(Ra - Rb).max() < 1e-8,
              "2 ranks: the same points and Radius (max diff %.1e, %.1e)" % (np.abs(Pa - Pb).max(), np.abs(Ra - Rb).max()))
    for name in ("SheetAreas", "DelaunayTetrahedra", "InteriorTetrahedra", "VoronoiFacets"):
        a, b = artest.field(par, name), artest.field(ref, name)
        check(len(a) == len(b) and np.allclose(a, b, rtol=1e-9), "2 ranks: field %s equal to the serial run (%s)" % (name, a))

artest.finish()
