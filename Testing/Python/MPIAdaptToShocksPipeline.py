"""pvbatch script: AdaptToShocks with its defaults, serial or distributed.

    pvbatch MPIAdaptToShocksPipeline.py <mesh.vtu> <output> [Prisms]
    mpiexec -np 2 pvbatch --symmetric MPIAdaptToShocksPipeline.py <pieces.pvtu> <output> [Prisms]

With "Prisms", AdaptToShocks makes prism layers (LayerType 'Prisms'),
otherwise it runs with all its defaults.

Distributed, the partitioned reader's pieces get one ghost level
(GhostCellsGenerator), as ParaView gives a distributed solution to a filter.
Every rank writes its piece of the adapted mesh as <output>.<rank>.vtu and
what it holds of port 1 (the fitted surfaces) as <output>.<rank>.vtp, and
prints its counts and the time AdaptToShocks took.
"""
import sys
import time

from paraview.simple import *
from paraview import servermanager
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter, vtkXMLUnstructuredGridWriter

import artest

artest.load_plugin(globals())
data, out_path = sys.argv[1], sys.argv[2]
pm = servermanager.vtkProcessModule.GetProcessModule()
rank, ranks = pm.GetPartitionId(), pm.GetNumberOfLocalPartitions()
if data.endswith(".pvtu"):
    mesh = GhostCellsGenerator(Input=XMLPartitionedUnstructuredGridReader(FileName=[data]))
else:
    mesh = XMLUnstructuredGridReader(FileName=[data])
adapt = AdaptToShocks(Input=mesh, **({"LayerType": "Prisms"} if sys.argv[3:] == ["Prisms"] else {}))
start = time.time()
adapt.UpdatePipeline()
seconds = time.time() - start
volume = adapt.GetClientSideObject().GetOutputDataObject(0)
surfaces = adapt.GetClientSideObject().GetOutputDataObject(1)
print("rank %d of %d: %d points, %d cells, %d surface triangles, AdaptToShocks %.2f s"
      % (rank, ranks, volume.GetNumberOfPoints(), volume.GetNumberOfCells(), surfaces.GetNumberOfCells(), seconds))
for obj, writer, ext in ((volume, vtkXMLUnstructuredGridWriter(), "vtu"), (surfaces, vtkXMLPolyDataWriter(), "vtp")):
    writer.SetFileName("%s.%d.%s" % (out_path, rank, ext))
    writer.SetInputData(obj)
    writer.SetDataModeToBinary()
    writer.Write()
