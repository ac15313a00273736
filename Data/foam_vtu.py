"""From an OpenFOAM case to a compressed .vtu (pvpython).

Shared by convert_wedge15Ma5.py and convert_cone20Ma2p5.py: the last time
step's internal mesh read with ParaView's OpenFOAMReader (cell-to-point data
on), the primitive arrays plus the conserved rhoU and rhoE as point and cell
data, field data, and a binary (base64), zlib-compressed file checked by
reading it back with plain VTK and with ParaView. (ParaView 5.11 from Debian
cannot read raw appended data, hence binary mode.)
"""
import os
import re
import sys

import numpy as np
from paraview import servermanager, simple
from vtkmodules.util import numpy_support as nps
from vtkmodules.vtkCommonCore import vtkDoubleArray
from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader, vtkXMLUnstructuredGridWriter

KEEP = ("rho", "U", "p", "T")


def foam_file(case):
    """The *.foam file ParaView's reader wants, made in the case directory."""
    if not os.path.isfile(os.path.join(case, "system", "controlDict")):
        sys.exit("%s is not an OpenFOAM case" % case)
    foam = os.path.join(case, os.path.basename(case) + ".foam")
    if not os.path.exists(foam):
        open(foam, "w").close()
    return foam


def read_last_time(case, cell_type, cell_name):
    """The internal mesh at the last time step, merged into one
    vtkUnstructuredGrid whose cells must all be `cell_type`. Returns
    (grid as read, time directory name, time value)."""
    reader = simple.OpenFOAMReader(FileName=foam_file(case))
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
    types = nps.vtk_to_numpy(src.GetCellTypesArray())
    if src.GetNumberOfCells() == 0 or not np.all(types == cell_type):
        sys.exit("expected only %s, got cell types %s" % (cell_name, sorted(set(types.tolist()))))
    return src, time_dir, t_last


def flow_grid(src, gamma):
    """A new grid with src's mesh, its KEEP arrays and the conserved
    rhoU = rho U and rhoE = p / (gamma - 1) + rho |U|^2 / 2, as point and cell
    data, in src's precision."""
    grid = vtkUnstructuredGrid()
    grid.SetPoints(src.GetPoints())
    grid.SetCells(src.GetCellTypesArray(), src.GetCells())
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
    return grid


def add_field(grid, name, values):
    """A double field-data array of one tuple."""
    a = vtkDoubleArray()
    a.SetName(name)
    a.SetNumberOfComponents(len(values))
    a.InsertNextTuple([float(x) for x in values])
    grid.GetFieldData().AddArray(a)


def write_and_check(grid, out, cell_type):
    """Writes `out` and reads it back (plain VTK and ParaView): the same mesh,
    cell type, point, cell and field arrays. Returns the grid read back."""
    os.makedirs(os.path.dirname(out), exist_ok=True)
    w = vtkXMLUnstructuredGridWriter()
    w.SetFileName(out)
    w.SetInputData(grid)
    w.SetDataModeToBinary()
    w.SetCompressorTypeToZLib()
    w.SetCompressionLevel(9)
    if not w.Write():
        sys.exit("writing %s failed" % out)
    rd = vtkXMLUnstructuredGridReader()
    rd.SetFileName(out)
    rd.Update()
    back = rd.GetOutput()
    assert back.GetNumberOfCells() == grid.GetNumberOfCells()
    assert back.GetNumberOfPoints() == grid.GetNumberOfPoints()
    for d0, d1 in ((grid.GetPointData(), back.GetPointData()), (grid.GetCellData(), back.GetCellData()),
                   (grid.GetFieldData(), back.GetFieldData())):
        for i in range(d0.GetNumberOfArrays()):
            n = d0.GetArrayName(i)
            assert np.array_equal(nps.vtk_to_numpy(d0.GetArray(n)), nps.vtk_to_numpy(d1.GetArray(n))), n
    assert np.all(nps.vtk_to_numpy(back.GetCellTypesArray()) == cell_type)
    pv = simple.XMLUnstructuredGridReader(FileName=[out])
    pv.UpdatePipeline()
    info = pv.GetDataInformation()
    assert info.GetNumberOfCells() == grid.GetNumberOfCells() and info.GetNumberOfPoints() == grid.GetNumberOfPoints()
    pnames = sorted(pv.PointData.keys())
    cnames = sorted(pv.CellData.keys())
    assert pnames == cnames == sorted(KEEP + ("rhoU", "rhoE")), (pnames, cnames)
    return back


def describe(grid, cell_name, out):
    """The report lines common to both converters."""
    def names(data):
        return ", ".join(data.GetArrayName(i) for i in range(data.GetNumberOfArrays()))
    print("mesh        %d points, %d cells (all %s)" % (grid.GetNumberOfPoints(), grid.GetNumberOfCells(), cell_name))
    print("point data  %s" % names(grid.GetPointData()))
    print("cell data   %s" % names(grid.GetCellData()))
    print("field data  %s" % names(grid.GetFieldData()))
    print("wrote       %s (%d bytes, binary/base64, zlib); read back OK" % (out, os.path.getsize(out)))
