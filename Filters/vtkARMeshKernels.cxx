// SPDX-License-Identifier: BSD-3-Clause
#include "vtkARMeshKernels.h"
#include "vtkARInputChecks.h"
#include "vtkARParallel.h"
#include "ARHugePages.h"

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
  vtkARParallel::AllReduceSum(status, 5);
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
  ar::ResizeHuge(cells, static_cast<std::size_t>(offsets.back()));
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

