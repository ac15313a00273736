"""Measure a captured shock in a solution: its position and its 10-90 %
thickness along lines normal to a surface (pvpython; numpy and VTK only).

The profile of a scalar (pressure by default) is probed on straight lines
through points of a surface (the fitted shock surface of AdaptToShocks, or an
exact shock plane or cone), along the surface normal, with vtkProbeFilter:
linear in each cell on the solution's point data.  On each line

    f(s) = (q(s) - q1) / (q2 - q1),

q1 and q2 the medians of the line's first and last fifth (the states ahead of
and behind the shock; the line is turned so that q rises along it).  The
shock's position is the crossing f = 1/2 nearest the surface (s = 0), and its
10-90 % thickness the distance from the last f <= 0.1 ahead of it to the first
f >= 0.9 behind it.  A line is rejected (not averaged) when it leaves the
domain at either end, when a fifth is not a plateau (the spread of f there
over 0.1), or when the jump is below 1 % of q1: it did not cross a clean shock.
Where the flow behind the shock is not uniform (a cone's), pass the exact
states: `measure(..., states=(q1, q2))`, q2 the value just behind the shock.

    import shock_measure as sm
    r = sm.measure(grid, origins, normals, half_length=0.02)   # one dict
    r["thickness"], r["offset"], r["valid"], r["points"]       # per line
    sm.summary(r)                                              # medians etc.
    sm.surface_stations(polydata, count=24, margin=0.02)       # points, normals

`Plugin/Scripts/adapt_case.py` reports it per cycle along each fitted surface,
`Testing/Benchmark/bench_payoff.py` along the exact shock of each case.
"""
import numpy as np

from vtkmodules.util import numpy_support as nps
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkPolyData

LOW, HIGH = 0.1, 0.9
PLATEAU_SPREAD = 0.1
MIN_JUMP = 0.01


def probe(grid, pts, name="p"):
    """Values of the point array `name` of `grid` at the points (n x 3), and a
    mask of the points inside the grid."""
    from vtkmodules.vtkFiltersCore import vtkProbeFilter
    if grid.GetPointData().GetArray(name) is None:
        raise ValueError("the solution has no point array %r (point arrays: %s)" % (
            name, [grid.GetPointData().GetArrayName(i) for i in range(grid.GetPointData().GetNumberOfArrays())]))
    vp = vtkPoints()
    vp.SetData(nps.numpy_to_vtk(np.ascontiguousarray(pts, dtype=np.float64), deep=1))
    pd = vtkPolyData()
    pd.SetPoints(vp)
    f = vtkProbeFilter()
    f.SetInputData(pd)
    f.SetSourceData(grid)
    f.PassPointArraysOff()
    f.Update()
    out = f.GetOutput().GetPointData()
    q = nps.vtk_to_numpy(out.GetArray(name)).astype(np.float64)
    if q.ndim > 1:
        q = np.linalg.norm(q, axis=1)
    return q, nps.vtk_to_numpy(out.GetArray(f.GetValidPointMaskArrayName())).astype(bool)


def _crossing(s, f, i, level):
    """s where f crosses `level` between samples i and i + 1 (linear)."""
    df = f[i + 1] - f[i]
    return s[i] if df == 0 else s[i] + (level - f[i]) * (s[i + 1] - s[i]) / df


def profile(s, q, states=None, downstream_plateau=True):
    """(position, thickness, q1, q2) of the rise of q along the line at the
    abscissae s (increasing), or None when the line crossed no clean shock;
    see the module docstring. `states` (q1, q2): the exact states ahead of
    and just behind the shock, for flows that are not uniform behind it (a
    cone's: p keeps rising towards the body); then only the upstream fifth
    must be a plateau; likewise with `downstream_plateau` False (q2 then the
    median of the last fifth)."""
    n = len(s)
    k = max(3, n // 5)
    if n < 3 * k:
        return None
    if np.median(q[-k:]) < np.median(q[:k]):
        s, q = -s[::-1], q[::-1]
        flipped = True
    else:
        flipped = False
    q1, q2 = (np.median(q[:k]), np.median(q[-k:])) if states is None else states
    if q2 - q1 <= MIN_JUMP * max(abs(q1), 1e-300):
        return None
    f = (q - q1) / (q2 - q1)
    if np.ptp(f[:k]) > PLATEAU_SPREAD or (states is None and downstream_plateau and np.ptp(f[-k:]) > PLATEAU_SPREAD):
        return None
    up = np.where((f[:-1] < 0.5) & (f[1:] >= 0.5))[0]
    if len(up) == 0:
        return None
    mids = np.array([_crossing(s, f, i, 0.5) for i in up])
    j = int(np.argmin(np.abs(mids)))
    i = up[j]
    lo = i
    while lo > 0 and f[lo] > LOW:
        lo -= 1
    hi = i + 1
    while hi < n - 1 and f[hi] < HIGH:
        hi += 1
    if f[lo] > LOW or f[hi] < HIGH:
        return None
    s_lo = _crossing(s, f, lo, LOW)
    s_hi = _crossing(s, f, hi - 1, HIGH)
    pos = mids[j]
    return (-pos if flipped else pos), s_hi - s_lo, q1, q2


def measure(grid, origins, normals, half_length, samples=801, name="p", states=None, clip=False):
    """Probe `name` on the lines origins[i] + s normals[i], |s| <= half_length,
    and measure each line's profile.  Returns a dict of per-line arrays:
    valid (bool), offset (position of f = 1/2 along the normal, from the
    origin), thickness (10-90 %), q1, q2, points (the f = 1/2 points).
    With `clip`, a line that leaves the domain is cut to its piece inside
    around the origin (a cone's shock is closer to the body than the line is
    long) and measured there when that piece is at least a quarter of the
    line, with the piece's fifths as its states; only the upstream fifth must
    then be a plateau (behind a cone's shock p keeps rising to the body, so
    q2, the median of the fifth at the body, is a little above the value
    just behind the shock and the thickness a little wide)."""
    o = np.asarray(origins, dtype=np.float64).reshape(-1, 3)
    nrm = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    nrm = nrm / np.linalg.norm(nrm, axis=1)[:, None]
    if not half_length > 0:
        raise ValueError("half_length must be positive (got %r)" % half_length)
    s = np.linspace(-half_length, half_length, samples)
    pts = o[:, None, :] + s[None, :, None] * nrm[:, None, :]
    q, ok = probe(grid, pts.reshape(-1, 3), name)
    q, ok = q.reshape(len(o), samples), ok.reshape(len(o), samples)
    m = len(o)
    r = dict(valid=np.zeros(m, bool), offset=np.full(m, np.nan), thickness=np.full(m, np.nan),
             q1=np.full(m, np.nan), q2=np.full(m, np.nan), points=np.full((m, 3), np.nan),
             half_length=half_length)
    for i in range(m):
        si, qi = s, q[i]
        if not ok[i].all():
            c = samples // 2
            if not (clip and ok[i][c]):
                continue
            a, b = c, c
            while a > 0 and ok[i][a - 1]:
                a -= 1
            while b < samples - 1 and ok[i][b + 1]:
                b += 1
            if b - a + 1 < samples // 4:
                continue
            si, qi = s[a:b + 1], q[i][a:b + 1]
        res = profile(si, qi, states, downstream_plateau=ok[i].all())
        if res is None:
            continue
        r["valid"][i] = True
        r["offset"][i], r["thickness"][i], r["q1"][i], r["q2"][i] = res
        r["points"][i] = o[i] + res[0] * nrm[i]
    return r


def summary(r):
    """Medians and ranges of a measure() result over its valid lines."""
    v = r["valid"]
    if not v.any():
        return dict(lines=len(v), valid=0)
    t, d = r["thickness"][v], r["offset"][v]
    return dict(lines=len(v), valid=int(v.sum()), thickness_median=float(np.median(t)),
                thickness_mean=float(t.mean()), thickness_min=float(t.min()), thickness_max=float(t.max()),
                offset_mean=float(d.mean()), offset_max_abs=float(np.abs(d).max()))


def surface_stations(surface, count=24, margin=0.0, depth_axis=None):
    """Up to `count` points of a triangulated surface (vtkPolyData) with their
    unit normals, spread over it (farthest-point sampling from its centre),
    at least `margin` from its boundary edges.  For a one-cell-deep case give
    the depth axis (0, 1, 2): the surface is a strip across the depth, its
    borders on the front and back planes do not count, the margin is taken
    in the cross-section and the points are moved to mid-depth."""
    from vtkmodules.vtkFiltersCore import vtkFeatureEdges, vtkPolyDataNormals, vtkTriangleFilter
    tri = vtkTriangleFilter()
    tri.SetInputData(surface)
    nf = vtkPolyDataNormals()
    nf.SetInputConnection(tri.GetOutputPort())
    nf.SplittingOff()
    nf.ConsistencyOn()
    nf.AutoOrientNormalsOff()
    nf.ComputePointNormalsOn()
    nf.Update()
    out = nf.GetOutput()
    if out.GetNumberOfPoints() == 0:
        return np.zeros((0, 3)), np.zeros((0, 3))
    P = nps.vtk_to_numpy(out.GetPoints().GetData()).astype(np.float64)
    N = nps.vtk_to_numpy(out.GetPointData().GetNormals()).astype(np.float64)
    keep = np.ones(len(P), bool)
    mid = None
    if depth_axis is not None:
        mid = 0.5 * (P[:, depth_axis].min() + P[:, depth_axis].max())
    if margin > 0:
        fe = vtkFeatureEdges()
        fe.SetInputData(out)
        fe.BoundaryEdgesOn()
        fe.FeatureEdgesOff()
        fe.NonManifoldEdgesOff()
        fe.ManifoldEdgesOff()
        fe.Update()
        edges = fe.GetOutput()
        if edges.GetNumberOfPoints():
            B = nps.vtk_to_numpy(edges.GetPoints().GetData()).astype(np.float64)
            Q = P.copy()
            if depth_axis is not None:
                # only the strip's ends (edges across the depth) bound it; an
                # edge on the front or back plane may differ in depth by
                # round-off (a plane fitted a hair out of square, then cut)
                lines = nps.vtk_to_numpy(edges.GetLines().GetConnectivityArray()).reshape(-1, 2)
                depth = np.ptp(P[:, depth_axis])
                across = lines[np.abs(B[lines[:, 0], depth_axis] - B[lines[:, 1], depth_axis]) > 0.5 * depth]
                B = B[np.unique(across)] if len(across) else B[:0]
                B[:, depth_axis] = 0.0
                Q[:, depth_axis] = 0.0
            if len(B):
                from scipy.spatial import cKDTree
                dist, _ = cKDTree(B).query(Q)
                keep = dist >= margin
    idx = np.where(keep)[0]
    if len(idx) == 0:
        return np.zeros((0, 3)), np.zeros((0, 3))
    chosen = [idx[np.argmin(np.linalg.norm(P[idx] - P[idx].mean(axis=0), axis=1))]]
    dmin = np.linalg.norm(P[idx] - P[chosen[0]], axis=1)
    while len(chosen) < min(count, len(idx)):
        k = int(np.argmax(dmin))
        if dmin[k] == 0:
            break
        chosen.append(idx[k])
        dmin = np.minimum(dmin, np.linalg.norm(P[idx] - P[idx[k]], axis=1))
    P, N = P[chosen], N[chosen]
    if mid is not None:
        P[:, depth_axis] = mid
    return P, N
