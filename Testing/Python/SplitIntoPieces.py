"""Splits a .vtu into a 2-piece .pvtu (cells split at the median x of their
centres; points at the cut are duplicated, as in any partitioned dataset),
carrying the serial ids as SerialCellId / SerialPointId (also as the cells'
and the points' global ids).

    pvpython SplitIntoPieces.py <in.vtu> <out.pvtu> [<serial-with-ids.vtu>]

The optional third file is the whole mesh with the same ids, for the serial
reference run. (ParaView's GenerateIds is not used for that: it replaces the
active scalars array, which can be one of the flow variables.)

The MPI tests read the pieces with the parallel reader: RedistributeDataSet
cannot be used with Debian's ParaView 5.11 under MPI (it exchanges the data
as raw-appended XML that this build's parser rejects).
"""
import sys

import numpy as np
from vtkmodules.all import vtkExtractCells, vtkXMLPUnstructuredGridWriter
from vtkmodules.numpy_interface import dataset_adapter as dsa
from vtkmodules.util.numpy_support import numpy_to_vtkIdTypeArray
from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
from vtkmodules.vtkCommonCore import vtkIdList
from vtkmodules.vtkCommonExecutionModel import vtkAlgorithm, vtkStreamingDemandDrivenPipeline
from vtkmodules.vtkFiltersCore import vtkCellCenters
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader


def with_serial_ids(path):
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    for data, n, name in ((grid.GetCellData(), grid.GetNumberOfCells(), "SerialCellId"),
                          (grid.GetPointData(), grid.GetNumberOfPoints(), "SerialPointId")):
        ids = numpy_to_vtkIdTypeArray(np.arange(n, dtype=np.int64), deep=1)
        ids.SetName(name)
        data.AddArray(ids)
    # The point ids are the points' global ids: GhostCellsGenerator matches
    # the partitions' interface points by them.
    grid.GetPointData().SetGlobalIds(grid.GetPointData().GetArray("SerialPointId"))
    # The cell ids are the cells' global ids, as a partitioner leaves them
    # (RedistributeDataSet's GenerateGlobalCellIds): a mesh gathered to
    # rank 0 is put back in the serial order by them.
    grid.GetCellData().SetGlobalIds(grid.GetCellData().GetArray("SerialCellId"))
    return grid


class Pieces(VTKPythonAlgorithmBase):
    """Serves piece 0 (x below the median cell centre) or piece 1 (the rest)."""

    def __init__(self, grid):
        VTKPythonAlgorithmBase.__init__(self, nInputPorts=0, nOutputPorts=1, outputType="vtkUnstructuredGrid")
        self.grid = grid
        centers = vtkCellCenters()
        centers.SetInputData(grid)
        centers.Update()
        x = np.asarray(dsa.WrapDataObject(centers.GetOutput()).Points)[:, 0]
        self.low = x < np.median(x)

    def RequestInformation(self, request, inInfo, outInfo):
        outInfo.GetInformationObject(0).Set(vtkAlgorithm.CAN_HANDLE_PIECE_REQUEST(), 1)
        return 1

    def RequestData(self, request, inInfo, outInfo):
        piece = outInfo.GetInformationObject(0).Get(vtkStreamingDemandDrivenPipeline.UPDATE_PIECE_NUMBER())
        ids = vtkIdList()
        for c in np.where(self.low if piece == 0 else ~self.low)[0]:
            ids.InsertNextId(int(c))
        extract = vtkExtractCells()
        extract.SetInputData(self.grid)
        extract.SetCellList(ids)
        extract.Update()
        out = self.GetOutputData(outInfo, 0)
        out.ShallowCopy(extract.GetOutput())
        out.GetPointData().RemoveArray("vtkOriginalPointIds")
        out.GetCellData().RemoveArray("vtkOriginalCellIds")
        return 1


if __name__ == "__main__":
    grid = with_serial_ids(sys.argv[1])
    if len(sys.argv) > 3:
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter
        whole = vtkXMLUnstructuredGridWriter()
        whole.SetInputData(grid)
        whole.SetFileName(sys.argv[3])
        whole.SetDataModeToBinary()
        if whole.Write() != 1:
            sys.exit("could not write %s" % sys.argv[3])
    source = Pieces(grid)
    writer = vtkXMLPUnstructuredGridWriter()
    writer.SetInputConnection(source.GetOutputPort())
    writer.SetFileName(sys.argv[2])
    writer.SetNumberOfPieces(2)
    writer.SetStartPiece(0)
    writer.SetEndPiece(1)
    writer.SetDataModeToBinary()
    if writer.Write() != 1:
        sys.exit("could not write %s" % sys.argv[2])
