// SPDX-License-Identifier: BSD-3-Clause
#include "vtkARParallel.h"

#include "ARHugePages.h"

#include "ARTetGeometry.h"

#include "vtkAppendFilter.h"
#include "vtkAppendPolyData.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkCommunicator.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkGeometryFilter.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkStaticCleanPolyData.h"
#include "vtkTriangleFilter.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <map>
#include <numeric>
#include <string>

void vtkARParallel::AdviseHugePages(vtkAbstractArray* array)
{
  if (array && array->GetSize() > 0)
  {
    ar::AdviseHugePages(array->GetVoidPointer(0),
      static_cast<std::size_t>(array->GetSize()) * static_cast<std::size_t>(array->GetDataTypeSize()));
  }
}

//------------------------------------------------------------------------------
int vtkARParallel::NumberOfRanks()
{
  vtkMultiProcessController* ctrl = vtkMultiProcessController::GetGlobalController();
  return ctrl ? ctrl->GetNumberOfProcesses() : 1;
}

int vtkARParallel::Rank()
{
  vtkMultiProcessController* ctrl = vtkMultiProcessController::GetGlobalController();
  return ctrl ? ctrl->GetLocalProcessId() : 0;
}

void vtkARParallel::AllReduceMax(double* values, int n)
{
  vtkMultiProcessController* ctrl = vtkMultiProcessController::GetGlobalController();
  if (ctrl && ctrl->GetNumberOfProcesses() > 1 && n > 0)
  {
    std::vector<double> local(values, values + n);
    ctrl->AllReduce(local.data(), values, n, vtkCommunicator::MAX_OP);
  }
}

void vtkARParallel::AllReduceSum(double* values, int n)
{
  vtkMultiProcessController* ctrl = vtkMultiProcessController::GetGlobalController();
  if (ctrl && ctrl->GetNumberOfProcesses() > 1 && n > 0)
  {
    std::vector<double> local(values, values + n);
    ctrl->AllReduce(local.data(), values, n, vtkCommunicator::SUM_OP);
  }
}

std::vector<double> vtkARParallel::GatherOnRoot(const std::vector<double>& local)
{
  vtkMultiProcessController* ctrl = vtkMultiProcessController::GetGlobalController();
  if (!ctrl || ctrl->GetNumberOfProcesses() < 2)
  {
    return local;
  }
  const int np = ctrl->GetNumberOfProcesses();
  double mine = static_cast<double>(local.size());
  std::vector<double> counts(np, 0.0);
  ctrl->Gather(&mine, counts.data(), 1, 0);
  std::vector<vtkIdType> lengths(np, 0), offsets(np, 0);
  vtkIdType total = 0;
  for (int r = 0; r < np; ++r)
  {
    lengths[r] = static_cast<vtkIdType>(counts[r]);
    offsets[r] = total;
    total += lengths[r];
  }
  std::vector<double> all(ctrl->GetLocalProcessId() == 0 ? total : 0);
  ctrl->GatherV(local.data(), all.data(), static_cast<vtkIdType>(local.size()), lengths.data(),
    offsets.data(), 0);
  return all;
}

//------------------------------------------------------------------------------
namespace
{
/**
 * The triangles `tri` (point ids) in BoundarySurface's canonical order, each
 * from its smallest point id (its orientation kept), sorted, as `surface`'s
 * polygons.
 */
void SetCanonicalTriangles(std::vector<std::array<vtkIdType, 3>>& tri, vtkPolyData* surface)
{
  for (std::array<vtkIdType, 3>& ids : tri)
  {
    const int k = ids[0] <= ids[1] && ids[0] <= ids[2] ? 0 : ids[1] <= ids[2] ? 1 : 2;
    ids = { ids[k], ids[(k + 1) % 3], ids[(k + 2) % 3] };
  }
  std::sort(tri.begin(), tri.end());
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(static_cast<vtkIdType>(tri.size() + 1));
  connectivity->SetNumberOfValues(static_cast<vtkIdType>(3 * tri.size()));
  for (std::size_t t = 0; t <= tri.size(); ++t)
  {
    offsets->SetValue(static_cast<vtkIdType>(t), static_cast<vtkIdType>(3 * t));
  }
  for (std::size_t t = 0; t < tri.size(); ++t)
  {
    std::copy(tri[t].begin(), tri[t].end(), connectivity->GetPointer(static_cast<vtkIdType>(3 * t)));
  }
  vtkNew<vtkCellArray> sorted;
  sorted->SetData(offsets, connectivity);
  surface->SetPolys(sorted);
}

/**
 * BoundarySurface of a grid of tetrahedra without ghosts, the faces matched
 * here (ar::TetFaceNeighbors: a bucket sort by their smallest node) instead of by
 * vtkGeometryFilter, which took 2.9 s on 5e6 tetrahedra: the same polydata,
 * vtkGeometryFilter's (each face once, as vtkTetra orders it, {0,1,3},
 * {1,2,3}, {2,0,3}, {0,2,1}; the points its faces use, in the input's order
 * and precision; the input's field data). Null where the grid is not such
 * (another cell type, a ghost array, a repeated corner, a face of three
 * cells): BoundarySurface then runs vtkGeometryFilter.
 */
vtkSmartPointer<vtkPolyData> TetrahedralBoundary(vtkDataSet* domain)
{
  auto* grid = vtkUnstructuredGrid::SafeDownCast(domain);
  if (!grid || !grid->GetPoints() || grid->GetCellGhostArray() || grid->GetPointGhostArray() ||
    grid->GetPointData()->GetArray(vtkDataSetAttributes::GhostArrayName()) ||
    grid->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()))
  {
    return nullptr;
  }
  const vtkIdType nCells = grid->GetNumberOfCells(), nPoints = grid->GetNumberOfPoints();
  vtkUnsignedCharArray* types = grid->GetCellTypesArray();
  if (!types || types->GetNumberOfValues() != nCells)
  {
    return nullptr;
  }
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    if (types->GetValue(c) != VTK_TETRA)
    {
      return nullptr;
    }
  }
  // (on threads: each cell, face and point writes its own entries; the
  // faces of a bucket are sorted whole, so the result is the same on any
  // number of threads)
  std::vector<vtkIdType> tets;
  ar::ResizeHuge(tets, 4 * static_cast<std::size_t>(nCells));
  std::atomic<bool> bad(false);
  {
    vtkCellArray* cells = grid->GetCells();
    vtkSMPTools::For(0, nCells, [&](vtkIdType first, vtkIdType last) {
      vtkNew<vtkIdList> scratch;
      for (vtkIdType c = first; c < last && !bad; ++c)
      {
        vtkIdType npts;
        const vtkIdType* pts;
        cells->GetCellAtId(c, npts, pts, scratch);
        if (npts != 4)
        {
          bad = true;
          return;
        }
        for (int k = 0; k < 4; ++k)
        {
          bool repeated = pts[k] < 0 || pts[k] >= nPoints;
          for (int m = 0; m < k; ++m)
          {
            repeated = repeated || pts[m] == pts[k];
          }
          if (repeated)
          {
            bad = true;
            return;
          }
          tets[4 * c + k] = pts[k];
        }
      }
    });
  }
  if (bad)
  {
    return nullptr;
  }
  // The faces that come once (ar::TetFaceNeighbors, shared with the
  // cavity), each as vtkTetra orders it; SetCanonicalTriangles then sorts
  // them, so their order here does not matter.
  static const int faceNodes[4][3] = { { 0, 1, 3 }, { 1, 2, 3 }, { 2, 0, 3 }, { 0, 2, 1 } };
  static const int oppositeCorner[4] = { 2, 0, 1, 3 }; // of vtkTetra's face f
  static_assert(sizeof(vtkIdType) == sizeof(std::int64_t), "vtkIdType must be 64 bits");
  std::vector<std::int64_t> neighbor;
  std::string error;
  if (!ar::TetFaceNeighbors(reinterpret_cast<const std::int64_t*>(tets.data()), static_cast<std::size_t>(nCells),
        static_cast<std::size_t>(nPoints), neighbor, error, vtkSMPTools::GetEstimatedNumberOfThreads()))
  {
    return nullptr;
  }
  std::vector<std::array<vtkIdType, 3>> tri;
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    for (int f = 0; f < 4; ++f)
    {
      if (neighbor[4 * c + oppositeCorner[f]] < 0)
      {
        tri.push_back({ tets[4 * c + faceNodes[f][0]], tets[4 * c + faceNodes[f][1]], tets[4 * c + faceNodes[f][2]] });
      }
    }
  }
  std::vector<char> used(static_cast<std::size_t>(nPoints), 0);
  for (const std::array<vtkIdType, 3>& t : tri)
  {
    used[t[0]] = used[t[1]] = used[t[2]] = 1;
  }
  // The used points, in the input's order and precision.
  std::vector<vtkIdType> newId(static_cast<std::size_t>(nPoints), -1);
  vtkIdType nUsed = 0;
  for (vtkIdType p = 0; p < nPoints; ++p)
  {
    newId[p] = used[p] ? nUsed++ : -1;
  }
  vtkNew<vtkPoints> points;
  points->SetDataType(grid->GetPoints()->GetDataType());
  points->SetNumberOfPoints(nUsed);
  vtkDataArray* in = grid->GetPoints()->GetData();
  vtkDataArray* out = points->GetData();
  for (vtkIdType p = 0; p < nPoints; ++p)
  {
    if (used[p])
    {
      out->SetTuple(newId[p], p, in);
    }
  }
  for (std::array<vtkIdType, 3>& t : tri)
  {
    t = { newId[t[0]], newId[t[1]], newId[t[2]] };
  }
  auto surface = vtkSmartPointer<vtkPolyData>::New();
  surface->SetPoints(points);
  surface->GetFieldData()->ShallowCopy(grid->GetFieldData());
  SetCanonicalTriangles(tri, surface);
  return surface;
}

/// The boundary surface of this rank's piece of the domain, as triangles.
vtkSmartPointer<vtkPolyData> BoundarySurface(vtkDataSet* domain)
{
  auto surface = vtkSmartPointer<vtkPolyData>::New();
  if (!domain || domain->GetNumberOfCells() == 0)
  {
    return surface;
  }
  if (vtkSmartPointer<vtkPolyData> tetrahedral = TetrahedralBoundary(domain))
  {
    return tetrahedral;
  }
  vtkNew<vtkGeometryFilter> geometry; // drops faces between owned and ghost cells
  geometry->SetInputData(domain);
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputConnection(geometry->GetOutputPort());
  triangles->PassVertsOff();
  triangles->PassLinesOff();
  triangles->Update();
  surface->ShallowCopy(triangles->GetOutput());
  surface->GetPointData()->Initialize();
  surface->GetCellData()->Initialize();
  // The triangles in a canonical order, each from its smallest point id
  // (its orientation kept), sorted: vtkGeometryFilter gathers its threads'
  // faces in the order the threads come, which varied from run to run on a
  // piece with ghost cells, and the sums over the faces near a point
  // (QuadricFit's centring along the boundary) then differed in the last
  // bit, and the fitted surface and the mesh after it with them.
  vtkCellArray* polys = surface->GetPolys();
  std::vector<std::array<vtkIdType, 3>> tri;
  tri.reserve(static_cast<std::size_t>(polys->GetNumberOfCells()));
  vtkIdType npts;
  const vtkIdType* ids;
  for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
  {
    if (npts == 3)
    {
      tri.push_back({ ids[0], ids[1], ids[2] });
    }
  }
  SetCanonicalTriangles(tri, surface);
  return surface;
}

/// The order of `ids` (a global-ids array) as a permutation, or empty where
/// there is no such array or two entries share an id.
std::vector<vtkIdType> GlobalIdOrder(vtkDataArray* ids, vtkIdType n)
{
  std::vector<vtkIdType> order;
  if (!ids || ids->GetNumberOfComponents() != 1 || ids->GetNumberOfTuples() != n)
  {
    return order;
  }
  std::vector<double> id(static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    id[i] = ids->GetComponent(i, 0);
  }
  order.resize(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), vtkIdType(0));
  std::sort(order.begin(), order.end(), [&](vtkIdType a, vtkIdType b) { return id[a] < id[b]; });
  for (vtkIdType i = 1; i < n; ++i)
  {
    if (!(id[order[i - 1]] < id[order[i]]))
    {
      order.clear();
      break;
    }
  }
  return order;
}

/// `grid` with its points in the order of their global ids, and its cells in
/// the order of theirs where they have them (else as they are); unchanged
/// without point global ids, with a repeated id, or with polyhedra.
void PutInGlobalIdOrder(vtkUnstructuredGrid* grid)
{
  const vtkIdType nPoints = grid->GetNumberOfPoints(), nCells = grid->GetNumberOfCells();
  const std::vector<vtkIdType> pointOrder = GlobalIdOrder(grid->GetPointData()->GetGlobalIds(), nPoints);
  if (pointOrder.empty() || nCells == 0)
  {
    return;
  }
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    if (grid->GetCellType(c) == VTK_POLYHEDRON)
    {
      return;
    }
  }
  std::vector<vtkIdType> cellOrder = GlobalIdOrder(grid->GetCellData()->GetGlobalIds(), nCells);
  if (cellOrder.empty())
  {
    cellOrder.resize(static_cast<std::size_t>(nCells));
    std::iota(cellOrder.begin(), cellOrder.end(), vtkIdType(0));
  }
  std::vector<vtkIdType> newIndex(static_cast<std::size_t>(nPoints));
  for (vtkIdType i = 0; i < nPoints; ++i)
  {
    newIndex[pointOrder[i]] = i;
  }
  vtkNew<vtkUnstructuredGrid> sorted;
  vtkNew<vtkPoints> points;
  points->SetDataType(grid->GetPoints()->GetDataType());
  points->SetNumberOfPoints(nPoints);
  sorted->GetPointData()->CopyAllocate(grid->GetPointData(), nPoints);
  for (vtkIdType i = 0; i < nPoints; ++i)
  {
    points->SetPoint(i, grid->GetPoint(pointOrder[i]));
    sorted->GetPointData()->CopyData(grid->GetPointData(), pointOrder[i], i);
  }
  sorted->SetPoints(points);
  sorted->Allocate(nCells);
  sorted->GetCellData()->CopyAllocate(grid->GetCellData(), nCells);
  vtkNew<vtkIdList> ids;
  for (vtkIdType i = 0; i < nCells; ++i)
  {
    grid->GetCellPoints(cellOrder[i], ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      ids->SetId(k, newIndex[ids->GetId(k)]);
    }
    sorted->InsertNextCell(grid->GetCellType(cellOrder[i]), ids);
    sorted->GetCellData()->CopyData(grid->GetCellData(), cellOrder[i], i);
  }
  sorted->GetFieldData()->ShallowCopy(grid->GetFieldData());
  grid->ShallowCopy(sorted);
}
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkPolyData> vtkARParallel::GatherPolyData(
  vtkPolyData* local, double tolerance, bool dropSharedTriangles)
{
  vtkMultiProcessController* c = vtkMultiProcessController::GetGlobalController();
  vtkMultiProcessController* ctrl = (c && c->GetNumberOfProcesses() > 1) ? c : nullptr;
  if (!ctrl)
  {
    return local;
  }
  std::vector<vtkSmartPointer<vtkDataObject>> pieces;
  ctrl->Gather(local, pieces, 0);
  auto result = vtkSmartPointer<vtkPolyData>::New();
  if (ctrl->GetLocalProcessId() != 0)
  {
    return result;
  }
  vtkNew<vtkAppendPolyData> append;
  for (auto& piece : pieces)
  {
    auto* pd = vtkPolyData::SafeDownCast(piece);
    if (pd && pd->GetNumberOfCells() > 0)
    {
      append->AddInputData(pd);
    }
  }
  if (append->GetNumberOfInputConnections(0) == 0)
  {
    return result;
  }
  vtkNew<vtkStaticCleanPolyData> merge;
  merge->SetInputConnection(append->GetOutputPort());
  merge->ToleranceIsAbsoluteOff();
  merge->SetTolerance(tolerance);
  merge->Update();
  vtkPolyData* merged = merge->GetOutput();
  // Per triangle (sorted corners): how often it comes with each orientation.
  // A face between two pieces comes twice with opposite orientations (each
  // side's outward face); a piece that every rank holds whole (a replicated
  // dataset) gives copies with the same orientation.
  auto keyOf = [](const vtkIdType* ids, int& parity) {
    std::array<vtkIdType, 3> key = { ids[0], ids[1], ids[2] };
    // The parity of the permutation that sorts the corners.
    parity = 0;
    for (int i = 0; i < 3; ++i)
    {
      for (int j = i + 1; j < 3; ++j)
      {
        parity ^= key[i] > key[j] ? 1 : 0;
      }
    }
    std::sort(key.begin(), key.end());
    return key;
  };
  std::map<std::array<vtkIdType, 3>, std::array<int, 2>> count;
  vtkIdType npts;
  const vtkIdType* ids;
  vtkCellArray* polys = merged->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
  {
    if (npts == 3)
    {
      int parity;
      const auto key = keyOf(ids, parity);
      ++count[key][parity];
    }
  }
  vtkNew<vtkCellArray> kept;
  for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
  {
    if (npts != 3)
    {
      kept->InsertNextCell(npts, ids);
      continue;
    }
    int parity;
    const auto key = keyOf(ids, parity);
    std::array<int, 2>& n = count[key];
    const bool interface = n[0] > 0 && n[1] > 0;
    if (dropSharedTriangles && interface)
    {
      continue;
    }
    if (n[0] + n[1] > 0)
    {
      kept->InsertNextCell(3, ids); // the first copy
    }
    n = { 0, 0 };
  }
  result->ShallowCopy(merged);
  result->SetPolys(kept);
  return result;
}

vtkSmartPointer<vtkPolyData> vtkARParallel::GatherDomainBoundary(vtkDataSet* domain)
{
  // Faces between two pieces (distributed without ghost cells) appear once
  // from each side: after merging coincident points they are dropped.
  return GatherPolyData(BoundarySurface(domain), 0.0, true);
}


//------------------------------------------------------------------------------
std::vector<double> vtkARParallel::AllGather(const std::vector<double>& local)
{
  vtkMultiProcessController* ctrl = vtkMultiProcessController::GetGlobalController();
  if (NumberOfRanks() <= 1 || !ctrl)
  {
    return local;
  }
  vtkNew<vtkDoubleArray> send, recv;
  send->SetNumberOfTuples(static_cast<vtkIdType>(local.size()));
  std::copy(local.begin(), local.end(), send->GetPointer(0));
  ctrl->AllGatherV(send, recv);
  return std::vector<double>(recv->GetPointer(0), recv->GetPointer(0) + recv->GetNumberOfTuples());
}

void vtkARParallel::BroadcastFromRoot(std::vector<double>& data)
{
  vtkMultiProcessController* ctrl = vtkMultiProcessController::GetGlobalController();
  if (NumberOfRanks() <= 1 || !ctrl)
  {
    return;
  }
  vtkIdType n = static_cast<vtkIdType>(data.size());
  ctrl->Broadcast(&n, 1, 0);
  data.resize(n);
  if (n > 0)
  {
    ctrl->Broadcast(data.data(), n, 0);
  }
}

void vtkARParallel::BroadcastFromRoot(std::vector<std::int64_t>& data)
{
  std::vector<double> values(data.begin(), data.end());
  BroadcastFromRoot(values);
  data.assign(values.begin(), values.end());
}

void vtkARParallel::BroadcastFromRoot(std::string& text)
{
  vtkMultiProcessController* ctrl = vtkMultiProcessController::GetGlobalController();
  if (NumberOfRanks() <= 1 || !ctrl)
  {
    return;
  }
  vtkIdType n = static_cast<vtkIdType>(text.size());
  ctrl->Broadcast(&n, 1, 0);
  text.resize(static_cast<std::size_t>(n));
  if (n > 0)
  {
    ctrl->Broadcast(&text[0], n, 0);
  }
}

void vtkARParallel::BroadcastFieldDataFromRoot(vtkFieldData* fd)
{
  vtkMultiProcessController* ctrl = vtkMultiProcessController::GetGlobalController();
  if (NumberOfRanks() <= 1 || !ctrl)
  {
    return;
  }
  vtkNew<vtkUnstructuredGrid> carrier; // a data object to carry the arrays
  const bool root = ctrl->GetLocalProcessId() == 0;
  if (root)
  {
    carrier->GetFieldData()->ShallowCopy(fd);
  }
  ctrl->Broadcast(carrier, 0);
  if (!root)
  {
    fd->ShallowCopy(carrier->GetFieldData());
  }
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkUnstructuredGrid> vtkARParallel::MergeOnRoot(vtkUnstructuredGrid* local)
{
  auto whole = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkMultiProcessController* ctrl = vtkMultiProcessController::GetGlobalController();
  std::vector<vtkSmartPointer<vtkDataObject>> parts;
  ctrl->Gather(local, parts, 0);
  if (ctrl->GetLocalProcessId() == 0)
  {
    vtkNew<vtkAppendFilter> merge;
    merge->MergePointsOn();
    merge->SetTolerance(0.0);
    for (auto& part : parts)
    {
      auto* grid = vtkUnstructuredGrid::SafeDownCast(part);
      if (grid && grid->GetNumberOfCells() > 0)
      {
        merge->AddInputData(grid);
      }
    }
    merge->Update();
    whole->ShallowCopy(merge->GetOutput());
  }
  return whole;
}

vtkSmartPointer<vtkUnstructuredGrid> vtkARParallel::GatherVolumeOnRoot(vtkUnstructuredGrid* piece)
{
  vtkMultiProcessController* ctrl = vtkMultiProcessController::GetGlobalController();
  vtkNew<vtkUnstructuredGrid> owned;
  owned->DeepCopy(piece);
  owned->RemoveGhostCells();
  owned->GetCellData()->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  owned->GetPointData()->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  auto whole = vtkSmartPointer<vtkUnstructuredGrid>::New();
  if (NumberOfRanks() <= 1 || !ctrl)
  {
    whole->ShallowCopy(owned);
    return whole;
  }
  whole = MergeOnRoot(owned);
  if (ctrl->GetLocalProcessId() == 0)
  {
    PutInGlobalIdOrder(whole);
    whole->GetFieldData()->ShallowCopy(piece->GetFieldData());
  }
  return whole;
}
