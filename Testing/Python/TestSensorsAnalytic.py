"""The sensors on the analytic planar oblique shock (Data/analytic_shock.py),
on a structured-then-tetrahedralized mesh and on a Gmsh mesh:
- W is in [1, 2], 1 far from the shock, highest at it;
- ShockCells lie within one cell of the exact Mn = 1 plane (parallel to the
  shock plane, at the exactly known offset d*), and a plane fitted to their
  centroids is within 1 degree of the exact shock plane;
- NormalMach crosses 1 where the exact Mn does;
- point and cell input give the same shock cells on the structured mesh.
"""
import numpy as np
from paraview.simple import *

import artest
from artest import check

artest.load_plugin(globals())

for mesh in ("oblique_shock_structured.vtu", "oblique_shock_unstructured.vtu"):
    reader = XMLUnstructuredGridReader(FileName=[artest.data(mesh)])
    src = artest.fetch(reader)
    n = artest.field(src, "ShockNormal")
    x0 = artest.field(src, "ShockOrigin")
    delta = artest.field(src, "SmearingWidth")[0]
    dstar = artest.field(src, "NormalMachUnityOffset")[0]
    centroids, longest = artest.cell_centroids(src)
    d = (centroids - x0) @ n  # signed distance of each cell centroid

    # ---- Weight function on the conserved variables (point data).
    wf = WeightFunction(Input=reader, Variables=["rho", "rhoU", "rhoE"], ComputePointWeight=1)
    out = artest.fetch(wf)
    W = np.asarray(out.CellData["WeightFunction"])
    check(W.min() >= 1.0 and W.max() <= 2.0, "%s: W in [1, 2] (%.6f .. %.6f)" % (mesh, W.min(), W.max()))
    far = np.abs(d) > 6 * delta
    check(far.sum() > 100 and W[far].max() < 1.01,
          "%s: W = 1 far from the shock (max %.5f over %d cells with |d| > 6 delta)" % (mesh, W[far].max(), far.sum()))
    top = np.argmax(W)
    check(abs(d[top]) <= 2 * longest[top],
          "%s: the highest W is at the shock (|d| = %.4f, cell size %.4f)" % (mesh, abs(d[top]), longest[top]))
    near = np.abs(d) < delta
    check(W[near].mean() > 1.3 and W[near].mean() > W[~near].mean() + 0.2,
          "%s: W near the shock %.3f vs elsewhere %.3f" % (mesh, W[near].mean(), W[~near].mean()))
    Wp = np.asarray(out.PointData["WeightFunction"])
    check(len(Wp) == out.GetNumberOfPoints() and Wp.min() >= 1.0 and Wp.max() <= 2.0,
          "%s: point twin of W present and in [1, 2]" % mesh)
    check("WeightFunction" not in src.CellData.keys(), "%s: input not modified" % mesh)

    # ---- Shock sensor on primitive variables.
    ss = ShockSensor(Input=reader, Velocity=["POINTS", "U"], Pressure=["POINTS", "p"],
                     Density=["POINTS", "rho"], Gamma=artest.field(src, "Gamma")[0])
    out = artest.fetch(ss)
    shock = np.asarray(out.CellData["ShockCells"]) == 1
    check(shock.sum() > 50, "%s: %d shock cells" % (mesh, shock.sum()))
    dist = np.abs(d[shock] - dstar)
    check(np.all(dist <= longest[shock]),
          "%s: every shock cell within one cell of the exact Mn = 1 plane (worst %.4f of its size)"
          % (mesh, (dist / longest[shock]).max()))
    normal, _ = artest.fit_plane(centroids[shock])
    angle = artest.angle_between_planes(normal, n)
    check(angle < 1.0, "%s: fitted shock plane within 1 degree of the exact one (%.3f deg)" % (mesh, angle))
    offset = np.mean(d[shock])
    check(abs(offset - dstar) < 0.5 * np.median(longest[shock]),
          "%s: fitted plane offset %.4f vs exact Mn = 1 offset d* = %.4f" % (mesh, offset, dstar))

    # NormalMach: at points near the shock, sign of (Mn - 1) matches the exact one.
    pts = np.asarray(out.Points)
    dp = (pts - x0) @ n
    mn = np.asarray(out.PointData["NormalMach"])
    band = (np.abs(dp - dstar) > 0.5 * delta) & (np.abs(dp - dstar) < 2 * delta)
    agree = np.mean((mn[band] > 1.0) == (dp[band] < dstar))
    check(agree > 0.97, "%s: Mn > 1 upstream and < 1 downstream of d* at %.1f%% of %d points" % (mesh, 100 * agree, band.sum()))

    # Conserved variables give the same answer as primitives.
    sc = ShockSensor(Input=reader, VariableSet=2, Density=["POINTS", "rho"], Momentum=["POINTS", "rhoU"],
                     TotalEnergy=["POINTS", "rhoE"])
    mn2 = np.asarray(artest.fetch(sc).PointData["NormalMach"])
    # Compared where grad p is resolved: far away it is round-off and so is
    # its direction, and Mn with it.
    resolved = np.abs(dp) < 3 * delta
    check(np.allclose(mn2[resolved], mn[resolved], rtol=1e-7, atol=1e-7),
          "%s: conserved-variable input gives the same Mn (max diff %.2e)" % (mesh, np.abs(mn2 - mn)[resolved].max()))
    st = ShockSensor(Input=reader, VariableSet=1, Velocity=["POINTS", "U"], Pressure=["POINTS", "p"],
                     Temperature=["POINTS", "T"], GasConstant=artest.field(src, "GasConstant")[0])
    mn3 = np.asarray(artest.fetch(st).PointData["NormalMach"])
    check(np.allclose(mn3[resolved], mn[resolved], rtol=1e-7, atol=1e-7),
          "%s: temperature input gives the same Mn (max diff %.2e)" % (mesh, np.abs(mn3 - mn)[resolved].max()))

    # Cell-data input (averaged to the points) finds the same shock.
    cells_only = PassArrays(Input=reader, PointDataArrays=[], CellDataArrays=["U", "p", "rho"])
    scell = ShockSensor(Input=cells_only, Velocity=["CELLS", "U"], Pressure=["CELLS", "p"],
                        Density=["CELLS", "rho"])
    shock_c = np.asarray(artest.fetch(scell).CellData["ShockCells"]) == 1
    normal_c, _ = artest.fit_plane(centroids[shock_c])
    check(shock_c.sum() > 50 and artest.angle_between_planes(normal_c, n) < 1.0,
          "%s: cell-data input: %d shock cells, plane within %.3f deg" % (mesh, shock_c.sum(), artest.angle_between_planes(normal_c, n)))
    for p in (scell, cells_only, st, sc, ss, wf, reader):
        Delete(p)

artest.finish()
