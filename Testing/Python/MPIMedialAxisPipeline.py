"""pvbatch script: WeightFunction -> Contour -> MedialAxisDelaunay (with the
mesh as Domain) on the analytic oblique shock, serial or distributed.

    pvbatch MPIMedialAxisPipeline.py <mesh.vtu> <output>
    mpiexec -np 2 pvbatch --symmetric MPIMedialAxisPipeline.py <pieces.pvtu> <output>

Distributed, the pieces get one ghost level (GhostCellsGenerator) so that
the weight function and the contour are those of the whole mesh. Rank 0
writes the sheet as <output>.vtp; every rank prints how many cells it holds.
"""
import sys

from paraview.simple import *
from paraview import servermanager
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

import artest

artest.load_plugin(globals())
data, out_path = sys.argv[1], sys.argv[2]
pm = servermanager.vtkProcessModule.GetProcessModule()
rank, ranks = pm.GetPartitionId(), pm.GetNumberOfLocalPartitions()

if data.endswith(".pvtu"):
    mesh = GhostCellsGenerator(Input=XMLPartitionedUnstructuredGridReader(FileName=[data]))
else:
    mesh = XMLUnstructuredGridReader(FileName=[data])
weight = WeightFunction(Input=mesh, Variables=["p", "rho"], ComputePointWeight=1)
contour = Contour(Input=weight, ContourBy=["POINTS", "WeightFunction"], Isosurfaces=[1.5], ComputeNormals=1)
medial = MedialAxisDelaunay(Input=contour, Domain=mesh)
medial.UpdatePipeline()
local = medial.GetClientSideObject().GetOutputDataObject(0)
print("rank %d of %d: sheet %d cells" % (rank, ranks, local.GetNumberOfCells()))
if rank == 0:
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(out_path + ".vtp")
    writer.SetInputData(local)
    writer.SetDataModeToBinary()
    writer.Write()
