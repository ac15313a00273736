"""The OpenFOAM case writer (SaveData 'case/case.foam') on four meshes, no
SourceCase, and on bad input.

Every written case is checked twice: by OpenFOAM's checkMesh ("Mesh OK.",
no failed check, its cell counts per type equal the input's 3-D cells) and
by this test's own reading of the polyMesh (foamcase.check_polymesh):
owner < neighbour and the internal faces sorted by owner then neighbour,
the patches contiguous after them, every cell closed, every face pointing
from owner to neighbour / out of the domain, every cell volume positive,
their sum the input's volume (VTK's vtkCellSizeFilter, to float precision); the checker itself
is shown to fail on a copy with one face reversed.
Meshes: (a) Data/oblique_shock_unstructured.vtu (tetrahedra; its point and
cell arrays become fields: cell arrays as they are, point-only ones
averaged to the cells, checked against vtkPointDataToCellData); (b)
EmbeddedRemesh's prism layers (LayerType Prisms: prisms, pyramids,
tetrahedra) on it; (c) Data/hybrid_wall.vtu (tetrahedra, prisms, hexahedra,
pyramids); (d) the OpenFOAM wedge (Data/wedge15Ma5.vtu as the OpenFOAM
reader's multiblock, with a frontAndBack patch) remeshed in 2-D by
EmbeddedRemesh: one cell deep, so frontAndBack is written `empty`, and
checkMesh must find a 2-D mesh (2 solution directions); (e) the same with
LayerType Prisms (layers of hexahedra along the shock, issue 13).
Bad input: an unwritable target (/proc), a non-empty directory that is not a
case the writer wrote, a volume with no 3-D cells, a SourceCase with no
constant/polyMesh/boundary, StartTime not a number: each an error naming
the cause, and nothing written (no case directory, no temporary left); a
failed overwrite leaves the previous case as it was.
"""
import glob
import os
import re
import shutil
import sys

import numpy as np
from paraview.simple import *
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkFiltersCore import vtkPointDataToCellData
from vtkmodules.vtkFiltersVerdict import vtkCellSizeFilter

import artest
import foamcase
from artest import check

BASHRC = foamcase.bashrc("the OpenFOAM case writer's checkMesh")
artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)
OUT = os.path.join(artest.OUTPUT_DIR, "FoamCaseWriterMeshes")
shutil.rmtree(OUT, ignore_errors=True)
os.makedirs(OUT)
TYPES = {10: "tetrahedra", 12: "hexahedra", 13: "prisms", 14: "pyramids"}


def volume_grid(data):
    """The 3-D cells' volume (vtkCellSizeFilter) and counts per checkMesh name."""
    if data.IsA("vtkMultiBlockDataSet"):
        data = data.GetBlock(0)
    types = vtk_to_numpy(data.GetCellTypesArray())
    size = vtkCellSizeFilter()
    size.SetInputData(data)
    size.Update()
    v = vtk_to_numpy(size.GetOutput().GetCellData().GetArray("Volume"))
    counts = {name: int((types == t).sum()) for t, name in TYPES.items() if (types == t).any()}
    return float(v[np.isin(types, list(TYPES))].sum()), counts


def write_and_check(label, proxy, data, two_d=False, **props):
    """SaveData into OUT/label/label.foam, checkMesh, check_polymesh."""
    case = os.path.join(OUT, label)
    before = len(messages.GetOutput())
    SaveData(os.path.join(case, label + ".foam"), proxy=proxy, **props)
    text = messages.GetOutput()[before:]
    check(os.path.isfile(os.path.join(case, label + ".foam")) and "ERROR" not in text,
          "%s: case written (marker file, no error) %r" % (label, text[-300:]))
    if not os.path.isdir(os.path.join(case, "constant", "polyMesh")):
        return case, None
    volume, counts = volume_grid(data)
    rc, log = foamcase.run(BASHRC, case, "checkMesh")
    ok = rc == 0 and "Mesh OK." in log and "Failed" not in log
    check(ok, "%s: checkMesh says 'Mesh OK.' (exit %d, no failed check)" % (label, rc))
    if not ok:
        artest.say(log[log.find("Checking"):][-3000:])
    found = {k: int(v) for k, v in re.findall(r"^\s+(hexahedra|prisms|pyramids|tetrahedra|polyhedra):\s+(\d+)", log, re.M)}
    found = {k: v for k, v in found.items() if v}
    check(found == counts, "%s: checkMesh's cells per type %s = the input's %s" % (label, found, counts))
    directions = re.search(r"Mesh has (\d) solution \(non-empty\) directions", log)
    want = 2 if two_d else 3
    check(directions and int(directions.group(1)) == want,
          "%s: checkMesh finds %d solution directions (%s)" % (label, want, directions.group(1) if directions else None))
    r = foamcase.check_polymesh(case, check, label)
    # 1e-7: coordinates a float holds exactly are written as the shortest
    # text of that float (the source's digits), within half a float ulp.
    check(abs(r[5].sum() - volume) <= 1e-7 * volume,
          "%s: the cells' volumes sum to the input's volume (%.12g, VTK %.12g)" % (label, r[5].sum(), volume))
    return case, r


# ---- (a) tetrahedra, fields from point and cell arrays.
tets = XMLUnstructuredGridReader(FileName=[artest.data("oblique_shock_unstructured.vtu")])
tdata = servermanager.Fetch(tets)


def check_fields(label, case, data):
    """Every array a field in 0/: cell arrays as they are, point-only arrays
    averaged to the cells (vtkPointDataToCellData), float exact."""
    cells = {data.GetCellData().GetArrayName(i) for i in range(data.GetCellData().GetNumberOfArrays())}
    points = {data.GetPointData().GetArrayName(i) for i in range(data.GetPointData().GetNumberOfArrays())}
    written = sorted(os.listdir(os.path.join(case, "0")))
    check(written == sorted(cells | points), "%s: every point and cell array is a field in 0/: %s" % (label, written))
    p2c = vtkPointDataToCellData()
    p2c.SetInputData(data)
    p2c.Update()
    for name in written:
        cls, dims, values, patches = foamcase.read_field(os.path.join(case, "0", name))
        source = data.GetCellData().GetArray(name) or p2c.GetOutput().GetCellData().GetArray(name)
        want = vtk_to_numpy(source).astype(np.float32)
        ncomp = source.GetNumberOfComponents()
        check(cls == ("volScalarField" if ncomp == 1 else "volVectorField") and dims == "[0 0 0 0 0 0 0]" and
              np.array_equal(values.astype(np.float32), want.reshape(values.shape)) and
              all(re.search(r"type\s+zeroGradient;", e) for e in patches.values()),
              "%s: field %s (%s) is the input's %s array, cell for cell (float exact), dimensionless, zeroGradient"
              % (label, name, cls, "cell" if name in cells else "point (averaged)"))


case, r = write_and_check("tetrahedra", tets, tdata)
check_fields("tetrahedra", case, tdata)

# ---- (b) prism layers of EmbeddedRemesh.
weight = WeightFunction(Input=tets, Variables=["p", "rho"], ComputePointWeight=1)
clusters = FeatureCluster(Input=weight, SensorArray=["POINTS", "WeightFunction"], SensorRange=[1.5, 2.0])
plane = QuadricFit(Input=OutputPort(clusters, 1), Domain=tets, Template="Plane", ClusterId=0)
layered = EmbeddedRemesh(Input=tets, Surfaces=[plane], LayerType="Prisms", NumberOfLayers=2)
ldata = servermanager.Fetch(layered)
_, counts = volume_grid(ldata)
check(counts.get("prisms", 0) > 0 and counts.get("tetrahedra", 0) > 0, "prisms: EmbeddedRemesh made prism layers %s" % counts)
write_and_check("prisms", layered, ldata)

# ---- (c) the hybrid wall mesh.
hybrid = XMLUnstructuredGridReader(FileName=[artest.data("hybrid_wall.vtu")])
hdata = servermanager.Fetch(hybrid)
_, counts = volume_grid(hdata)
check(len(counts) == 4, "hybrid: the input has tetrahedra, prisms, hexahedra and pyramids %s" % counts)
case, r = write_and_check("hybrid", hybrid, hdata)
check_fields("hybrid", case, hdata)

# ---- (d) the 2-D wedge remeshed by EmbeddedRemesh: frontAndBack empty.
wedge = XMLUnstructuredGridReader(FileName=[artest.data("wedge15Ma5.vtu")])


PATCHES = artest.WEDGE_PATCHES
source, _ = artest.wedge_multiblock(wedge)
wfit = artest.wedge_shock_plane(wedge)
adapted = EmbeddedRemesh(Input=source, Surfaces=[wfit])
adata = servermanager.Fetch(adapted)
_, counts = volume_grid(adata)
check(counts.get("prisms", 0) > 0 and "tetrahedra" not in counts, "2-D: the wedge remeshed in 2-D %s" % counts)
case, r = write_and_check("wedge2D", adapted, adata, two_d=True)
if r is not None:
    types = {name: e["type"] for name, e in r[4]}
    want = {name: ("empty" if name == "frontAndBack" else "patch") for name in PATCHES}
    check(types == want, "2-D: patch types %s (frontAndBack empty, one cell deep; the others patch)" % types)
    faces = {name: int(e["nFaces"]) for name, e in r[4]}
    blocks = {name: adata.GetBlock(1).GetBlock(i).GetNumberOfCells() for i, name in enumerate(PATCHES)}
    check(faces == blocks, "2-D: faces per patch %s = EmbeddedRemesh's patch blocks %s" % (faces, blocks))
    cls, _, _, patches = foamcase.read_field(os.path.join(case, "0", "p"))
    check(re.search(r"type\s+empty;", patches["frontAndBack"]) is not None, "2-D: field p is empty on frontAndBack")

# ---- (e) the 2-D wedge with layers (issue 13): hexahedra along the shock
# between the planes, wedges elsewhere; frontAndBack holds their quads.
layered2d = EmbeddedRemesh(Input=source, Surfaces=[wfit], LayerType="Prisms")
l2data = servermanager.Fetch(layered2d)
_, counts = volume_grid(l2data)
check(counts.get("hexahedra", 0) > 0 and counts.get("prisms", 0) > 0 and len(counts) == 2,
      "2-D layers: the wedge remeshed in 2-D with layers of hexahedra %s" % counts)
case, r = write_and_check("wedge2DLayers", layered2d, l2data, two_d=True)
if r is not None:
    faces = {name: int(e["nFaces"]) for name, e in r[4]}
    blocks = {name: l2data.GetBlock(1).GetBlock(i).GetNumberOfCells() for i, name in enumerate(PATCHES)}
    check(faces == blocks, "2-D layers: faces per patch %s = EmbeddedRemesh's patch blocks %s" % (faces, blocks))

# ---- The checker can fail: one face reversed in a copy.
bad = os.path.join(OUT, "reversed")
shutil.copytree(os.path.join(OUT, "hybrid"), bad)
path = os.path.join(bad, "constant", "polyMesh", "faces")
with open(path) as f:
    text = f.read()
m = re.search(r"\n(\d)\(([^()]*)\)\n", text)
text = text[:m.start()] + "\n%s(%s)\n" % (m.group(1), " ".join(reversed(m.group(2).split()))) + text[m.end():]
with open(path, "w") as f:
    f.write(text)
failures = []
foamcase.check_polymesh(bad, lambda ok, msg: failures.append(msg) if not ok else None, "reversed")
check(any("points from its owner" in f for f in failures) and any("closed" in f for f in failures),
      "the polyMesh checker fails on a copy with one face reversed (%d checks failed)" % len(failures))


# ---- Bad input: an error naming the cause, nothing written.
def refused(label, proxy, path, fragment, **props):
    case = os.path.dirname(path)
    parent, name = os.path.dirname(case), os.path.basename(case)
    existed = os.path.exists(case)
    before_entries = set(os.listdir(parent)) if os.path.isdir(parent) else set()
    before = len(messages.GetOutput())
    SaveData(path, proxy=proxy, **props)
    text = messages.GetOutput()[before:]
    check(fragment in text and "nothing is written" in text, "%s: error says %r (%r)" % (label, fragment, text[-400:].strip()))
    new = [e for e in (set(os.listdir(parent)) if os.path.isdir(parent) else set()) - before_entries if name in e]
    check(not new and os.path.exists(case) == existed,
          "%s: nothing written, no temporary left in %s %s" % (label, parent, new))


refused("unwritable", hybrid, "/proc/arcase/arcase.foam", "cannot create")
foreign = os.path.join(OUT, "foreign")
os.makedirs(foreign)
with open(os.path.join(foreign, "notes.txt"), "w") as f:
    f.write("mine\n")
refused("foreign directory", hybrid, os.path.join(foreign, "foreign.foam"), "not empty and holds no case")
check(os.listdir(foreign) == ["notes.txt"], "foreign directory: its file untouched")
tri = artest.grid_of([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [(5, [0, 1, 2])])
tri_source = PVTrivialProducer()
tri_source.GetClientSideObject().SetOutput(tri)
refused("no 3-D cells", tri_source, os.path.join(OUT, "flat", "flat.foam"), "no 3-D cells")
nomesh = os.path.join(OUT, "nomesh_source")
os.makedirs(os.path.join(nomesh, "system"))
refused("SourceCase without polyMesh", hybrid, os.path.join(OUT, "c1", "c1.foam"), "has no constant/polyMesh/boundary",
        SourceCase=nomesh)
refused("StartTime", hybrid, os.path.join(OUT, "c2", "c2.foam"), "is not a number", StartTime="start")
# A failed overwrite of a case the writer wrote leaves it as it was.
keep = os.path.join(OUT, "hybrid")
snapshot = {p: open(p, "rb").read() for p in glob.glob(os.path.join(keep, "**"), recursive=True) if os.path.isfile(p)}
refused("failed overwrite", tri_source, os.path.join(keep, "hybrid.foam"), "no 3-D cells")
now = {p: open(p, "rb").read() for p in glob.glob(os.path.join(keep, "**"), recursive=True) if os.path.isfile(p)}
check(now == snapshot, "failed overwrite: the existing case (%d files) is untouched" % len(snapshot))
# A successful overwrite replaces it as a whole.
with open(os.path.join(keep, "extra"), "w") as f:
    f.write("solver output\n")
SaveData(os.path.join(keep, "hybrid.foam"), proxy=hybrid)
check(not os.path.exists(os.path.join(keep, "extra")) and os.path.isfile(os.path.join(keep, "constant", "polyMesh", "faces")),
      "overwrite: a case the writer wrote is replaced as a whole")
artest.finish()
