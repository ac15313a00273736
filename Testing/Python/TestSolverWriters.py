"""The solver-mesh writers (Gmsh MSH 2.2, SU2) through paraview.simple's
SaveData, on the three input forms; every written file is parsed back here:
- node count, element counts per type, physical names / marker tags and the
  number of faces per patch equal what the input holds (counted from the
  input with VTK, not typed in);
- every volume element read back in the format's node order has a positive
  Jacobian at each corner, using the format's own reference element (Gmsh
  reference manual, "Node ordering"; SU2 = VTK's orders), and the checker
  refuses a wedge written in the other order (it can fail);
- the total boundary area equals the VTK mesh's boundary area (1e-9
  relative), per patch too, and the volume enclosed by the written boundary
  faces (divergence theorem) equals the VTK mesh's volume: the faces are
  complete and point out of the domain;
- gmsh reads the .msh back (`gmsh f.msh -0`), with the same node and element
  counts;
- bad input (no 3-D cells, quadratic and polyhedral cells, an inverted
  cell, NaN, a patch face off the volume or on an interior face, an
  unwritable path) gives an error naming the problem and no file, and an
  existing file is left untouched.
Meshes: a hand-made hybrid (one hexahedron, tetrahedron, wedge and pyramid,
mapped by a random affine map, checked valid by vtkCellValidator), in forms
(b) PatchId/PatchNames, (c) volume only and (a) a multiblock of polydata
patches; Data/wedge15Ma5.vtu (hexahedra, form (c)); and the OpenFOAM reader's
multiblock of the wedge15Ma5 tutorial after blockMesh (form (a)). gmsh reads
every .msh back. gmsh, OpenFOAM and its tutorials are installed by the
README's set-up; where one is missing the test fails naming its package.
"""
import glob
import os
import shutil
import subprocess
import sys
import traceback

import numpy as np
from paraview.simple import *
from vtkmodules.vtkCommonCore import (vtkIdList, vtkOutputWindow, vtkPoints, vtkStringArray,
                                      vtkStringOutputWindow, vtkIntArray)
from vtkmodules.vtkCommonDataModel import (vtkCompositeDataSet, vtkMultiBlockDataSet, vtkPolyData,
                                           vtkUnstructuredGrid, vtkCellArray)
from vtkmodules.vtkFiltersGeneral import vtkCellValidator
from vtkmodules.vtkFiltersGeometry import vtkGeometryFilter
from vtkmodules.vtkFiltersVerdict import vtkCellSizeFilter
from vtkmodules.util.numpy_support import vtk_to_numpy

import artest
import foamcase
from artest import check

GMSH = artest.require_program("gmsh", "gmsh")
BASHRC = foamcase.bashrc("the OpenFOAM reader's multiblock of the wedge15Ma5 tutorial")
TUTORIAL = foamcase.tutorial("compressible/rhoCentralFoam/wedge15Ma5")

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)
sys.excepthook = lambda *e: (artest.say("".join(traceback.format_exception(*e))), sys.exit(3))
OUT = os.path.join(artest.OUTPUT_DIR, "SolverWriters")
shutil.rmtree(OUT, ignore_errors=True)
os.makedirs(OUT)
rng = np.random.default_rng(11)

VTK_TRIANGLE, VTK_QUAD, VTK_TETRA, VTK_HEX, VTK_WEDGE, VTK_PYRAMID = 5, 9, 10, 12, 13, 14
NAMES = {VTK_TETRA: "tet", VTK_HEX: "hex", VTK_WEDGE: "wedge", VTK_PYRAMID: "pyramid",
         VTK_TRIANGLE: "tri", VTK_QUAD: "quad"}
GMSH_TO_VTK = {2: VTK_TRIANGLE, 3: VTK_QUAD, 4: VTK_TETRA, 5: VTK_HEX, 6: VTK_WEDGE, 7: VTK_PYRAMID}

# ---- Reference elements. Gmsh: reference manual, "Node ordering" (prism:
# 0 at the origin, 1 along u, 2 along v, 3 above 0 along w; pyramid: base
# 0 (0,0), 1 along u, 3 along v, apex along w). VTK/SU2 (VTK class docs,
# SU2 uses VTK's orders): the first face's right-hand normal points to the
# last node (tet), the opposite face (hex), the apex (pyramid), but AWAY
# from the top triangle (wedge).
TET = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
HEX = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
PYR = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0.5, 0.5, 1)]
REF_GMSH = {VTK_TETRA: TET, VTK_HEX: HEX, VTK_PYRAMID: PYR,
            VTK_WEDGE: [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (0, 1, 1)]}
REF_VTK = {VTK_TETRA: TET, VTK_HEX: HEX, VTK_PYRAMID: PYR,
           VTK_WEDGE: [(0, 0, 0), (0, 1, 0), (1, 0, 0), (0, 0, 1), (0, 1, 1), (1, 0, 1)]}
EDGES = {VTK_TETRA: [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)],
         VTK_HEX: [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)],
         VTK_WEDGE: [(0, 1), (1, 2), (2, 0), (3, 4), (4, 5), (5, 3), (0, 3), (1, 4), (2, 5)],
         VTK_PYRAMID: [(0, 1), (1, 2), (2, 3), (3, 0), (0, 4), (1, 4), (2, 4), (3, 4)]}


def corner_stencils(ref, edges):
    """For each corner with three edges: (corner, neighbours, sign of the
    reference Jacobian with the neighbours in that order)."""
    ref = np.asarray(ref, float)
    out = []
    for i in range(len(ref)):
        nb = [b if a == i else a for a, b in edges if i in (a, b)]
        if len(nb) != 3:
            continue  # the pyramid's apex
        s = np.sign(np.linalg.det(np.array([ref[j] - ref[i] for j in nb])))
        assert s != 0
        out.append((i, nb, s))
    return out


STENCILS = {"gmsh": {t: corner_stencils(REF_GMSH[t], EDGES[t]) for t in EDGES},
            "su2": {t: corner_stencils(REF_VTK[t], EDGES[t]) for t in EDGES}}


def min_corner_jacobian(x, nodes, vtk_type, convention):
    """Smallest corner Jacobian of an element read back in `convention`'s node
    order, signed so that a valid element has all of them positive."""
    worst = np.inf
    for i, nb, s in STENCILS[convention][vtk_type]:
        j = s * np.linalg.det(np.array([x[nodes[k]] - x[nodes[i]] for k in nb]))
        worst = min(worst, j)
    return worst


def face_area_and_flux(x, faces):
    """Area and (1/3) sum x.n dA of polygons (fan triangles)."""
    area = 0.0
    flux = 0.0
    for f in faces:
        p = x[list(f)]
        for t in range(1, len(f) - 1):
            c = np.cross(p[t] - p[0], p[t + 1] - p[0])
            area += 0.5 * np.linalg.norm(c)
            flux += np.dot(p[0], c) / 6.0
    return area, flux


# ---------------------------------------------------------------- parsers
def parse_msh(path):
    with open(path) as f:
        lines = f.read().split("\n")
    i = 0
    mesh = {"names": {}, "nodes": None, "elements": []}
    while i < len(lines):
        line = lines[i].strip()
        if line == "$MeshFormat":
            mesh["format"] = lines[i + 1].strip()
            i += 2
        elif line == "$PhysicalNames":
            n = int(lines[i + 1])
            for k in range(n):
                dim, tag, name = lines[i + 2 + k].split(None, 2)
                mesh["names"][int(tag)] = (int(dim), name.strip().strip('"'))
            i += 2 + n
        elif line == "$Nodes":
            n = int(lines[i + 1])
            rows = np.array([l.split() for l in lines[i + 2:i + 2 + n]], float)
            assert np.all(rows[:, 0] == np.arange(1, n + 1)), "node ids are not 1..n"
            mesh["nodes"] = np.vstack([np.zeros(3), rows[:, 1:4]])  # 1-based
            i += 2 + n
        elif line == "$Elements":
            n = int(lines[i + 1])
            for l in lines[i + 2:i + 2 + n]:
                v = [int(t) for t in l.split()]
                etype, ntags = v[1], v[2]
                mesh["elements"].append((GMSH_TO_VTK[etype], v[3:3 + ntags], v[3 + ntags:]))
            i += 2 + n
        else:
            i += 1
    return mesh


def parse_su2(path):
    with open(path) as f:
        lines = [l.split("%")[0].strip() for l in f]
    lines = [l for l in lines if l]
    mesh = {"elements": [], "markers": {}}
    i = 0
    while i < len(lines):
        key, _, value = lines[i].partition("=")
        if key == "NDIME":
            mesh["ndime"] = int(value)
            i += 1
        elif key == "NELEM":
            n = int(value)
            for k, l in enumerate(lines[i + 1:i + 1 + n]):
                v = [int(t) for t in l.split()]
                assert v[-1] == k, "element index"
                mesh["elements"].append((v[0], v[1:-1]))
            i += 1 + n
        elif key == "NPOIN":
            n = int(value)
            rows = np.array([l.split() for l in lines[i + 1:i + 1 + n]], float)
            assert np.all(rows[:, 3] == np.arange(n)), "point index"
            mesh["nodes"] = rows[:, :3]
            i += 1 + n
        elif key == "NMARK":
            mesh["nmark"] = int(value)
            i += 1
        elif key == "MARKER_TAG":
            tag = value.strip()
            n = int(lines[i + 1].partition("=")[2])
            assert lines[i + 1].startswith("MARKER_ELEMS"), "MARKER_ELEMS after MARKER_TAG"
            mesh["markers"][tag] = [[int(t) for t in l.split()] for l in lines[i + 2:i + 2 + n]]
            i += 2 + n
        else:
            raise AssertionError("unexpected line in %s: %r" % (path, lines[i]))
    return mesh


def normalized(path):
    """(nodes, volume elements [(vtk type, nodes 0-based in the format's
    order)], patches {name: [faces]}) of a written file."""
    if path.endswith(".msh"):
        m = parse_msh(path)
        vol_tags = [t for t, (d, _) in m["names"].items() if d == 3]
        check(m["format"] == "2.2 0 8", "%s: $MeshFormat 2.2 0 8" % os.path.basename(path))
        check(len(vol_tags) == 1, "%s: one 3-D physical group" % os.path.basename(path))
        volume, patches = [], {}
        for t, tags, nodes in m["elements"]:
            ids = [n - 1 for n in nodes]
            dim, name = m["names"][tags[0]]
            if t in (VTK_TRIANGLE, VTK_QUAD):
                assert dim == 2, "a face in a 3-D group"
                patches.setdefault(name, []).append(ids)
            else:
                assert dim == 3, "a volume element in a 2-D group"
                volume.append((t, ids))
        return m["nodes"][1:], volume, patches, m["names"][vol_tags[0]][1] if vol_tags else None
    m = parse_su2(path)
    check(m["ndime"] == 3 and m["nmark"] == len(m["markers"]),
          "%s: NDIME= 3, NMARK equals the markers" % os.path.basename(path))
    patches = {k: [f[1:] for f in v] for k, v in m["markers"].items()}
    for k, v in m["markers"].items():
        assert all((f[0] == 5 and len(f) == 4) or (f[0] == 9 and len(f) == 5) for f in v), "marker element types"
    return m["nodes"], m["elements"], patches, None


# ---------------------------------------------------------------- VTK references
def grid_numbers(grid):
    """Volume cell counts by type, volume, boundary area, used points of a
    grid's 3-D cells (computed by VTK)."""
    vol = vtkUnstructuredGrid()
    pts = grid.GetPoints()
    vol.SetPoints(pts)
    vol.Allocate(grid.GetNumberOfCells())
    counts = {}
    ids = vtkIdList()
    used = set()
    for c in range(grid.GetNumberOfCells()):
        t = grid.GetCellType(c)
        if t in (VTK_TETRA, VTK_HEX, VTK_WEDGE, VTK_PYRAMID):
            grid.GetCellPoints(c, ids)
            vol.InsertNextCell(t, ids)
            counts[t] = counts.get(t, 0) + 1
            used.update(ids.GetId(i) for i in range(ids.GetNumberOfIds()))
    size = vtkCellSizeFilter()
    size.SetInputData(vol)
    size.Update()
    volume = vtk_to_numpy(size.GetOutput().GetCellData().GetArray("Volume")).sum()
    geom = vtkGeometryFilter()
    geom.SetInputData(vol)
    geom.Update()
    surf = geom.GetOutput()
    size2 = vtkCellSizeFilter()
    size2.SetInputData(surf)
    size2.Update()
    area = vtk_to_numpy(size2.GetOutput().GetCellData().GetArray("Area")).sum()
    return counts, volume, area, len(used), surf.GetNumberOfCells()


def verify(path, grid, patch_faces, label, volume_name=None):
    """Parses `path` and checks it against the VTK grid `grid` (3-D cells)
    and the expected {patch name: number of faces}."""
    name = "%s %s" % (label, os.path.splitext(path)[1])
    check(os.path.exists(path), "%s: file written" % name)
    if not os.path.exists(path):
        return
    convention = "gmsh" if path.endswith(".msh") else "su2"
    counts, volume, area, n_used, n_boundary = grid_numbers(grid)
    x, elements, patches, vname = normalized(path)
    check(len(x) == n_used, "%s: %d nodes = the points of the 3-D cells (%d)" % (name, len(x), n_used))
    got = {}
    for t, _ in elements:
        got[t] = got.get(t, 0) + 1
    check(got == counts, "%s: elements per type %s = input %s" % (
        name, {NAMES[k]: v for k, v in got.items()}, {NAMES[k]: v for k, v in counts.items()}))
    worst = min(min_corner_jacobian(x, nodes, t, convention) for t, nodes in elements)
    check(worst > 0, "%s: every element has positive corner Jacobians in the %s order (min %.3g)" % (name, convention, worst))
    check({k: len(v) for k, v in patches.items()} == patch_faces,
          "%s: patches and faces %s = expected %s" % (name, {k: len(v) for k, v in patches.items()}, patch_faces))
    all_faces = [f for v in patches.values() for f in v]
    check(len(all_faces) == n_boundary, "%s: %d boundary faces = VTK's surface (%d)" % (name, len(all_faces), n_boundary))
    a, flux = face_area_and_flux(x, all_faces)
    check(abs(a - area) <= 1e-9 * area, "%s: boundary area %.12g = VTK's %.12g" % (name, a, area))
    check(abs(flux - volume) <= 1e-9 * volume,
          "%s: volume enclosed by the outward boundary faces %.12g = VTK's %.12g" % (name, flux, volume))
    if volume_name is not None:
        check(vname == volume_name, "%s: volume physical group named %r" % (name, vname))
    if convention == "gmsh":
        r = subprocess.run([GMSH, path, "-0", "-o", path + ".gmsh.msh", "-format", "msh22"],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60)
        ok = r.returncode == 0 and "Error" not in r.stdout
        check(ok, "%s: gmsh reads it back (exit %d)" % (name, r.returncode))
        if ok:
            m2 = parse_msh(path + ".gmsh.msh")
            check(len(m2["nodes"]) - 1 == len(x) and len(m2["elements"]) == len(elements) + len(all_faces),
                  "%s: gmsh's copy has the same nodes and elements" % name)
    return x, elements, patches


def producer(data):
    src = PVTrivialProducer()
    src.GetClientSideObject().SetOutput(data)
    return src


def save(data, path, **props):
    if os.path.exists(path):
        os.remove(path)
    before = len(messages.GetOutput())
    SaveData(path, proxy=producer(data), **props)
    return messages.GetOutput()[before:]


# ---------------------------------------------------------------- the hybrid mesh
def hybrid():
    """One hexahedron, tetrahedron, wedge and pyramid (VTK node orders),
    apart from each other, mapped by a random affine map of positive
    determinant."""
    cells = []
    pts = []

    def add(t, coords, shift):
        base = len(pts)
        pts.extend(np.asarray(coords, float) + [shift, 0, 0])
        cells.append((t, list(range(base, base + len(coords)))))

    add(VTK_HEX, HEX, 0.0)
    add(VTK_TETRA, TET, 2.0)
    add(VTK_WEDGE, REF_VTK[VTK_WEDGE], 4.0)
    add(VTK_PYRAMID, PYR, 6.0)
    A = np.eye(3) + 0.3 * rng.standard_normal((3, 3))
    if np.linalg.det(A) < 0:
        A[:, 0] *= -1
    x = np.asarray(pts) @ A.T + rng.standard_normal(3)
    return artest.grid_of(x, cells)


def cell_faces_of(grid, cell):
    """The faces of one cell (VTK's face tables) as point-id lists."""
    c = grid.GetCell(cell)
    return [[c.GetFace(f).GetPointId(i) for i in range(c.GetFace(f).GetNumberOfPoints())]
            for f in range(c.GetNumberOfFaces())]


H = hybrid()
validator = vtkCellValidator()
validator.SetInputData(H)
validator.Update()
states = vtk_to_numpy(validator.GetOutput().GetCellData().GetArray("ValidityState"))
check(np.all(states == 0), "hybrid input: vtkCellValidator finds all 4 cells valid (states %s)" % list(states))

# The checker has teeth: the VTK wedge read in Gmsh's order is inverted.
xw = np.array([H.GetPoint(i) for i in range(H.GetNumberOfPoints())])
wedge_ids = [H.GetCell(2).GetPointId(i) for i in range(6)]
check(min_corner_jacobian(xw, wedge_ids, VTK_WEDGE, "su2") > 0 and
      min_corner_jacobian(xw, wedge_ids, VTK_WEDGE, "gmsh") < 0,
      "checker: a VTK wedge is valid in the VTK/SU2 order and inverted in Gmsh's (so the writer must reorder)")

# Form (c): volume only -> one patch.
for ext in (".msh", ".su2"):
    path = os.path.join(OUT, "hybrid_c" + ext)
    save(H, path)
    verify(path, H, {"boundary": 20}, "hybrid form (c)", volume_name="fluid" if ext == ".msh" else None)
path = os.path.join(OUT, "hybrid_c_named.msh")
save(H, path, VolumeName="air", DefaultPatchName="walls")
verify(path, H, {"walls": 20}, "hybrid form (c), named", volume_name="air")

# Form (b): PatchId boundary cells + PatchNames. wall: hex bottom + tet base
# (given in the inward order: written outward anyway); inlet: a wedge
# triangle; the rest (17 faces) goes to the default patch.
def with_patches(names=True):
    g = vtkUnstructuredGrid()
    g.DeepCopy(H)
    pid = vtkIntArray()
    pid.SetName("PatchId")
    for _ in range(4):
        pid.InsertNextValue(-1)
    hexf = cell_faces_of(H, 0)
    tetf = cell_faces_of(H, 1)
    wedf = cell_faces_of(H, 2)
    for ids, patch in ((hexf[4], 0), (tetf[3][::-1], 0), (wedf[0], 1)):
        g.InsertNextCell(VTK_QUAD if len(ids) == 4 else VTK_TRIANGLE, len(ids), ids)
        pid.InsertNextValue(patch)
    g.GetCellData().AddArray(pid)
    if names:
        s = vtkStringArray()
        s.SetName("PatchNames")
        s.InsertNextValue("wall")
        s.InsertNextValue("inlet")
        g.GetFieldData().AddArray(s)
    return g


B = with_patches()
for ext in (".msh", ".su2"):
    path = os.path.join(OUT, "hybrid_b" + ext)
    text = save(B, path)
    x, elements, patches = verify(path, H, {"wall": 2, "inlet": 1, "boundary": 17}, "hybrid form (b)")
    check("17 boundary faces of the volume are in no patch" in text, "form (b) %s: warns about the 17 unpatched faces" % ext)
    # The wall's faces are the hex bottom and the tet base, as sets of points.
    hexf, tetf = cell_faces_of(H, 0), cell_faces_of(H, 1)
    want = sorted([sorted(xw[hexf[4]].round(12).tolist()), sorted(xw[tetf[3]].round(12).tolist())])
    got = sorted(sorted(x[f].round(12).tolist()) for f in patches["wall"])
    check(got == want, "form (b) %s: patch 'wall' holds exactly the hex bottom and the tet base" % ext)
path = os.path.join(OUT, "hybrid_b_nonames.su2")
save(with_patches(names=False), path)
verify(path, H, {"patch0": 2, "patch1": 1, "boundary": 17}, "hybrid form (b) without PatchNames")

# Form (a): a multiblock: the volume and a "boundary" block of polydata
# patches with their own (float) copies of the points.
def patch_poly(faces_xyz):
    pd = vtkPolyData()
    p = vtkPoints()  # float, as the OpenFOAM reader gives
    polys = vtkCellArray()
    for f in faces_xyz:
        polys.InsertNextCell(len(f))
        for q in f:
            polys.InsertCellPoint(p.InsertNextPoint(*q))
    pd.SetPoints(p)
    pd.SetPolys(polys)
    return pd


def multiblock(extra=None):
    mb = vtkMultiBlockDataSet()
    mb.SetBlock(0, H)
    mb.GetMetaData(0).Set(vtkCompositeDataSet.NAME(), "internalMesh")
    bnd = vtkMultiBlockDataSet()
    all_faces = [(c, f) for c in range(4) for f in cell_faces_of(H, c)]
    groups = {"hexSides": [f for c, f in all_faces if c == 0],
              "others": [f for c, f in all_faces if c != 0][:-1]}
    groups = {k: [[xw[i] for i in f] for f in v] for k, v in groups.items()}
    if extra:  # {name: faces as coordinates}
        groups.update(extra)
    for i, (name, faces) in enumerate(groups.items()):
        bnd.SetBlock(i, patch_poly(faces))
        bnd.GetMetaData(i).Set(vtkCompositeDataSet.NAME(), name)
    mb.SetBlock(1, bnd)
    mb.GetMetaData(1).Set(vtkCompositeDataSet.NAME(), "boundary")
    return mb


# H's points are doubles; the patches' float copies differ by ~1e-8 relative
# (the OpenFOAM reader's blocks share exact floats): the default tolerance
# 1e-6 of the diagonal matches them.
M = multiblock()
for ext in (".msh", ".su2"):
    path = os.path.join(OUT, "hybrid_a" + ext)
    save(M, path)
    verify(path, H, {"hexSides": 6, "others": 13, "boundary": 1}, "hybrid form (a)")

# ---------------------------------------------------------------- wedge15Ma5 (hexahedra, form (c))
reader = XMLUnstructuredGridReader(FileName=[artest.data("wedge15Ma5.vtu")])
reader.UpdatePipeline()
from paraview import servermanager
W = servermanager.Fetch(reader)
for ext in (".msh", ".su2"):
    path = os.path.join(OUT, "wedge15Ma5" + ext)
    SaveData(path, proxy=reader)
    n_boundary = grid_numbers(W)[4]
    verify(path, W, {"boundary": n_boundary}, "wedge15Ma5 form (c)")

# ---------------------------------------------------------------- OpenFOAM reader multiblock (form (a))
case = os.path.join(OUT, "foamcase")
shutil.rmtree(case, ignore_errors=True)
shutil.copytree(TUTORIAL, case)
code, _ = foamcase.run(BASHRC, case, "blockMesh")
check(code == 0, "OpenFOAM case: blockMesh exits 0")
open(os.path.join(case, "case.foam"), "w").close()
foam = OpenFOAMReader(FileName=os.path.join(case, "case.foam"))
foam.MeshRegions = ["internalMesh"] + [n for n in foam.MeshRegions.Available if n.startswith("patch/")]
foam.UpdatePipeline()
F = servermanager.Fetch(foam)
volume = F.GetBlock(0)
expected = {}
bnd = F.GetBlock(1)
for i in range(bnd.GetNumberOfBlocks()):
    expected[bnd.GetMetaData(i).Get(vtkCompositeDataSet.NAME())] = bnd.GetBlock(i).GetNumberOfCells()
artest.say("OpenFOAM reader patches: %s" % expected)
for ext in (".msh", ".su2"):
    path = os.path.join(OUT, "foam_a" + ext)
    before = len(messages.GetOutput())
    SaveData(path, proxy=foam)
    text = messages.GetOutput()[before:]
    check("no patch" not in text, "OpenFOAM multiblock %s: every boundary face is in a reader patch" % ext)
    verify(path, volume, expected, "OpenFOAM multiblock form (a)")

# ---------------------------------------------------------------- bad input
def refused(data, fragment, label, path=None, **props):
    for ext in (".msh", ".su2"):
        p = path + ext if path else os.path.join(OUT, "bad_" + label.replace(" ", "_") + ext)
        text = save(data, p, **props) if not path else None
        if path:
            before = len(messages.GetOutput())
            SaveData(p, proxy=producer(data), **props)
            text = messages.GetOutput()[before:]
        check(fragment in text and "nothing is written" in text,
              "%s %s: error says '%s'" % (label, ext, fragment))
        leftovers = glob.glob(p + "*")
        check(not leftovers, "%s %s: no file (or temporary) left: %s" % (label, ext, leftovers))


grid_of = artest.grid_of


tri = grid_of(TET[:3], [(VTK_TRIANGLE, [0, 1, 2])])
refused(tri, "no 3-D cells", "no 3-D cells")
quadratic = grid_of(TET + [(0.5, 0, 0), (0.5, 0.5, 0), (0, 0.5, 0), (0, 0, 0.5), (0.5, 0, 0.5), (0, 0.5, 0.5)],
                    [(24, list(range(10)))])
refused(quadratic, "QuadraticTetra", "quadratic tetra")
poly = vtkUnstructuredGrid()
poly.DeepCopy(grid_of(TET, []))
faces = [4, 3, 0, 1, 3, 3, 1, 2, 3, 3, 2, 0, 3, 3, 0, 2, 1]
stream = vtkIdList()  # the face stream: nfaces, then (npts, ids) per face
for v in faces:
    stream.InsertNextId(v)
poly.InsertNextCell(42, stream)
check(poly.GetCellType(0) == 42, "polyhedron test input is a polyhedron")
refused(poly, "Polyhedron", "polyhedron")
refused(grid_of(TET, [(VTK_TETRA, [0, 2, 1, 3])]), "inverted or degenerate", "inverted tet")
refused(grid_of([(0, 0, 0), (1, 0, 0), (0, float("nan"), 0), (0, 0, 1)], [(VTK_TETRA, [0, 1, 2, 3])]),
        "NaN or Inf", "NaN point")
# A PatchId face using a point no 3-D cell uses.
off = grid_of(TET + [(5, 5, 5)], [(VTK_TETRA, [0, 1, 2, 3]), (VTK_TRIANGLE, [0, 1, 4])])
pid = vtkIntArray()
pid.SetName("PatchId")
for v in (-1, 0):
    pid.InsertNextValue(v)
off.GetCellData().AddArray(pid)
refused(off, "which no 3-D cell uses", "patch point off the volume")
# A PatchId face on the face two tetrahedra share.
two = grid_of(TET + [(1, 1, 1)], [(VTK_TETRA, [0, 1, 2, 3]), (VTK_TETRA, [1, 2, 3, 4]), (VTK_TRIANGLE, [1, 2, 3])])
pid2 = vtkIntArray()
pid2.SetName("PatchId")
for v in (-1, -1, 0):
    pid2.InsertNextValue(v)
two.GetCellData().AddArray(pid2)
refused(two, "interior face", "patch on an interior face")
# A multiblock patch moved off the mesh.
moved = multiblock(extra={"moved": [[xw[k] + [0.0, 0.0, 0.37] for k in cell_faces_of(H, 1)[0]]]})
refused(moved, "has no point of the volume within", "multiblock patch off the mesh")
# A multiblock patch face that is also in another patch.
twice = multiblock(extra={"again": [[xw[k] for k in cell_faces_of(H, 0)[0]]]})
refused(twice, "is also in patch 'hexSides'", "face in two patches")
# Unwritable path.
refused(H, "cannot open", "unwritable path", path="/nonexistent-dir/mesh")
# An existing file stays as it was when a write fails.
keep = os.path.join(OUT, "keep.msh")
save(H, keep)
with open(keep) as f:
    content = f.read()
before = len(messages.GetOutput())
SaveData(keep, proxy=producer(tri))
check("nothing is written" in messages.GetOutput()[before:], "failed overwrite: error reported")
with open(keep) as f:
    check(f.read() == content, "failed overwrite: the existing .msh is untouched")

artest.finish()
