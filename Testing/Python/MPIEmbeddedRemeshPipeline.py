"""pvbatch script: WeightFunction -> FeatureCluster -> QuadricFit (plane) ->
EmbeddedRemesh (LocalCavity, or FullDomain) on the analytic oblique shock, serial or
distributed.

    pvbatch MPIEmbeddedRemeshPipeline.py <mesh.vtu> <output> [--mode=FullDomain] [--layers=Prisms]
    mpiexec -np 2 pvbatch --symmetric MPIEmbeddedRemeshPipeline.py <pieces.pvtu> <output> <plane.vtp> [--mode=FullDomain] [--layers=Prisms]

The serial run fits the plane with QuadricFit and writes it as
<output>.plane.vtp; the distributed run reads that plane (on rank 0 only:
EmbeddedRemesh gathers the surface pieces), so the comparison is of
EmbeddedRemesh alone.

Distributed, the pieces get one ghost level (GhostCellsGenerator). Every
rank writes its piece of the remeshed volume as <output>.<rank>.vtu and of
the embedded surface as <output>.<rank>.vtp, and prints its counts and the
time EmbeddedRemesh took.
"""
import sys
import time

from paraview.simple import *
from paraview import servermanager
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter, vtkXMLUnstructuredGridWriter

import artest

artest.load_plugin(globals())
mode = next((a.split("=", 1)[1] for a in sys.argv if a.startswith("--mode=")), "LocalCavity")
layers = next((a.split("=", 1)[1] for a in sys.argv if a.startswith("--layers=")), "Tetrahedra")
argv = [a for a in sys.argv if not a.startswith("--mode=") and not a.startswith("--layers=")]
data, out_path = argv[1], argv[2]
pm = servermanager.vtkProcessModule.GetProcessModule()
rank, ranks = pm.GetPartitionId(), pm.GetNumberOfLocalPartitions()

if data.endswith(".pvtu"):
    domain = XMLPartitionedUnstructuredGridReader(FileName=[data])
    mesh = GhostCellsGenerator(Input=domain)
else:
    mesh = domain = XMLUnstructuredGridReader(FileName=[data])
if len(argv) > 3:
    plane = XMLPolyDataReader(FileName=[argv[3]])  # piece 0 on rank 0, nothing on rank 1
else:
    weight = WeightFunction(Input=mesh, Variables=["p", "rho"], ComputePointWeight=1)
    clusters = FeatureCluster(Input=weight, SensorArray=["POINTS", "WeightFunction"], SensorRange=[1.5, 2.0])
    plane = QuadricFit(Input=OutputPort(clusters, 1), Domain=domain, Template="Plane", ClusterId=0)
    plane.UpdatePipeline()
    if rank == 0:
        w = vtkXMLPolyDataWriter()
        w.SetFileName(out_path + ".plane.vtp")
        w.SetInputData(plane.GetClientSideObject().GetOutputDataObject(0))
        w.SetDataModeToBinary()
        w.Write()
er = EmbeddedRemesh(Input=mesh, Surfaces=[plane], Mode=mode, LayerType=layers, NumberOfLayers=3)
start = time.time()
er.UpdatePipeline()
seconds = time.time() - start
volume = er.GetClientSideObject().GetOutputDataObject(0)
surface = er.GetClientSideObject().GetOutputDataObject(1)
region = volume.GetCellData().GetArray("Region")
new = sum(1 for i in range(volume.GetNumberOfCells()) if region.GetValue(i) == 1) if region else -1
print("rank %d of %d: %d cells, %d new, %d surface triangles, EmbeddedRemesh %.2f s"
      % (rank, ranks, volume.GetNumberOfCells(), new, surface.GetNumberOfCells(), seconds))
for obj, writer, ext in ((volume, vtkXMLUnstructuredGridWriter(), "vtu"), (surface, vtkXMLPolyDataWriter(), "vtp")):
    writer.SetFileName("%s.%d.%s" % (out_path, rank, ext))
    writer.SetInputData(obj)
    writer.SetDataModeToBinary()
    writer.Write()
