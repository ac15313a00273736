"""The Gmsh MSH 2.2 files of vtkGmshWriter through OpenFOAM's own reader:
write a mesh with SaveData('.msh'), make a minimal case, run `gmshToFoam`
and `checkMesh` (also on the OpenFOAM cone's mesh adapted by EmbeddedRemesh, with and
without prism layers), and assert
- gmshToFoam exits 0;
- constant/polyMesh/boundary has exactly the written physical names as
  patches, with the number of faces written to each;
- checkMesh exits 0 and reports "Mesh OK." (no failed check: a prism in the
  wrong node order would give negative volumes / wrongly oriented faces),
  with our cell count and our cell count per type, and our total volume
  (1e-6 relative: checkMesh prints 6 digits);
- the volume physical group became a cellZone of every cell.
Meshes: Data/wedge15Ma5.vtu (4800 hexahedra, form (c): one patch), and a
connected, conforming hybrid (a hexahedron with a pyramid on top, a wedge
on its side and a tetrahedron on the wedge's triangle) with named patches
(form (b)).
Fails (naming the package) when OpenFOAM is not installed: the README's
set-up installs it (AR_OPENFOAM_BASHRC overrides where its bashrc is looked
for).
"""
import os
import re
import shutil
import sys
import traceback

import artest
import foamcase
from artest import check

BASHRC = foamcase.bashrc("gmshToFoam")

import numpy as np
from paraview.simple import *
from paraview import servermanager
from vtkmodules.vtkCommonCore import vtkIntArray, vtkOutputWindow, vtkStringArray, vtkStringOutputWindow
from vtkmodules.vtkFiltersGeneral import vtkCellValidator
from vtkmodules.vtkFiltersVerdict import vtkCellSizeFilter
from vtkmodules.util.numpy_support import vtk_to_numpy

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)
sys.excepthook = lambda *e: (artest.say("".join(traceback.format_exception(*e))), sys.exit(3))
OUT = os.path.join(artest.OUTPUT_DIR, "GmshToFoam")
shutil.rmtree(OUT, ignore_errors=True)
os.makedirs(OUT)

def foam(case, command):
    return foamcase.run(BASHRC, case, command)


def boundary_patches(case):
    """{name: nFaces} of constant/polyMesh/boundary."""
    with open(os.path.join(case, "constant", "polyMesh", "boundary")) as f:
        return foamcase.boundary_patches(f.read())


def msh_patches(path):
    """{physical name: number of 2-D elements} and the 3-D group's name."""
    with open(path) as f:
        lines = f.read().split("\n")
    i = lines.index("$PhysicalNames")
    names = {}
    for l in lines[i + 2:i + 2 + int(lines[i + 1])]:
        dim, tag, name = l.split(None, 2)
        names[int(tag)] = (int(dim), name.strip('"'))
    j = lines.index("$Elements")
    counts = {}
    for l in lines[j + 2:j + 2 + int(lines[j + 1])]:
        v = l.split()
        dim, name = names[int(v[3])]
        if dim == 2:
            counts[name] = counts.get(name, 0) + 1
    volume = [n for d, n in names.values() if d == 3]
    return counts, volume


def run_case(label, grid, expected_types):
    """Writes `grid` as .msh, converts it, checks it. expected_types:
    checkMesh's names -> counts, from the input."""
    case = os.path.join(OUT, label)
    foamcase.make_case(case)
    msh = os.path.join(case, "mesh.msh")
    src = PVTrivialProducer()
    src.GetClientSideObject().SetOutput(grid)
    SaveData(msh, proxy=src)
    check(os.path.exists(msh), "%s: mesh.msh written" % label)
    written, volume_groups = msh_patches(msh)
    rc, log = foam(case, "gmshToFoam mesh.msh")
    check(rc == 0, "%s: gmshToFoam exits 0" % label)
    if rc != 0:
        artest.say(log[-2000:])
        return
    got = boundary_patches(case)
    check(got == written, "%s: polyMesh/boundary patches %s = the written physical groups %s" % (label, got, written))
    rc, log = foam(case, "checkMesh")
    check(rc == 0 and "Mesh OK." in log and "Failed" not in log,
          "%s: checkMesh exits 0 and says 'Mesh OK.' (no failed check)" % label)
    if "Mesh OK." not in log:
        artest.say(log[log.find("Checking"):][-3000:])
    cells = re.search(r"^\s*cells:\s+(\d+)", log, re.M)
    check(cells and int(cells.group(1)) == grid_cells(grid),
          "%s: checkMesh cells %s = ours %d" % (label, cells.group(1) if cells else None, grid_cells(grid)))
    types = {k: int(v) for k, v in re.findall(r"^\s+(hexahedra|prisms|pyramids|tetrahedra|polyhedra):\s+(\d+)", log, re.M)}
    want = {k: expected_types.get(k, 0) for k in ("hexahedra", "prisms", "pyramids", "tetrahedra", "polyhedra")}
    check(types == want, "%s: checkMesh cell types %s = ours %s" % (label, types, want))
    vol = re.search(r"Total volume = (\d+(?:\.\d+)?(?:[eE][-+]?\d+)?)", log)
    ours = grid_volume(grid)
    check(vol and abs(float(vol.group(1)) - ours) <= 1e-5 * ours,
          "%s: checkMesh total volume %s = ours %.7g" % (label, vol.group(1) if vol else None, ours))
    zone = re.search(r"^\s+%s\s+(\d+)\s" % re.escape(volume_groups[0]), log, re.M) if volume_groups else None
    check(zone and int(zone.group(1)) == grid_cells(grid),
          "%s: cellZone '%s' holds every cell" % (label, volume_groups[0] if volume_groups else None))


def grid_cells(grid):
    return sum(1 for c in range(grid.GetNumberOfCells()) if grid.GetCellType(c) in (10, 12, 13, 14))


def grid_volume(grid):
    size = vtkCellSizeFilter()
    size.SetInputData(grid)
    size.Update()
    return float(vtk_to_numpy(size.GetOutput().GetCellData().GetArray("Volume")).sum())


# ---- Data/wedge15Ma5.vtu: hexahedra, no patches.
reader = XMLUnstructuredGridReader(FileName=[artest.data("wedge15Ma5.vtu")])
reader.UpdatePipeline()
W = servermanager.Fetch(reader)
run_case("wedge15Ma5", W, {"hexahedra": W.GetNumberOfCells()})

# ---- A connected, conforming hybrid in VTK's node orders.
X = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1),
     (0.5, 0.5, 1.8), (2, 0, 0.5), (2, 1, 0.5), (1.3, -0.8, 0.5)]
CELLS = [(12, [0, 1, 2, 3, 4, 5, 6, 7]),   # hexahedron
         (14, [4, 5, 6, 7, 8]),             # pyramid on the hex's top face
         (13, [1, 9, 5, 2, 10, 6]),         # wedge on the hex's x = 1 face
         (10, [1, 9, 5, 11])]               # tetrahedron on the wedge's y = 0 triangle
H = artest.grid_of(X, CELLS)
validator = vtkCellValidator()
validator.SetInputData(H)
validator.Update()
states = vtk_to_numpy(validator.GetOutput().GetCellData().GetArray("ValidityState"))
check(np.all(states == 0), "hybrid: vtkCellValidator finds the 4 cells valid (%s)" % list(states))
# Patches: the hex bottom (quad) and the tet's three outer faces; the rest
# goes to the default patch.
pid = vtkIntArray()
pid.SetName("PatchId")
for _ in CELLS:
    pid.InsertNextValue(-1)
for t, ids, patch in ((9, [0, 3, 2, 1], 0), (5, [1, 11, 9], 1), (5, [9, 11, 5], 1), (5, [5, 11, 1], 1)):
    H.InsertNextCell(t, len(ids), ids)
    pid.InsertNextValue(patch)
H.GetCellData().AddArray(pid)
names = vtkStringArray()
names.SetName("PatchNames")
names.InsertNextValue("floor")
names.InsertNextValue("tip")
H.GetFieldData().AddArray(names)
run_case("hybrid", H, {"hexahedra": 1, "prisms": 1, "pyramids": 1, "tetrahedra": 1})

# ---- The cone's mesh adapted by EmbeddedRemesh: the solver takes it.
cone = XMLUnstructuredGridReader(FileName=[artest.data("cone20Ma2p5.vtu")])
fit = artest.cone_shock_fit(cone)
adapted = EmbeddedRemesh(Input=cone, Surfaces=[fit])
adapted.UpdatePipeline()
A = servermanager.Fetch(adapted)
check(A.GetCellData().GetArray("Region") is not None, "cone: EmbeddedRemesh ran (%d cells)" % A.GetNumberOfCells())
run_case("cone_adapted", A, {"tetrahedra": A.GetNumberOfCells()})

# ---- The same with prism layers on both sides of the shock cone: prisms,
# pyramids and tetrahedra (the solver takes the hybrid mesh).
layered = EmbeddedRemesh(Input=cone, Surfaces=[fit], LayerType="Prisms", NumberOfLayers=4)
layered.UpdatePipeline()
L = servermanager.Fetch(layered)
count = {t: sum(1 for c in range(L.GetNumberOfCells()) if L.GetCellType(c) == t) for t in (10, 13, 14)}
check(count[13] > 0 and count[14] > 0, "cone with prism layers: EmbeddedRemesh ran (%d prisms, %d pyramids, "
      "%d tetrahedra)" % (count[13], count[14], count[10]))
run_case("cone_adapted_prisms", L, {"prisms": count[13], "pyramids": count[14], "tetrahedra": count[10]})

artest.finish()
