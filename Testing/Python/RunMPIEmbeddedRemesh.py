"""MPI test driver (run with pvpython): EmbeddedRemesh (LocalCavity, then
FullDomain) under `mpiexec -np 2 pvbatch` equals the serial run.

    pvpython RunMPIEmbeddedRemesh.py <pvbatch> <mpiexec>

Splits Data/oblique_shock_unstructured.vtu into a 2-piece .pvtu, runs
MPIEmbeddedRemeshPipeline.py (the oblique shock with QuadricFit's plane)
serially on the whole mesh (where it also writes the plane) and on 2
ranks on the pieces with that plane, and compares the
union of the ranks' outputs with the serial output: total, new and kept
cells, embedded surface triangles and field data equal; the volume equal to
1e-9; every cell of positive volume; conforming; the boundary the input's,
face for face; every embedded triangle a face between two cells. The cavity
is refilled on rank 0: rank 1 keeps its far field and has no new cells.
FullDomain gathers the whole mesh to rank 0 (TetGen is serial): rank 1
ends with no cells. LocalCavity with prism layers (LayerType Prisms, 3 per
side): the union of the ranks' cells equals the serial run's cell for cell
(each cell fingerprinted by its type and its points' coordinates), the
field data too, and the far field stays on rank 1.
"""
import os
import sys

import numpy as np

import artest
from artest import check
from vtkmodules.util.numpy_support import vtk_to_numpy

pvbatch, mpiexec = sys.argv[1], sys.argv[2]
pvpython = os.path.join(os.path.dirname(pvbatch), "pvpython")
here = os.path.dirname(os.path.abspath(__file__))
script = os.path.join(here, "MPIEmbeddedRemeshPipeline.py")

FACES = ((1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1))


# The field data: every array of the serial run on both ranks, with the
# serial run's value (the Seconds* timings apart). Exact, except where MPI's
# sums run in another order than the serial run's (the mean of the new
# cells' angles: 1e-12 relative; the relative volume change, itself a
# round-off of about 1e-14: 1e-12 absolute).
ROUNDING = {"MeanDihedralAngleNew": ("relative", 1e-12), "RelativeVolumeChange": ("absolute", 1e-12)}


def compare_field_data(label, ref, par):
    names = sorted(n for n in ref.FieldData.keys() if not n.startswith("Seconds"))
    missing, differ = [], []
    for name in names:
        b = np.asarray(artest.field(ref, name), dtype=np.float64)
        for r, p in enumerate(par):
            if name not in p.FieldData.keys():
                missing.append("%s (rank %d)" % (name, r))
                continue
            a = np.asarray(artest.field(p, name), dtype=np.float64)
            kind, tol = ROUNDING.get(name, ("exact", 0.0))
            scale = np.abs(b).max() if kind == "relative" and b.size else 1.0
            if a.shape != b.shape or np.abs(a - b).max(initial=0.0) > tol * scale:
                differ.append("%s (rank %d: %s, serial %s)" % (name, r, a.tolist(), b.tolist()))
    check(len(names) >= 30 and not missing and not differ,
          "%s: all %d field-data arrays of the serial run on both ranks, equal to it (missing: %s; differ: %s)"
          % (label, len(names), missing, differ))


def compare(mode):
    out = artest.OUTPUT_DIR
    pieces = os.path.join(out, "mpier_pieces.pvtu")
    whole = os.path.join(out, "mpier_whole.vtu")
    serial = os.path.join(out, "mpier_serial_" + mode)
    parallel = os.path.join(out, "mpier_np2_" + mode)
    for f in [serial + ".0.vtu", parallel + ".0.vtu", parallel + ".1.vtu"]:
        if os.path.exists(f):
            os.remove(f)
    rc, _ = artest.run([pvpython, os.path.join(here, "SplitIntoPieces.py"), artest.data("oblique_shock_unstructured.vtu"), pieces, whole])
    check(rc == 0 and os.path.exists(pieces), "split into a 2-piece .pvtu")
    rc, _ = artest.run([pvbatch, script, whole, serial, "--mode=" + mode])
    check(rc == 0 and os.path.exists(serial + ".0.vtu"), "%s: serial pvbatch run" % mode)
    rc, text = artest.run([mpiexec, "--allow-run-as-root", "--oversubscribe", "-np", "2", pvbatch, "--symmetric", script,
                           pieces, parallel, serial + ".plane.vtp", "--mode=" + mode])
    check(rc == 0 and os.path.exists(parallel + ".1.vtu"), "%s: mpiexec -np 2 pvbatch run" % mode)
    check("ERROR" not in text and "passes through" not in text, "no error under MPI")

    def tets(ds):
        conn = vtk_to_numpy(ds.VTKObject.GetCells().GetConnectivityArray())
        return conn.reshape(-1, 4)

    def keys(P, tris):
        c = np.round(P[tris] * 1e9).astype(np.int64)
        order = np.lexsort((c[:, :, 2], c[:, :, 1], c[:, :, 0]), axis=1)
        return [tuple(r) for r in np.take_along_axis(c, order[:, :, None], axis=1).reshape(-1, 9)]

    def face_counts(parts):
        counts = {}
        for P, T in parts:
            for k in keys(P, np.concatenate([T[:, list(f)] for f in FACES])):
                counts[k] = counts.get(k, 0) + 1
        return counts

    def volumes(P, T):
        a, b, c, d = (P[T[:, i]] for i in range(4))
        return np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a)) / 6.0


    if os.path.exists(serial + ".0.vtu") and os.path.exists(parallel + ".1.vtu"):
        src = artest.load(whole)
        ref = artest.load(serial + ".0.vtu")
        refS = artest.load(serial + ".0.vtp")
        par = [artest.load("%s.%d.vtu" % (parallel, r)) for r in range(2)]
        parS = [artest.load("%s.%d.vtp" % (parallel, r)) for r in range(2)]

        def counts(ds):
            region = np.asarray(ds.CellData["Region"])
            return ds.GetNumberOfCells(), int((region == 1).sum()), int((region == 0).sum())

        n_ref, new_ref, kept_ref = counts(ref)
        per_rank = [counts(p) for p in par]
        n_par, new_par, kept_par = (sum(c[i] for c in per_rank) for i in range(3))
        check(new_ref > 0, "serial: %d cells, %d new, %d kept" % (n_ref, new_ref, kept_ref))
        check((n_par, new_par, kept_par) == (n_ref, new_ref, kept_ref),
              "2 ranks: %d cells, %d new, %d kept (serial %d, %d, %d); per rank %s"
              % (n_par, new_par, kept_par, n_ref, new_ref, kept_ref, per_rank))
        if mode == "LocalCavity":
            check(per_rank[1][1] == 0 and per_rank[1][2] > 0 and per_rank[0][1] == new_ref,
                  "the cavity is refilled on rank 0; rank 1 keeps its far field (%d cells)" % per_rank[1][0])
        else:
            check(per_rank[1][0] == 0 and per_rank[0][1] == new_ref and kept_ref == 0,
                  "FullDomain: the whole mesh is remeshed on rank 0; rank 1 ends empty")
        s_ref, s_par = refS.GetNumberOfCells(), sum(p.GetNumberOfCells() for p in parS)
        check(s_ref > 50 and s_par == s_ref, "embedded surface: %d triangles (serial %d)" % (s_par, s_ref))
        compare_field_data(mode, ref, par)
        P0, T0 = np.asarray(src.Points, dtype=np.float64), tets(src)
        parts = [(np.asarray(p.Points, dtype=np.float64), tets(p)) for p in par]
        vols = np.concatenate([volumes(P, T) for P, T in parts])
        check(vols.min() > 0, "every cell of the 2 ranks has a positive volume (min %.3e)" % vols.min())
        v_ref = volumes(np.asarray(ref.Points, dtype=np.float64), tets(ref)).sum()
        check(abs(vols.sum() / v_ref - 1) < 1e-9 and abs(vols.sum() / volumes(P0, T0).sum() - 1) < 1e-9,
              "volume equal to the serial run's and the input's (%.1e relative)" % (vols.sum() / v_ref - 1))
        c0, c1 = face_counts([(P0, T0)]), face_counts(parts)
        check(max(c1.values()) <= 2, "the union of the ranks' cells is conforming")
        check({k for k, n in c1.items() if n == 1} == {k for k, n in c0.items() if n == 1},
              "the union's boundary is the input's, face for face (%d faces)" % sum(1 for n in c0.values() if n == 1))
        S = vtk_to_numpy(parS[0].VTKObject.GetPolys().GetConnectivityArray()).reshape(-1, 3)
        on = [c1.get(k, 0) for k in keys(np.asarray(parS[0].Points, dtype=np.float64), S)]
        check(len(S) > 50 and all(n == 2 for n in on), "all %d embedded triangles are faces between two cells" % len(S))
        ref_cells = sorted(keys(np.asarray(ref.Points, dtype=np.float64), tets(ref)[:, :3]))
        par_cells = sorted(sum((keys(P, T[:, :3]) for P, T in parts), []))
        same = sum(1 for a, b in zip(ref_cells, par_cells) if a == b)
        artest.say("cells identical to the serial run's (3-corner fingerprint, sorted): %d of %d" % (same, len(ref_cells)))
        check(ref_cells == par_cells, "the 2-rank mesh is the serial mesh, cell for cell")
        check(all("p" in p.PointData.keys() for p in par), "the fields are carried (p)")
        # The fields equal the serial run's bit for bit: each point found by
        # its coordinates, each cell by its centre (rank 0 interpolates in
        # the gathered cavity as the serial run does in the input).
        def rounded(X):
            return [tuple(r) for r in np.round(X * 1e9).astype(np.int64)]

        Pref = np.asarray(ref.Points, dtype=np.float64)
        at_point = {k: i for i, k in enumerate(rounded(Pref))}
        at_centre = {k: i for i, k in enumerate(rounded(Pref[tets(ref)].mean(axis=1)))}
        for kind, where in (("PointData", lambda P, T: rounded(P)), ("CellData", lambda P, T: rounded(P[T].mean(axis=1)))):
            index = at_point if kind == "PointData" else at_centre
            names = list(getattr(ref, kind).keys())
            differ, compared = set(), 0
            for p, (P, T) in zip(par, parts):
                if p.GetNumberOfCells() == 0:
                    continue
                pairs = np.array([(i, index.get(k, -1)) for i, k in enumerate(where(P, T))])
                found = pairs[:, 1] >= 0
                compared += int(found.sum())
                if not found.all():
                    differ.add("(unmatched)")
                for name in names:
                    if name not in getattr(p, kind).keys():
                        differ.add(name)
                        continue
                    a, b = np.asarray(getattr(p, kind)[name]), np.asarray(getattr(ref, kind)[name])
                    if not np.array_equal(a[pairs[found, 0]], b[pairs[found, 1]]):
                        differ.add(name)
            check(compared > 0 and not differ, "%s: the 2 ranks' %s arrays %s equal the serial run's exactly "
                  "(%d tuples; differ: %s)" % (mode, kind, names, compared, sorted(differ)))


for mode in ("LocalCavity", "FullDomain"):
    compare(mode)


def fingerprints(ds):
    """Every cell as (type, its points' coordinates rounded to 1e-9, sorted)."""
    grid = ds.VTKObject
    P = np.round(np.asarray(ds.Points, dtype=np.float64) * 1e9).astype(np.int64)
    out = []
    for c in range(grid.GetNumberOfCells()):
        ids = grid.GetCell(c).GetPointIds()
        out.append((grid.GetCellType(c),) + tuple(sorted(tuple(P[ids.GetId(k)]) for k in range(ids.GetNumberOfIds()))))
    return out


def compare_layers():
    out = artest.OUTPUT_DIR
    pieces = os.path.join(out, "mpier_pieces.pvtu")
    whole = os.path.join(out, "mpier_whole.vtu")
    plane = os.path.join(out, "mpier_serial_LocalCavity.plane.vtp")
    serial = os.path.join(out, "mpier_serial_prisms")
    parallel = os.path.join(out, "mpier_np2_prisms")
    for f in [serial + ".0.vtu", parallel + ".0.vtu", parallel + ".1.vtu"]:
        if os.path.exists(f):
            os.remove(f)
    rc, _ = artest.run([pvbatch, script, whole, serial, plane, "--layers=Prisms"])
    check(rc == 0 and os.path.exists(serial + ".0.vtu"), "prisms: serial pvbatch run")
    rc, text = artest.run([mpiexec, "--allow-run-as-root", "--oversubscribe", "-np", "2", pvbatch, "--symmetric", script,
                           pieces, parallel, plane, "--layers=Prisms"])
    check(rc == 0 and os.path.exists(parallel + ".1.vtu"), "prisms: mpiexec -np 2 pvbatch run")
    check("ERROR" not in text and "passes through" not in text, "prisms: no error under MPI")
    if not (os.path.exists(serial + ".0.vtu") and os.path.exists(parallel + ".1.vtu")):
        return
    ref = artest.load(serial + ".0.vtu")
    par = [artest.load("%s.%d.vtu" % (parallel, r)) for r in range(2)]
    types = lambda ds: np.bincount([ds.VTKObject.GetCellType(c) for c in range(ds.GetNumberOfCells())], minlength=15)
    t_ref, t_par = types(ref), types(par[0]) + types(par[1])
    check(t_ref[13] > 0 and t_ref[14] > 0 and np.array_equal(t_ref, t_par),
          "prisms: cells per type equal (serial %d tetrahedra, %d prisms, %d pyramids; 2 ranks %d, %d, %d)"
          % (t_ref[10], t_ref[13], t_ref[14], t_par[10], t_par[13], t_par[14]))
    region1 = np.asarray(par[1].CellData["Region"])
    check(len(region1) > 0 and (region1 == 0).all(), "prisms: rank 1 keeps its far field (%d cells), no new cell" % len(region1))
    compare_field_data("prisms", ref, par)
    check(sorted(fingerprints(ref)) == sorted(fingerprints(par[0]) + fingerprints(par[1])),
          "prisms: the 2-rank mesh is the serial mesh, cell for cell (every type)")


compare_layers()
artest.finish()
