"""The OpenFOAM wedge adapted by EmbeddedRemesh's 2-D mode goes back to
OpenFOAM as a 2-D case: the wedge as an OpenFOAM-reader multiblock
(internalMesh + inlet, outlet, top, obstacle, frontAndBack), remeshed around
QuadricFit's shock plane, written with the Gmsh writer (SaveData '.msh'),
converted by gmshToFoam; frontAndBack set to `empty`; checkMesh must say
"Mesh OK." with two solution directions (a 2-D mesh), our cell counts per
type (hexahedra and prisms) and our total volume, and polyMesh/boundary must
hold each patch with the faces we wrote.
Fails (naming the package) when OpenFOAM is not installed: the README's
set-up installs it (AR_OPENFOAM_BASHRC overrides where its bashrc is looked
for).
"""
import os
import re
import shutil
import sys

import artest
import foamcase
from artest import check

BASHRC = foamcase.bashrc("gmshToFoam")

import numpy as np
from paraview.simple import *
from paraview import servermanager
from vtkmodules.vtkFiltersVerdict import vtkCellSizeFilter
from vtkmodules.util.numpy_support import vtk_to_numpy

artest.load_plugin(globals())
CASE = os.path.join(artest.OUTPUT_DIR, "EmbeddedRemesh2DFoam")
shutil.rmtree(CASE, ignore_errors=True)
foamcase.make_case(CASE)


def foam(command):
    return foamcase.run(BASHRC, CASE, command)


# ---- The wedge as the OpenFOAM reader gives it, the shock plane, the 2-D remesh.
reader = XMLUnstructuredGridReader(FileName=[artest.data("wedge15Ma5.vtu")])


source, names = artest.wedge_multiblock(reader)
patches = artest.WEDGE_PATCHES
fit = artest.wedge_shock_plane(reader)
adapted = EmbeddedRemesh(Input=source, Surfaces=[fit])
adapted.UpdatePipeline()
out = servermanager.Fetch(adapted)
mesh = out.GetBlock(0)
types = vtk_to_numpy(mesh.GetCellTypesArray())
n_hex, n_prism = int(np.sum(types == 12)), int(np.sum(types == 13))
check(mesh.GetCellData().GetArray("Region") is not None and n_prism > 0,
      "the wedge remeshed in 2-D: %d hexahedra, %d prisms" % (n_hex, n_prism))
written = {name: out.GetBlock(1).GetBlock(i).GetNumberOfCells() for i, name in enumerate(patches)}

# ---- .msh -> gmshToFoam -> frontAndBack empty -> checkMesh.
msh = os.path.join(CASE, "mesh.msh")
SaveData(msh, proxy=adapted)
check(os.path.exists(msh), "mesh.msh written")
rc, log = foam("gmshToFoam mesh.msh")
check(rc == 0, "gmshToFoam exits 0")
if rc != 0:
    artest.say(log[-2000:])
    artest.finish()
path = os.path.join(CASE, "constant", "polyMesh", "boundary")
with open(path) as f:
    text = f.read()
got = foamcase.boundary_patches(text)
check(got == written, "polyMesh/boundary patches %s = the written patches %s" % (got, written))
text, n = re.subn(r"(frontAndBack\s*\{[^{}]*?type\s+)\w+;", r"\1empty;", text)
with open(path, "w") as f:
    f.write(text)
check(n == 1, "frontAndBack set to empty")
rc, log = foam("checkMesh")
check(rc == 0 and "Mesh OK." in log and "Failed" not in log, "checkMesh exits 0 and says 'Mesh OK.' (no failed check)")
if "Mesh OK." not in log:
    artest.say(log[log.find("Checking"):][-3000:])
check("Mesh has 2 solution (non-empty) directions" in log, "checkMesh: a 2-D mesh (two solution directions)")
found = {k: int(v) for k, v in re.findall(r"^\s+(hexahedra|prisms|tetrahedra|pyramids|polyhedra):\s+(\d+)", log, re.M)}
check(found.get("hexahedra") == n_hex and found.get("prisms") == n_prism and found.get("tetrahedra", 0) == 0,
      "checkMesh cell types %s = ours (%d hexahedra, %d prisms)" % (found, n_hex, n_prism))
size = vtkCellSizeFilter()
size.SetInputData(mesh)
size.Update()
ours = float(vtk_to_numpy(size.GetOutput().GetCellData().GetArray("Volume")).sum())
vol = re.search(r"Total volume = (\d+(?:\.\d+)?(?:[eE][-+]?\d+)?)", log)
check(vol and abs(float(vol.group(1)) - ours) <= 1e-5 * ours,
      "checkMesh total volume %s = ours %.7g" % (vol.group(1) if vol else None, ours))
artest.finish()
