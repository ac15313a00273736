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


def fit_plane(points, weights=None):
    """Least-squares plane through points: (unit normal, centroid)."""
    p = np.asarray(points, dtype=float)
    w = np.ones(len(p)) if weights is None else np.asarray(weights, dtype=float)
    c = (p * w[:, None]).sum(axis=0) / w.sum()
    q = (p - c) * np.sqrt(w)[:, None]
    _, _, vt = np.linalg.svd(q, full_matrices=False)
    return vt[-1], c


def angle_between_planes(n1, n2):
    """Angle in degrees between two planes given by their normals."""
    c = abs(np.dot(n1, n2)) / (np.linalg.norm(n1) * np.linalg.norm(n2))
    return np.degrees(np.arccos(min(1.0, c)))


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
