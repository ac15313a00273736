"""Convert the solved OpenFOAM case wedge15Ma5 to a compressed VTK .vtu (pvpython).

Usage:  pvpython Data/convert_wedge15Ma5.py CASE_DIR OUTPUT.vtu

Reads the last time step of CASE_DIR with ParaView's OpenFOAMReader
(internalMesh only, cell-to-point data on, polyhedra not decomposed), merges it
into one vtkUnstructuredGrid of hexahedra and writes OUTPUT.vtu
(vtkXMLUnstructuredGridWriter, DataMode Binary, i.e. base64 inline, zlib
compressed; Debian's ParaView 5.11 cannot read raw appended data).

Arrays, each as point data and as cell data:
    rho, U (3), p, T                    from the solver
    rhoU (3) = rho U
    rhoE     = p / (gamma - 1) + 0.5 rho |U|^2
Field data (doubles):
    Gamma                    Cp / (Cp - R), from constant/thermophysicalProperties
    GasConstant              R = 8314.47 / molWeight
    UpstreamMach             |U_in| / sqrt(gamma R T_in), inlet fixedValue of U and T
    WedgeAngle               degrees, from the blockMeshDict vertices of the "obstacle" patch
    WedgeTip                 (x, y, z): ramp corner, z at mid-span
    ShockAngleThetaBetaMach  degrees, weak oblique-shock solution (Data/theta_beta_mach.py)

Everything is read from the case files; nothing about the flow is hard-coded
except the patch names "inlet" and "obstacle" of the tutorial.
"""

import math
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__ if "__file__" in globals() else sys.argv[0]))
sys.path.insert(0, HERE)
import foam_case  # noqa: E402
import foam_vtu  # noqa: E402
import theta_beta_mach  # noqa: E402

from vtkmodules.vtkCommonDataModel import VTK_HEXAHEDRON  # noqa: E402



def wedge_geometry(case):
    """(wedge angle in degrees, tip point) from the blockMeshDict vertices of patch 'obstacle'."""
    path = os.path.join(case, "system", "blockMeshDict")
    if not os.path.exists(path):
        path = os.path.join(case, "constant", "polyMesh", "blockMeshDict")
    bm = foam_case.read_dict(path)
    scale = 1.0
    for key in ("scale", "convertToMeters"):
        try:
            scale = foam_case.scalar(bm, key)
            break
        except KeyError:
            pass
    verts = [tuple(scale * float(c) for c in v.split())
             for v in re.findall(r"\(([^()]*)\)", foam_case.sub(bm, "vertices", "("))]
    boundary = foam_case.sub(bm, "boundary", "(")
    faces = foam_case.sub(foam_case.sub(boundary, "obstacle"), "faces", "(")
    ids = sorted({int(i) for f in re.findall(r"\(([^()]*)\)", faces) for i in f.split()})
    pts = sorted({(round(verts[i][0], 12), round(verts[i][1], 12)) for i in ids})
    if len(pts) != 2:
        raise RuntimeError("obstacle patch is not a single straight ramp: %s" % pts)
    (x0, y0), (x1, y1) = pts  # sorted by x: tip first
    angle = math.degrees(math.atan2(y1 - y0, x1 - x0))
    zs = [v[2] for v in verts]
    tip = (x0, y0, 0.5 * (min(zs) + max(zs)))
    return angle, tip, ((x0, y0), (x1, y1))


# ---------------------------------------------------------------- main
def main(argv):
    if len(argv) != 3:
        sys.exit("usage: pvpython %s CASE_DIR OUTPUT.vtu" % argv[0])
    case = os.path.abspath(argv[1])
    out = os.path.abspath(argv[2])
    src, time_dir, _ = foam_vtu.read_last_time(case, VTK_HEXAHEDRON, "hexahedra")
    gamma, r_gas, cp, mol_weight = foam_case.gas_properties(case)
    u_in, t_in, _ = foam_case.inlet_state(case, time_dir)
    mach = math.sqrt(sum(c * c for c in u_in)) / math.sqrt(gamma * r_gas * t_in)
    wedge, tip, ramp = wedge_geometry(case)
    beta = theta_beta_mach.shock_angle(mach, wedge, gamma)

    grid = foam_vtu.flow_grid(src, gamma)
    for name, values in (("Gamma", (gamma,)), ("GasConstant", (r_gas,)), ("UpstreamMach", (mach,)),
                         ("WedgeAngle", (wedge,)), ("WedgeTip", tip), ("ShockAngleThetaBetaMach", (beta,))):
        foam_vtu.add_field(grid, name, values)
    foam_vtu.write_and_check(grid, out, VTK_HEXAHEDRON)

    print("case        %s (time %s)" % (case, time_dir))
    print("gas         Cp %g, molWeight %g -> R %.6g, gamma %.6g" % (cp, mol_weight, r_gas, gamma))
    print("inlet       U %s, T %g -> Mach %.6g" % (u_in, t_in, mach))
    print("ramp        %s -> %s: wedge angle %.6g deg, tip %s" % (ramp[0], ramp[1], wedge, tip))
    print("shock       theta-beta-Mach weak solution beta = %.4f deg" % beta)
    foam_vtu.describe(grid, "VTK_HEXAHEDRON", out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
