"""pvbatch script: the OpenFOAM case writer, serial or distributed.

    pvbatch MPIFoamCaseWriterPipeline.py <cone.vtu | pieces.pvtu> <directory>
    mpiexec -np 2 pvbatch --symmetric MPIFoamCaseWriterPipeline.py <pieces.pvtu> <directory>

Writes two cases of the bundled cone with SaveData('<dir>/<case>/<case>.foam'):
- volume: the plain volume (one patch, the boundary), its point fields
  averaged to the cells; distributed, the partitioned reader's pieces with
  one ghost level (GhostCellsGenerator), as ParaView distributes data;
- patches: the OpenFOAM reader's form (a multiblock of internalMesh and the
  cone's five patches, artest.openfoam_multiblock); distributed, each rank
  holds the cells and the patch faces whose centres lie on its side of the
  median x of the cell centres (a patch face's cell may be on the other rank).
"""
import os
import sys

import numpy as np
from paraview.simple import *
from paraview import servermanager
from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet
from vtkmodules.vtkFiltersCore import vtkExtractCells
from vtkmodules.vtkCommonCore import vtkIdList
from vtkmodules.vtkFiltersCore import vtkCellCenters
from vtkmodules.util.numpy_support import vtk_to_numpy

import artest

artest.load_plugin(globals())
data, out_dir = sys.argv[1], sys.argv[2]
pm = servermanager.vtkProcessModule.GetProcessModule()
rank, ranks = pm.GetPartitionId(), pm.GetNumberOfLocalPartitions()

if data.endswith(".pvtu"):
    volume = GhostCellsGenerator(Input=XMLPartitionedUnstructuredGridReader(FileName=[data]))
else:
    volume = XMLUnstructuredGridReader(FileName=[data])
SaveData(os.path.join(out_dir, "volume", "volume.foam"), proxy=volume)

# the cone with its patches, this rank's part of it
cone = artest.load(artest.data("cone20Ma2p5.vtu"))  # the whole mesh on every rank
mb, _ = artest.openfoam_multiblock(cone.VTKObject, artest.cone_patches, artest.CONE_PATCHES)


def centres_x(block):
    centers = vtkCellCenters()
    centers.SetInputData(block)
    centers.Update()
    return vtk_to_numpy(centers.GetOutput().GetPoints().GetData())[:, 0]


median = np.median(centres_x(cone.VTKObject))


def part(block):
    if ranks == 1:
        return block
    x = centres_x(block) if block.GetNumberOfCells() else np.zeros(0)
    ids = vtkIdList()
    for c in np.where((x < median) == (rank == 0))[0]:
        ids.InsertNextId(int(c))
    extract = vtkExtractCells()
    extract.SetInputData(block)
    extract.SetCellList(ids)
    extract.Update()
    out = extract.GetOutput()
    out.GetPointData().RemoveArray("vtkOriginalPointIds")
    out.GetCellData().RemoveArray("vtkOriginalCellIds")
    return out


mine = vtkMultiBlockDataSet()
mine.CopyStructure(mb)
for i in range(mb.GetNumberOfBlocks()):
    b = mb.GetBlock(i)
    if b.IsA("vtkMultiBlockDataSet"):
        inner = vtkMultiBlockDataSet()
        inner.SetNumberOfBlocks(b.GetNumberOfBlocks())
        for j in range(b.GetNumberOfBlocks()):
            inner.SetBlock(j, part(b.GetBlock(j)))
            inner.GetMetaData(j).Set(vtkMultiBlockDataSet.NAME(), b.GetMetaData(j).Get(vtkMultiBlockDataSet.NAME()))
        mine.SetBlock(i, inner)
    else:
        mine.SetBlock(i, part(b))
    mine.GetMetaData(i).Set(vtkMultiBlockDataSet.NAME(), mb.GetMetaData(i).Get(vtkMultiBlockDataSet.NAME()))
producer = PVTrivialProducer()
producer.GetClientSideObject().SetOutput(mine)
SaveData(os.path.join(out_dir, "patches", "patches.foam"), proxy=producer)
print("rank %d of %d: wrote" % (rank, ranks))
