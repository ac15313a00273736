"""pvbatch script: QuadricFit of a plane and a cone cluster trimmed to a
domain, serial or distributed.

    pvbatch MPIQuadricFitPipeline.py <domain.vtu> <output>
    mpiexec -np 2 pvbatch --symmetric MPIQuadricFitPipeline.py <pieces.pvtu> <output>

The medial points (the same on every run: a tilted plane and a cone through
the unit cube, fixed seed) are dealt out over the ranks, point i to rank
i % ranks. The domain: serial, the whole mesh; distributed, the partitioned
reader's pieces as they are (faces between the pieces appear in both pieces'
boundaries) and through GhostCellsGenerator. Rank 0 writes each surface as
<output>.<domain>.<template>.vtp; every rank prints how many cells it holds.
"""
import sys

import numpy as np
from paraview.simple import *
from paraview import servermanager
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

import artest

artest.load_plugin(globals())
data, out_path = sys.argv[1], sys.argv[2]
pm = servermanager.vtkProcessModule.GetProcessModule()
rank, ranks = pm.GetPartitionId(), pm.GetNumberOfLocalPartitions()

rng = np.random.default_rng(11)
xy = rng.uniform(0.05, 0.95, (600, 2))
plane = np.c_[xy, 0.5 - 0.2 * (xy[:, 0] - 0.5) + 0.1 * (xy[:, 1] - 0.5) + rng.normal(0, 0.003, 600)]
th = np.radians(30.0)
s, phi = rng.uniform(0.4, 1.5, 3000), rng.uniform(-np.pi, np.pi, 3000)
cone = np.c_[-0.3 + s * np.cos(th), 0.5 + s * np.sin(th) * np.cos(phi), 0.5 + s * np.sin(th) * np.sin(phi)]
cone = cone[np.all((cone > 0.03) & (cone < 0.97), axis=1)]
xyz = np.vstack([plane, cone])
ids = np.r_[np.zeros(len(plane), dtype=np.int32), np.ones(len(cone), dtype=np.int32)]
size = np.full(len(xyz), 0.05)
mine = np.arange(len(xyz)) % ranks == rank

pd = vtkPolyData()
pts = vtkPoints()
pts.SetData(numpy_to_vtk(np.ascontiguousarray(xyz[mine]), deep=1))
pd.SetPoints(pts)
for name, values in (("ClusterId", ids), ("LocalSize", size), ("Weight", 1.0 / size)):
    a = numpy_to_vtk(np.ascontiguousarray(values[mine]), deep=1)
    a.SetName(name)
    pd.GetPointData().AddArray(a)
medial = PVTrivialProducer()
medial.GetClientSideObject().SetOutput(pd)

if data.endswith(".pvtu"):
    reader = XMLPartitionedUnstructuredGridReader(FileName=[data])
    domains = {"pieces": reader, "ghosts": GhostCellsGenerator(Input=reader)}
else:
    domains = {"whole": XMLUnstructuredGridReader(FileName=[data])}

for label, domain in domains.items():
    for cluster, template in ((0, "Plane"), (1, "Cone")):
        fit = QuadricFit(Input=medial, Domain=domain, ClusterId=cluster, Template=template, Margin=10)
        fit.UpdatePipeline()
        local = fit.GetClientSideObject().GetOutputDataObject(0)
        print("rank %d of %d: %s %s %d cells" % (rank, ranks, label, template, local.GetNumberOfCells()))
        if rank == 0:
            writer = vtkXMLPolyDataWriter()
            writer.SetFileName("%s.%s.%s.vtp" % (out_path, label, template))
            writer.SetInputData(local)
            writer.SetDataModeToBinary()
            writer.Write()

# The whole chain on the mesh itself: WeightFunction -> FeatureCluster ->
# QuadricFit with the reader as Domain (the medial points come from port 1
# of FeatureCluster: its request must not make the reader read everything).
if data.endswith(".pvtu"):
    chain_mesh = GhostCellsGenerator(Input=reader)
    chain_domain = reader
else:
    chain_mesh = chain_domain = domains["whole"]
weight = WeightFunction(Input=chain_mesh, Variables=["p", "rho"], ComputePointWeight=1)
clusters = FeatureCluster(Input=weight, SensorArray=["POINTS", "WeightFunction"], SensorRange=[1.5, 2.0])
fit = QuadricFit(Input=OutputPort(clusters, 1), Domain=chain_domain, Template="Plane", ClusterId=0)
fit.UpdatePipeline()
local = fit.GetClientSideObject().GetOutputDataObject(0)
print("rank %d of %d: chain Plane %d cells" % (rank, ranks, local.GetNumberOfCells()))
if rank == 0:
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName("%s.chain.Plane.vtp" % out_path)
    writer.SetInputData(local)
    writer.SetDataModeToBinary()
    writer.Write()
