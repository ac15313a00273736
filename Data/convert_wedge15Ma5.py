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
import theta_beta_mach  # noqa: E402

from paraview import simple  # noqa: E402
from paraview import servermanager  # noqa: E402
from paraview.vtk.util import numpy_support as nps  # noqa: E402
import numpy as np  # noqa: E402
from vtkmodules.vtkCommonCore import vtkDoubleArray  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid, VTK_HEXAHEDRON  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter, vtkXMLUnstructuredGridReader  # noqa: E402

KEEP = ("rho", "U", "p", "T")


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
    if not os.path.isfile(os.path.join(case, "system", "controlDict")):
        sys.exit("%s is not an OpenFOAM case" % case)

    # the reader wants a *.foam file in the case directory
    foam = os.path.join(case, os.path.basename(case) + ".foam")
    if not os.path.exists(foam):
        open(foam, "w").close()

    reader = simple.OpenFOAMReader(FileName=foam)
    reader.MeshRegions = ["internalMesh"]
    reader.CellArrays = list(KEEP)
    reader.Createcelltopointfiltereddata = 1
    reader.Decomposepolyhedra = 0
    reader.SkipZeroTime = 1
    reader.UpdatePipelineInformation()
    times = list(reader.TimestepValues)
    if not times:
        sys.exit("no time steps in %s" % case)
    t_last = max(times)
    time_dirs = [d for d in os.listdir(case)
                 if re.fullmatch(r"[0-9.eE+-]+", d) and os.path.isdir(os.path.join(case, d))]
    time_dir = min(time_dirs, key=lambda d: abs(float(d) - t_last))
    merged = simple.MergeBlocks(Input=reader)
    merged.UpdatePipeline(t_last)
    src = servermanager.Fetch(merged)
    if not isinstance(src, vtkUnstructuredGrid):
        sys.exit("MergeBlocks gave %s, expected vtkUnstructuredGrid" % src.GetClassName())

    ncells = src.GetNumberOfCells()
    types = nps.vtk_to_numpy(src.GetCellTypesArray()) if src.GetCellTypesArray() else \
        np.array([src.GetCellType(i) for i in range(ncells)])
    if ncells == 0 or not np.all(types == VTK_HEXAHEDRON):
        sys.exit("expected only hexahedra, got cell types %s" % sorted(set(types.tolist())))

    grid = vtkUnstructuredGrid()
    grid.SetPoints(src.GetPoints())
    grid.SetCells(src.GetCellTypesArray(), src.GetCells())

    gamma, r_gas, cp, mol_weight = foam_case.gas_properties(case)
    u_in, t_in, _ = foam_case.inlet_state(case, time_dir)
    mach = math.sqrt(sum(c * c for c in u_in)) / math.sqrt(gamma * r_gas * t_in)
    wedge, tip, ramp = wedge_geometry(case)
    beta = theta_beta_mach.shock_angle(mach, wedge, gamma)

    for kind, sdata, ddata in (("point", src.GetPointData(), grid.GetPointData()),
                               ("cell", src.GetCellData(), grid.GetCellData())):
        arr = {}
        for name in KEEP:
            a = sdata.GetArray(name)
            if a is None:
                sys.exit("no %s array %s in the reader output" % (kind, name))
            arr[name] = nps.vtk_to_numpy(a)
        dtype = arr["p"].dtype
        rho = arr["rho"].astype(np.float64)
        u = arr["U"].astype(np.float64)
        p = arr["p"].astype(np.float64)
        rho_u = rho[:, None] * u
        rho_e = p / (gamma - 1.0) + 0.5 * rho * np.einsum("ij,ij->i", u, u)
        for name in KEEP:
            ddata.AddArray(sdata.GetArray(name))
        for name, values in (("rhoU", rho_u), ("rhoE", rho_e)):
            v = nps.numpy_to_vtk(np.ascontiguousarray(values.astype(dtype)), deep=1)
            v.SetName(name)
            ddata.AddArray(v)

    def field(name, values):
        a = vtkDoubleArray()
        a.SetName(name)
        a.SetNumberOfComponents(len(values))
        a.InsertNextTuple(values)
        grid.GetFieldData().AddArray(a)

    field("Gamma", (gamma,))
    field("GasConstant", (r_gas,))
    field("UpstreamMach", (mach,))
    field("WedgeAngle", (wedge,))
    field("WedgeTip", tip)
    field("ShockAngleThetaBetaMach", (beta,))

    os.makedirs(os.path.dirname(out), exist_ok=True)
    w = vtkXMLUnstructuredGridWriter()
    w.SetFileName(out)
    w.SetInputData(grid)
    w.SetDataModeToBinary()
    w.SetCompressorTypeToZLib()
    w.SetCompressionLevel(9)
    if not w.Write():
        sys.exit("writing %s failed" % out)

    # ---- read back: plain VTK reader and the ParaView proxy
    rd = vtkXMLUnstructuredGridReader()
    rd.SetFileName(out)
    rd.Update()
    back = rd.GetOutput()
    assert back.GetNumberOfCells() == grid.GetNumberOfCells()
    assert back.GetNumberOfPoints() == grid.GetNumberOfPoints()
    for d0, d1 in ((grid.GetPointData(), back.GetPointData()), (grid.GetCellData(), back.GetCellData())):
        for i in range(d0.GetNumberOfArrays()):
            n = d0.GetArrayName(i)
            assert np.array_equal(nps.vtk_to_numpy(d0.GetArray(n)), nps.vtk_to_numpy(d1.GetArray(n))), n
    assert np.all(nps.vtk_to_numpy(back.GetCellTypesArray()) == VTK_HEXAHEDRON)
    pv = simple.XMLUnstructuredGridReader(FileName=[out])
    pv.UpdatePipeline()
    info = pv.GetDataInformation()
    assert info.GetNumberOfCells() == ncells and info.GetNumberOfPoints() == grid.GetNumberOfPoints()
    pnames = sorted(pv.PointData.keys())
    cnames = sorted(pv.CellData.keys())
    assert pnames == cnames == sorted(KEEP + ("rhoU", "rhoE")), (pnames, cnames)

    print("case        %s (time %s)" % (case, time_dir))
    print("gas         Cp %g, molWeight %g -> R %.6g, gamma %.6g" % (cp, mol_weight, r_gas, gamma))
    print("inlet       U %s, T %g -> Mach %.6g" % (u_in, t_in, mach))
    print("ramp        %s -> %s: wedge angle %.6g deg, tip %s" % (ramp[0], ramp[1], wedge, tip))
    print("shock       theta-beta-Mach weak solution beta = %.4f deg" % beta)
    print("mesh        %d points, %d cells (all VTK_HEXAHEDRON)" % (grid.GetNumberOfPoints(), ncells))
    print("point data  %s" % ", ".join(grid.GetPointData().GetArrayName(i)
                                        for i in range(grid.GetPointData().GetNumberOfArrays())))
    print("cell data   %s" % ", ".join(grid.GetCellData().GetArrayName(i)
                                       for i in range(grid.GetCellData().GetNumberOfArrays())))
    print("field data  %s" % ", ".join(grid.GetFieldData().GetArrayName(i)
                                        for i in range(grid.GetFieldData().GetNumberOfArrays())))
    print("wrote       %s (%d bytes, binary/base64, zlib); read back OK" % (out, os.path.getsize(out)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
