"""Write the analytic oblique-shock datasets into Data/.

    pvpython Data/make_analytic_shock.py        (from any directory; needs gmsh)

Outputs (next to this script):
  oblique_shock_structured.vtu    unit cube, 16^3 hexahedra x 6 tetrahedra
                                  (Kuhn split along the (0,0,0)-(1,1,1)
                                  diagonal, conforming) = 24576 tets
  oblique_shock_unstructured.vtu  unit cube, gmsh Delaunay tetrahedra, h = 1/16

Each carries the fields of analytic_shock.ObliqueShock (delta = 1/16) as point
data (at the points) and as cell data (at the cell centroids): rho, U, p, T,
rhoU, rhoE, SignedDistance; and field data ShockNormal, ShockOrigin,
SmearingWidth, UpstreamMach, DeflectionAngle, ShockAngle, Gamma, GasConstant,
NormalMachUnityOffset.  Written in XML Binary mode (not raw appended), zlib,
double precision.
"""

import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from analytic_shock import ObliqueShock  # noqa: E402

from vtkmodules.util.numpy_support import numpy_to_vtk  # noqa: E402
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import (  # noqa: E402
    VTK_TETRA, vtkCellArray, vtkUnstructuredGrid)
from vtkmodules.vtkIOXML import (  # noqa: E402
    vtkXMLUnstructuredGridReader, vtkXMLUnstructuredGridWriter)

N = 16                 # structured cells per edge
H = 1.0 / N            # characteristic length, gmsh
DELTA = 1.0 / 16.0     # smearing width (one structured cell)


# ---------------------------------------------------------------------------
# meshes
# ---------------------------------------------------------------------------
def tet_volumes(points, tets):
    x0 = points[tets[:, 0]]
    a = points[tets[:, 1]] - x0
    b = points[tets[:, 2]] - x0
    c = points[tets[:, 3]] - x0
    return np.einsum("ij,ij->i", a, np.cross(b, c)) / 6.0


def orient_positive(points, tets):
    """Swap nodes 1 and 2 of tets whose VTK volume is negative."""
    tets = tets.copy()
    neg = tet_volumes(points, tets) < 0.0
    tets[neg, 1], tets[neg, 2] = tets[neg, 2].copy(), tets[neg, 1].copy()
    return tets


def structured_cube(n=N):
    """Unit cube, n^3 hexahedra, each split into 6 tets about its main diagonal."""
    g = np.linspace(0.0, 1.0, n + 1)
    # point id = i + (n+1) (j + (n+1) k), x fastest (vtkImageData order)
    zz, yy, xx = np.meshgrid(g, g, g, indexing="ij")
    points = np.column_stack([xx.ravel(), yy.ravel(), zz.ravel()])
    m = n + 1
    step = np.array([1, m, m * m])
    i, j, k = np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij")
    base = (i + m * (j + m * k)).transpose(2, 1, 0).ravel()  # cell order x fastest
    perms = [(0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)]
    local = []
    for a, b, _ in perms:   # path (0,0,0) -> e_a -> e_a + e_b -> (1,1,1)
        local.append([0, step[a], step[a] + step[b], step.sum()])
    local = np.array(local)                             # (6, 4)
    tets = (base[:, None, None] + local[None, :, :]).reshape(-1, 4)
    return points, orient_positive(points, tets)


GEO = """// unit cube, built-in kernel, written by make_analytic_shock.py
h = {h!r};
Point(1) = {{0, 0, 0, h}}; Point(2) = {{1, 0, 0, h}};
Point(3) = {{1, 1, 0, h}}; Point(4) = {{0, 1, 0, h}};
Point(5) = {{0, 0, 1, h}}; Point(6) = {{1, 0, 1, h}};
Point(7) = {{1, 1, 1, h}}; Point(8) = {{0, 1, 1, h}};
Line(1) = {{1, 2}}; Line(2) = {{2, 3}}; Line(3) = {{3, 4}}; Line(4) = {{4, 1}};
Line(5) = {{5, 6}}; Line(6) = {{6, 7}}; Line(7) = {{7, 8}}; Line(8) = {{8, 5}};
Line(9) = {{1, 5}}; Line(10) = {{2, 6}}; Line(11) = {{3, 7}}; Line(12) = {{4, 8}};
Curve Loop(1) = {{1, 2, 3, 4}};     Plane Surface(1) = {{1}};   // z = 0
Curve Loop(2) = {{5, 6, 7, 8}};     Plane Surface(2) = {{2}};   // z = 1
Curve Loop(3) = {{1, 10, -5, -9}};  Plane Surface(3) = {{3}};   // y = 0
Curve Loop(4) = {{3, 12, -7, -11}}; Plane Surface(4) = {{4}};   // y = 1
Curve Loop(5) = {{4, 9, -8, -12}};  Plane Surface(5) = {{5}};   // x = 0
Curve Loop(6) = {{2, 11, -6, -10}}; Plane Surface(6) = {{6}};   // x = 1
Surface Loop(1) = {{1, 2, 3, 4, 5, 6}};
Volume(1) = {{1}};
Physical Volume("domain", 1) = {{1}};
Mesh.CharacteristicLengthMin = h;
Mesh.CharacteristicLengthMax = h;
Mesh.CharacteristicLengthExtendFromBoundary = 1;
Mesh.Algorithm = 6;      // Frontal-Delaunay (surfaces)
Mesh.Algorithm3D = 1;    // Delaunay (volume)
Mesh.Optimize = 1;
Mesh.RandomSeed = 1;
"""


def read_msh22(path, types=None):
    """Minimal ASCII MSH 2.2 reader: the nodes used by the elements of `types`
    (Gmsh element type -> (VTK type, node count); default: 4-node tetrahedra),
    and those elements as blocks [(VTK type, 0-based point ids)]."""
    GMSH_TYPES = types or {4: (VTK_TETRA, 4)}
    with open(path, "r") as f:
        lines = f.read().split("\n")
    pos = 0
    ids, xyz, cells = None, None, {t: [] for t in GMSH_TYPES}
    while pos < len(lines):
        key = lines[pos].strip()
        pos += 1
        if key == "$MeshFormat":
            ver, ftype = lines[pos].split()[:2]
            if not ver.startswith("2.") or ftype != "0":
                raise RuntimeError("%s: need ASCII MSH 2.2, got %s %s" % (path, ver, ftype))
            pos += 1
        elif key == "$Nodes":
            nn = int(lines[pos])
            pos += 1
            arr = np.array([ln.split() for ln in lines[pos:pos + nn]], dtype=float)
            pos += nn
            ids = arr[:, 0].astype(np.int64)
            xyz = arr[:, 1:4]
        elif key == "$Elements":
            ne = int(lines[pos])
            pos += 1
            for ln in lines[pos:pos + ne]:
                w = ln.split()
                t = int(w[1])
                if t in GMSH_TYPES:
                    ntag = int(w[2])
                    cells[t].append([int(v) for v in w[3 + ntag:3 + ntag + GMSH_TYPES[t][1]]])
            pos += ne
    if ids is None:
        raise RuntimeError("%s: no nodes" % path)
    lut = np.full(ids.max() + 1, -1, dtype=np.int64)
    lut[ids] = np.arange(ids.size)
    blocks = []
    for t, (vtk_type, n) in GMSH_TYPES.items():
        if cells[t]:
            c = lut[np.array(cells[t], dtype=np.int64)]
            if (c < 0).any():
                raise RuntimeError("%s: an element refers to an unknown node" % path)
            blocks.append((vtk_type, c))
    if not blocks:
        raise RuntimeError("%s: none of the wanted elements" % path)
    used = np.unique(np.concatenate([c.ravel() for _, c in blocks]))
    remap = np.full(ids.size, -1, dtype=np.int64)
    remap[used] = np.arange(used.size)
    return xyz[used], [(t, remap[c]) for t, c in blocks]


def gmsh_mesh(geo_text, types=None):
    """Runs gmsh (3-D, MSH 2.2, one thread) on a .geo text in a scratch
    folder; returns read_msh22's points and blocks."""
    gmsh = shutil.which("gmsh")
    if gmsh is None:
        raise RuntimeError("gmsh not found on PATH: apt-get install gmsh (the README's set-up installs it)")
    tmp = tempfile.mkdtemp(prefix="ar_gmsh_")
    try:
        geo = os.path.join(tmp, "mesh.geo")
        msh = os.path.join(tmp, "mesh.msh")
        with open(geo, "w") as f:
            f.write(geo_text)
        subprocess.run([gmsh, geo, "-3", "-format", "msh22", "-nt", "1",
                        "-v", "2", "-o", msh], check=True,
                       stdout=subprocess.DEVNULL)
        return read_msh22(msh, types)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def gmsh_cube(h=H):
    points, blocks = gmsh_mesh(GEO.format(h=h))
    return points, orient_positive(points, blocks[0][1])


# ---------------------------------------------------------------------------
# VTK
# ---------------------------------------------------------------------------
def _vtk_array(name, values):
    arr = numpy_to_vtk(np.ascontiguousarray(values, dtype=np.float64), deep=1)
    arr.SetName(name)
    return arr


def build_grid(points, tets, shock):
    grid = vtkUnstructuredGrid()
    pts = vtkPoints()
    pts.SetDataTypeToDouble()
    pts.SetData(_vtk_array("Points", points))
    grid.SetPoints(pts)
    cells = vtkCellArray()
    offsets = numpy_to_vtk(np.arange(0, 4 * len(tets) + 1, 4, dtype=np.int64),
                           deep=1)
    conn = numpy_to_vtk(np.ascontiguousarray(tets.ravel(), dtype=np.int64), deep=1)
    cells.SetData(offsets, conn)
    grid.SetCells(VTK_TETRA, cells)

    names = ["rho", "U", "p", "T", "rhoU", "rhoE", "SignedDistance"]
    pf = shock.fields(points)
    cf = shock.fields(points[tets].mean(axis=1))
    for nm in names:
        grid.GetPointData().AddArray(_vtk_array(nm, pf[nm]))
        grid.GetCellData().AddArray(_vtk_array(nm, cf[nm]))
    grid.GetPointData().SetActiveScalars("p")
    grid.GetPointData().SetActiveVectors("U")

    add_field_data(grid, shock)
    return grid


def add_field_data(grid, shock):
    """The shock's parameters (ObliqueShock.field_data) as field data."""
    for nm, val in shock.field_data().items():
        arr = vtkDoubleArray()
        arr.SetName(nm)
        val = np.atleast_1d(np.asarray(val, dtype=float))
        arr.SetNumberOfComponents(1)
        arr.SetNumberOfTuples(val.size)
        for i, v in enumerate(val):
            arr.SetValue(i, float(v))
        grid.GetFieldData().AddArray(arr)


def write_vtu(grid, path):
    w = vtkXMLUnstructuredGridWriter()
    w.SetFileName(path)
    w.SetInputData(grid)
    w.SetDataModeToBinary()
    w.SetCompressorTypeToZLib()
    w.SetCompressionLevel(9)
    w.SetIdTypeToInt32()
    if w.Write() != 1:
        raise RuntimeError("failed to write " + path)


def read_back(path, ncells, npoints):
    r = vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    if g.GetNumberOfCells() != ncells or g.GetNumberOfPoints() != npoints:
        raise RuntimeError("%s: read back %d cells / %d points, expected %d / %d"
                           % (path, g.GetNumberOfCells(), g.GetNumberOfPoints(),
                              ncells, npoints))
    return g


def main():
    shock = ObliqueShock(delta=DELTA)
    meshes = [("oblique_shock_structured.vtu", structured_cube()),
              ("oblique_shock_unstructured.vtu", gmsh_cube())]
    for name, (points, tets) in meshes:
        vol = tet_volumes(points, tets)
        if vol.min() <= 0.0 or abs(vol.sum() - 1.0) > 1e-10:
            raise RuntimeError("%s: bad mesh (min volume %g, total %.15g)"
                               % (name, vol.min(), vol.sum()))
        path = os.path.join(HERE, name)
        write_vtu(build_grid(points, tets, shock), path)
        read_back(path, len(tets), len(points))
        print("%s: %d points, %d tets, %d bytes"
              % (path, len(points), len(tets), os.path.getsize(path)))
    print(shock.summary())


if __name__ == "__main__":
    main()
