// SPDX-License-Identifier: BSD-3-Clause
#include "vtkARMeshKernels.h"
#include "vtkARInputChecks.h"

#include "vtkAlgorithm.h"
#include "vtkAppendPolyData.h"
#include "vtkCellData.h"
#include "vtkDataSet.h"
#include "vtkDataSetAttributesFieldList.h"
#include "vtkGenericCell.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkSMPThreadLocalObject.h"
#include "vtkStaticCellLocator.h"
#include "vtkStaticPointLocator.h"
#include "vtkGeometryFilter.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStaticCleanPolyData.h"
#include "vtkTriangleFilter.h"
#include "vtkArrayDispatch.h"
#include "vtkCellArray.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkDataArrayRange.h"
#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiProcessController.h"
#include "vtkPoints.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <map>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <numeric>

namespace
{
// The linear 3-D cell types (explicit: vtkCellTypes::GetDimension builds a
// cell per call and complains about unknown type numbers).
std::array<bool, 256> MakeVolumeCellTable()
{
  std::array<bool, 256> table{};
  for (int t : { VTK_TETRA, VTK_VOXEL, VTK_HEXAHEDRON, VTK_WEDGE, VTK_PYRAMID,
         VTK_PENTAGONAL_PRISM, VTK_HEXAGONAL_PRISM, VTK_POLYHEDRON, VTK_CONVEX_POINT_SET })
  {
    table[t] = true;
  }
  return table;
}
std::array<bool, 256> MakeLowerDimensionalTable()
{
  std::array<bool, 256> table{};
  for (int t : { VTK_EMPTY_CELL, VTK_VERTEX, VTK_POLY_VERTEX, VTK_LINE, VTK_POLY_LINE,
         VTK_TRIANGLE, VTK_TRIANGLE_STRIP, VTK_POLYGON, VTK_PIXEL, VTK_QUAD })
  {
    table[t] = true;
  }
  return table;
}
const std::array<bool, 256> VolumeCells = MakeVolumeCellTable();
const std::array<bool, 256> LowerDimensionalCells = MakeLowerDimensionalTable();
}

const bool* vtkARMeshKernels::MeshView::VolumeCellTable = VolumeCells.data();

//------------------------------------------------------------------------------
bool vtkARMeshKernels::MeshView::Build(vtkUnstructuredGrid* grid, std::string& error)
{
  *this = MeshView();
  if (!grid)
  {
    error = "there is no input unstructured grid";
    return false;
  }
  this->NumberOfPoints = grid->GetPoints() ? grid->GetNumberOfPoints() : 0;
  this->NumberOfCells = grid->GetCells() ? grid->GetNumberOfCells() : 0;
  if (this->NumberOfPoints == 0 || this->NumberOfCells == 0)
  {
    // An empty partition is legal under MPI; callers decide collectively.
    this->NumberOfCells = 0;
    return true;
  }

  vtkDataArray* pts = grid->GetPoints()->GetData();
  if (auto* d = vtkDoubleArray::FastDownCast(pts))
  {
    this->X = d->GetPointer(0);
  }
  else
  {
    this->XStore.resize(3 * static_cast<size_t>(this->NumberOfPoints));
    const auto range = vtk::DataArrayValueRange<3>(pts);
    double* dst = this->XStore.data();
    vtkSMPTools::For(0, static_cast<vtkIdType>(range.size()), [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType i = b; i < e; ++i)
      {
        dst[i] = range[i];
      }
    });
    this->X = this->XStore.data();
  }

  vtkCellArray* cells = grid->GetCells();
  if (cells->IsStorage64Bit())
  {
    this->Offsets = cells->GetOffsetsArray64()->GetPointer(0);
    this->Connectivity = cells->GetConnectivityArray64()->GetPointer(0);
  }
  else
  {
    auto* off = cells->GetOffsetsArray32();
    auto* conn = cells->GetConnectivityArray32();
    this->OffsetStore.assign(off->GetPointer(0), off->GetPointer(0) + off->GetNumberOfValues());
    this->ConnectivityStore.assign(
      conn->GetPointer(0), conn->GetPointer(0) + conn->GetNumberOfValues());
    this->Offsets = this->OffsetStore.data();
    this->Connectivity = this->ConnectivityStore.data();
  }
  this->Types = grid->GetCellTypesArray()->GetPointer(0);
  vtkUnsignedCharArray* cg = grid->GetCellGhostArray();
  this->CellGhosts = cg ? cg->GetPointer(0) : nullptr;
  vtkUnsignedCharArray* pg = grid->GetPointGhostArray();
  this->PointGhosts = pg ? pg->GetPointer(0) : nullptr;
  return true;
}

//------------------------------------------------------------------------------
vtkARMeshKernels::CellCensus vtkARMeshKernels::Census(const MeshView& mesh)
{
  vtkSMPThreadLocal<CellCensus> local;
  vtkSMPTools::For(0, mesh.NumberOfCells, [&](vtkIdType begin, vtkIdType end) {
    CellCensus& census = local.Local();
    for (vtkIdType c = begin; c < end; ++c)
    {
      if (mesh.IsVolumeCell(c))
      {
        if (mesh.CellSize(c) > MaxCellPoints)
        {
          ++census.TooManyPoints;
        }
        else
        {
          ++census.VolumeCells;
        }
      }
      else if (LowerDimensionalCells[mesh.Types[c]])
      {
        ++census.LowerDimensional;
      }
      else
      {
        ++census.NonLinear;
      }
    }
  });
  CellCensus total;
  for (const CellCensus& part : local)
  {
    total.VolumeCells += part.VolumeCells;
    total.LowerDimensional += part.LowerDimensional;
    total.NonLinear += part.NonLinear;
    total.TooManyPoints += part.TooManyPoints;
  }
  return total;
}

//------------------------------------------------------------------------------
bool vtkARMeshKernels::GradientOperator(
  const MeshView& mesh, vtkIdType c, double W[][3], int& n, double& measure)
{
  n = mesh.CellSize(c);
  measure = 0.0;
  if (n < 4 || n > MaxCellPoints)
  {
    return false;
  }
  const vtkIdType* ids = mesh.CellPoints(c);
  if (n == 4)
  {
    // Tetrahedron: the exact P1 gradient from the inverse Jacobian.
    double Jinv[3][3];
    if (!TetInverseJacobian(mesh.X, ids, Jinv, measure))
    {
      return false;
    }
    for (int k = 0; k < 3; ++k)
    {
      W[0][k] = -(Jinv[k][0] + Jinv[k][1] + Jinv[k][2]);
      W[1][k] = Jinv[k][0];
      W[2][k] = Jinv[k][1];
      W[3][k] = Jinv[k][2];
    }
    return true;
  }
  double xc[3] = { 0.0, 0.0, 0.0 };
  for (int a = 0; a < n; ++a)
  {
    const double* x = mesh.X + 3 * ids[a];
    xc[0] += x[0];
    xc[1] += x[1];
    xc[2] += x[2];
  }
  const double inv = 1.0 / n;
  xc[0] *= inv;
  xc[1] *= inv;
  xc[2] *= inv;

  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  double scale = 0.0;
  for (int a = 0; a < n; ++a)
  {
    const double* x = mesh.X + 3 * ids[a];
    W[a][0] = x[0] - xc[0];
    W[a][1] = x[1] - xc[1];
    W[a][2] = x[2] - xc[2];
    const Eigen::Map<const Eigen::Vector3d> d(W[a]);
    M.noalias() += d * d.transpose();
    scale += d.squaredNorm();
  }
  const double det = M.determinant();
  // Relative test: det(M) ~ (trace/3)^3 for a well-shaped cell.
  const double ref = scale * scale * scale / 27.0;
  if (!(det > 1e-12 * ref))
  {
    return false;
  }
  const Eigen::Matrix3d Minv = M.inverse();
  for (int a = 0; a < n; ++a)
  {
    Eigen::Map<Eigen::Vector3d> w(W[a]);
    const Eigen::Vector3d d = w;
    w.noalias() = Minv * d;
  }
  measure = std::sqrt(det) / 3.0;
  return true;
}

//------------------------------------------------------------------------------
bool vtkARMeshKernels::AgreeToProceed(vtkAlgorithm* self, const std::string& problem,
  const MeshView& mesh, const CellCensus& census, const char* need)
{
  if (census.NonLinear > 0)
  {
    vtkWarningWithObjectMacro(self, << census.NonLinear
                    << " non-linear (quadratic or higher-order) cells are ignored; "
                       "apply Tessellate first to include them.");
  }
  if (census.TooManyPoints > 0)
  {
    vtkWarningWithObjectMacro(self, << census.TooManyPoints << " polyhedra with more than "
                    << MaxCellPoints << " points are ignored.");
  }
  // A NaN or Inf coordinate makes the cells at it degenerate, which the
  // loops would skip without a word: refused here, for every filter.
  const std::string finite =
    mesh.X ? vtkARInputChecks::NonFinitePoints(mesh.X, mesh.NumberOfPoints, "the input mesh") : std::string();
  // [0] ranks with a problem, [1] linear 3-D cells, [2] cells,
  // [3] ranks holding cells without ghost cells, [4] ranks holding cells.
  const bool hasCells = mesh.NumberOfCells > 0;
  double status[5] = { (problem.empty() && finite.empty()) ? 0.0 : 1.0, static_cast<double>(census.VolumeCells),
    static_cast<double>(mesh.NumberOfCells), (hasCells && !mesh.CellGhosts) ? 1.0 : 0.0,
    hasCells ? 1.0 : 0.0 };
  AllReduceSum(status, 5);
  std::string message = finite + problem;
  if (status[0] == 0.0 && status[2] == 0.0)
  {
    message = "The input mesh is empty. ";
  }
  else if (status[0] == 0.0 && status[1] == 0.0)
  {
    message = "The input has no linear 3-D cells (" + std::to_string(census.LowerDimensional) +
      " vertices, lines or 2-D cells here): " + need +
      " needs a volume mesh of tetrahedra, pyramids, wedges, hexahedra or polyhedra. ";
  }
  if (!message.empty())
  {
    vtkErrorWithObjectMacro(self, << message << "The output is the input, unchanged.");
    return false;
  }
  if (status[0] > 0.0)
  {
    return false; // another rank reported its problem
  }
  if (status[4] > 1.0 && status[3] > 0.0)
  {
    vtkWarningWithObjectMacro(self,
      "The mesh is distributed without ghost cells: values next to partition boundaries can "
      "differ from a serial run. Apply 'Ghost Cells Generator' upstream.");
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkARMeshKernels::CellColumnsToPoints(const MeshView& mesh, const double* cellTable,
  int cellStride, const std::vector<int>& cellColumns, double* pointTable, int pointStride,
  const std::vector<int>& pointColumns, vtkAlgorithm* abortSource)
{
  const int nc = static_cast<int>(cellColumns.size());
  std::vector<double> avg;
  const bool ok = CellsToPoints(
    mesh, nc,
    [&](vtkIdType c, double* values, double& weight) {
      double W[MaxCellPoints][3];
      int n;
      if (!mesh.IsVolumeCell(c) || !GradientOperator(mesh, c, W, n, weight))
      {
        return false;
      }
      for (int k = 0; k < nc; ++k)
      {
        values[k] = cellTable[static_cast<size_t>(c) * cellStride + cellColumns[k]];
      }
      return true;
    },
    avg, abortSource);
  if (!ok)
  {
    return false;
  }
  vtkSMPTools::For(0, mesh.NumberOfPoints, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType p = b; p < e; ++p)
    {
      for (int k = 0; k < nc; ++k)
      {
        pointTable[static_cast<size_t>(p) * pointStride + pointColumns[k]] =
          avg[static_cast<size_t>(p) * nc + k];
      }
    }
  });
  return true;
}

//------------------------------------------------------------------------------
void vtkARMeshKernels::RequestExtraGhostLevels(
  vtkInformationVector** inputVector, vtkInformationVector* outputVector, int extra, int port)
{
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  vtkInformation* outInfo = outputVector->GetInformationObject(port);
  using SDDP = vtkStreamingDemandDrivenPipeline;
  inInfo->Set(SDDP::UPDATE_PIECE_NUMBER(), outInfo->Get(SDDP::UPDATE_PIECE_NUMBER()));
  inInfo->Set(SDDP::UPDATE_NUMBER_OF_PIECES(), outInfo->Get(SDDP::UPDATE_NUMBER_OF_PIECES()));
  inInfo->Set(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS(),
    outInfo->Get(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS()) + extra);
}

//------------------------------------------------------------------------------
int vtkARMeshKernels::NumberOfRanks()
{
  vtkMultiProcessController* ctrl = vtkMultiProcessController::GetGlobalController();
  return ctrl ? ctrl->GetNumberOfProcesses() : 1;
}

void vtkARMeshKernels::AllReduceMax(double* values, int n)
{
  vtkMultiProcessController* ctrl = vtkMultiProcessController::GetGlobalController();
  if (ctrl && ctrl->GetNumberOfProcesses() > 1 && n > 0)
  {
    std::vector<double> local(values, values + n);
    ctrl->AllReduce(local.data(), values, n, vtkCommunicator::MAX_OP);
  }
}

void vtkARMeshKernels::AllReduceSum(double* values, int n)
{
  vtkMultiProcessController* ctrl = vtkMultiProcessController::GetGlobalController();
  if (ctrl && ctrl->GetNumberOfProcesses() > 1 && n > 0)
  {
    std::vector<double> local(values, values + n);
    ctrl->AllReduce(local.data(), values, n, vtkCommunicator::SUM_OP);
  }
}

std::vector<double> vtkARMeshKernels::GatherOnRoot(const std::vector<double>& local)
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
void vtkARMeshKernels::Threaded(const std::function<void()>& work)
{
  const char* env = std::getenv("VTK_SMP_BACKEND_IN_USE");
  if ((env == nullptr || *env == '\0') && std::strcmp(vtkSMPTools::GetBackend(), "Sequential") == 0)
  {
    vtkSMPTools::LocalScope(vtkSMPTools::Config{ std::string("STDThread") }, work);
  }
  else
  {
    work();
  }
}

bool vtkARMeshKernels::Aborted(vtkAlgorithm* self)
{
  return self != nullptr && self->GetAbortExecute() != 0;
}

//------------------------------------------------------------------------------
namespace
{
struct PackWorker
{
  template <typename ArrayT>
  void operator()(ArrayT* array, double* dest, int stride, int offset, vtkIdType& bad)
  {
    const auto tuples = vtk::DataArrayTupleRange(array);
    const int nc = array->GetNumberOfComponents();
    std::atomic<vtkIdType> firstBad(-1);
    vtkSMPTools::For(0, static_cast<vtkIdType>(tuples.size()), [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType i = b; i < e; ++i)
      {
        const auto t = tuples[i];
        double* d = dest + static_cast<size_t>(i) * stride + offset;
        for (int k = 0; k < nc; ++k)
        {
          const double v = static_cast<double>(t[k]);
          d[k] = v;
          if (!std::isfinite(v))
          {
            vtkIdType expected = -1;
            firstBad.compare_exchange_strong(expected, i);
          }
        }
      }
    });
    bad = firstBad;
  }
};
}

vtkIdType vtkARMeshKernels::PackComponents(vtkDataArray* array, double* dest, int stride, int offset)
{
  vtkIdType bad = -1;
  PackWorker worker;
  if (!vtkArrayDispatch::Dispatch::Execute(array, worker, dest, stride, offset, bad))
  {
    worker(array, dest, stride, offset, bad);
  }
  return bad;
}

//------------------------------------------------------------------------------
namespace
{
/// The boundary surface of this rank's piece of the domain, as triangles.
vtkSmartPointer<vtkPolyData> BoundarySurface(vtkDataSet* domain)
{
  auto surface = vtkSmartPointer<vtkPolyData>::New();
  if (!domain || domain->GetNumberOfCells() == 0)
  {
    return surface;
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
  return surface;
}
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkPolyData> vtkARMeshKernels::GatherPolyData(
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

vtkSmartPointer<vtkPolyData> vtkARMeshKernels::GatherDomainBoundary(vtkDataSet* domain)
{
  // Faces between two pieces (distributed without ghost cells) appear once
  // from each side: after merging coincident points they are dropped.
  return GatherPolyData(BoundarySurface(domain), 0.0, true);
}

vtkSmartPointer<vtkDoubleArray> vtkARMeshKernels::FieldArray(const char* name, const double* values, int n)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfTuples(n);
  for (int i = 0; i < n; ++i)
  {
    a->SetValue(i, values[i]);
  }
  return a;
}

//------------------------------------------------------------------------------
namespace
{
/// One array of a field transfer: as vtkDataSetAttributes::CopyData
/// (CopyTuple: InsertTuple) and InterpolatePoint (InterpolateTuple, or the
/// nearest tuple for an attribute flagged 2) do it, tuple by tuple.
void TransferArray(vtkAbstractArray* from, vtkAbstractArray* to, bool nearest,
  const vtkARMeshKernels::TupleSources& sources)
{
  const vtkIdType n = sources.Size();
  const int width = sources.Width;
  if (to->GetNumberOfTuples() < n)
  {
    to->SetNumberOfTuples(n); // then InsertTuple and InterpolateTuple write in place, safe on threads
  }
  auto fill = [&](vtkIdType b, vtkIdType e, vtkIdList* ids) {
    for (vtkIdType i = b; i < e; ++i)
    {
      const vtkIdType* src = &sources.Ids[static_cast<std::size_t>(i) * width];
      if (src[0] < 0)
      {
        continue;
      }
      if (width == 1 || src[1] < 0)
      {
        to->InsertTuple(i, src[0], from);
        continue;
      }
      double* w = const_cast<double*>(&sources.Weights[static_cast<std::size_t>(i) * width]);
      int m = 2; // the tuples interpolated: up to the first negative id
      while (m < width && src[m] >= 0)
      {
        ++m;
      }
      if (nearest)
      {
        // vtkDataSetAttributes::InterpolatePoint's rule, its integer
        // maxWeight included (the last tuple of positive weight wins).
        vtkIdType maxId = src[0];
        vtkIdType maxWeight = 0;
        for (int j = 0; j < m; ++j)
        {
          if (w[j] > maxWeight)
          {
            maxWeight = static_cast<vtkIdType>(w[j]);
            maxId = src[j];
          }
        }
        to->InsertTuple(i, maxId, from);
        continue;
      }
      ids->SetNumberOfIds(m);
      std::copy(src, src + m, ids->GetPointer(0));
      to->InterpolateTuple(i, ids, from, w);
    }
  };
  if (vtkDataArray::SafeDownCast(from) && vtkDataArray::SafeDownCast(to))
  {
    vtkSMPThreadLocalObject<vtkIdList> local;
    vtkSMPTools::For(0, n, [&](vtkIdType b, vtkIdType e) {
      fill(b, e, local.Local());
    });
  }
  else
  {
    vtkNew<vtkIdList> ids;
    fill(0, n, ids);
  }
  to->Modified();
}

/// Whether `to` interpolates the attribute that its array `index` is by
/// taking the nearest tuple (vtkDataSetAttributes' INTERPOLATE flag 2).
bool NearestFor(vtkDataSetAttributes* attributes, int index, vtkDataSetAttributes* to)
{
  const int attribute = attributes->IsArrayAnAttribute(index);
  return attribute != -1 && to->GetCopyAttribute(attribute, vtkDataSetAttributes::INTERPOLATE) == 2;
}
}

//------------------------------------------------------------------------------
void vtkARMeshKernels::TransferData(
  vtkDataSetAttributes* from, vtkDataSetAttributes* to, const TupleSources& sources)
{
  // CopyAllocate and InterpolateAllocate give each output array the name of
  // the input array it is made for: pair them by name when names are unique.
  std::map<std::string, int> named;
  bool unique = true;
  for (int k = 0; k < from->GetNumberOfArrays() && unique; ++k)
  {
    const char* name = from->GetAbstractArray(k)->GetName();
    unique = name && *name && named.emplace(name, k).second;
  }
  std::vector<std::pair<int, int>> pairs; // (from, to) array indices
  for (int k = 0; k < to->GetNumberOfArrays() && unique; ++k)
  {
    const char* name = to->GetAbstractArray(k)->GetName();
    const auto it = name ? named.find(name) : named.end();
    unique = it != named.end();
    if (unique)
    {
      pairs.emplace_back(it->second, k);
    }
  }
  if (unique)
  {
    for (const auto& p : pairs)
    {
      TransferArray(from->GetAbstractArray(p.first), to->GetAbstractArray(p.second),
        NearestFor(to, p.second, to), sources);
    }
    return;
  }
  // Ambiguous names: vtkDataSetAttributes' own calls, tuple by tuple.
  vtkNew<vtkIdList> ids;
  const int width = sources.Width;
  for (vtkIdType i = 0; i < sources.Size(); ++i)
  {
    const vtkIdType* src = &sources.Ids[static_cast<std::size_t>(i) * width];
    if (src[0] < 0)
    {
      continue;
    }
    if (width == 1 || src[1] < 0)
    {
      to->CopyData(from, src[0], i);
      continue;
    }
    int m = 2;
    while (m < width && src[m] >= 0)
    {
      ++m;
    }
    ids->SetNumberOfIds(m);
    std::copy(src, src + m, ids->GetPointer(0));
    to->InterpolatePoint(from, i, ids, const_cast<double*>(&sources.Weights[static_cast<std::size_t>(i) * width]));
  }
}

//------------------------------------------------------------------------------
void vtkARMeshKernels::TransferData(const vtkDataSetAttributesFieldList& list, int index,
  vtkDataSetAttributes* from, vtkDataSetAttributes* to, const TupleSources& sources)
{
  list.TransformData(index, from, to, [&](vtkAbstractArray* in, vtkAbstractArray* out) {
    // vtkDataSetAttributesFieldList::InterpolatePoint asks the input whether
    // the array is an attribute, the output how to interpolate it.
    int k = 0;
    while (k < from->GetNumberOfArrays() && from->GetAbstractArray(k) != in)
    {
      ++k;
    }
    TransferArray(in, out, k < from->GetNumberOfArrays() && NearestFor(from, k, to), sources);
  });
}

//------------------------------------------------------------------------------
struct vtkARMeshKernels::TetLocator::vtkInternals
{
  static constexpr double Tolerance = 1e-10; // on the barycentric coordinates
  static constexpr int MaxSteps = 1000;

  vtkSmartPointer<vtkUnstructuredGrid> Tets;
  MeshView Mesh;
  std::vector<vtkIdType> LinkOffsets, Links; // the tetrahedra of each point, by increasing id
  vtkNew<vtkPolyData> VertexSet;             // the points used by a tetrahedron
  std::vector<vtkIdType> VertexId;           // their ids in Tets
  vtkNew<vtkStaticPointLocator> Vertices;
  mutable vtkSmartPointer<vtkStaticCellLocator> Cells; // the fallback, built when first needed
  mutable vtkIdType Fallbacks = 0;

  /// x's barycentric coordinates in cell c (false: a flat cell).
  bool Barycentric(vtkIdType c, const double x[3], double b[4]) const
  {
    const vtkIdType* v = this->Mesh.CellPoints(c);
    const double* p[4] = { this->Mesh.X + 3 * v[0], this->Mesh.X + 3 * v[1], this->Mesh.X + 3 * v[2],
      this->Mesh.X + 3 * v[3] };
    double sum = 0.0;
    for (int i = 0; i < 4; ++i)
    {
      // the signed volume of the tetrahedron with x in place of corner i
      const double* q[4] = { p[0], p[1], p[2], p[3] };
      q[i] = x;
      const double a[3] = { q[1][0] - q[0][0], q[1][1] - q[0][1], q[1][2] - q[0][2] };
      const double e[3] = { q[2][0] - q[0][0], q[2][1] - q[0][1], q[2][2] - q[0][2] };
      const double f[3] = { q[3][0] - q[0][0], q[3][1] - q[0][1], q[3][2] - q[0][2] };
      b[i] = a[0] * (e[1] * f[2] - e[2] * f[1]) + a[1] * (e[2] * f[0] - e[0] * f[2]) +
        a[2] * (e[0] * f[1] - e[1] * f[0]);
      sum += b[i];
    }
    if (!(std::abs(sum) > 0.0))
    {
      return false;
    }
    for (int i = 0; i < 4; ++i)
    {
      b[i] /= sum;
    }
    return true;
  }

  /// The cell across the face of c opposite its corner i, -1 if none: the
  /// cell other than c in all three corners' (sorted) links, which are
  /// contiguous, so the cells themselves need not be read.
  vtkIdType Neighbour(vtkIdType c, int i) const
  {
    const vtkIdType* v = this->Mesh.CellPoints(c);
    const vtkIdType* at[3];
    const vtkIdType* end[3];
    for (int k = 0; k < 3; ++k)
    {
      const vtkIdType p = v[(i + 1 + k) % 4];
      at[k] = this->Links.data() + this->LinkOffsets[p];
      end[k] = this->Links.data() + this->LinkOffsets[p + 1];
    }
    while (at[0] < end[0] && at[1] < end[1] && at[2] < end[2])
    {
      const vtkIdType a = *at[0], b = *at[1], d = *at[2];
      if (a == b && b == d)
      {
        if (a != c)
        {
          return a;
        }
        ++at[0], ++at[1], ++at[2];
        continue;
      }
      const vtkIdType lo = std::max(a, std::max(b, d));
      for (int k = 0; k < 3; ++k)
      {
        at[k] = std::lower_bound(at[k], end[k], lo);
      }
    }
    return -1;
  }

  vtkIdType CellOfPoint(vtkIdType p) const
  {
    return p >= 0 && p + 1 < static_cast<vtkIdType>(this->LinkOffsets.size()) &&
        this->LinkOffsets[p] < this->LinkOffsets[p + 1]
      ? this->Links[this->LinkOffsets[p]]
      : -1;
  }

  /// The walk from `start` (< 0: the nearest vertex's cell); -1 if it fails.
  vtkIdType Walk(const double x[3], vtkIdType start, double w[4]) const
  {
    vtkIdType c = start;
    if (c < 0)
    {
      const vtkIdType v = this->Vertices->FindClosestPoint(x);
      c = v >= 0 ? this->CellOfPoint(this->VertexId[v]) : -1;
    }
    for (int step = 0; c >= 0 && step < MaxSteps; ++step)
    {
      double b[4];
      if (!this->Barycentric(c, x, b))
      {
        return -1;
      }
      int order[4] = { 0, 1, 2, 3 };
      std::sort(order, order + 4, [&](int i, int j) { return b[i] < b[j] || (b[i] == b[j] && i < j); });
      if (b[order[0]] >= -Tolerance)
      {
        std::copy(b, b + 4, w);
        return c;
      }
      vtkIdType next = -1;
      for (int k = 0; k < 4 && next < 0 && b[order[k]] < -Tolerance; ++k)
      {
        next = this->Neighbour(c, order[k]);
      }
      c = next;
    }
    return -1;
  }
};

vtkARMeshKernels::TetLocator::TetLocator()
  : Internals(new vtkInternals)
{
}

vtkARMeshKernels::TetLocator::~TetLocator() = default;

//------------------------------------------------------------------------------
void vtkARMeshKernels::PointCells(const MeshView& mesh, const std::vector<char>* use,
  std::vector<vtkIdType>& offsets, std::vector<vtkIdType>& cells)
{
  const vtkIdType np = mesh.NumberOfPoints, nc = mesh.NumberOfCells;
  offsets.assign(static_cast<std::size_t>(np) + 1, 0);
  for (vtkIdType c = 0; c < nc; ++c)
  {
    if (!use || (*use)[c])
    {
      const vtkIdType* ids = mesh.CellPoints(c);
      for (int k = 0; k < mesh.CellSize(c); ++k)
      {
        ++offsets[ids[k] + 1];
      }
    }
  }
  std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
  cells.resize(static_cast<std::size_t>(offsets.back()));
  std::vector<vtkIdType> fill(offsets.begin(), offsets.end() - 1);
  for (vtkIdType c = 0; c < nc; ++c)
  {
    if (!use || (*use)[c])
    {
      const vtkIdType* ids = mesh.CellPoints(c);
      for (int k = 0; k < mesh.CellSize(c); ++k)
      {
        cells[fill[ids[k]]++] = c;
      }
    }
  }
}

void vtkARMeshKernels::TetLocator::Build(vtkUnstructuredGrid* tets)
{
  vtkInternals& in = *this->Internals;
  in.Tets = tets;
  in.Cells = nullptr;
  std::string error;
  in.Mesh.Build(tets, error);
  const vtkIdType np = in.Mesh.NumberOfPoints, nc = in.Mesh.NumberOfCells;
  // Point-to-cell links, each point's cells by increasing id (so that the
  // walk's start does not depend on how the links were built).
  PointCells(in.Mesh, nullptr, in.LinkOffsets, in.Links);
  // The used points, for the nearest-vertex start.
  in.VertexId.clear();
  for (vtkIdType p = 0; p < np; ++p)
  {
    if (in.LinkOffsets[p] < in.LinkOffsets[p + 1])
    {
      in.VertexId.push_back(p);
    }
  }
  vtkNew<vtkPoints> used;
  used->SetDataTypeToDouble();
  used->SetNumberOfPoints(static_cast<vtkIdType>(in.VertexId.size()));
  for (std::size_t k = 0; k < in.VertexId.size(); ++k)
  {
    used->SetPoint(static_cast<vtkIdType>(k), in.Mesh.X + 3 * in.VertexId[k]);
  }
  in.VertexSet->Initialize();
  in.VertexSet->SetPoints(used);
  in.Vertices->SetDataSet(in.VertexSet);
  in.Vertices->BuildLocator();
}

void vtkARMeshKernels::TetLocator::Locate(
  vtkIdType n, const double* x, const vtkIdType* start, vtkIdType* cell, double* weights) const
{
  const vtkInternals& in = *this->Internals;
  in.Fallbacks = 0;
  if (in.Mesh.NumberOfCells == 0)
  {
    std::fill(cell, cell + n, -1);
    return;
  }
  // The queries in Morton order of their points, so that neighbouring
  // queries walk through the same cells (memory, not arithmetic, is the
  // cost); each answer is independent of the others, so the order changes
  // no result.
  double lo[3], hi[3];
  {
    double bounds[6];
    in.Tets->GetPoints()->GetBounds(bounds);
    for (int d = 0; d < 3; ++d)
    {
      lo[d] = bounds[2 * d];
      hi[d] = bounds[2 * d + 1] > bounds[2 * d] ? bounds[2 * d + 1] : bounds[2 * d] + 1.0;
    }
  }
  std::vector<std::pair<std::uint64_t, vtkIdType>> order(static_cast<std::size_t>(n));
  vtkSMPTools::For(0, n, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType q = b; q < e; ++q)
    {
      std::uint64_t key = 0;
      for (int d = 0; d < 3; ++d)
      {
        const double t = std::min(std::max((x[3 * q + d] - lo[d]) / (hi[d] - lo[d]), 0.0), 1.0);
        std::uint64_t v = static_cast<std::uint64_t>(t * 2097151.0); // 21 bits
        // spread the 21 bits to every third position
        v = (v | (v << 32)) & 0x1f00000000ffffULL;
        v = (v | (v << 16)) & 0x1f0000ff0000ffULL;
        v = (v | (v << 8)) & 0x100f00f00f00f00fULL;
        v = (v | (v << 4)) & 0x10c30c30c30c30c3ULL;
        v = (v | (v << 2)) & 0x1249249249249249ULL;
        key |= v << d;
      }
      order[q] = { key, q };
    }
  });
  vtkSMPTools::Sort(order.begin(), order.end());
  // Fixed blocks of consecutive queries (the same whatever the number of
  // threads): a query with no start of its own walks from the previous
  // query's cell in its block, the first from its nearest vertex's; a walk
  // that fails from a given start is tried again from the nearest vertex.
  const vtkIdType block = 256;
  vtkSMPTools::For(0, (n + block - 1) / block, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType k0 = b * block; k0 < std::min(n, e * block); k0 += block)
    {
      vtkIdType previous = -1;
      for (vtkIdType k = k0; k < std::min(n, k0 + block); ++k)
      {
        const vtkIdType q = order[k].second;
        const vtkIdType from = start && start[q] >= 0 ? start[q] : previous;
        double w[4];
        cell[q] = in.Walk(x + 3 * q, from, w);
        if (cell[q] < 0 && from >= 0)
        {
          cell[q] = in.Walk(x + 3 * q, -1, w);
        }
        if (cell[q] >= 0)
        {
          previous = cell[q];
          if (weights)
          {
            std::copy(w, w + 4, weights + 4 * q);
          }
        }
      }
    }
  });
  // The walks that failed, in query order on this thread.
  vtkNew<vtkGenericCell> gcell;
  for (vtkIdType q = 0; q < n; ++q)
  {
    if (cell[q] >= 0)
    {
      continue;
    }
    ++in.Fallbacks;
    if (!in.Cells)
    {
      in.Cells = vtkSmartPointer<vtkStaticCellLocator>::New();
      in.Cells->SetDataSet(in.Tets);
      in.Cells->BuildLocator();
    }
    double p[3] = { x[3 * q], x[3 * q + 1], x[3 * q + 2] };
    double pcoords[3], vtkWeights[VTK_CELL_SIZE];
    int subId;
    cell[q] = in.Cells->FindCell(p, 0.0, gcell, subId, pcoords, vtkWeights);
    if (cell[q] < 0)
    {
      double closest[3], dist2;
      in.Cells->FindClosestPoint(p, closest, gcell, cell[q], subId, dist2);
      std::copy(closest, closest + 3, p);
    }
    double w[4] = { 0.25, 0.25, 0.25, 0.25 };
    if (cell[q] >= 0 && weights && in.Barycentric(cell[q], p, w))
    {
      std::copy(w, w + 4, weights + 4 * q);
    }
    else if (weights)
    {
      std::fill(weights + 4 * q, weights + 4 * q + 4, 0.25);
    }
  }
}

vtkIdType vtkARMeshKernels::TetLocator::CellOfPoint(vtkIdType p) const
{
  return this->Internals->CellOfPoint(p);
}

const vtkIdType* vtkARMeshKernels::TetLocator::CellPoints(vtkIdType c) const
{
  return this->Internals->Mesh.CellPoints(c);
}

vtkIdType vtkARMeshKernels::TetLocator::LastFallbacks() const
{
  return this->Internals->Fallbacks;
}
