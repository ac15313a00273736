"""pvbatch script: the sensors pipeline on one dataset, serial or distributed.

    pvbatch MPISensorsPipeline.py <data.vtu> <output>
    mpiexec -np 2 pvbatch --symmetric MPISensorsPipeline.py <pieces.pvtu> <output>

Serial: the whole mesh. Distributed: the partitioned reader (one piece per
rank) -> GhostCellsGenerator (built because the sensors request ghost
levels). Both carry SerialCellId / SerialPointId from SplitIntoPieces.py. Then
ShockSensor -> WeightFunction -> FeatureCluster; every rank writes its piece with its ghost
flags, for RunMPISensors.py to compare.
"""
import sys

from paraview.simple import *
from paraview import servermanager

import artest

artest.load_plugin(globals())
data, out_path = sys.argv[1], sys.argv[2]
ranks = servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()

if data.endswith(".pvtu"):
    upstream = GhostCellsGenerator(Input=XMLPartitionedUnstructuredGridReader(FileName=[data]))
else:
    upstream = XMLUnstructuredGridReader(FileName=[data])
ss = ShockSensor(Input=upstream, Velocity=["POINTS", "U"], Pressure=["POINTS", "p"], Density=["POINTS", "rho"])
wf = WeightFunction(Input=ss, Variables=["rho", "rhoU", "rhoE"], ComputePointWeight=1)
fc = FeatureCluster(Input=wf, SensorArray=["POINTS", "WeightFunction"], SensorRange=[1.5, 2.0], DilationRings=1)
fc.UpdatePipeline()

# Run with pvbatch --symmetric: the script runs on every rank; each writes its
# own piece, with its ghost flags, as <output>.<rank>.vtu.
rank = servermanager.vtkProcessModule.GetProcessModule().GetPartitionId()
local = fc.GetClientSideObject().GetOutputDataObject(0)
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter
writer = vtkXMLUnstructuredGridWriter()
writer.SetFileName("%s.%d.vtu" % (out_path, rank))
writer.SetInputData(local)
writer.SetDataModeToBinary()
writer.Write()
print("rank %d of %d wrote %d cells" % (rank, ranks, local.GetNumberOfCells()))
if rank == 0:
    # FeatureCluster's medial points are produced on rank 0.
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter
    medial = vtkXMLPolyDataWriter()
    medial.SetFileName("%s.medial.vtp" % out_path)
    medial.SetInputData(fc.GetClientSideObject().GetOutputDataObject(1))
    medial.SetDataModeToBinary()
    medial.Write()
