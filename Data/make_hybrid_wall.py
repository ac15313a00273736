"""Write Data/hybrid_wall.vtu: a hybrid mesh with near-wall layers (the
paper's Fig. 4 situation, on a box) carrying the analytic oblique shock.

    pvpython Data/make_hybrid_wall.py        (from any directory; needs gmsh)

Geometry: the unit cube; the wall is its bottom face z = 0. Near-wall layers
(Gmsh's structured extrusion of the wall, 5 layers, total thickness 0.1,
first layer 0.01105, growth about 1.3): the half x <= 0.5 of the wall is
triangulated and extruded into prisms (VTK_WEDGE), the half x >= 0.5 is
quadrangulated and extruded into hexahedra. Above the layers (0.1 <= z <= 1)
Gmsh's Delaunay tetrahedra, with pyramids where they meet the hexahedra's
top quads (Gmsh makes them). Size h = 0.1.

The layer region is exactly the slab z <= 0.1: every prism, hexahedron and
pyramid lies in 0 <= z <= 0.1 + (pyramid apices above it), every
tetrahedron above z = 0.1.

Fields: analytic_shock.ObliqueShock (delta = 1/16, the same as
oblique_shock_*.vtu) at the points (rho, U, p, T, rhoU, rhoE,
SignedDistance) and at the cell centroids (rho, U, p, T); its field data
(ShockNormal, ShockOrigin, ...).
The shock plane passes through the cube's centre and crosses the wall and
the layers (its normal's z component is -0.23).

Node order: VTK's (Gmsh's prism has the opposite orientation; every cell is
oriented so that all its corner Jacobians are positive, which the script
checks). Written in XML Binary mode (zlib), double precision.
"""

import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "Testing", "Python"))

from analytic_shock import ObliqueShock  # noqa: E402
from make_analytic_shock import _vtk_array, add_field_data, gmsh_mesh, read_back, write_vtu  # noqa: E402
from artest import corner_jacobians  # noqa: E402

from vtkmodules.util.numpy_support import numpy_to_vtk  # noqa: E402
from vtkmodules.vtkCommonCore import vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import (  # noqa: E402
    VTK_HEXAHEDRON, VTK_PYRAMID, VTK_TETRA, VTK_WEDGE, vtkCellArray, vtkUnstructuredGrid)

H = 0.1                 # mesh size
THICKNESS = 0.1         # total layer thickness
# Cumulative heights of the 5 layers as fractions of THICKNESS: first layer
# 0.01105, each next one 1.3 times thicker.
LAYERS = [0.1105, 0.2541, 0.4409, 0.6837, 1.0]
DELTA = 1.0 / 16.0

GEO = """// unit cube with near-wall layers on z = 0, written by make_hybrid_wall.py
h = {h!r};
T = {t!r};
Point(1) = {{0, 0, 0, h}}; Point(2) = {{0.5, 0, 0, h}}; Point(3) = {{1, 0, 0, h}};
Point(4) = {{1, 1, 0, h}}; Point(5) = {{0.5, 1, 0, h}}; Point(6) = {{0, 1, 0, h}};
Line(1) = {{1, 2}}; Line(2) = {{2, 3}}; Line(3) = {{3, 4}}; Line(4) = {{4, 5}};
Line(5) = {{5, 6}}; Line(6) = {{6, 1}}; Line(7) = {{2, 5}};
Curve Loop(1) = {{1, 7, 5, 6}}; Plane Surface(1) = {{1}};   // prisms above it
Curve Loop(2) = {{2, 3, 4, -7}}; Plane Surface(2) = {{2}};  // hexahedra above it
Recombine Surface{{2}};
a[] = Extrude {{0, 0, T}} {{ Surface{{1}}; Layers{{ {{1,1,1,1,1}}, {{{layers}}} }}; Recombine; }};
b[] = Extrude {{0, 0, T}} {{ Surface{{2}}; Layers{{ {{1,1,1,1,1}}, {{{layers}}} }}; Recombine; }};
c[] = Extrude {{0, 0, 1 - T}} {{ Surface{{a[0], b[0]}}; }};  // unstructured: tetrahedra (+ pyramids)
Mesh.Algorithm = 6;      // Frontal-Delaunay (surfaces)
Mesh.Algorithm3D = 1;    // Delaunay (volume)
Mesh.Optimize = 1;
Mesh.RandomSeed = 1;
"""

# Gmsh element type -> (VTK type, number of nodes)
GMSH_TYPES = {4: (VTK_TETRA, 4), 5: (VTK_HEXAHEDRON, 8), 6: (VTK_WEDGE, 6), 7: (VTK_PYRAMID, 5)}

# Per VTK type: the node swap that inverts a cell (the corner Jacobians are
# the tests' own, Testing/Python/artest.py).
FLIP = {VTK_TETRA: [0, 2, 1, 3], VTK_PYRAMID: [0, 3, 2, 1, 4], VTK_WEDGE: [0, 2, 1, 3, 5, 4],
        VTK_HEXAHEDRON: [0, 3, 2, 1, 4, 7, 6, 5]}


def gmsh_hybrid():
    points, blocks = gmsh_mesh(GEO.format(h=H, t=THICKNESS, layers=", ".join(repr(x) for x in LAYERS)),
                               GMSH_TYPES)
    # VTK orientation: flip every cell whose corners are all negative.
    oriented = []
    for vtk_type, cells in blocks:
        j = corner_jacobians(points, cells, vtk_type)
        flip = (j < 0).all(axis=1)
        cells = cells.copy()
        cells[flip] = cells[flip][:, FLIP[vtk_type]]
        j = corner_jacobians(points, cells, vtk_type)
        if j.min() <= 0.0:
            raise RuntimeError("type %d: %d cells with a non-positive corner Jacobian"
                               % (vtk_type, int((j.min(axis=1) <= 0).sum())))
        oriented.append((vtk_type, cells))
    return points, oriented


def build_grid(points, blocks, shock):
    grid = vtkUnstructuredGrid()
    pts = vtkPoints()
    pts.SetDataTypeToDouble()
    pts.SetData(_vtk_array("Points", points))
    grid.SetPoints(pts)
    grid.Allocate(sum(len(c) for _, c in blocks))
    centroids = []
    for vtk_type, cells in blocks:
        for c in cells:
            grid.InsertNextCell(vtk_type, len(c), [int(v) for v in c])
        centroids.append(points[cells].mean(axis=1))
    centroids = np.concatenate(centroids)
    pf = shock.fields(points)
    cf = shock.fields(centroids)
    for nm in ["rho", "U", "p", "T", "rhoU", "rhoE", "SignedDistance"]:
        grid.GetPointData().AddArray(_vtk_array(nm, pf[nm]))
    for nm in ["rho", "U", "p", "T"]:  # (fewer cell arrays: the file stays well under 1 MB)
        grid.GetCellData().AddArray(_vtk_array(nm, cf[nm]))
    grid.GetPointData().SetActiveScalars("p")
    grid.GetPointData().SetActiveVectors("U")
    add_field_data(grid, shock)
    return grid


def main():
    shock = ObliqueShock(delta=DELTA)
    points, blocks = gmsh_hybrid()
    counts = {t: len(c) for t, c in blocks}
    for t, c in blocks:
        z = points[c][:, :, 2]
        if t == VTK_TETRA and z.min() < THICKNESS - 1e-12:
            raise RuntimeError("a tetrahedron reaches into the layers")
        if t in (VTK_WEDGE, VTK_HEXAHEDRON) and z.max() > THICKNESS + 1e-12:
            raise RuntimeError("a layer cell reaches above the layers")
    grid = build_grid(points, blocks, shock)
    path = os.path.join(HERE, "hybrid_wall.vtu")
    write_vtu(grid, path)
    read_back(path, grid.GetNumberOfCells(), len(points))
    print("%s: %d points, %d tetrahedra, %d prisms, %d hexahedra, %d pyramids, %d bytes"
          % (path, len(points), counts.get(VTK_TETRA, 0), counts.get(VTK_WEDGE, 0),
             counts.get(VTK_HEXAHEDRON, 0), counts.get(VTK_PYRAMID, 0), os.path.getsize(path)))


if __name__ == "__main__":
    main()
