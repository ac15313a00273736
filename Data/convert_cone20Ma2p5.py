"""Convert the solved OpenFOAM case cone20Ma2p5 to a compressed VTK .vtu (pvpython).

Usage:  pvpython Data/convert_cone20Ma2p5.py CASE_DIR OUTPUT.vtu

Reads the last time step of CASE_DIR (made by Data/make_cone20Ma2p5.sh) with
ParaView's OpenFOAMReader (internalMesh only, cell-to-point data on, polyhedra
not decomposed), checks that every cell is a tetrahedron, and writes
OUTPUT.vtu (vtkXMLUnstructuredGridWriter, DataMode Binary, i.e. base64 inline,
zlib compressed; Debian's ParaView 5.11 cannot read raw appended data).

Arrays, each as point data and as cell data (Float32, as read):
    rho, U (3), p, T                    from the solver
    rhoU (3) = rho U
    rhoE     = p / (gamma - 1) + 0.5 rho |U|^2
Field data (doubles):
    Gamma                      Cp / (Cp - R), from constant/thermophysicalProperties
    GasConstant                R = 8314.47 / molWeight
    UpstreamMach               |U_in| / sqrt(gamma R T_in), inlet fixedValue of U and T
    ConeHalfAngle              degrees  } fitted to the points of the "cone" patch:
    ConeTip                    (x, y, z)} tip = its point furthest upstream,
    ConeAxis                   (x, y, z)} axis = unit normal of the circle the
                                          directions tip->point lie on (least squares)
    ShockAngleTaylorMaccoll    degrees, conical shock half-angle (Data/taylor_maccoll.py)
    ConePressureRatioTaylorMaccoll   p on the cone surface / upstream p (Taylor-Maccoll)

Everything is read from the case files; nothing about the flow is hard-coded
except the patch names "inlet" and "cone".

Physics check (printed; exit status 1 if it fails): the shock half-angle is
measured from the written grid on five meridians (0, 45, 90, 135, 180 deg
about the axis; 0 and 180 lie in the symmetry plane).  On each, along lines
normal to the axis at 18 stations 0.1 .. 0.95 cone lengths from the tip, the
outermost point where p crosses (p1 + p2) / 2 (p1 upstream, p2 Taylor-Maccoll
just behind the shock) is found by linear interpolation in the tetrahedra
(point data), and a line through the tip is fitted to these points (least
squares).  It must agree with Taylor-Maccoll within 1 deg.  The mean cone-
surface pressure (point data on the cone) is printed next to Taylor-Maccoll.
"""

import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__ if "__file__" in globals() else sys.argv[0]))
sys.path.insert(0, HERE)
import foam_case  # noqa: E402
import foam_vtu  # noqa: E402
import taylor_maccoll  # noqa: E402

from paraview import simple  # noqa: E402
from paraview import servermanager  # noqa: E402
from paraview.vtk.util import numpy_support as nps  # noqa: E402
import numpy as np  # noqa: E402
from vtkmodules.vtkCommonDataModel import VTK_TETRA  # noqa: E402



def cone_geometry(points, upstream):
    """(half-angle deg, tip, axis, max deviation deg) of a sharp cone through `points` (n x 3).

    The tip is the point furthest upstream (smallest coordinate along the
    direction `upstream`, the inflow velocity; the cone patch has a mesh vertex
    at the tip).  The axis is the unit vector a with u_i . a = cos(half-angle)
    for all unit directions u_i from the tip to the points: the eigenvector of
    the smallest eigenvalue of the covariance of the u_i (they lie on a circle
    about a); it is fitted, not assumed, and checked against the inflow later.
    """
    pts = np.asarray(points, dtype=np.float64)
    s = pts @ (np.asarray(upstream, dtype=np.float64) / np.linalg.norm(upstream))
    tip = pts[np.argmin(s)]
    d = pts - tip
    r = np.linalg.norm(d, axis=1)
    u = d[r > 1e-9 * r.max()] / r[r > 1e-9 * r.max(), None]
    cu = u - u.mean(axis=0)
    w, v = np.linalg.eigh(cu.T @ cu)
    axis = v[:, 0]
    if np.mean(u @ axis) < 0.0:
        axis = -axis
    ang = np.degrees(np.arccos(np.clip(u @ axis, -1.0, 1.0)))
    half = float(np.mean(ang))
    return half, tip, axis / np.linalg.norm(axis), float(np.max(np.abs(ang - half)))


# ---------------------------------------------------------------- physics check
MAX_SHOCK_ANGLE_ERROR = 1.0  # degrees


def probe_p(grid, pts):
    """p probed at the points (n x 3) in `grid`, and which points lie inside it
    (vtkProbeFilter, Plugin/Scripts/shock_measure.py's probe). Also used by
    make_validation_case.py."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Plugin", "Scripts"))
    import shock_measure
    return shock_measure.probe(grid, pts, "p")


def measure_shock(grid, tip, axis, half_angle, p1, p2):
    """Shock half-angle (deg) per meridian, from the (p1 + p2) / 2 crossings; see the docstring."""
    pts = nps.vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64) - tip
    along = pts @ axis
    radial = np.linalg.norm(pts - along[:, None] * axis, axis=1)
    length = along[np.abs(np.degrees(np.arctan2(radial, along)) - half_angle) < 1e-3].max()
    rmax = 0.995 * radial.max()
    e1 = np.array([0.0, 1.0, 0.0]) - axis[1] * axis
    if np.linalg.norm(e1) < 1e-6:
        e1 = np.array([1.0, 0.0, 0.0]) - axis[0] * axis
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(axis, e1)
    pmid = 0.5 * (p1 + p2)
    tan_c = math.tan(math.radians(half_angle))
    result = {}
    for psi in (0, 45, 90, 135, 180):
        d = math.cos(math.radians(psi)) * e1 + math.sin(math.radians(psi)) * e2
        xs, rs = [], []
        for x in np.linspace(0.1, 0.95, 18) * length:
            rr = np.linspace(x * tan_c * 1.001, rmax, 2000)
            p, ok = probe_p(grid, tip + x * axis + rr[:, None] * d)
            hit = np.where(ok[:-1] & ok[1:] & ((p[:-1] - pmid) * (p[1:] - pmid) <= 0.0)
                           & (p[:-1] != p[1:]))[0]
            if len(hit) == 0:
                continue
            i = hit[-1]
            xs.append(x)
            rs.append(rr[i] + (pmid - p[i]) * (rr[i + 1] - rr[i]) / (p[i + 1] - p[i]))
        if len(xs) < 5:
            raise RuntimeError("shock not found on meridian %d deg" % psi)
        xs, rs = np.array(xs), np.array(rs)
        beta = math.degrees(math.atan((xs @ rs) / (xs @ xs)))
        local = np.degrees(np.arctan2(rs, xs))
        result[psi] = (beta, local.min(), local.max(), len(xs))
    return result, length


def physics_check(grid, tip, axis, half_angle, p1, tm):
    meridians, length = measure_shock(grid, tip, axis, half_angle, p1, p1 * tm.shock_p2_p1)
    for psi, (beta, lo, hi, n) in sorted(meridians.items()):
        print("check       meridian %3d deg: shock angle %.3f deg (line through the tip, %d stations; "
              "local %.2f .. %.2f)" % (psi, beta, n, lo, hi))
    beta = float(np.mean([v[0] for v in meridians.values()]))
    # cone-surface pressure from the point data on the cone
    pts = nps.vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64) - tip
    along = pts @ axis
    radial = np.linalg.norm(pts - along[:, None] * axis, axis=1)
    on = (np.abs(np.degrees(np.arctan2(radial, along)) - half_angle) < 1e-3) & (along > 1e-9)
    p = nps.vtk_to_numpy(grid.GetPointData().GetArray("p")).astype(np.float64) / p1
    far = on & (along > 0.3 * length)
    print("check       shock angle %.3f deg (mean of the meridians) vs Taylor-Maccoll %.3f deg: %+.3f deg"
          % (beta, tm.shock_angle, beta - tm.shock_angle))
    print("check       cone surface p/p1: %.4f mean (%.4f .. %.4f) over %d points at 0.3 .. 1 cone lengths, "
          "%.4f mean over all %d; Taylor-Maccoll %.4f"
          % (p[far].mean(), p[far].min(), p[far].max(), far.sum(), p[on].mean(), on.sum(), tm.cone_p_p1))
    return abs(beta - tm.shock_angle) <= MAX_SHOCK_ANGLE_ERROR


# ---------------------------------------------------------------- main
def main(argv):
    if len(argv) != 3:
        sys.exit("usage: pvpython %s CASE_DIR OUTPUT.vtu" % argv[0])
    case = os.path.abspath(argv[1])
    out = os.path.abspath(argv[2])
    src, time_dir, t_last = foam_vtu.read_last_time(case, VTK_TETRA, "tetrahedra")
    foam = foam_vtu.foam_file(case)

    # cone patch points (geometry only)
    patch = simple.OpenFOAMReader(FileName=foam)
    patch.MeshRegions = ["patch/cone"]
    patch.CellArrays = []
    patch.SkipZeroTime = 1
    pmerged = simple.MergeBlocks(Input=patch)
    pmerged.UpdatePipeline(t_last)
    cone_pts = servermanager.Fetch(pmerged)
    if cone_pts is None or cone_pts.GetNumberOfPoints() < 10:
        sys.exit("no points on patch 'cone'")
    gamma, r_gas, cp, mol_weight = foam_case.gas_properties(case)
    u_in, t_in, p_in = foam_case.inlet_state(case, time_dir)
    half_angle, tip, axis, dev = cone_geometry(nps.vtk_to_numpy(cone_pts.GetPoints().GetData()), u_in)
    if dev > 0.05:
        sys.exit("patch 'cone' is not a sharp cone: point directions deviate by up to %.3g deg" % dev)

    mach = math.sqrt(sum(c * c for c in u_in)) / math.sqrt(gamma * r_gas * t_in)
    flow_angle = math.degrees(math.acos(min(1.0, abs(np.dot(u_in, axis)) / np.linalg.norm(u_in))))
    if flow_angle > 0.01:
        sys.exit("the inflow is not along the cone axis (angle %.4g deg): Taylor-Maccoll does not apply"
                 % flow_angle)
    tm = taylor_maccoll.taylor_maccoll(mach, half_angle, gamma)

    grid = foam_vtu.flow_grid(src, gamma)
    for name, values in (("Gamma", (gamma,)), ("GasConstant", (r_gas,)), ("UpstreamMach", (mach,)),
                         ("ConeHalfAngle", (half_angle,)), ("ConeTip", tip), ("ConeAxis", axis),
                         ("ShockAngleTaylorMaccoll", (tm.shock_angle,)),
                         ("ConePressureRatioTaylorMaccoll", (tm.cone_p_p1,))):
        foam_vtu.add_field(grid, name, values)
    back = foam_vtu.write_and_check(grid, out, VTK_TETRA)

    print("case        %s (time %s)" % (case, time_dir))
    print("gas         Cp %g, molWeight %g -> R %.6g, gamma %.6g" % (cp, mol_weight, r_gas, gamma))
    print("inlet       U %s, T %g, p %g -> Mach %.6g" % (u_in, t_in, p_in, mach))
    print("cone        half-angle %.6f deg (points within %.2g deg), tip (%.3g, %.3g, %.3g), "
          "axis (%.6f, %.6f, %.6f)" % ((half_angle, dev) + tuple(tip) + tuple(axis)))
    print("shock       Taylor-Maccoll beta = %.4f deg; cone surface p/p1 = %.4f, Mach %.4f"
          % (tm.shock_angle, tm.cone_p_p1, tm.cone_mach))
    foam_vtu.describe(grid, "VTK_TETRA", out)
    if not physics_check(back, tip, axis, half_angle, p_in, tm):
        print("FAILED: the measured shock angle is more than %g deg off Taylor-Maccoll (%s kept)"
              % (MAX_SHOCK_ANGLE_ERROR, out), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
