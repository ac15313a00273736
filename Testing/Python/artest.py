"""Shared helpers of the pvpython / pvbatch tests.

The tests run under ctest with AR_PLUGIN (the built plugin), AR_DATA_DIR,
AR_BASELINE_DIR and AR_TEST_OUTPUT_DIR in the environment. Each test records
its checks with `check` and ends with `finish()`, which exits non-zero when a
check failed: the comparisons are the tests' results.
"""
import os
import sys

import numpy as np

PLUGIN = os.environ.get("AR_PLUGIN", "")
DATA_DIR = os.environ.get("AR_DATA_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "Data"))
BASELINE_DIR = os.environ.get("AR_BASELINE_DIR", os.path.join(os.path.dirname(__file__), "..", "Baseline"))
OUTPUT_DIR = os.environ.get("AR_TEST_OUTPUT_DIR", os.getcwd())

_failures = []
_checks = [0]


def _report_exception(kind, value, trace):
    """Uncaught exceptions go to the real stderr: a test that replaces VTK's
    output window (to read the filters' error messages) would swallow them."""
    import traceback
    sys.__stderr__.write("".join(traceback.format_exception(kind, value, trace)))
    sys.__stderr__.flush()


sys.excepthook = _report_exception


def data(name):
    return os.path.join(DATA_DIR, name)


def load_plugin(namespace):
    """Loads the plugin into paraview.simple's namespace `namespace`."""
    from paraview.simple import LoadPlugin
    if not PLUGIN or not os.path.exists(PLUGIN):
        print("AR_PLUGIN does not name the built plugin: %r" % PLUGIN)
        sys.exit(2)
    LoadPlugin(PLUGIN, remote=False, ns=namespace)
    _plugin[0] = namespace


_plugin = [None]  # the namespace holding the plugin's proxies (load_plugin's)


def say(text):
    """Prints to the real stdout (pvpython routes print() through VTK's output
    window, which a test may capture)."""
    sys.__stdout__.write(text + "\n")
    sys.__stdout__.flush()


def check(condition, message):
    _checks[0] += 1
    status = "ok  " if condition else "FAIL"
    say("%s %s" % (status, message))
    if not condition:
        _failures.append(message)


def finish():
    say("%d checks, %d failed" % (_checks[0], len(_failures)))
    sys.exit(1 if _failures or _checks[0] == 0 else 0)


def fetch(proxy, port=0):
    """The proxy's output (port `port`) on this process, wrapped for numpy."""
    from paraview import servermanager
    from vtkmodules.numpy_interface import dataset_adapter as dsa
    proxy.UpdatePipeline()
    return dsa.WrapDataObject(servermanager.Fetch(proxy, idx=port))


def field(dataset, name):
    return np.asarray(dataset.FieldData[name]).ravel()


def cell_centroids(dataset):
    """Vertex centroids and longest edge of every cell of a wrapped grid."""
    vtk = dataset.VTKObject
    pts = np.asarray(dataset.Points)
    from vtkmodules.util.numpy_support import vtk_to_numpy
    offsets = vtk_to_numpy(vtk.GetCells().GetOffsetsArray())
    conn = vtk_to_numpy(vtk.GetCells().GetConnectivityArray())
    n = len(offsets) - 1
    centroids = np.zeros((n, 3))
    longest = np.zeros(n)
    for c in range(n):
        ids = conn[offsets[c]:offsets[c + 1]]
        x = pts[ids]
        centroids[c] = x.mean(axis=0)
        d = x[:, None, :] - x[None, :, :]
        longest[c] = np.sqrt((d ** 2).sum(axis=2)).max()
    return centroids, longest


def require_program(program, package):
    """The full path of `program`. Every program a test calls is installed by
    the README's set-up command, so a missing one is a failure, never a skip:
    the test stops (exit 1) with the Debian package that provides it."""
    import shutil
    found = shutil.which(program)
    if found is None:
        say("FAIL `%s` is not installed: apt-get install %s (the README's set-up command, "
            "bash Plugin/Scripts/setup.sh test, installs it)" % (program, package))
        sys.exit(1)
    return found


def child_environment():
    """The environment for the pvbatch / mpiexec children of a test driver.
    pvpython initializes MPI as a singleton: its OMPI_/PMIX_ variables would
    make a child mpiexec fail, so they are left out."""
    here = os.path.dirname(os.path.abspath(__file__))
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "OPAL_", "PMI_", "HYDRA_"))}
    env["PYTHONPATH"] = here + os.pathsep + env.get("PYTHONPATH", "")
    return env


def run(cmd):
    """Runs a child command, prints its command line and the end of its
    output; returns (exit code, output)."""
    import subprocess
    say("$ " + " ".join(cmd))
    r = subprocess.run(cmd, env=child_environment(), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True, timeout=600)
    say(r.stdout[-3000:])
    return r.returncode, r.stdout


def load(path):
    """A VTK XML file (any type), wrapped for numpy."""
    from vtkmodules.numpy_interface import dataset_adapter as dsa
    from vtkmodules.vtkIOXML import vtkXMLGenericDataObjectReader
    r = vtkXMLGenericDataObjectReader()
    r.SetFileName(path)
    r.Update()
    return dsa.WrapDataObject(r.GetOutput())


def contents(ds):
    """name -> bytes of a dataset's points, cells (connectivity, offsets,
    types; a polydata's polygons) and every point, cell and field array but
    the Seconds* timings."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    g = ds.VTKObject if hasattr(ds, "VTKObject") else ds
    out = {}
    if g.GetPoints() is not None:
        out["points"] = vtk_to_numpy(g.GetPoints().GetData()).tobytes()
    cells = g.GetCells() if g.IsA("vtkUnstructuredGrid") else g.GetPolys() if g.IsA("vtkPolyData") else None
    if cells is not None:
        out["connectivity"] = vtk_to_numpy(cells.GetConnectivityArray()).astype(np.int64).tobytes()
        out["offsets"] = vtk_to_numpy(cells.GetOffsetsArray()).astype(np.int64).tobytes()
    if g.IsA("vtkUnstructuredGrid") and g.GetCellTypesArray() is not None:
        out["types"] = vtk_to_numpy(g.GetCellTypesArray()).tobytes()
    for kind, data in (("point ", g.GetPointData()), ("cell ", g.GetCellData()), ("field ", g.GetFieldData())):
        for i in range(data.GetNumberOfArrays()):
            a = data.GetArray(i)
            if a is not None and not (kind == "field " and a.GetName().startswith("Seconds")):
                out[kind + a.GetName()] = vtk_to_numpy(a).tobytes()
    return out


def differences(a, b):
    """What differs between two datasets, bit for bit (contents): a list of
    names, empty when they are equal."""
    ca, cb = contents(a), contents(b)
    return sorted(k for k in set(ca) | set(cb) if ca.get(k) != cb.get(k))


def same_mesh(a, b):
    """Whether two unstructured grids are the same mesh bit for bit up to
    their numbering: the same cells (type and corners' exact coordinates)
    and, at every point (by its exact coordinates), the same value of every
    point array. Returns (equal, what differs)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    ga = a.VTKObject if hasattr(a, "VTKObject") else a
    gb = b.VTKObject if hasattr(b, "VTKObject") else b
    P = [vtk_to_numpy(g.GetPoints().GetData()).astype(np.float64) for g in (ga, gb)]
    _, inverse = np.unique(np.vstack(P), axis=0, return_inverse=True)
    ids = [inverse[:len(P[0])], inverse[len(P[0]):]]
    if len(np.unique(ids[0])) != len(P[0]) or len(np.unique(ids[1])) != len(P[1]):
        return False, "coincident points"
    keys = []
    for g, pid in zip((ga, gb), ids):
        off = vtk_to_numpy(g.GetCells().GetOffsetsArray()).astype(np.int64)
        conn = pid[vtk_to_numpy(g.GetCells().GetConnectivityArray()).astype(np.int64)]
        sizes = np.diff(off)
        key = np.full((len(sizes), 9), -1, dtype=np.int64)
        key[:, 0] = vtk_to_numpy(g.GetCellTypesArray())
        rows = np.repeat(np.arange(len(sizes)), sizes)
        cols = np.arange(len(conn)) - np.repeat(off[:-1], sizes)
        corners = np.full((len(sizes), 8), np.iinfo(np.int64).max, dtype=np.int64)
        corners[rows, cols] = conn
        key[:, 1:] = np.sort(corners, axis=1)
        keys.append(key[np.lexsort(key.T[::-1])])
    if keys[0].shape != keys[1].shape or not np.array_equal(keys[0], keys[1]):
        return False, "cells (%d and %d)" % (len(keys[0]), len(keys[1]))
    order = [np.argsort(pid) for pid in ids]
    differ = []
    for i in range(ga.GetPointData().GetNumberOfArrays()):
        name = ga.GetPointData().GetArrayName(i)
        x, y = ga.GetPointData().GetArray(name), gb.GetPointData().GetArray(name)
        if x is None:
            continue
        if y is None or not np.array_equal(vtk_to_numpy(x)[order[0]], vtk_to_numpy(y)[order[1]]):
            differ.append(name)
    return not differ, "point arrays " + ", ".join(differ) if differ else ""


def fit_plane(points, weights=None):
    """Least-squares plane through points: (unit normal, centroid)."""
    p = np.asarray(points, dtype=float)
    w = np.ones(len(p)) if weights is None else np.asarray(weights, dtype=float)
    c = (p * w[:, None]).sum(axis=0) / w.sum()
    q = (p - c) * np.sqrt(w)[:, None]
    _, _, vt = np.linalg.svd(q, full_matrices=False)
    return vt[-1], c


def angle_deg(a, b):
    """Angle in degrees between vectors a and b (or row by row between two
    (n, 3) arrays), as atan2(|a x b|, a . b): accurate to rounding at every
    angle, where arccos of the cosine cannot resolve less than ~1e-6 degree
    next to 0 and 180 (nor arcsin next to 90)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.einsum("...i,...i->...", a, b)))


def angle_between_planes(n1, n2):
    """Angle in degrees (0 to 90) between two planes given by their normals."""
    a = angle_deg(n1, n2)
    return np.minimum(a, 180.0 - a)


def grid_of(points, cells):
    """A vtkUnstructuredGrid (double points) from [(x, y, z)] and [(vtk_type, [ids])]."""
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid
    g = vtkUnstructuredGrid()
    p = vtkPoints()
    p.SetDataTypeToDouble()
    for q in points:
        p.InsertNextPoint(*q)
    g.SetPoints(p)
    for t, ids in cells:
        g.InsertNextCell(t, len(ids), ids)
    return g


# ---------------------------------------------------------------------------
# Mixed meshes (tetrahedra, pyramids, prisms, hexahedra) in numpy: the
# validity checks of the EmbeddedRemesh tests, independent of the filters'
# own quality arrays. Node order and orientation are VTK's (the one
# vtkCellSizeFilter measures as a positive volume; see Remesh/ARCellQuality.h).

VTK_TETRA, VTK_HEXAHEDRON, VTK_WEDGE, VTK_PYRAMID = 10, 12, 13, 14

# Faces of each cell type, outward (right-hand normal) for a valid cell.
FACES = {
    VTK_TETRA: [(1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1)],
    VTK_PYRAMID: [(0, 3, 2, 1), (0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)],
    VTK_WEDGE: [(0, 1, 2), (3, 5, 4), (0, 3, 4, 1), (1, 4, 5, 2), (2, 5, 3, 0)],
    VTK_HEXAHEDRON: [(0, 4, 7, 3), (1, 2, 6, 5), (0, 1, 5, 4), (3, 7, 6, 2), (0, 3, 2, 1), (4, 5, 6, 7)],
}

# Per type: the corners (node, three edge ends) whose determinant is positive
# for a valid cell. The pyramid's apex has four edges: it is valid when its
# base corners are and the base is on the apex's inner side, which the four
# base corners (each with the apex as third edge end) already see.
CORNERS = {
    VTK_TETRA: [(0, 1, 2, 3)],
    VTK_PYRAMID: [(0, 1, 3, 4), (1, 2, 0, 4), (2, 3, 1, 4), (3, 0, 2, 4)],
    VTK_WEDGE: [(0, 2, 1, 3), (1, 0, 2, 4), (2, 1, 0, 5), (3, 4, 5, 0), (4, 5, 3, 1), (5, 3, 4, 2)],
    VTK_HEXAHEDRON: [(0, 1, 3, 4), (1, 2, 0, 5), (2, 3, 1, 6), (3, 0, 2, 7),
                     (4, 7, 5, 0), (5, 4, 6, 1), (6, 5, 7, 2), (7, 6, 4, 3)],
}
TYPE_NAMES = {VTK_TETRA: "tetrahedra", VTK_PYRAMID: "pyramids", VTK_WEDGE: "prisms", VTK_HEXAHEDRON: "hexahedra"}


def corner_jacobians(points, cells, vtk_type):
    """(n_cells, n_corners) determinants of the corners' edge vectors."""
    out = []
    for p, a, b, c in CORNERS[vtk_type]:
        x = points[cells[:, p]]
        out.append(np.einsum("ij,ij->i", points[cells[:, a]] - x,
                             np.cross(points[cells[:, b]] - x, points[cells[:, c]] - x)))
    return np.column_stack(out)


def cells_of(ds):
    """Per cell of a wrapped grid: its type and its point ids (a list of arrays)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    vtk = ds.VTKObject
    offsets = vtk_to_numpy(vtk.GetCells().GetOffsetsArray())
    conn = vtk_to_numpy(vtk.GetCells().GetConnectivityArray())
    types = vtk_to_numpy(vtk.GetCellTypesArray())
    return types, [conn[offsets[c]:offsets[c + 1]] for c in range(len(types))]


def by_type(types, cells, t):
    """The ids of the cells of type t and their point ids as one array."""
    idx = np.nonzero(types == t)[0]
    return idx, (np.array([cells[c] for c in idx]) if len(idx) else np.zeros((0, 1), dtype=np.int64))


def _sorted_corners(P, ids):
    """(m, k) point ids -> (m, 3 k) int64: each polygon's corners rounded to
    1e-9 and sorted, i.e. the polygon named by its coordinates."""
    c = np.round(P[ids] * 1e9).astype(np.int64)
    order = np.lexsort((c[:, :, 2], c[:, :, 1], c[:, :, 0]), axis=1)
    return np.take_along_axis(c, order[:, :, None], axis=1).reshape(len(c), -1)


def coord_key(P, ids):
    """A face (triangle or quad: its point ids) named by its coordinates, so
    that meshes with different point numberings can be compared."""
    return _sorted_corners(P, np.asarray(ids, dtype=np.int64)[None, :])[0].tobytes()


def face_cells(P, types, cells):
    """Every face of every cell (by coord_key): the cells that have it, and
    the point ids of the face in one of them (outward for that cell)."""
    owners, corners = {}, {}
    for t, fs in FACES.items():
        idx, C = by_type(types, cells, t)
        if len(idx) == 0:
            continue
        for f in fs:
            ids = C[:, list(f)]
            for c, k, i in zip(idx, _sorted_corners(P, ids), ids):
                key = k.tobytes()
                owners.setdefault(key, []).append(int(c))
                corners[key] = i
    return owners, corners


def faces(P, types, cells):
    """Every face (by coord_key): how many cells use it, and the corners of one of them."""
    owners, corners = face_cells(P, types, cells)
    return {k: len(v) for k, v in owners.items()}, corners


def boundary_edges(corners, keys):
    """How many of the faces `keys` (coord_keys with their point ids in
    `corners`) use each edge: a watertight boundary uses each twice."""
    edges = {}
    for k in keys:
        ids = corners[k]
        for a in range(len(ids)):
            e = tuple(sorted((int(ids[a]), int(ids[(a + 1) % len(ids)]))))
            edges[e] = edges.get(e, 0) + 1
    return edges


def cell_volumes(P, types, cells):
    """Every cell's volume by the divergence theorem over its outward faces:
    V = sum over faces of the signed volume of (x0, face), a quad split into
    four triangles at its centroid (the same split from both cells that share
    it, so the volumes of a conforming mesh add up to the domain's)."""
    vol = np.zeros(len(types))
    for t, fs in FACES.items():
        idx, C = by_type(types, cells, t)
        if len(idx) == 0:
            continue
        x0 = P[C[:, 0]]
        v = np.zeros(len(idx))
        for f in fs:
            X = [P[C[:, i]] - x0 for i in f]
            if len(f) == 3:
                v += np.einsum("ij,ij->i", X[0], np.cross(X[1], X[2]))
            else:
                m = sum(X) / 4.0
                for k in range(4):
                    v += np.einsum("ij,ij->i", X[k], np.cross(X[(k + 1) % 4], m))
        vol[idx] = v / 6.0
    return vol


def dihedral_angles(P, cells, t):
    """(n_cells, n_edges) interior dihedral angles (degrees) of cells of type
    t: at each edge, 180 minus the angle between the outward normals of its
    two faces (a quad's normal: the cross product of its diagonals)."""
    fs = FACES[t]
    normals = []
    for f in fs:
        if len(f) == 3:
            n = np.cross(P[cells[:, f[1]]] - P[cells[:, f[0]]], P[cells[:, f[2]]] - P[cells[:, f[0]]])
        else:
            n = np.cross(P[cells[:, f[2]]] - P[cells[:, f[0]]], P[cells[:, f[3]]] - P[cells[:, f[1]]])
        normals.append(n / np.linalg.norm(n, axis=1)[:, None])
    out = []
    for i in range(len(fs)):
        for j in range(i + 1, len(fs)):
            if len(set(fs[i]) & set(fs[j])) == 2:  # the two faces share an edge
                out.append(angle_deg(-normals[i], normals[j]))
    return np.column_stack(out)


def cell_sizes(proxy):
    """vtkCellSizeFilter's (CellSize's) volume of every cell of a proxy's output."""
    from paraview.simple import CellSize
    return np.asarray(fetch(CellSize(Input=proxy, ComputeVolume=1, ComputeArea=0, ComputeLength=0,
                                     ComputeVertexCount=0)).CellData["Volume"])


def polygon_angles(P, poly):
    """Interior angles (degrees) of each polygon (rows of point ids)."""
    n = poly.shape[1]
    out = []
    for k in range(n):
        a, b, c = P[poly[:, (k - 1) % n]], P[poly[:, k]], P[poly[:, (k + 1) % n]]
        out.append(angle_deg(a - b, c - b))
    return np.column_stack(out)


def edge_ratio(P, cells, t):
    """Longest / shortest edge of each cell of type t."""
    edges = set()
    for f in FACES[t]:
        for k in range(len(f)):
            edges.add(tuple(sorted((f[k], f[(k + 1) % len(f)]))))
    L = np.column_stack([np.linalg.norm(P[cells[:, a]] - P[cells[:, b]], axis=1) for a, b in edges])
    return L.max(axis=1) / L.min(axis=1)


def locator_of(polydata):
    """A cell locator on a vtkPolyData (for distance)."""
    from vtkmodules.vtkCommonDataModel import vtkStaticCellLocator
    loc = vtkStaticCellLocator()
    loc.SetDataSet(polydata)
    loc.BuildLocator()
    return loc


def distance(loc, x):
    """The distance from the point x to the cells of a locator_of."""
    from vtkmodules.vtkCommonCore import reference
    from vtkmodules.vtkCommonDataModel import vtkGenericCell
    closest, cid, sub, d2 = [0.0, 0.0, 0.0], reference(0), reference(0), reference(0.0)
    loc.FindClosestPoint(list(x), closest, vtkGenericCell(), cid, sub, d2)
    return float(np.sqrt(d2.get()))


def skin(grid):
    """The boundary surface of a vtkUnstructuredGrid (vtkGeometryFilter)."""
    from vtkmodules.vtkFiltersGeometry import vtkGeometryFilter
    g = vtkGeometryFilter()
    g.SetInputData(grid)
    g.Update()
    return g.GetOutput()


CONE_PATCHES = ["inlet", "outlet", "symmetry", "farfield", "cone"]


def cone_patches(c, b):
    """The bundled cone's boundary patches, for openfoam_multiblock: each
    boundary face (centre c, the volume's bounds b) named as the OpenFOAM
    case names it (CONE_PATCHES)."""
    names = np.full(len(c), "cone", dtype=object)
    names[np.abs(c[:, 0] - b[0]) < 1e-6] = "inlet"
    names[np.abs(c[:, 0] - b[1]) < 1e-6] = "outlet"
    names[np.abs(c[:, 2] - b[4]) < 1e-6] = "symmetry"
    far = np.hypot(c[:, 1], c[:, 2]) > 0.6 * b[3]  # the outer cylinder (the cone body is near the axis)
    names[far & (names == "cone")] = "farfield"
    return names


def openfoam_multiblock(volume, classify, patches):
    """`volume` (a vtkUnstructuredGrid) as ParaView's OpenFOAM reader gives a
    case: a multiblock of "internalMesh" and a "boundary" block with one
    polydata leaf per patch, in the order of `patches`. The boundary faces
    (vtkGeometryFilter) are named by `classify(centres, bounds)`, which gets
    the faces' centres (n x 3) and the volume's bounds and returns one patch
    name per face. Each leaf's cells carry FaceId, the face's index. Returns
    the multiblock and the face names (a numpy array, one per face)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonCore import vtkIntArray
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkCompositeDataSet, vtkMultiBlockDataSet, vtkPolyData
    from vtkmodules.vtkFiltersGeometry import vtkGeometryFilter
    g = vtkGeometryFilter()
    g.SetInputData(volume)
    g.Update()
    skin = g.GetOutput()
    P = vtk_to_numpy(skin.GetPoints().GetData()).astype(np.float64)
    offsets = vtk_to_numpy(skin.GetPolys().GetOffsetsArray())
    conn = vtk_to_numpy(skin.GetPolys().GetConnectivityArray())
    faces = [conn[offsets[f]:offsets[f + 1]] for f in range(len(offsets) - 1)]
    names = np.asarray(classify(np.array([P[f].mean(axis=0) for f in faces]), volume.GetBounds()), dtype=object)
    mb = vtkMultiBlockDataSet()
    mb.SetNumberOfBlocks(2)
    mb.SetBlock(0, volume)
    mb.GetMetaData(0).Set(vtkCompositeDataSet.NAME(), "internalMesh")
    boundary = vtkMultiBlockDataSet()
    boundary.SetNumberOfBlocks(len(patches))
    for i, name in enumerate(patches):
        pd = vtkPolyData()
        pd.SetPoints(skin.GetPoints())
        cells = vtkCellArray()
        face_id = vtkIntArray()
        face_id.SetName("FaceId")
        for f in np.where(names == name)[0]:
            cells.InsertNextCell(len(faces[f]), [int(v) for v in faces[f]])
            face_id.InsertNextValue(int(f))
        pd.SetPolys(cells)
        pd.GetCellData().AddArray(face_id)
        boundary.SetBlock(i, pd)
        boundary.GetMetaData(i).Set(vtkCompositeDataSet.NAME(), name)
    mb.SetBlock(1, boundary)
    mb.GetMetaData(1).Set(vtkCompositeDataSet.NAME(), "boundary")
    return mb, names


def cone_shock_fit(cone):
    """QuadricFit's cone on the cone case's shock (proxy `cone`, the reader):
    ShockSensor -> FeatureCluster on NormalMach 0.8-1.2 -> QuadricFit (Cone)."""
    from paraview.simple import OutputPort
    ns = _plugin[0]
    ShockSensor, FeatureCluster, QuadricFit = ns["ShockSensor"], ns["FeatureCluster"], ns["QuadricFit"]
    sensor = ShockSensor(Input=cone, Velocity=["POINTS", "U"], Pressure=["POINTS", "p"], Density=["POINTS", "rho"],
                         Gamma=field(fetch(cone), "Gamma")[0])
    clusters = FeatureCluster(Input=sensor, SensorArray=["POINTS", "NormalMach"], SensorRange=[0.8, 1.2])
    return QuadricFit(Input=OutputPort(clusters, 1), Domain=cone, Template="Cone", ClusterId=0)


def check_valid_mesh(label, source, output, embedded=None):
    """The usual validity of an adapted mesh (wrapped grids `source` in,
    `output` out): every corner Jacobian of every cell positive (tetrahedra,
    pyramids, prisms, hexahedra; NonPositiveJacobianCells 0), conforming (no
    triangle or quad face in more than two cells), the boundary equal to the
    input's face for face and watertight (every boundary edge in two boundary
    faces), the volume (by the divergence theorem over the faces) conserved
    to 1e-9, and, given the embedded surface (a wrapped polydata of
    triangles or quads), each of its faces a face between two cells."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    P0, P1 = np.asarray(source.Points, dtype=np.float64), np.asarray(output.Points, dtype=np.float64)
    types0, cells0 = cells_of(source)
    types1, cells1 = cells_of(output)
    worst = []
    for t in (VTK_TETRA, VTK_PYRAMID, VTK_WEDGE, VTK_HEXAHEDRON):
        idx, C = by_type(types1, cells1, t)
        if len(idx):
            worst.append((corner_jacobians(P1, C, t).min(), TYPE_NAMES[t], len(idx)))
    known = sum(n for _, _, n in worst)
    check(known == len(types1) and min(w for w, _, _ in worst) > 0
          and field(output, "NonPositiveJacobianCells")[0] == 0,
          "%s: every corner Jacobian is positive (%s)" % (label, ", ".join(
              "%d %s, min %.2e" % (n, name, w) for w, name, n in worst)))
    count0, _ = faces(P0, types0, cells0)
    count1, corners1 = faces(P1, types1, cells1)
    b0 = {k for k, c in count0.items() if c == 1}
    b1 = {k for k, c in count1.items() if c == 1}
    edges = boundary_edges(corners1, b1)
    check(max(count1.values()) <= 2 and set(edges.values()) == {2},
          "%s: conforming (no face in more than two cells), watertight (each of %d boundary edges in two "
          "boundary faces)" % (label, len(edges)))
    # A one-cell-deep (2-D) mesh is remeshed on its front and back planes: the
    # boundary off them must be the input's.
    depth = [k for k in range(3) if len(np.unique(P0[:, k])) == 2]
    if depth:
        levels = np.round(np.unique(P0[:, depth[0]]) * 1e9).astype(np.int64)  # as the face keys hold them
        def off_planes(keys):
            return {k for k in keys
                    if not any(np.all(np.frombuffer(k, dtype=np.int64).reshape(-1, 3)[:, depth[0]] == z) for z in levels)}
        b0, b1 = off_planes(b0), off_planes(b1)
    check(b0 == b1, "%s: the boundary%s is the input's, face for face (%d faces)"
          % (label, " off the front and back planes" if depth else "", len(b1)))
    v0, v1 = cell_volumes(P0, types0, cells0), cell_volumes(P1, types1, cells1)
    check(v1.min() > 0 and abs(v1.sum() / v0.sum() - 1) < 1e-9,
          "%s: every cell's volume positive, the total conserved (%.1e relative)" % (label, v1.sum() / v0.sum() - 1))
    if embedded is not None and embedded.GetNumberOfCells() > 0:
        PS = np.asarray(embedded.Points, dtype=np.float64)
        polys = embedded.VTKObject.GetPolys()
        off, conn = vtk_to_numpy(polys.GetOffsetsArray()), vtk_to_numpy(polys.GetConnectivityArray())
        on = [count1.get(coord_key(PS, conn[off[i]:off[i + 1]]), 0) for i in range(len(off) - 1)]
        check(all(c == 2 for c in on), "%s: all %d faces of the embedded surface are faces between two cells"
              % (label, len(on)))


WEDGE_PATCHES = ["inlet", "outlet", "top", "obstacle", "frontAndBack"]


def _wedge_patches(centre, b):
    names = np.full(len(centre), "obstacle", dtype=object)
    names[np.abs(centre[:, 1] - b[3]) < 1e-7] = "top"
    names[np.abs(centre[:, 0] - b[0]) < 1e-7] = "inlet"
    names[np.abs(centre[:, 0] - b[1]) < 1e-7] = "outlet"
    names[(np.abs(centre[:, 2] - b[4]) < 1e-9) | (np.abs(centre[:, 2] - b[5]) < 1e-9)] = "frontAndBack"
    return names


def wedge_multiblock(reader):
    """The bundled wedge (proxy `reader` of wedge15Ma5.vtu) as ParaView's
    OpenFOAM reader gives it: internalMesh and the patches WEDGE_PATCHES
    (classified by position). Returns (a PVTrivialProducer, the patch names)."""
    from paraview.simple import PVTrivialProducer
    mb, names = openfoam_multiblock(fetch(reader).VTKObject, _wedge_patches, WEDGE_PATCHES)
    source = PVTrivialProducer()
    source.GetClientSideObject().SetOutput(mb)
    return source, names


def wedge_shock_plane(reader):
    """QuadricFit's plane on the bundled wedge's shock: WeightFunction (rho,
    rhoU, rhoE) -> FeatureCluster on W 1.5-2 -> QuadricFit (Plane) of cluster 0."""
    from paraview.simple import OutputPort
    ns = _plugin[0]
    weight = ns["WeightFunction"](Input=reader, Variables=["rho", "rhoU", "rhoE"], ComputePointWeight=1)
    clusters = ns["FeatureCluster"](Input=weight, SensorArray=["POINTS", "WeightFunction"], SensorRange=[1.5, 2.0])
    return ns["QuadricFit"](Input=OutputPort(clusters, 1), Domain=reader, Template="Plane", ClusterId=0)
