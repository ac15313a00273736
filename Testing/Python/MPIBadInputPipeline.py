"""pvbatch script of RunMPIBadInput.py: bad input on the distributed oblique
shock (2 pieces with a ghost level) and QuadricFit's plane (read on rank 0):
EmbeddedRemesh with SurfaceEdgeLength 1e-9, RemovalFactor 0 and
SurfaceEdgeLength 1e6, EmbeddedRemesh on pieces of which rank 1's has a
crack of duplicated points ("crack": only rank 1 finds it, both must refuse),
FeatureCluster with a range that selects every node, and a job that runs out
of memory on rank 0 only ("memory"). Every rank prints, per case, one line "RESULT <case> <rank> <cells in>
<cells out> <ran> <points of output 1> <message>" (cells in: of the filter's
input, with the ghost levels it asked for; ran: 1 if the array the filter
adds is there; the message from the cause's first word on), so that the
driver sees both ranks answer, with the same refusal, and none hang.

    mpiexec -np 2 pvbatch --symmetric MPIBadInputPipeline.py <pieces.pvtu> <plane.vtp>
"""
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid

from paraview.simple import *
from paraview import servermanager
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow

import artest

artest.load_plugin(globals())
messages = vtkStringOutputWindow()
vtkOutputWindow.SetInstance(messages)
rank = servermanager.vtkProcessModule.GetProcessModule().GetPartitionId()
mesh = GhostCellsGenerator(Input=XMLPartitionedUnstructuredGridReader(FileName=[sys.argv[1]]))
plane = XMLPolyDataReader(FileName=[sys.argv[2]])


def report(case, proxy, start, added):
    """`added`: the array the filter adds when it runs (absent when refused)."""
    before = len(messages.GetOutput())
    proxy.UpdatePipeline()
    algorithm = proxy.GetClientSideObject()
    out, second = algorithm.GetOutputDataObject(0), algorithm.GetOutputDataObject(1)
    text = messages.GetOutput()[before:].replace("\n", " ")
    cells = algorithm.GetInputDataObject(0, 0).GetNumberOfCells()  # its input, with the ghosts it asked for
    ran = out.GetCellData().HasArray(added) or out.GetPointData().HasArray(added)
    artest.say("RESULT %s %d %d %d %d %d %s" % (case, rank, cells, out.GetNumberOfCells(), int(ran),
                                             second.GetNumberOfPoints(), text[text.find(start):][:400]))


report("fine", EmbeddedRemesh(Input=mesh, Surfaces=[plane], SurfaceEdgeLength=1e-9), "SurfaceEdgeLength", "Region")
report("large", EmbeddedRemesh(Input=mesh, Surfaces=[plane], SurfaceEdgeLength=1e6), "SurfaceEdgeLength", "Region")
report("removal", EmbeddedRemesh(Input=mesh, Surfaces=[plane], RemovalFactor=0.0), "RemovalFactor", "Region")
# Rank 1's piece (with its ghost cells) cracked: its cells left of their
# median centroid get their own copies of the nodes they share with the rest.
mesh.UpdatePipeline()
piece = vtkUnstructuredGrid()
piece.DeepCopy(mesh.GetClientSideObject().GetOutputDataObject(0))
if rank == 1:
    T = vtk_to_numpy(piece.GetCells().GetConnectivityArray()).reshape(-1, 4)
    centroid = vtk_to_numpy(piece.GetPoints().GetData())[T].mean(axis=1)
    left = centroid[:, 0] < np.median(centroid[:, 0])
    shared = np.intersect1d(T[left].ravel(), T[~left].ravel())
    copy_of = {}
    for i in shared:
        copy_of[int(i)] = piece.GetPoints().InsertNextPoint(piece.GetPoint(int(i)))
        pd = piece.GetPointData()
        for a in range(pd.GetNumberOfArrays()):
            pd.GetArray(a).InsertNextTuple(pd.GetArray(a).GetTuple(int(i)))
    for c in np.nonzero(left)[0]:
        T[c] = [copy_of.get(int(v), int(v)) for v in T[c]]
    piece.GetCells().GetConnectivityArray().Modified()
    piece.Modified()
    artest.say("rank 1: crack of %d duplicated points" % len(shared))
cracked = TrivialProducer()
cracked.GetClientSideObject().SetOutput(piece)
report("crack", EmbeddedRemesh(Input=cracked, Surfaces=[plane]), "EmbeddedRemesh", "Region")
weight = WeightFunction(Input=mesh, Variables=["p", "rho"], ComputePointWeight=1)
report("everything", FeatureCluster(Input=weight, SensorArray=["POINTS", "WeightFunction"], SensorRange=[-10, 10]),
       "SensorRange", "ClusterId")
# Rank 0 runs out of memory in its part alone (the surface remesh: at
# SurfaceSizeFactor 0.02 CGAL makes about 5.6e5 triangles, well under the
# job-size cap, and rank 0's address space is capped at what it holds plus
# 60 MB): rank 0 names it, rank 1 learns that another rank failed, neither
# waits for ever.
import resource  # noqa: E402
if rank == 0:
    with open("/proc/self/status") as f:
        size_kb = int([line for line in f if line.startswith("VmSize")][0].split()[1])
    resource.setrlimit(resource.RLIMIT_AS, (size_kb * 1024 + 60 * 1024 * 1024, resource.RLIM_INFINITY))
report("memory", EmbeddedRemesh(Input=mesh, Surfaces=[plane], SurfaceSizeFactor=0.02),
       "EmbeddedRemesh", "Region")
