// SPDX-License-Identifier: BSD-3-Clause
#include "vtkEmbeddedRemesh.h"
#include "vtkEmbeddedRemeshPlanes.h"
#include "vtkEmbeddedRemeshStages.h"

#include "ARCavity.h"
#include "ARCellQuality.h"
#include "ARLayerRelease.h"
#include "ARMeshSize.h"
#include "ARPrismLayers.h"
#include "ARSurfaceRemesh.h"
#include "ARTetGeometry.h"
#include "vtkARInputChecks.h"
#include "vtkARMeshKernels.h"
#include "vtkARParallel.h"
#include "vtkARFieldTransfer.h"

#include "vtkAppendFilter.h"
#include "vtkAppendPolyData.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkCellTypes.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataObjectTreeIterator.h"
#include "vtkDataSet.h"
#include "vtkDataSetAttributesFieldList.h"
#include "vtkDoubleArray.h"
#include "vtkExtractCells.h"
#include "vtkIdTypeArray.h"
#include "vtkFieldData.h"
#include "vtkGenericCell.h"
#include "vtkGeometryFilter.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkMultiProcessController.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPThreadLocalObject.h"
#include "vtkSmartPointer.h"
#include "vtkStaticCellLocator.h"
#include "vtkStaticCleanPolyData.h"
#include "vtkStaticPointLocator.h"
#include "vtkTriangleFilter.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <chrono>
#include <cmath>
#include <new>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkEmbeddedRemesh);


//------------------------------------------------------------------------------
double vtkEmbeddedRemesh::GetSurfaceSizeFactorUsed(bool twoDimensional) const
{
  if (this->SurfaceSizeFactor > 0.0)
  {
    return this->SurfaceSizeFactor;
  }
  if (this->LayerType == PRISMS)
  {
    return 1.0;
  }
  // In 3-D the refill gets free points a regular tetrahedron's height off S
  // (ar::CavityOptions::OffsetPointSpacing), which make the cells on S as
  // fine across it as along: 0.21 there reaches what 0.2 did without them
  // with a margin (SurfaceSizeRatio 0.28-0.31 instead of 0.31-0.345), at
  // 8-17 % more nodes on the validation cases and 3 % on the 5e6 cube (0.2
  // with the points: 9-25 %, and the 5e6 step 30-32 s).
  return twoDimensional ? 0.2 : 0.21;
}

//------------------------------------------------------------------------------
vtkEmbeddedRemesh::vtkEmbeddedRemesh()
{
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(2);
}

//------------------------------------------------------------------------------
int vtkEmbeddedRemesh::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Remove(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE());
    info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
    info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkMultiBlockDataSet");
    return 1;
  }
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  info->Set(vtkAlgorithm::INPUT_IS_REPEATABLE(), 1);
  // Optional for the executive, so that an empty Surfaces selection gives the
  // filter's one message (RequestData) instead of the pipeline's generic
  // errors on every update.
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkEmbeddedRemesh::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkDataObject" : "vtkPolyData");
  return 1;
}

//------------------------------------------------------------------------------
int vtkEmbeddedRemesh::RequestDataObject(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return MeshAndSurfaceDataObjects(inputVector, outputVector);
}

//------------------------------------------------------------------------------
int vtkEmbeddedRemesh::MeshAndSurfaceDataObjects(vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataObject* input = vtkDataObject::GetData(inputVector[0], 0);
  if (!input)
  {
    return 0;
  }
  vtkInformation* info = outputVector->GetInformationObject(0);
  vtkDataObject* output = info->Get(vtkDataObject::DATA_OBJECT());
  const bool composite = vtkMultiBlockDataSet::SafeDownCast(input) != nullptr;
  if (!output || (composite ? !vtkMultiBlockDataSet::SafeDownCast(output) : !vtkUnstructuredGrid::SafeDownCast(output)))
  {
    vtkSmartPointer<vtkDataObject> fresh;
    if (composite)
    {
      fresh = vtkSmartPointer<vtkMultiBlockDataSet>::New();
    }
    else
    {
      fresh = vtkSmartPointer<vtkUnstructuredGrid>::New();
    }
    info->Set(vtkDataObject::DATA_OBJECT(), fresh);
  }
  vtkInformation* info1 = outputVector->GetInformationObject(1);
  if (!vtkPolyData::SafeDownCast(info1->Get(vtkDataObject::DATA_OBJECT())))
  {
    info1->Set(vtkDataObject::DATA_OBJECT(), vtkSmartPointer<vtkPolyData>::New());
  }
  return 1;
}

//------------------------------------------------------------------------------
vtkUnstructuredGrid* vtkEmbeddedRemesh::VolumeLeaf(vtkDataObject* data)
{
  if (auto* grid = vtkUnstructuredGrid::SafeDownCast(data))
  {
    return grid;
  }
  auto* mb = vtkMultiBlockDataSet::SafeDownCast(data);
  if (!mb)
  {
    return nullptr;
  }
  vtkUnstructuredGrid* volume = nullptr;
  vtkSmartPointer<vtkDataObjectTreeIterator> it;
  it.TakeReference(mb->NewTreeIterator());
  for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
  {
    auto* grid = vtkUnstructuredGrid::SafeDownCast(it->GetCurrentDataObject());
    const char* name = it->GetCurrentMetaData()->Get(vtkCompositeDataSet::NAME());
    const bool isInternal = name && std::string(name) == "internalMesh";
    bool solid = false;
    for (vtkIdType c = 0; grid && c < grid->GetNumberOfCells() && !solid; ++c)
    {
      solid = vtkCellTypes::GetDimension(grid->GetCellType(c)) == 3;
    }
    if (grid && solid && (isInternal || !volume))
    {
      volume = grid;
      if (isInternal)
      {
        break;
      }
    }
  }
  return volume;
}

//------------------------------------------------------------------------------
int vtkEmbeddedRemesh::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // Threads for this filter's own work only: the process's SMP backend is
  // left as the user has it.
  int result = 1;
  vtkARMeshKernels::Threaded([&]() { result = this->ExecuteData(request, inputVector, outputVector); });
  return result;
}

//------------------------------------------------------------------------------
int vtkEmbeddedRemesh::ExecuteData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataObject* inputObject = vtkDataObject::GetData(inputVector[0], 0);
  vtkPolyData* embedded = vtkPolyData::GetData(outputVector, 1);
  embedded->Initialize();
  std::vector<vtkDataSet*> surfaces;
  for (int k = 0; k < inputVector[1]->GetNumberOfInformationObjects(); ++k)
  {
    surfaces.push_back(vtkDataSet::GetData(inputVector[1], k));
  }
  if (surfaces.empty())
  {
    vtkErrorMacro(<< "EmbeddedRemesh has no feature surface: connect one or more to Surfaces (e.g. "
                     "Quadric Fit's or Medial Axis Delaunay's output). The input passes through unchanged.");
    vtkDataObject::GetData(outputVector, 0)->ShallowCopy(inputObject);
    return 1;
  }
  // Whatever the core throws (std::bad_alloc when a job outgrows the
  // memory despite the size estimate, a CGAL precondition) becomes an error,
  // never an abort of the application.
  auto remesh = [&](vtkUnstructuredGrid* volume, vtkUnstructuredGrid* out, vtkEmbeddedRemeshPlanes* planes) {
    std::string failure;
    try
    {
      return this->RemeshVolume(volume, surfaces, out, embedded, planes);
    }
    catch (const std::exception& e)
    {
      failure = vtkEmbeddedRemeshFailure(e);
    }
    vtkErrorMacro(<< failure << " The input passes through unchanged.");
    out->ShallowCopy(volume);
    embedded->Initialize();
    if (planes)
    {
      planes->Valid = false;
    }
    return 1;
  };
  if (auto* grid = vtkUnstructuredGrid::SafeDownCast(inputObject))
  {
    return remesh(grid, vtkUnstructuredGrid::GetData(outputVector, 0), nullptr);
  }
  // A multiblock (ParaView's OpenFOAM reader): the volume leaf ("internalMesh",
  // else the first unstructured grid with 3-D cells) is remeshed; the patch
  // leaves pass through, as the boundary does not change.
  auto* input = vtkMultiBlockDataSet::SafeDownCast(inputObject);
  auto* output = vtkMultiBlockDataSet::GetData(outputVector, 0);
  output->CopyStructure(input);
  vtkUnstructuredGrid* volume = VolumeLeaf(input);
  vtkSmartPointer<vtkDataObjectTreeIterator> it;
  it.TakeReference(input->NewTreeIterator());
  vtkNew<vtkUnstructuredGrid> remeshed;
  double missing = volume ? 0.0 : 1.0; // the distributed remesh is collective: all or none
  vtkARParallel::AllReduceMax(&missing, 1);
  if (volume && missing > 0.0)
  {
    vtkErrorMacro(<< "The multiblock input has no volume block on another rank; EmbeddedRemesh "
                     "under MPI needs the volume on every rank. The input passes through unchanged.");
    output->ShallowCopy(input);
    return 1;
  }
  if (!volume)
  {
    vtkErrorMacro(<< "The multiblock input has no block with 3-D cells (e.g. internalMesh). The "
                     "input passes through unchanged.");
    output->ShallowCopy(input);
    return 1;
  }
  vtkEmbeddedRemeshPlanes planes;
  remesh(volume, remeshed, &planes);
  for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
  {
    vtkDataObject* leaf = it->GetCurrentDataObject();
    vtkSmartPointer<vtkPolyData> rebuilt;
    if (leaf == volume)
    {
      output->SetDataSet(it, remeshed);
    }
    else if (planes.Valid &&
      (rebuilt = vtkEmbeddedRemeshRebuildPatch(vtkPolyData::SafeDownCast(leaf), planes)))
    {
      // 2-D mode: a patch on the front/back planes, rebuilt on the new cells.
      output->SetDataSet(it, rebuilt);
    }
    else if (leaf)
    {
      vtkSmartPointer<vtkDataObject> copy;
      copy.TakeReference(leaf->NewInstance());
      copy->ShallowCopy(leaf);
      output->SetDataSet(it, copy);
    }
  }
  return 1;
}

namespace
{
/// The prisms and pyramids an earlier adaptation left floating in the mesh
/// (ARLayerRelease.h), split so that the cavity may take them.
struct ReleasedLayers
{
  std::vector<vtkIdType> Cell; ///< per cell of `Release`: its input cell
  ar::LayerRelease Release;
};

/// Keeps input cell `c` as it is: its nodes locked, and a 3-D cell's faces
/// bound the region S is trimmed at (LockedCellFaces).
void LockCell(vtkUnstructuredGrid* input, vtkIdType c, vtkIdType npts, const vtkIdType* pts, vtkGenericCell* cell,
  ar::CavityOptions& options, std::vector<vtkIdType>& otherCell)
{
  for (vtkIdType k = 0; k < npts; ++k)
  {
    options.LockedNodes[pts[k]] = 1;
  }
  otherCell.push_back(c);
  if (vtkCellTypes::GetDimension(input->GetCellType(c)) == 3)
  {
    input->GetCell(c, cell);
    for (int f = 0; f < cell->GetNumberOfFaces(); ++f)
    {
      vtkCell* face = cell->GetFace(f);
      options.LockedCellFaces.push_back(face->GetNumberOfPoints());
      for (vtkIdType k = 0; k < face->GetNumberOfPoints(); ++k)
      {
        options.LockedCellFaces.push_back(face->GetPointId(k));
      }
    }
  }
}

/// V for the core: the input's tetrahedra (`tetCell`: their input cells),
/// then the released layers' tetrahedra (their input cell; in
/// options.CellGroups their group); the other 3-D cells and the
/// boundary-patch faces kept (`otherCell`, in input order), their nodes
/// locked and the 3-D ones' faces given as LockedCellFaces. The prisms and
/// pyramids are released where ARLayerRelease allows it, against the
/// tetrahedra and the faces of the other kept 3-D cells, and locked
/// otherwise. False with `problem` for a cell type EmbeddedRemesh does not
/// take.
bool SplitVolume(vtkUnstructuredGrid* input, ar::TetMesh& tets, ar::CavityOptions& options,
  std::vector<vtkIdType>& tetCell, std::vector<vtkIdType>& otherCell, ReleasedLayers& released, std::string& problem)
{
  const vtkIdType nPoints = input->GetNumberOfPoints();
  tets.Points.resize(3 * nPoints);
  for (vtkIdType i = 0; i < nPoints; ++i)
  {
    input->GetPoint(i, &tets.Points[3 * i]);
  }
  options.LockedNodes.assign(nPoints, 0);
  const vtkIdType nCells = input->GetNumberOfCells();
  vtkIdType nTets = 0;
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    nTets += input->GetCellType(c) == VTK_TETRA ? 1 : 0;
  }
  tets.Tetrahedra.reserve(4 * static_cast<std::size_t>(nTets));
  tetCell.reserve(static_cast<std::size_t>(nTets));
  vtkNew<vtkIdList> ids;
  vtkNew<vtkGenericCell> lockedCell;
  ar::LayerCells layers; // the prisms and pyramids, decided on below
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    const int type = input->GetCellType(c);
    vtkIdType npts;
    const vtkIdType* pts;
    input->GetCellPoints(c, npts, pts, ids);
    if (type == VTK_TETRA)
    {
      tets.Tetrahedra.insert(tets.Tetrahedra.end(), pts, pts + 4);
      tetCell.push_back(c);
    }
    else if (type == VTK_WEDGE || type == VTK_PYRAMID)
    {
      layers.Sizes.push_back(static_cast<int>(npts));
      layers.Ids.insert(layers.Ids.end(), pts, pts + npts);
      released.Cell.push_back(c);
    }
    else if (type == VTK_HEXAHEDRON || type == VTK_VOXEL || type == VTK_POLYHEDRON || type == VTK_TRIANGLE ||
      type == VTK_QUAD || type == VTK_POLYGON)
    {
      // Kept as they are: other 3-D cells, and boundary-patch faces (2-D
      // cells with a PatchId, as the solver writers take them). The 3-D
      // ones (e.g. near-wall layers) bound a region S is trimmed at.
      LockCell(input, c, npts, pts, lockedCell, options, otherCell);
    }
    else
    {
      std::ostringstream msg;
      msg << "Cell " << c << " has type " << type
          << "; EmbeddedRemesh takes linear 3-D cells (tetrahedra are remeshed; hexahedra, "
             "wedges, pyramids and polyhedra are kept) and triangles, quads or polygons as "
             "boundary-patch faces (kept).";
      problem = msg.str();
      return false;
    }
  }
  if (released.Cell.empty())
  {
    return true;
  }
  // LockedCellFaces holds the other 3-D cells' faces so far: what a layer
  // must not share a quad with.
  ar::LayerRelease& lr = released.Release;
  lr = ar::ReleaseFloatingLayers(tets.Points.data(), tets.Tetrahedra.data(), tets.NumberOfTetrahedra(), layers,
    options.LockedCellFaces);
  for (std::size_t k = 0; k < released.Cell.size(); ++k)
  {
    if (lr.Group[k] < 0)
    {
      vtkIdType npts;
      const vtkIdType* pts;
      input->GetCellPoints(released.Cell[k], npts, pts, ids);
      LockCell(input, released.Cell[k], npts, pts, lockedCell, options, otherCell);
    }
  }
  std::sort(otherCell.begin(), otherCell.end()); // input order, as the kept cells come out
  if (!lr.TetrahedronCell.empty())
  {
    options.CellGroups.assign(tetCell.size(), -1);
    for (std::size_t t = 0; t < lr.TetrahedronCell.size(); ++t)
    {
      tets.Tetrahedra.insert(tets.Tetrahedra.end(), &lr.Tetrahedra[4 * t], &lr.Tetrahedra[4 * t] + 4);
      tetCell.push_back(released.Cell[lr.TetrahedronCell[t]]);
      options.CellGroups.push_back(lr.Group[lr.TetrahedronCell[t]]);
    }
  }
  return true;
}

/// After the refill: the released groups the cavity did not take come back
/// as their cells (`restored`, input cells, added to the kept ones), their
/// tetrahedra are skipped (`skipKept`, per tetrahedron of V); returns the
/// released cells the cavity took.
vtkIdType RestoreKeptLayers(const ReleasedLayers& released, const ar::CavityOptions& options,
  const ar::CavityRemesh& result, std::vector<char>& skipKept, std::vector<vtkIdType>& restored)
{
  const ar::LayerRelease& lr = released.Release;
  if (lr.NumberOfGroups == 0)
  {
    return 0;
  }
  std::vector<char> kept(static_cast<std::size_t>(lr.NumberOfGroups), 0);
  for (const std::int64_t src : result.SourceCell)
  {
    if (src >= 0 && options.CellGroups[src] >= 0)
    {
      kept[options.CellGroups[src]] = 1;
    }
  }
  skipKept.assign(options.CellGroups.size(), 0);
  for (std::size_t t = 0; t < options.CellGroups.size(); ++t)
  {
    skipKept[t] = options.CellGroups[t] >= 0 && kept[options.CellGroups[t]] ? 1 : 0;
  }
  vtkIdType taken = 0;
  for (std::size_t k = 0; k < released.Cell.size(); ++k)
  {
    const std::int64_t g = lr.Group[k];
    if (g >= 0 && kept[g])
    {
      restored.push_back(released.Cell[k]);
    }
    taken += g >= 0 && !kept[g] ? 1 : 0;
  }
  return taken;
}

/// The kept non-tetrahedral cells (`otherCell`) in the output's point ids.
void AddKeptCells(vtkUnstructuredGrid* input, const std::vector<vtkIdType>& otherCell,
  const std::vector<vtkIdType>& outOfInput, vtkEmbeddedRemeshCells& cells)
{
  vtkNew<vtkIdList> ids;
  for (vtkIdType c : otherCell)
  {
    input->GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      ids->SetId(k, outOfInput[ids->GetId(k)]);
    }
    if (input->GetCellType(c) == VTK_POLYHEDRON)
    {
      vtkNew<vtkIdList> faces;
      input->GetFaceStream(c, faces);
      // The face stream holds point ids after each face's count: map them.
      vtkIdType pos = 1;
      for (vtkIdType f = 0; f < faces->GetId(0); ++f)
      {
        const vtkIdType n = faces->GetId(pos++);
        for (vtkIdType k = 0; k < n; ++k, ++pos)
        {
          faces->SetId(pos, outOfInput[faces->GetId(pos)]);
        }
      }
      cells.AddPolyhedron(c, faces);
    }
    else
    {
      cells.Add(input->GetCellType(c), ids->GetNumberOfIds(), ids->GetPointer(0), c, 0, -1, 0);
    }
  }
}

/// The removed tetrahedra (`cavityTet`, of V, whose points are the input's)
/// on the input's points.
vtkSmartPointer<vtkUnstructuredGrid> CavityGrid(
  vtkUnstructuredGrid* input, const ar::TetMesh& V, const std::vector<std::size_t>& cavityTet)
{
  const auto nCavity = static_cast<vtkIdType>(cavityTet.size());
  auto cavity = vtkSmartPointer<vtkUnstructuredGrid>::New();
  cavity->SetPoints(input->GetPoints());
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(nCavity + 1);
  connectivity->SetNumberOfValues(4 * nCavity);
  vtkARParallel::AdviseHugePages(offsets);
  vtkARParallel::AdviseHugePages(connectivity);
  vtkSMPTools::For(0, nCavity, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType c = b; c < e; ++c)
    {
      const std::int64_t* pts = &V.Tetrahedra[4 * cavityTet[c]];
      for (int k = 0; k < 4; ++k)
      {
        connectivity->SetValue(4 * c + k, pts[k]);
      }
      offsets->SetValue(c, 4 * c);
    }
  });
  offsets->SetValue(nCavity, 4 * nCavity);
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, connectivity);
  cavity->SetCells(VTK_TETRA, cells);
  return cavity;
}

/// Fields: kept points and cells copy theirs; new ones interpolate from the
/// input's cells that were removed (the cavity holds every new point), so
/// the cost follows the cavity, not the whole mesh. A new point takes the
/// linear interpolation in the removed tetrahedron that contains it, a new
/// cell the values of the removed tetrahedron that contains its centre
/// (TetLocator: the same answer whatever the threads do).
void InterpolateFromCavity(vtkUnstructuredGrid* input, const ar::TetMesh& V, vtkUnstructuredGrid* output,
  const ar::CavityRemesh& result, const std::vector<vtkIdType>& tetCell, const std::vector<vtkIdType>& sourceCell)
{
  const vtkIdType nOut = output->GetNumberOfPoints();
  const auto nCellsOut = static_cast<vtkIdType>(sourceCell.size());
  output->GetPointData()->InterpolateAllocate(input->GetPointData(), nOut);
  output->GetCellData()->CopyAllocate(input->GetCellData(), nCellsOut);
  std::vector<char> keptTet(tetCell.size(), 0);
  for (const std::int64_t src : result.SourceCell)
  {
    if (src >= 0)
    {
      keptTet[src] = 1;
    }
  }
  std::vector<vtkIdType> cavityCell; // input cell id of each cavity cell
  std::vector<std::size_t> cavityTet; // and its tetrahedron of V
  for (std::size_t t = 0; t < tetCell.size(); ++t)
  {
    if (!keptTet[t])
    {
      cavityCell.push_back(tetCell[t]);
      cavityTet.push_back(t);
    }
  }
  vtkSmartPointer<vtkUnstructuredGrid> cavity = CavityGrid(input, V, cavityTet);
  vtkARFieldTransfer::TetLocator locator;
  locator.Build(cavity);
  std::vector<char> isNew(nOut, 0);
  std::vector<vtkIdType> startOf(nOut, -1);
  for (vtkIdType i = 0; i < nOut; ++i)
  {
    isNew[i] = result.SourcePoint[i] < 0 ? 1 : 0;
    startOf[i] = isNew[i] ? -1 : locator.CellOfPoint(result.SourcePoint[i]);
  }
  const vtkEmbeddedRemeshNewTuples found = vtkEmbeddedRemeshLocateNew(locator, output, isNew, startOf, sourceCell);

  vtkARFieldTransfer::TupleSources pointSources(nOut, 4), cellSources(nCellsOut, 1);
  for (vtkIdType i = 0; i < nOut; ++i)
  {
    if (result.SourcePoint[i] >= 0)
    {
      pointSources.Copy(i, result.SourcePoint[i]);
    }
  }
  for (vtkIdType k = 0; k < nCellsOut; ++k)
  {
    if (sourceCell[k] >= 0)
    {
      cellSources.Copy(k, sourceCell[k]);
    }
  }
  found.Fill(locator, pointSources, cellSources, &cavityCell);
  vtkARFieldTransfer::TransferData(input->GetPointData(), output->GetPointData(), pointSources);
  vtkARFieldTransfer::TransferData(input->GetCellData(), output->GetCellData(), cellSources);
}
}

//------------------------------------------------------------------------------
int vtkEmbeddedRemesh::RemeshVolume(vtkUnstructuredGrid* input,
  const std::vector<vtkDataSet*>& surfaces, vtkUnstructuredGrid* output, vtkPolyData* embedded,
  vtkEmbeddedRemeshPlanes* planes)
{
  auto passThrough = [&](const std::string& message) {
    vtkErrorMacro(<< message << " The input passes through unchanged.");
    output->ShallowCopy(input);
    return 1;
  };
  auto cancelled = [&]() {
    if (!this->CheckAbort())
    {
      return false;
    }
    output->ShallowCopy(input);
    return true;
  };
  std::string problem;
  if (!vtkEmbeddedRemeshOptionsValid(this, problem))
  {
    return passThrough(problem);
  }
  if (vtkARParallel::NumberOfRanks() > 1)
  {
    return this->RemeshDistributed(input, surfaces, output, embedded);
  }
  if (!input || input->GetNumberOfCells() == 0)
  {
    return passThrough("The volume mesh is empty.");
  }
  vtkEmbeddedRemeshLap lap; // Seconds* in the field data
  vtkEmbeddedRemeshSummary summary;
  // ---- Coordinates and conformity, before any mesher sees them.
  problem = vtkEmbeddedRemeshCheckCoordinates(input, surfaces);
  if (!problem.empty())
  {
    return passThrough("EmbeddedRemesh: " + problem);
  }
  // ---- 2-D mode: a one-cell-deep mesh is remeshed on its cross-section.
  std::string not2D = "TwoDimensional is Off";
  if (this->TwoDimensional == TWO_DIMENSIONAL_AUTO)
  {
    vtkEmbeddedRemeshLayout layout;
    if (vtkEmbeddedRemeshDetect2D(input, layout, not2D))
    {
      return this->Remesh2D(input, layout, surfaces, output, embedded, planes);
    }
  }
  // ---- The feature surfaces, merged and triangulated.
  const vtkEmbeddedRemeshSoup s = vtkEmbeddedRemeshCollectSurfaces(surfaces);
  if (s.Triangles.empty())
  {
    return passThrough("The feature surface is empty (no Surfaces connected, or none has triangles).");
  }
  // ---- V: its tetrahedra; other 3-D cells are kept and lock their nodes.
  const vtkIdType nPoints = input->GetNumberOfPoints();
  ar::TetMesh tets;
  ar::CavityOptions options;
  std::vector<vtkIdType> tetCell, otherCell;
  ReleasedLayers released;
  if (!SplitVolume(input, tets, options, tetCell, otherCell, released, problem))
  {
    return passThrough(problem);
  }
  if (tetCell.empty())
  {
    return passThrough("The volume mesh has no tetrahedra to remesh, and it is not a one-cell-deep "
                       "(2-D) mesh either (" + not2D + ").");
  }
  this->UpdateProgress(0.1);
  if (cancelled())
  {
    return 1;
  }
  summary.Seconds.emplace_back("SecondsInput", lap());

  // ---- S remeshed at the edge length: SurfaceSizeFactor times the input's
  // size at S, h_S (the median l_v at the node of V nearest to each S point).
  std::vector<double> lv =
    ar::LongestEdgeAtNodes(tets.Points.data(), nPoints, tets.Tetrahedra.data(), tets.NumberOfTetrahedra());
  const double inputSize =
    vtkEmbeddedRemeshInputSizeAt(tets.Points.data(), nPoints, 3, lv, nullptr, s.Points.data(), s.NumberOfPoints());
  const double edge = this->SurfaceEdgeLength > 0.0 ? this->SurfaceEdgeLength : this->GetSurfaceSizeFactorUsed() * inputSize;
  if (!(edge > 0.0))
  {
    return passThrough("Could not find the mesh size near the feature surface; set SurfaceEdgeLength.");
  }
  const double volumeBefore = ar::TotalSignedVolume(tets); // (ComputeStatistics' TotalVolume, without its angles)
  {
    // The job's size, before CGAL or TetGen allocate it.
    double area = 0.0, diagonal = 0.0;
    vtkEmbeddedRemeshSurfaceAreaAndDiagonal(s, area, diagonal);
    if (!vtkEmbeddedRemeshJobFits(this, 3, area, diagonal, edge, inputSize, volumeBefore,
          static_cast<double>(tets.NumberOfTetrahedra()), problem))
    {
      return passThrough(problem);
    }
  }
  const vtkEmbeddedRemeshSoup r = vtkEmbeddedRemeshRemeshSurface(this, s, edge);
  this->UpdateProgress(0.3);
  if (cancelled())
  {
    return 1;
  }
  summary.Seconds.emplace_back("SecondsSurfaceMeshing", lap());

  // ---- The cavity and its refill.
  if (!vtkEmbeddedRemeshCavityOptions(this, edge, options, problem))
  {
    return passThrough(problem);
  }
  options.LongestEdges = std::move(lv); // V's l_v, not computed again
  ar::CavityRemesh result;
  if (!ar::RemeshLocalCavity(tets, r.Points.data(), r.NumberOfPoints(), r.Triangles.data(), r.NumberOfTriangles(),
        options, result, problem))
  {
    return passThrough("EmbeddedRemesh: " + problem);
  }
  this->UpdateProgress(0.8);
  if (cancelled())
  {
    return 1;
  }
  lap();

  // ---- Output mesh: the refill's tetrahedra (kept and new), the kept
  // other cells, the layers; the refill's points are the output's.
  const auto nOut = static_cast<vtkIdType>(result.SourcePoint.size());
  std::vector<vtkIdType> outOfInput(nPoints, -1);
  vtkIdType keptPoints = 0;
  for (vtkIdType i = 0; i < nOut; ++i)
  {
    if (result.SourcePoint[i] >= 0)
    {
      outOfInput[result.SourcePoint[i]] = i;
      ++keptPoints;
    }
  }
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(nOut);
  vtkARParallel::AdviseHugePages(points->GetData());
  for (vtkIdType i = 0; i < nOut; ++i)
  {
    points->SetPoint(i, &result.Mesh.Points[3 * i]);
  }
  output->Initialize();
  output->GetFieldData()->ShallowCopy(input->GetFieldData());
  output->SetPoints(points);
  vtkEmbeddedRemeshCells cells(output);
  cells.Reserve(result.SourceCell.size() + otherCell.size() + result.Prisms.size() / 6 + result.Pyramids.size() / 5,
    4 * result.SourceCell.size() + 8 * otherCell.size() + result.Prisms.size() + result.Pyramids.size());
  std::vector<char> skipKept; // the tetrahedra of released layers the cavity left
  std::vector<vtkIdType> restored;
  summary.RemovedLayerCells = static_cast<double>(RestoreKeptLayers(released, options, result, skipKept, restored));
  cells.AddRefillTetrahedra(result, nullptr, &tetCell, points, skipKept.empty() ? nullptr : &skipKept);
  AddKeptCells(input, otherCell, outOfInput, cells);
  AddKeptCells(input, restored, outOfInput, cells);
  cells.AddRefillLayers(result, nullptr, points);
  vtkEmbeddedRemeshCompleteCells(output, cells, this->InterpolateFields,
    [&] { InterpolateFromCavity(input, tets, output, result, tetCell, cells.Sources()); }, lap, summary);

  // ---- Field data and the embedded surface.
  summary.InputNodes = static_cast<double>(nPoints);
  summary.OutputNodes = static_cast<double>(nOut);
  summary.NewNodes = static_cast<double>(nOut - keptPoints);
  summary.AddRefill(result);
  summary.SurfaceEdgeLength = edge;
  summary.InputSize = inputSize;
  summary.VolumeBefore = volumeBefore;
  summary.VolumeAfter = cells.VolumeAfter;
  summary.Write(output, options.Layers);
  vtkEmbeddedRemeshSetEmbedded(embedded, points, result.Surface, nullptr);
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkEmbeddedRemesh::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Mode: " << this->Mode << "\n";
  os << indent << "SurfaceEdgeLength: " << this->SurfaceEdgeLength << "\n";
  os << indent << "SurfaceSizeFactor: " << this->SurfaceSizeFactor << "\n";
  os << indent << "RemovalFactor: " << this->RemovalFactor << "\n";
  os << indent << "VisibilityTest: " << this->VisibilityTest << "\n";
  os << indent << "BoundaryMargin: " << this->BoundaryMargin << "\n";
  os << indent << "MaxRadiusEdgeRatio: " << this->MaxRadiusEdgeRatio << "\n";
  os << indent << "MinDihedralAngle: " << this->MinDihedralAngle << "\n";
  os << indent << "TwoDimensional: " << this->TwoDimensional << "\n";
  os << indent << "MinTriangleAngle: " << this->MinTriangleAngle << "\n";
  os << indent << "LayerType: " << this->LayerType << "\n";
  os << indent << "NumberOfLayers: " << this->NumberOfLayers << "\n";
  os << indent << "FirstLayerThickness: " << this->FirstLayerThickness << "\n";
  os << indent << "GrowthRatio: " << this->GrowthRatio << "\n";
  os << indent << "TotalThickness: " << this->TotalThickness << "\n";
  os << indent << "InterpolateFields: " << this->InterpolateFields << "\n";
}
