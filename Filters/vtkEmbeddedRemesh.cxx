// SPDX-License-Identifier: BSD-3-Clause
#include "vtkEmbeddedRemesh.h"
#include "vtkEmbeddedRemeshPlanes.h"
#include "vtkEmbeddedRemeshQuality.h"

#include "ARCavity.h"
#include "ARCellQuality.h"
#include "ARMeshSize.h"
#include "ARPrismLayers.h"
#include "ARSurfaceRemesh.h"
#include "ARTetGeometry.h"
#include "vtkARInputChecks.h"
#include "vtkARMeshKernels.h"

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

namespace
{
/// Area and bounding-box diagonal of a triangle soup: the job-size
/// estimate's surface terms, in the serial and the MPI driver (T: the index
/// type; the MPI driver broadcasts the triangles as doubles).
template <typename T>
void SurfaceAreaAndDiagonal(
  const std::vector<double>& points, const std::vector<T>& tris, double& area, double& diagonal)
{
  area = 0.0;
  double lo[3] = { VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, VTK_DOUBLE_MAX };
  double hi[3] = { -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX };
  for (std::size_t t = 0; t + 2 < tris.size(); t += 3)
  {
    const double* a = &points[3 * static_cast<std::size_t>(tris[t])];
    const double* b = &points[3 * static_cast<std::size_t>(tris[t + 1])];
    const double* c = &points[3 * static_cast<std::size_t>(tris[t + 2])];
    const double u[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
    const double v[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
    double w[3];
    vtkMath::Cross(u, v, w);
    area += 0.5 * vtkMath::Norm(w);
    for (const double* x : { a, b, c })
    {
      for (int k = 0; k < 3; ++k)
      {
        lo[k] = std::min(lo[k], x[k]);
        hi[k] = std::max(hi[k], x[k]);
      }
    }
  }
  diagonal = std::sqrt(vtkMath::Distance2BetweenPoints(lo, hi));
}
/// The prism-layer options from the filter's properties (vtkEmbeddedRemeshQuality.h).
bool LayerOptionsOf(vtkEmbeddedRemesh* self, double edge, ar::PrismLayerOptions& layers, std::string& problem)
{
  return vtkEmbeddedRemeshLayerOptions(self, edge, layers, problem);
}

/// NaN/Inf coordinates in the volume or a surface, or duplicated points (a
/// crack) in the volume: the problem (empty when there is none), checked
/// before any mesher sees the mesh (TetGen fails on, or corrupts its heap
/// with, a crack).
std::string CoordinatesAndConformity(vtkUnstructuredGrid* input, const std::vector<vtkDataSet*>& surfaces)
{
  std::string bad = vtkARInputChecks::NonFinitePoints(input, "the volume mesh");
  for (std::size_t k = 0; k < surfaces.size() && bad.empty(); ++k)
  {
    const std::string what = "feature surface " + std::to_string(k) + " (the Surfaces input)";
    bad = vtkARInputChecks::NonFinitePoints(surfaces[k], what.c_str());
  }
  if (bad.empty())
  {
    bad = vtkARInputChecks::DuplicatedPoints(input);
  }
  if (!bad.empty())
  {
    bad.pop_back(); // the checks end their messages with a space
  }
  return bad;
}

/// The feature surfaces as bare triangles (geometry only: their arrays are
/// not wanted), added to `append`.
void AddSurfaceTriangles(const std::vector<vtkDataSet*>& surfaces, vtkAppendPolyData* append)
{
  for (vtkDataSet* ds : surfaces)
  {
    if (!ds || ds->GetNumberOfCells() == 0)
    {
      continue;
    }
    vtkNew<vtkGeometryFilter> geometry;
    geometry->SetInputData(ds);
    vtkNew<vtkTriangleFilter> triangles;
    triangles->SetInputConnection(geometry->GetOutputPort());
    triangles->PassVertsOff();
    triangles->PassLinesOff();
    triangles->Update();
    vtkNew<vtkPolyData> bare;
    bare->SetPoints(triangles->GetOutput()->GetPoints());
    bare->SetPolys(triangles->GetOutput()->GetPolys());
    append->AddInputData(bare);
  }
}
}

//------------------------------------------------------------------------------
vtkEmbeddedRemeshQuality vtkEmbeddedRemeshAddQualityArrays(vtkUnstructuredGrid* output, vtkIntArray* region)
{
  const vtkIdType n = output->GetNumberOfCells();
  vtkNew<vtkDoubleArray> minAngle, maxAngle, aspect;
  minAngle->SetName("MinDihedralAngle");
  maxAngle->SetName("MaxDihedralAngle");
  aspect->SetName("AspectRatio");
  for (vtkDoubleArray* a : { minAngle.Get(), maxAngle.Get(), aspect.Get() })
  {
    a->SetNumberOfTuples(n);
  }
  // On threads (vtkSMPTools) over fixed blocks of 20000 cells; the sums are
  // combined in block order, so the result depends neither on timing nor on
  // the number of threads.
  const vtkIdType blockSize = 20000;
  const vtkIdType nBlocks = (n + blockSize - 1) / blockSize;
  std::vector<vtkEmbeddedRemeshQuality> partial(static_cast<std::size_t>(nBlocks));
  auto work = [&](vtkIdType w) {
    vtkEmbeddedRemeshQuality& sums = partial[w];
    const vtkIdType first = w * blockSize, last = std::min(n, first + blockSize);
    vtkNew<vtkIdList> scratch;
    double x[8 * 3];
    for (vtkIdType c = first; c < last; ++c)
    {
      vtkIdType npts;
      const vtkIdType* pts;
      output->GetCellPoints(c, npts, pts, scratch); // the thread-safe overload
      ar::CellShape shape;
      static const int voxelToHexahedron[8] = { 0, 1, 3, 2, 4, 5, 7, 6 };
      const int type = output->GetCellType(c);
      switch (type)
      {
        case VTK_TETRA:
          shape = ar::CellShape::Tetrahedron;
          break;
        case VTK_PYRAMID:
          shape = ar::CellShape::Pyramid;
          break;
        case VTK_WEDGE:
          shape = ar::CellShape::Wedge;
          break;
        case VTK_HEXAHEDRON:
        case VTK_VOXEL:
          shape = ar::CellShape::Hexahedron;
          break;
        default:
          minAngle->SetValue(c, -1.0);
          maxAngle->SetValue(c, -1.0);
          aspect->SetValue(c, -1.0);
          continue;
      }
      for (vtkIdType k = 0; k < npts; ++k)
      {
        output->GetPoint(pts[type == VTK_VOXEL ? voxelToHexahedron[k] : k], &x[3 * k]);
      }
      const ar::CellQuality q = ar::ComputeCellQuality(shape, x);
      minAngle->SetValue(c, q.MinDihedralAngle);
      maxAngle->SetValue(c, q.MaxDihedralAngle);
      aspect->SetValue(c, q.AspectRatio);
      sums.NonPositiveJacobian += q.MinCornerJacobian > 0.0 ? 0.0 : 1.0;
      if (region->GetValue(c) == 1)
      {
        sums.NewCells += 1.0;
        sums.NewMinDihedral = std::min(sums.NewMinDihedral, q.MinDihedralAngle);
        sums.NewDihedralSum += q.MinDihedralAngle;
        sums.NewMaxAspectRatio = std::max(sums.NewMaxAspectRatio, q.AspectRatio);
      }
      else if (region->GetValue(c) == 2 || shape != ar::CellShape::Tetrahedron)
      {
        if (region->GetValue(c) == 2)
        {
          (shape == ar::CellShape::Wedge         ? sums.NewPrisms
              : shape == ar::CellShape::Pyramid   ? sums.NewPyramids
              : shape == ar::CellShape::Hexahedron ? sums.NewLayerHexahedra
                                                  : sums.NewLayerTetrahedra) += 1.0;
        }
        // layer cells: new prism layers, kept non-tetrahedral (near-wall) cells
        sums.LayerMaxAspectRatio = std::max(sums.LayerMaxAspectRatio, q.AspectRatio);
        sums.LayerMinDihedral = std::min(sums.LayerMinDihedral, q.MinDihedralAngle);
        sums.LayerCells += 1.0;
      }
    }
  };
  vtkSMPTools::For(0, nBlocks, 1, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType w = b; w < e; ++w)
    {
      work(w);
    }
  });
  vtkEmbeddedRemeshQuality sums;
  for (const vtkEmbeddedRemeshQuality& s : partial)
  {
    sums.NewCells += s.NewCells;
    sums.NewMinDihedral = std::min(sums.NewMinDihedral, s.NewMinDihedral);
    sums.NewDihedralSum += s.NewDihedralSum;
    sums.NewMaxAspectRatio = std::max(sums.NewMaxAspectRatio, s.NewMaxAspectRatio);
    sums.LayerMaxAspectRatio = std::max(sums.LayerMaxAspectRatio, s.LayerMaxAspectRatio);
    sums.LayerMinDihedral = std::min(sums.LayerMinDihedral, s.LayerMinDihedral);
    sums.LayerCells += s.LayerCells;
    sums.NewPrisms += s.NewPrisms;
    sums.NewPyramids += s.NewPyramids;
    sums.NewLayerTetrahedra += s.NewLayerTetrahedra;
    sums.NewLayerHexahedra += s.NewLayerHexahedra;
    sums.NonPositiveJacobian += s.NonPositiveJacobian;
  }
  output->GetCellData()->AddArray(minAngle);
  output->GetCellData()->AddArray(maxAngle);
  output->GetCellData()->AddArray(aspect);
  return sums;
}

void vtkEmbeddedRemeshAddQualityFields(vtkUnstructuredGrid* output, const vtkEmbeddedRemeshQuality& sums)
{
  auto field = [&](const char* name, double value) {
    output->GetFieldData()->AddArray(vtkARMeshKernels::FieldArray(name, &value, 1));
  };
  const bool any = sums.NewCells > 0.0;
  field("MinDihedralAngleNew", any ? sums.NewMinDihedral : 0.0);
  field("MeanDihedralAngleNew", any ? sums.NewDihedralSum / sums.NewCells : 0.0);
  field("MaxAspectRatioNew", sums.NewMaxAspectRatio);
  field("MaxAspectRatioLayerCells", sums.LayerMaxAspectRatio);
  field("MinDihedralAngleLayerCells", sums.LayerCells > 0.0 ? sums.LayerMinDihedral : 0.0);
  field("NonPositiveJacobianCells", sums.NonPositiveJacobian);
  field("LayerCells", sums.NewPrisms + sums.NewPyramids + sums.NewLayerTetrahedra + sums.NewLayerHexahedra);
  field("Prisms", sums.NewPrisms);
  field("Pyramids", sums.NewPyramids);
  field("LayerClosureTetrahedra", sums.NewLayerTetrahedra);
  field("LayerHexahedra", sums.NewLayerHexahedra);
}

void vtkEmbeddedRemeshReduceQuality(vtkEmbeddedRemeshQuality& q)
{
  double sums[8] = { q.NewCells, q.NewDihedralSum, q.NonPositiveJacobian, q.LayerCells, q.NewPrisms,
    q.NewPyramids, q.NewLayerTetrahedra, q.NewLayerHexahedra };
  double maxima[4] = { -q.NewMinDihedral, q.NewMaxAspectRatio, q.LayerMaxAspectRatio, -q.LayerMinDihedral };
  vtkARMeshKernels::AllReduceSum(sums, 8);
  vtkARMeshKernels::AllReduceMax(maxima, 4);
  q.NewCells = sums[0];
  q.NewDihedralSum = sums[1];
  q.NonPositiveJacobian = sums[2];
  q.LayerCells = sums[3];
  q.NewPrisms = sums[4];
  q.NewPyramids = sums[5];
  q.NewLayerTetrahedra = sums[6];
  q.NewLayerHexahedra = sums[7];
  q.NewMinDihedral = -maxima[0];
  q.NewMaxAspectRatio = maxima[1];
  q.LayerMaxAspectRatio = maxima[2];
  q.LayerMinDihedral = -maxima[3];
}

double vtkEmbeddedRemeshOutputSizeAtSurface(const ar::CavityRemesh& r)
{
  std::vector<double> lv =
    ar::LongestEdgeAtNodes(r.Mesh.Points.data(), r.Mesh.Points.size() / 3, r.Mesh.Tetrahedra.data(),
      r.Mesh.NumberOfTetrahedra());
  ar::AccumulateLongestEdges(ar::CellShape::Wedge, r.Mesh.Points.data(), r.Prisms.data(), r.Prisms.size() / 6, lv);
  ar::AccumulateLongestEdges(ar::CellShape::Pyramid, r.Mesh.Points.data(), r.Pyramids.data(), r.Pyramids.size() / 5, lv);
  return ar::MedianAtNodes(lv, r.Surface.data(), r.Surface.size());
}

void vtkEmbeddedRemeshAddSizeFields(vtkUnstructuredGrid* output, double edge, double inputSize, double outputSize)
{
  auto field = [&](const char* name, double value) {
    output->GetFieldData()->AddArray(vtkARMeshKernels::FieldArray(name, &value, 1));
  };
  field("InputSizeAtSurface", inputSize);
  field("SurfaceSizeFactor", inputSize > 0.0 ? edge / inputSize : 0.0);
  field("OutputSizeAtSurface", outputSize);
  field("SurfaceSizeRatio", inputSize > 0.0 ? outputSize / inputSize : 0.0);
}

bool vtkEmbeddedRemeshOptionsValid(vtkEmbeddedRemesh* self, std::string& problem)
{
  vtkARInputChecks::Properties p;
  p.OneOf("Mode", self->GetMode(), { "LocalCavity", "FullDomain" })
    .InRange("SurfaceEdgeLength", self->GetSurfaceEdgeLength(), 0.0, VTK_DOUBLE_MAX,
      "S's edge length; 0 sets it from the input's size at S")
    .AboveAndAtMost("RemovalFactor", self->GetRemovalFactor(), 0.0, 1e3,
      "the radius of removal in units of max(l_s, l_v)")
    .InRange("BoundaryMargin", self->GetBoundaryMargin(), 0.0, 1e3,
      "S is trimmed this many of its edge lengths away from V's boundary")
    .InRange("MaxRadiusEdgeRatio", self->GetMaxRadiusEdgeRatio(), 1.0, 100.0,
      "TetGen's radius-edge bound; below 1 it cannot be met")
    .InRange("MinDihedralAngle", self->GetMinDihedralAngle(), 0.0, 30.0, "degrees")
    .OneOf("TwoDimensional", self->GetTwoDimensional(), { "Auto", "Off" })
    .InRange("MinTriangleAngle", self->GetMinTriangleAngle(), 0.0, 30.0, "degrees");
  const double f = self->GetSurfaceSizeFactor();
  if (self->GetSurfaceEdgeLength() <= 0.0 && !(f >= 0.0 && f <= 10.0))
  {
    std::ostringstream msg;
    msg << "SurfaceSizeFactor is " << f
        << "; it must lie in [0, 10] (S's edge length in units of the input's size at S, "
           "below 1 refines; 0 automatic), or set SurfaceEdgeLength.";
    p.Add(msg.str());
  }
  if (p.Ok())
  {
    return true;
  }
  problem = "EmbeddedRemesh: " + p.Message();
  problem.pop_back(); // the callers add " The input passes through unchanged."
  return false;
}

bool vtkEmbeddedRemeshJobFits(vtkEmbeddedRemesh* self, int dimension, double extent, double size,
  double edge, double inputSize, double domain, double inputCells, std::string& problem)
{
  const bool byLength = self->GetSurfaceEdgeLength() > 0.0;
  std::ostringstream who;
  if (byLength)
  {
    who << "SurfaceEdgeLength is " << edge;
  }
  else
  {
    who << "SurfaceSizeFactor is " << self->GetSurfaceSizeFactorUsed() << " (S's edge length "
        << edge << ", the input's size at S " << inputSize << " times it)";
  }
  const char* what = dimension == 3 ? "the feature surface" : "the feature curve";
  if (edge > size)
  {
    std::ostringstream msg;
    msg << "EmbeddedRemesh: " << who.str() << ", longer than " << what << " itself ("
        << (dimension == 3 ? "its bounding box's diagonal is " : "its length is ") << size
        << "): it cannot be meshed at that length. The edge length must lie in (0, " << size
        << "] here, and be well below it; 0 sets it from the input's size at S (" << inputSize << ").";
    problem = msg.str();
    return false;
  }
  // The cavity: a slab of the removal radius on both sides of S (the
  // whole domain with FullDomain), its cells graded linearly from `edge` at
  // S to the input's size H at the slab's faces: per unit of S, the
  // integral of 1 / size(d)^dimension over d in [0, D] on each side.
  const double H = std::max(edge, inputSize);
  const double D = self->GetRemovalFactor() * H;
  const bool full = self->GetMode() == vtkEmbeddedRemesh::FULL_DOMAIN;
  const double slab = std::min(2.0 * extent * D, domain > 0.0 ? domain : VTK_DOUBLE_MAX);
  const double cavity = full ? domain : slab;
  // Cells per edge^d of graded volume: 8.5 tetrahedra (the regular
  // tetrahedron's; TetGen's refill of the oblique shock measured within 2%
  // of it at SurfaceSizeFactor 0.1-0.2), 2.9 triangles (the equilateral
  // triangle's 2.31 gave 80% of CGAL's count on the wedge at 0.05-0.2).
  double boundaryElements, cavityElements;
  if (dimension == 3)
  {
    boundaryElements = extent / (0.25 * std::sqrt(3.0) * edge * edge);
    cavityElements = 8.5 * slab * (H + edge) / (2.0 * edge * edge * H * H);
  }
  else
  {
    boundaryElements = extent / edge;
    cavityElements = 2.9 * slab / (edge * H);
  }
  if (full)
  {
    // The far field, remeshed at about its size: TetGen's quality mesh of
    // it has about twice the input's cells (1.9x on Kuhn cubes of 5.1e6
    // tetrahedra: 11.1e6 new cells; on the oblique shock's Gmsh mesh the
    // 4689 cells LocalCavity keeps became 12613 with FullDomain).
    cavityElements += 2.0 * inputCells;
  }
  // Prism layers: NumberOfLayers prisms on each side of every S triangle.
  // (2-D: NumberOfLayers quads on each side of every curve segment.)
  const double layerElements = self->GetLayerType() == vtkEmbeddedRemesh::PRISMS
    ? 2.0 * self->GetNumberOfLayers() * boundaryElements
    : 0.0;
  const double total = boundaryElements + cavityElements + layerElements;
  const double cap = vtkARInputChecks::MaximumElements();
  if (std::isfinite(total) && total <= cap)
  {
    return true;
  }
  std::ostringstream msg;
  msg.precision(3);
  msg << "EmbeddedRemesh: " << who.str() << ": the job would not fit in memory. "
      << (dimension == 3 ? "The feature surface's " : "The feature curve's ")
      << (dimension == 3 ? "area " : "length ") << extent << " over the edge length"
      << (dimension == 3 ? " squared" : "") << " gives about " << boundaryElements
      << (dimension == 3 ? " surface triangles" : " curve segments") << ", and the cavity ("
      << (dimension == 3 ? "volume " : "area ") << cavity << ", cells graded from " << edge << " at S to "
      << H << ") about " << cavityElements << (dimension == 3 ? " tetrahedra" : " triangles");
  if (layerElements > 0.0)
  {
    msg << ", the prism layers about " << layerElements << " cells";
  }
  msg << ": an estimated " << total << " elements, above the cap of " << cap
      << " (half of this machine's " << vtkARInputChecks::PhysicalMemory() / (1024.0 * 1024.0 * 1024.0)
      << " GiB of memory at " << static_cast<int>(vtkARInputChecks::BytesPerElement)
      << " bytes per element). Raise "
      << (byLength ? "SurfaceEdgeLength" : "SurfaceSizeFactor")
      << " (0 for both chooses the edge from the input's size at S, " << inputSize << ").";
  problem = msg.str();
  return false;
}

//------------------------------------------------------------------------------
bool vtkEmbeddedRemeshLayerOptions(vtkEmbeddedRemesh* self, double edge, ar::PrismLayerOptions& layers, std::string& problem)
{
  layers = ar::PrismLayerOptions();
  if (self->GetLayerType() == vtkEmbeddedRemesh::TETRAHEDRA)
  {
    return true;
  }
  std::ostringstream msg;
  if (self->GetLayerType() != vtkEmbeddedRemesh::PRISMS)
  {
    msg << "LayerType is " << self->GetLayerType() << "; it must be 0 (Tetrahedra) or 1 (Prisms).";
  }
  else if (self->GetNumberOfLayers() < 1 || self->GetNumberOfLayers() > 100)
  {
    msg << "NumberOfLayers is " << self->GetNumberOfLayers() << "; prism layers need 1 to 100 per side.";
  }
  else if (!(self->GetGrowthRatio() > 0.0) || !std::isfinite(self->GetGrowthRatio()))
  {
    msg << "GrowthRatio is " << self->GetGrowthRatio() << "; it must be a positive number.";
  }
  else if (!(self->GetFirstLayerThickness() >= 0.0) || !std::isfinite(self->GetFirstLayerThickness()))
  {
    msg << "FirstLayerThickness is " << self->GetFirstLayerThickness()
        << "; it must be positive (or 0 for a stack half a surface edge high).";
  }
  else if (!(self->GetTotalThickness() >= 0.0) || !std::isfinite(self->GetTotalThickness()))
  {
    msg << "TotalThickness is " << self->GetTotalThickness() << "; it must be positive (or 0 to use FirstLayerThickness).";
  }
  if (!msg.str().empty())
  {
    problem = "EmbeddedRemesh: " + msg.str();
    return false;
  }
  layers.NumberOfLayers = self->GetNumberOfLayers();
  layers.GrowthRatio = self->GetGrowthRatio();
  layers.TotalThickness = self->GetTotalThickness();
  layers.FirstLayerThickness = self->GetFirstLayerThickness();
  if (layers.TotalThickness <= 0.0 && layers.FirstLayerThickness <= 0.0)
  {
    // Automatic: the stack on each side half a surface edge high (the core
    // derives the first layer from it). Higher stacks (above about 0.6 edge
    // on the cone) leave TetGen slivers against the closure at S's border.
    layers.TotalThickness = 0.5 * edge;
  }
  return true;
}

void vtkEmbeddedRemeshAddLayerFields(
  vtkUnstructuredGrid* output, const ar::PrismLayerOptions& layers, double limitedColumns)
{
  std::vector<double> z;
  std::string unused;
  const bool on = layers.NumberOfLayers > 0 && ar::PrismLayerDistances(layers, z, unused);
  for (const auto& [name, value] : { std::make_pair("LimitedColumns", limitedColumns),
         std::make_pair("LayerStackHeight", on ? z.back() : 0.0),
         std::make_pair("FirstLayerThicknessUsed", on ? z[1] : 0.0) })
  {
    output->GetFieldData()->AddArray(vtkARMeshKernels::FieldArray(name, &value, 1));
  }
}

//------------------------------------------------------------------------------
double vtkEmbeddedRemesh::GetSurfaceSizeFactorUsed() const
{
  if (this->SurfaceSizeFactor > 0.0)
  {
    return this->SurfaceSizeFactor;
  }
  return this->LayerType == PRISMS ? 1.0 : 0.2;
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
    catch (const std::bad_alloc&)
    {
      failure = "EmbeddedRemesh ran out of memory (std::bad_alloc) while remeshing; raise SurfaceEdgeLength "
                "(or SurfaceSizeFactor), or remesh a smaller region (LocalCavity, a lower RemovalFactor).";
    }
    catch (const std::exception& e)
    {
      failure = std::string("EmbeddedRemesh failed: ") + e.what() + ".";
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
  vtkARMeshKernels::AllReduceMax(&missing, 1);
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
  std::string sizeProblem;
  if (!vtkEmbeddedRemeshOptionsValid(this, sizeProblem))
  {
    return passThrough(sizeProblem);
  }
  if (vtkARMeshKernels::NumberOfRanks() > 1)
  {
    return this->RemeshDistributed(input, surfaces, output, embedded);
  }
  if (!input || input->GetNumberOfCells() == 0)
  {
    return passThrough("The volume mesh is empty.");
  }
  // Wall-clock seconds per stage, reported in the output's field data.
  auto stageStart = std::chrono::steady_clock::now();
  auto lap = [&stageStart]() {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - stageStart).count();
    stageStart = now;
    return s;
  };
  // ---- Coordinates and conformity, before any mesher sees them (TetGen
  // fails on, or corrupts its heap with, a crack of duplicated points). Its
  // time counts in SecondsInput.
  {
    const std::string bad = CoordinatesAndConformity(input, surfaces);
    if (!bad.empty())
    {
      return passThrough("EmbeddedRemesh: " + bad);
    }
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
  vtkNew<vtkAppendPolyData> append;
  AddSurfaceTriangles(surfaces, append);
  if (append->GetNumberOfInputConnections(0) == 0)
  {
    return passThrough("The feature surface is empty (no Surfaces connected, or none has cells).");
  }
  vtkNew<vtkStaticCleanPolyData> clean;
  clean->SetInputConnection(append->GetOutputPort());
  clean->SetTolerance(0.0);
  clean->Update();
  vtkPolyData* surface = clean->GetOutput();
  std::vector<double> sPoints(3 * surface->GetNumberOfPoints());
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
  {
    surface->GetPoint(i, &sPoints[3 * i]);
  }
  std::vector<std::int64_t> sTris;
  {
    vtkIdType npts;
    const vtkIdType* ids;
    vtkCellArray* polys = surface->GetPolys();
    for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
    {
      if (npts == 3)
      {
        sTris.insert(sTris.end(), { ids[0], ids[1], ids[2] });
      }
    }
  }
  if (sTris.empty())
  {
    return passThrough("The feature surface has no triangles.");
  }

  // ---- V: its tetrahedra; other 3-D cells are kept and lock their nodes.
  const vtkIdType nPoints = input->GetNumberOfPoints();
  ar::TetMesh tets;
  tets.Points.resize(3 * nPoints);
  for (vtkIdType i = 0; i < nPoints; ++i)
  {
    input->GetPoint(i, &tets.Points[3 * i]);
  }
  ar::CavityOptions options;
  options.LockedNodes.assign(nPoints, 0);
  std::vector<vtkIdType> tetCell, otherCell;
  vtkNew<vtkIdList> ids;
  vtkNew<vtkGenericCell> lockedCell;
  for (vtkIdType c = 0; c < input->GetNumberOfCells(); ++c)
  {
    const int type = input->GetCellType(c);
    input->GetCellPoints(c, ids);
    if (type == VTK_TETRA)
    {
      for (vtkIdType k = 0; k < 4; ++k)
      {
        tets.Tetrahedra.push_back(ids->GetId(k));
      }
      tetCell.push_back(c);
    }
    else if (type == VTK_HEXAHEDRON || type == VTK_WEDGE || type == VTK_PYRAMID ||
      type == VTK_VOXEL || type == VTK_POLYHEDRON || type == VTK_TRIANGLE || type == VTK_QUAD ||
      type == VTK_POLYGON)
    {
      // Kept as they are: other 3-D cells, and boundary-patch faces (2-D
      // cells with a PatchId, as the solver writers take them).
      for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
      {
        options.LockedNodes[ids->GetId(k)] = 1;
      }
      otherCell.push_back(c);
      // The 3-D ones (e.g. near-wall layers) bound a region S is trimmed at.
      if (vtkCellTypes::GetDimension(type) == 3)
      {
        input->GetCell(c, lockedCell);
        for (int f = 0; f < lockedCell->GetNumberOfFaces(); ++f)
        {
          vtkCell* face = lockedCell->GetFace(f);
          options.LockedCellFaces.push_back(face->GetNumberOfPoints());
          for (vtkIdType k = 0; k < face->GetNumberOfPoints(); ++k)
          {
            options.LockedCellFaces.push_back(face->GetPointId(k));
          }
        }
      }
    }
    else
    {
      std::ostringstream msg;
      msg << "Cell " << c << " has type " << type
          << "; EmbeddedRemesh takes linear 3-D cells (tetrahedra are remeshed; hexahedra, "
             "wedges, pyramids and polyhedra are kept) and triangles, quads or polygons as "
             "boundary-patch faces (kept).";
      return passThrough(msg.str());
    }
  }
  if (tetCell.empty())
  {
    return passThrough("The volume mesh has no tetrahedra to remesh, and it is not a one-cell-deep "
                       "(2-D) mesh either (" + not2D + ").");
  }
  this->UpdateProgress(0.1);
  if (this->CheckAbort())
  {
    output->ShallowCopy(input); // cancelled
    return 1;
  }
  const double secondsInput = lap();

  // ---- S remeshed at the edge length: SurfaceSizeFactor times the input's
  // size at S, h_S (the median l_v at the node of V nearest to each S point).
  double inputSize = 0.0;
  {
    const std::vector<double> lv =
      ar::LongestEdgeAtNodes(tets.Points.data(), nPoints, tets.Tetrahedra.data(), tets.NumberOfTetrahedra());
    vtkNew<vtkStaticPointLocator> locator;
    locator->SetDataSet(input);
    locator->BuildLocator();
    std::vector<double> near;
    for (std::size_t i = 0; i < sPoints.size() / 3; ++i)
    {
      const vtkIdType j = locator->FindClosestPoint(&sPoints[3 * i]);
      if (j >= 0 && lv[j] > 0.0)
      {
        near.push_back(lv[j]);
      }
    }
    inputSize = ar::Median(std::move(near));
  }
  const double edge = this->SurfaceEdgeLength > 0.0 ? this->SurfaceEdgeLength : this->GetSurfaceSizeFactorUsed() * inputSize;
  if (!(edge > 0.0))
  {
    return passThrough("Could not find the mesh size near the feature surface; set SurfaceEdgeLength.");
  }
  std::string error;
  {
    // The job's size, before CGAL or TetGen allocate it.
    double area = 0.0, diagonal = 0.0;
    SurfaceAreaAndDiagonal(sPoints, sTris, area, diagonal);
    if (!vtkEmbeddedRemeshJobFits(this, 3, area, diagonal, edge, inputSize, ar::ComputeStatistics(tets).TotalVolume,
          static_cast<double>(tets.NumberOfTetrahedra()), error))
    {
      return passThrough(error);
    }
  }
  std::vector<double> rPoints;
  std::vector<std::int64_t> rTris;
  if (!ar::RemeshSurfaceIsotropic(sPoints, sTris, edge, rPoints, rTris, error))
  {
    vtkWarningMacro(<< "The feature surface is used as it is (not remeshed): " << error);
    rPoints = sPoints;
    rTris = sTris;
  }
  this->UpdateProgress(0.3);
  if (this->CheckAbort())
  {
    output->ShallowCopy(input); // cancelled
    return 1;
  }
  const double secondsSurface = lap();

  // ---- The cavity and its refill.
  options.RemovalFactor = this->RemovalFactor;
  options.VisibilityTest = this->VisibilityTest;
  options.BoundaryMargin = this->BoundaryMargin;
  options.FullDomain = this->Mode == FULL_DOMAIN;
  options.Quality.MaxRadiusEdgeRatio = this->MaxRadiusEdgeRatio;
  options.Quality.MinDihedralAngle = this->MinDihedralAngle;
  std::string layerProblem;
  if (!LayerOptionsOf(this, edge, options.Layers, layerProblem))
  {
    return passThrough(layerProblem);
  }
  ar::CavityRemesh result;
  if (!ar::RemeshLocalCavity(tets, rPoints.data(), rPoints.size() / 3, rTris.data(), rTris.size() / 3,
        options, result, error))
  {
    return passThrough("EmbeddedRemesh: " + error);
  }
  this->UpdateProgress(0.8);
  if (this->CheckAbort())
  {
    output->ShallowCopy(input); // cancelled
    return 1;
  }
  lap();

  // ---- Output mesh: new tetrahedra and kept cells, in the output's point ids.
  const auto nOut = static_cast<vtkIdType>(result.SourcePoint.size());
  std::vector<vtkIdType> outOfInput(nPoints, -1);
  for (vtkIdType i = 0; i < nOut; ++i)
  {
    if (result.SourcePoint[i] >= 0)
    {
      outOfInput[result.SourcePoint[i]] = i;
    }
  }
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(nOut);
  for (vtkIdType i = 0; i < nOut; ++i)
  {
    points->SetPoint(i, &result.Mesh.Points[3 * i]);
  }
  output->Initialize();
  output->GetFieldData()->ShallowCopy(input->GetFieldData());
  output->SetPoints(points);
  const auto nTets = static_cast<vtkIdType>(result.SourceCell.size());
  output->Allocate(nTets + static_cast<vtkIdType>(otherCell.size()));
  std::vector<vtkIdType> sourceCell; // input cell of each output cell, -1 new
  vtkNew<vtkIntArray> region, layer, side;
  region->SetName("Region"); // 0 kept, 1 new tetrahedron of the refill, 2 layer cell
  layer->SetName("Layer");   // layer cells: k, 0 next to S; others -1
  side->SetName("LayerSide"); // layer cells: +1 on S's normal side, -1 on the other; others 0
  vtkIdType newCount = 0;
  auto addCell = [&](int type, vtkIdType n, const vtkIdType* pts, vtkIdType src, int reg, int k, int s) {
    output->InsertNextCell(type, n, pts);
    sourceCell.push_back(src);
    region->InsertNextValue(reg);
    layer->InsertNextValue(k);
    side->InsertNextValue(s);
    newCount += reg > 0 ? 1 : 0;
  };
  const bool layered = !result.TetrahedronLayer.empty();
  for (vtkIdType t = 0; t < nTets; ++t)
  {
    const std::int64_t* v = &result.Mesh.Tetrahedra[4 * t];
    const vtkIdType pts[4] = { v[0], v[1], v[2], v[3] };
    const std::int64_t src = result.SourceCell[t];
    const int k = layered ? result.TetrahedronLayer[t] : -1;
    addCell(VTK_TETRA, 4, pts, src >= 0 ? tetCell[src] : -1, src >= 0 ? 0 : k >= 0 ? 2 : 1, k,
      k >= 0 ? result.TetrahedronSide[t] : 0);
  }
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
      output->InsertNextCell(VTK_POLYHEDRON, faces);
      sourceCell.push_back(c);
      region->InsertNextValue(0);
      layer->InsertNextValue(-1);
      side->InsertNextValue(0);
    }
    else
    {
      addCell(input->GetCellType(c), ids->GetNumberOfIds(), ids->GetPointer(0), c, 0, -1, 0);
    }
  }
  // The prism layers and the pyramids closing them at S's border.
  for (std::size_t p = 0; p < result.Prisms.size() / 6; ++p)
  {
    vtkIdType pts[6];
    std::copy(&result.Prisms[6 * p], &result.Prisms[6 * p] + 6, pts);
    addCell(VTK_WEDGE, 6, pts, -1, 2, result.PrismLayer[p], result.PrismSide[p]);
  }
  for (std::size_t p = 0; p < result.Pyramids.size() / 5; ++p)
  {
    vtkIdType pts[5];
    std::copy(&result.Pyramids[5 * p], &result.Pyramids[5 * p] + 5, pts);
    addCell(VTK_PYRAMID, 5, pts, -1, 2, result.PyramidLayer[p], result.PyramidSide[p]);
  }

  const double secondsOutput = lap();

  // ---- Fields: kept points and cells copy theirs; new ones interpolate
  // from the input's cells that were removed (the cavity holds every new
  // point), so the cost follows the cavity, not the whole mesh. A new point
  // takes the linear interpolation in the removed tetrahedron that contains
  // it, a new cell the values of the removed tetrahedron that contains its
  // centre (TetLocator: the same answer whatever the threads do).
  if (this->InterpolateFields)
  {
    vtkPointData* inPD = input->GetPointData();
    vtkPointData* outPD = output->GetPointData();
    vtkCellData* inCD = input->GetCellData();
    vtkCellData* outCD = output->GetCellData();
    const auto nCellsOut = static_cast<vtkIdType>(sourceCell.size());
    outPD->InterpolateAllocate(inPD, nOut);
    outCD->CopyAllocate(inCD, nCellsOut);
    std::vector<char> keptTet(tetCell.size(), 0);
    for (const std::int64_t src : result.SourceCell)
    {
      if (src >= 0)
      {
        keptTet[src] = 1;
      }
    }
    std::vector<vtkIdType> cavityCell; // input cell id of each cavity cell
    for (std::size_t t = 0; t < tetCell.size(); ++t)
    {
      if (!keptTet[t])
      {
        cavityCell.push_back(tetCell[t]);
      }
    }
    const auto nCavity = static_cast<vtkIdType>(cavityCell.size());
    vtkNew<vtkUnstructuredGrid> cavity; // the removed tetrahedra, on the input's points
    cavity->SetPoints(input->GetPoints());
    {
      vtkNew<vtkIdTypeArray> offsets, connectivity;
      offsets->SetNumberOfValues(nCavity + 1);
      connectivity->SetNumberOfValues(4 * nCavity);
      vtkSMPThreadLocalObject<vtkIdList> scratch;
      vtkSMPTools::For(0, nCavity, [&](vtkIdType b, vtkIdType e) {
        vtkIdList* corners = scratch.Local();
        for (vtkIdType c = b; c < e; ++c)
        {
          vtkIdType npts;
          const vtkIdType* pts;
          input->GetCellPoints(cavityCell[c], npts, pts, corners);
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
    }
    vtkARMeshKernels::TetLocator locator;
    locator.Build(cavity);

    // The new points, each walked to from its nearest cavity vertex.
    std::vector<vtkIdType> newPoint;
    std::vector<vtkIdType> queryOf(nOut, -1); // new point -> its query
    for (vtkIdType i = 0; i < nOut; ++i)
    {
      if (result.SourcePoint[i] < 0)
      {
        queryOf[i] = static_cast<vtkIdType>(newPoint.size());
        newPoint.push_back(i);
      }
    }
    const auto nNewPoints = static_cast<vtkIdType>(newPoint.size());
    std::vector<double> where(3 * newPoint.size());
    for (vtkIdType q = 0; q < nNewPoints; ++q)
    {
      std::copy(&result.Mesh.Points[3 * newPoint[q]], &result.Mesh.Points[3 * newPoint[q]] + 3, &where[3 * q]);
    }
    std::vector<vtkIdType> pointIn(newPoint.size());
    std::vector<double> weights(4 * newPoint.size());
    locator.Locate(nNewPoints, where.data(), nullptr, pointIn.data(), weights.data());
    const vtkIdType pointFallbacks = locator.LastFallbacks();

    // The new cells' centres, each walked to from the cavity cell of one of
    // its corners (a new point's, or a kept point's first).
    std::vector<vtkIdType> newCell;
    for (vtkIdType k = 0; k < nCellsOut; ++k)
    {
      if (sourceCell[k] < 0)
      {
        newCell.push_back(k);
      }
    }
    const auto nNewCells = static_cast<vtkIdType>(newCell.size());
    std::vector<double> centres(3 * newCell.size());
    std::vector<vtkIdType> starts(newCell.size(), -1), cellIn(newCell.size());
    {
      vtkSMPThreadLocalObject<vtkIdList> scratch;
      vtkSMPTools::For(0, nNewCells, [&](vtkIdType b, vtkIdType e) {
        vtkIdList* corners = scratch.Local();
        for (vtkIdType q = b; q < e; ++q)
        {
          vtkIdType npts;
          const vtkIdType* pts;
          output->GetCellPoints(newCell[q], npts, pts, corners);
          double* centre = &centres[3 * q];
          std::fill(centre, centre + 3, 0.0);
          for (vtkIdType j = 0; j < npts; ++j)
          {
            for (int d = 0; d < 3; ++d)
            {
              centre[d] += result.Mesh.Points[3 * pts[j] + d] / static_cast<double>(npts);
            }
            if (starts[q] < 0)
            {
              starts[q] = queryOf[pts[j]] >= 0 ? pointIn[queryOf[pts[j]]]
                                               : locator.CellOfPoint(result.SourcePoint[pts[j]]);
            }
          }
        }
      });
    }
    locator.Locate(nNewCells, centres.data(), starts.data(), cellIn.data(), nullptr);
    vtkDebugMacro(<< "interpolation: " << nNewPoints << " new points (" << pointFallbacks
                  << " located by the cell locator), " << nNewCells << " new cells ("
                  << locator.LastFallbacks() << ")");

    // The copies and the interpolation, array by array.
    vtkARMeshKernels::TupleSources pointSources(nOut, 4), cellSources(nCellsOut, 1);
    for (vtkIdType i = 0; i < nOut; ++i)
    {
      if (result.SourcePoint[i] >= 0)
      {
        pointSources.Copy(i, result.SourcePoint[i]);
      }
    }
    for (vtkIdType q = 0; q < nNewPoints; ++q)
    {
      pointSources.Interpolate(newPoint[q], locator.CellPoints(pointIn[q]), &weights[4 * q]);
    }
    for (vtkIdType k = 0; k < nCellsOut; ++k)
    {
      if (sourceCell[k] >= 0)
      {
        cellSources.Copy(k, sourceCell[k]);
      }
    }
    for (vtkIdType q = 0; q < nNewCells; ++q)
    {
      cellSources.Copy(newCell[q], cavityCell[cellIn[q]]);
    }
    vtkARMeshKernels::TransferData(inPD, outPD, pointSources);
    vtkARMeshKernels::TransferData(inCD, outCD, cellSources);
  }
  const double secondsInterpolation = lap();
  output->GetCellData()->AddArray(region);
  output->GetCellData()->AddArray(layer);
  output->GetCellData()->AddArray(side);
  const vtkEmbeddedRemeshQuality quality = vtkEmbeddedRemeshAddQualityArrays(output, region);
  const double secondsQuality = lap();

  // ---- Field data and the embedded surface.
  const ar::TetMeshStatistics before = ar::ComputeStatistics(tets);
  double volumeAfter = ar::ComputeStatistics(result.Mesh).TotalVolume;
  for (std::size_t p = 0; p < result.Prisms.size() / 6; ++p)
  {
    double x[18];
    for (int k = 0; k < 6; ++k)
    {
      std::copy(&result.Mesh.Points[3 * result.Prisms[6 * p + k]], &result.Mesh.Points[3 * result.Prisms[6 * p + k]] + 3, x + 3 * k);
    }
    volumeAfter += ar::CellVolume(ar::CellShape::Wedge, x);
  }
  for (std::size_t p = 0; p < result.Pyramids.size() / 5; ++p)
  {
    double x[15];
    for (int k = 0; k < 5; ++k)
    {
      std::copy(&result.Mesh.Points[3 * result.Pyramids[5 * p + k]], &result.Mesh.Points[3 * result.Pyramids[5 * p + k]] + 3, x + 3 * k);
    }
    volumeAfter += ar::CellVolume(ar::CellShape::Pyramid, x);
  }
  auto field = [&](const char* name, double value) {
    output->GetFieldData()->AddArray(vtkARMeshKernels::FieldArray(name, &value, 1));
  };
  vtkIdType keptPoints = 0;
  for (const std::int64_t src : result.SourcePoint)
  {
    keptPoints += src >= 0 ? 1 : 0;
  }
  field("TwoDimensional", 0.0);
  field("KeptCells", static_cast<double>(sourceCell.size() - newCount));
  field("NewCells", static_cast<double>(newCount));
  field("InputNodes", static_cast<double>(nPoints));
  field("OutputNodes", static_cast<double>(nOut));
  field("NewNodes", static_cast<double>(nOut - keptPoints));
  field("RemovedNodes", static_cast<double>(result.RemovedNodes));
  field("SurfaceTriangles", static_cast<double>(result.Surface.size() / 3));
  field("SurfaceTrianglesAtLockedCells", static_cast<double>(result.SurfaceTrianglesAtLockedCells));
  field("SurfaceEdgeLength", edge);
  vtkEmbeddedRemeshAddSizeFields(output, edge, inputSize, vtkEmbeddedRemeshOutputSizeAtSurface(result));
  vtkEmbeddedRemeshAddLayerFields(output, options.Layers, static_cast<double>(result.LimitedColumns));
  vtkEmbeddedRemeshAddQualityFields(output, quality);
  field("SecondsInput", secondsInput);
  field("SecondsSurfaceMeshing", secondsSurface);
  field("SecondsSetup", result.Seconds.Setup);
  field("SecondsRemoval", result.Seconds.Removal);
  field("SecondsCavity", result.Seconds.Cavity);
  field("SecondsLayers", result.Seconds.Layers);
  field("SecondsRefill", result.Seconds.Refill);
  field("RefillAttempts", result.RefillAttempts);
  field("SecondsAssembly", result.Seconds.Assembly);
  field("SecondsOutput", secondsOutput);
  field("SecondsInterpolation", secondsInterpolation);
  field("SecondsQuality", secondsQuality);
  field("RelativeVolumeChange",
    before.TotalVolume > 0.0 ? (volumeAfter - before.TotalVolume) / before.TotalVolume : 0.0);
  vtkNew<vtkCellArray> faces;
  for (std::size_t f = 0; f < result.Surface.size(); f += 3)
  {
    const vtkIdType tri[3] = { result.Surface[f], result.Surface[f + 1], result.Surface[f + 2] };
    faces->InsertNextCell(3, tri);
  }
  embedded->SetPoints(points);
  embedded->SetPolys(faces);
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
namespace
{
using Coord = std::array<double, 3>;
constexpr int TetFace[4][3] = { { 1, 2, 3 }, { 0, 3, 2 }, { 0, 1, 3 }, { 0, 2, 1 } };

/// Doubles from every rank, concatenated in rank order, on every rank.
std::vector<double> AllGatherDoubles(vtkMultiProcessController* ctrl, const std::vector<double>& local)
{
  vtkNew<vtkDoubleArray> send, recv;
  send->SetNumberOfTuples(static_cast<vtkIdType>(local.size()));
  std::copy(local.begin(), local.end(), send->GetPointer(0));
  ctrl->AllGatherV(send, recv);
  return std::vector<double>(recv->GetPointer(0), recv->GetPointer(0) + recv->GetNumberOfTuples());
}

/// Rank 0's doubles on every rank.
void BroadcastDoubles(vtkMultiProcessController* ctrl, std::vector<double>& data)
{
  vtkIdType n = static_cast<vtkIdType>(data.size());
  ctrl->Broadcast(&n, 1, 0);
  data.resize(n);
  if (n > 0)
  {
    ctrl->Broadcast(data.data(), n, 0);
  }
}
}

int vtkEmbeddedRemesh::RemeshDistributed(vtkUnstructuredGrid* input,
  const std::vector<vtkDataSet*>& surfaces, vtkUnstructuredGrid* output, vtkPolyData* embedded)
{
  vtkMultiProcessController* ctrl = vtkMultiProcessController::GetGlobalController();
  const int rank = ctrl->GetLocalProcessId();
  // Every failure is agreed on by all ranks before anyone returns, so that
  // the collective calls stay matched.
  std::string problem;
  auto failed = [&]() {
    double bad = problem.empty() ? 0.0 : 1.0;
    vtkARMeshKernels::AllReduceMax(&bad, 1);
    return bad > 0.0;
  };
  auto passThrough = [&]() {
    vtkErrorMacro(<< (problem.empty() ? std::string("EmbeddedRemesh failed on another rank.") : problem)
                  << " The input passes through unchanged.");
    output->ShallowCopy(input);
    return 1;
  };
  // ---- Coordinates and conformity of this rank's piece, as in serial (a
  // crack makes TetGen crash), agreed on by every rank: a crack on one rank
  // refuses the whole job.
  problem = CoordinatesAndConformity(input, surfaces);
  if (!problem.empty())
  {
    problem = "EmbeddedRemesh (rank " + std::to_string(rank) + "): " + problem;
  }
  if (failed())
  {
    return passThrough();
  }
  // ---- This rank's tetrahedra, owned and ghost (the ghosts complete l_v).
  const vtkIdType nPoints = input->GetNumberOfPoints();
  vtkUnsignedCharArray* ghosts = input->GetCellGhostArray();
  ar::TetMesh V;
  V.Points.resize(3 * nPoints);
  for (vtkIdType i = 0; i < nPoints; ++i)
  {
    input->GetPoint(i, &V.Points[3 * i]);
  }
  std::vector<vtkIdType> tetCell;
  std::vector<char> owned;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < input->GetNumberOfCells() && problem.empty(); ++c)
  {
    const bool ghost = ghosts && (ghosts->GetValue(c) & vtkDataSetAttributes::DUPLICATECELL);
    if (input->GetCellType(c) != VTK_TETRA)
    {
      const int type = input->GetCellType(c);
      problem = "EmbeddedRemesh under MPI takes tetrahedral meshes only (cell " + std::to_string(c) +
        " has type " + std::to_string(type) + "); remesh hybrid or patch-carrying meshes on one rank." +
        ((type == VTK_HEXAHEDRON || type == VTK_WEDGE) && this->TwoDimensional == TWO_DIMENSIONAL_AUTO
            ? " The 2-D mode (one-cell-deep meshes) runs on one rank only."
            : "");
      break;
    }
    input->GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < 4; ++k)
    {
      V.Tetrahedra.push_back(ids->GetId(k));
    }
    tetCell.push_back(c);
    owned.push_back(ghost ? 0 : 1);
  }
  if (problem.empty())
  {
    problem = vtkARInputChecks::NonFinitePoints(V.Points.data(), nPoints, "the volume mesh (this rank's piece)");
    for (std::size_t k = 0; k < surfaces.size() && problem.empty(); ++k)
    {
      const std::string what = "feature surface " + std::to_string(k) + " (the Surfaces input)";
      problem = vtkARInputChecks::NonFinitePoints(surfaces[k], what.c_str());
    }
    if (!problem.empty())
    {
      problem = "EmbeddedRemesh: " + problem.substr(0, problem.size() - 1);
    }
  }
  if (failed())
  {
    return passThrough();
  }
  const std::size_t nT = tetCell.size();
  double nOwned = static_cast<double>(std::count(owned.begin(), owned.end(), 1));
  vtkARMeshKernels::AllReduceSum(&nOwned, 1);
  if (nOwned == 0)
  {
    problem = "The volume mesh is empty.";
    return passThrough();
  }

  // ---- S: the surface pieces gathered to rank 0, merged there.
  vtkNew<vtkAppendPolyData> append;
  AddSurfaceTriangles(surfaces, append);
  vtkNew<vtkPolyData> localSurface;
  if (append->GetNumberOfInputConnections(0) > 0)
  {
    append->Update();
    localSurface->ShallowCopy(append->GetOutput());
  }
  vtkSmartPointer<vtkPolyData> gathered = vtkARMeshKernels::GatherPolyData(localSurface, 0.0, false);
  std::vector<double> sPoints, sTris; // triangles as doubles, for the broadcast
  if (rank == 0 && gathered->GetNumberOfCells() > 0)
  {
    vtkNew<vtkStaticCleanPolyData> clean;
    clean->SetInputData(gathered);
    clean->SetTolerance(0.0);
    clean->Update();
    vtkPolyData* surface = clean->GetOutput();
    sPoints.resize(3 * surface->GetNumberOfPoints());
    for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
    {
      surface->GetPoint(i, &sPoints[3 * i]);
    }
    vtkIdType npts;
    const vtkIdType* pts;
    vtkCellArray* polys = surface->GetPolys();
    for (polys->InitTraversal(); polys->GetNextCell(npts, pts);)
    {
      if (npts == 3)
      {
        sTris.insert(sTris.end(), { double(pts[0]), double(pts[1]), double(pts[2]) });
      }
    }
  }
  BroadcastDoubles(ctrl, sPoints);
  BroadcastDoubles(ctrl, sTris);
  if (sTris.empty())
  {
    problem = "The feature surface is empty (no Surfaces connected, or none has triangles).";
    return passThrough();
  }
  this->UpdateProgress(0.1);

  // ---- l_v (complete at the nodes of owned cells, thanks to the ghosts).
  const std::vector<double> lv = ar::LongestEdgeAtNodes(V.Points.data(), nPoints, V.Tetrahedra.data(), nT);
  std::vector<char> ownedNode(nPoints, 0);
  for (std::size_t t = 0; t < nT; ++t)
  {
    for (int k = 0; owned[t] && k < 4; ++k)
    {
      ownedNode[V.Tetrahedra[4 * t + k]] = 1;
    }
  }

  // ---- The input's size at S: the median l_v at the mesh node nearest to
  // each S point (the nearest over all ranks' owned nodes), as in serial.
  double inputSize = 0.0;
  const std::size_t nS = sPoints.size() / 3;
  {
    vtkNew<vtkPoints> candidates;
    candidates->SetDataTypeToDouble();
    std::vector<vtkIdType> candidateNode;
    for (vtkIdType i = 0; i < nPoints; ++i)
    {
      if (ownedNode[i])
      {
        candidates->InsertNextPoint(&V.Points[3 * i]);
        candidateNode.push_back(i);
      }
    }
    std::vector<double> mine(2 * nS, 0.0); // squared distance, l_v
    if (!candidateNode.empty())
    {
      vtkNew<vtkPolyData> cloud;
      cloud->SetPoints(candidates);
      vtkNew<vtkStaticPointLocator> locator;
      locator->SetDataSet(cloud);
      locator->BuildLocator();
      for (std::size_t i = 0; i < nS; ++i)
      {
        const vtkIdType j = candidateNode[locator->FindClosestPoint(&sPoints[3 * i])];
        mine[2 * i] = vtkMath::Distance2BetweenPoints(&sPoints[3 * i], &V.Points[3 * j]);
        mine[2 * i + 1] = lv[j];
      }
    }
    else
    {
      for (std::size_t i = 0; i < nS; ++i)
      {
        mine[2 * i] = VTK_DOUBLE_MAX;
      }
    }
    const std::vector<double> all = AllGatherDoubles(ctrl, mine);
    std::vector<double> near;
    for (std::size_t i = 0; i < nS; ++i)
    {
      double best = VTK_DOUBLE_MAX, size = 0.0;
      for (std::size_t r = 0; r < all.size() / (2 * nS); ++r)
      {
        const double* e = &all[2 * (r * nS + i)];
        if (e[0] < best)
        {
          best = e[0];
          size = e[1];
        }
      }
      if (size > 0.0)
      {
        near.push_back(size);
      }
    }
    inputSize = ar::Median(std::move(near));
  }
  const double edge = this->SurfaceEdgeLength > 0.0 ? this->SurfaceEdgeLength : this->GetSurfaceSizeFactorUsed() * inputSize;
  if (!(edge > 0.0))
  {
    problem = "Could not find the mesh size near the feature surface; set SurfaceEdgeLength.";
    return passThrough();
  }
  {
    // The job's size (the same on every rank: S and the sums are global).
    double area = 0.0, diagonal = 0.0;
    SurfaceAreaAndDiagonal(sPoints, sTris, area, diagonal);
    double volume = 0.0;
    for (std::size_t t = 0; t < nT; ++t)
    {
      if (owned[t])
      {
        const std::int64_t* q = &V.Tetrahedra[4 * t];
        const double* x = V.Points.data();
        volume += std::abs(ar::TetSignedVolume(x + 3 * q[0], x + 3 * q[1], x + 3 * q[2], x + 3 * q[3]));
      }
    }
    vtkARMeshKernels::AllReduceSum(&volume, 1);
    if (!vtkEmbeddedRemeshJobFits(this, 3, area, diagonal, edge, inputSize, volume, nOwned, problem))
    {
      return passThrough(); // the same verdict on every rank
    }
  }

  // ---- S remeshed on rank 0, sent to every rank.
  std::vector<double> rPoints;
  std::vector<std::int64_t> rTris;
  std::vector<double> rTrisD;
  std::string error;
  if (rank == 0)
  {
    std::vector<std::int64_t> tris(sTris.begin(), sTris.end());
    if (!ar::RemeshSurfaceIsotropic(sPoints, tris, edge, rPoints, rTris, error))
    {
      vtkWarningMacro(<< "The feature surface is used as it is (not remeshed): " << error);
      rPoints = sPoints;
      rTris = tris;
    }
    rTrisD.assign(rTris.begin(), rTris.end());
  }
  BroadcastDoubles(ctrl, rPoints);
  BroadcastDoubles(ctrl, rTrisD);
  rTris.assign(rTrisD.begin(), rTrisD.end());
  this->UpdateProgress(0.3);

  // ---- The domain boundary: owned faces with no neighbour among this
  // rank's owned and ghost cells, from every rank.
  std::vector<double> boundary;
  {
    std::map<std::array<std::int64_t, 3>, std::pair<int, std::size_t>> faces; // count, 4 t + f
    for (std::size_t t = 0; t < nT; ++t)
    {
      for (int f = 0; f < 4; ++f)
      {
        std::array<std::int64_t, 3> key;
        for (int k = 0; k < 3; ++k)
        {
          key[k] = V.Tetrahedra[4 * t + TetFace[f][k]];
        }
        std::sort(key.begin(), key.end());
        auto& e = faces[key];
        ++e.first;
        e.second = 4 * t + f;
      }
    }
    std::vector<double> mine;
    for (const auto& e : faces)
    {
      const std::size_t t = e.second.second / 4;
      const int f = static_cast<int>(e.second.second % 4);
      if (e.second.first == 1 && owned[t])
      {
        for (int k = 0; k < 3; ++k)
        {
          const double* x = &V.Points[3 * V.Tetrahedra[4 * t + TetFace[f][k]]];
          mine.insert(mine.end(), x, x + 3);
        }
      }
    }
    boundary = AllGatherDoubles(ctrl, mine);
  }

  // ---- Removal flags at this rank's nodes; the cavity: owned cells at removed nodes.
  ar::CavityOptions options;
  options.RemovalFactor = this->RemovalFactor;
  options.VisibilityTest = this->VisibilityTest;
  options.BoundaryMargin = this->BoundaryMargin;
  options.Quality.MaxRadiusEdgeRatio = this->MaxRadiusEdgeRatio;
  options.Quality.MinDihedralAngle = this->MinDihedralAngle;
  if (!LayerOptionsOf(this, edge, options.Layers, problem))
  {
    return passThrough(); // the same properties on every rank: all refuse
  }
  options.BoundaryTriangles = boundary;
  // FullDomain: every node goes, so the whole mesh is gathered to rank 0
  // (TetGen is serial) and remeshed there.
  options.FullDomain = this->Mode == FULL_DOMAIN;
  std::vector<std::uint8_t> removed;
  if (!ar::ComputeRemovedNodes(V, rPoints.data(), rPoints.size() / 3, rTris.data(), rTris.size() / 3,
        options, removed, error))
  {
    problem = "EmbeddedRemesh: " + error;
  }
  if (failed())
  {
    return passThrough();
  }
  std::vector<char> cavity(nT, 0), selected(nT, 0);
  for (std::size_t t = 0; t < nT; ++t)
  {
    for (int k = 0; owned[t] && k < 4; ++k)
    {
      cavity[t] = cavity[t] || removed[V.Tetrahedra[4 * t + k]];
    }
  }
  double nCavity = static_cast<double>(std::count(cavity.begin(), cavity.end(), 1));
  vtkARMeshKernels::AllReduceSum(&nCavity, 1);
  if (nCavity == 0)
  {
    problem = "EmbeddedRemesh: no node of the volume mesh lies near the feature surface: nothing to remesh.";
    return passThrough();
  }
  // Three node rings of kept cells around it, over all ranks (by coordinates):
  // the refill may grow the cavity twice at forced slivers and needs the
  // cells around the grown cavity's nodes.
  selected = cavity;
  for (int ring = 0; ring < 3; ++ring)
  {
    std::vector<char> mark(nPoints, 0);
    std::vector<double> mine;
    for (std::size_t t = 0; t < nT; ++t)
    {
      for (int k = 0; selected[t] && k < 4; ++k)
      {
        const std::int64_t v = V.Tetrahedra[4 * t + k];
        if (!mark[v])
        {
          mark[v] = 1;
          mine.insert(mine.end(), &V.Points[3 * v], &V.Points[3 * v] + 3);
        }
      }
    }
    const std::vector<double> all = AllGatherDoubles(ctrl, mine);
    std::set<Coord> nodes;
    for (std::size_t k = 0; k < all.size(); k += 3)
    {
      nodes.insert(Coord{ all[k], all[k + 1], all[k + 2] });
    }
    for (vtkIdType v = 0; v < nPoints; ++v)
    {
      mark[v] = nodes.count(Coord{ V.Points[3 * v], V.Points[3 * v + 1], V.Points[3 * v + 2] }) ? 1 : 0;
    }
    for (std::size_t t = 0; t < nT; ++t)
    {
      for (int k = 0; owned[t] && !selected[t] && k < 4; ++k)
      {
        selected[t] = mark[V.Tetrahedra[4 * t + k]];
      }
    }
  }

  // ---- The selected cells (with their fields) to rank 0.
  vtkNew<vtkUnstructuredGrid> tagged;
  tagged->ShallowCopy(input);
  vtkNew<vtkUnsignedCharArray> cavityArray;
  cavityArray->SetName("ARCavity");
  cavityArray->SetNumberOfTuples(input->GetNumberOfCells());
  cavityArray->FillValue(0);
  vtkNew<vtkIdTypeArray> source;
  source->SetName("ARSource"); // rank, cell
  source->SetNumberOfComponents(2);
  source->SetNumberOfTuples(input->GetNumberOfCells());
  vtkNew<vtkIdList> pick;
  for (std::size_t t = 0; t < nT; ++t)
  {
    cavityArray->SetValue(tetCell[t], cavity[t]);
    source->SetTypedComponent(tetCell[t], 0, rank);
    source->SetTypedComponent(tetCell[t], 1, tetCell[t]);
    if (selected[t])
    {
      pick->InsertNextId(tetCell[t]);
    }
  }
  tagged->GetCellData()->AddArray(cavityArray);
  tagged->GetCellData()->AddArray(source);
  tagged->GetCellData()->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  tagged->GetPointData()->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  vtkNew<vtkExtractCells> extract;
  extract->SetInputData(tagged);
  extract->SetCellList(pick);
  extract->Update();
  vtkNew<vtkUnstructuredGrid> part;
  part->ShallowCopy(extract->GetOutput());
  part->GetPointData()->RemoveArray("vtkOriginalPointIds");
  part->GetCellData()->RemoveArray("vtkOriginalCellIds");
  std::vector<vtkSmartPointer<vtkDataObject>> parts;
  ctrl->Gather(part, parts, 0);

  // ---- Rank 0 refills the gathered cavity.
  vtkNew<vtkUnstructuredGrid> G; // the gathered cells, points merged
  ar::CavityRemesh result;
  std::vector<double> removedCells; // rank, cell of every gathered cell that goes
  if (rank == 0)
  {
    vtkNew<vtkAppendFilter> merge;
    merge->MergePointsOn();
    merge->SetTolerance(0.0);
    for (auto& piece : parts)
    {
      auto* grid = vtkUnstructuredGrid::SafeDownCast(piece);
      if (grid && grid->GetNumberOfCells() > 0)
      {
        merge->AddInputData(grid);
      }
    }
    merge->Update();
    G->ShallowCopy(merge->GetOutput());
    ar::TetMesh gathered;
    gathered.Points.resize(3 * G->GetNumberOfPoints());
    for (vtkIdType i = 0; i < G->GetNumberOfPoints(); ++i)
    {
      G->GetPoint(i, &gathered.Points[3 * i]);
    }
    auto* flags = vtkUnsignedCharArray::SafeDownCast(G->GetCellData()->GetArray("ARCavity"));
    for (vtkIdType c = 0; c < G->GetNumberOfCells(); ++c)
    {
      G->GetCellPoints(c, ids);
      for (vtkIdType k = 0; k < 4; ++k)
      {
        gathered.Tetrahedra.push_back(ids->GetId(k));
      }
      options.CavityCells.push_back(flags ? flags->GetValue(c) : 0);
    }
    if (!ar::RemeshLocalCavity(gathered, rPoints.data(), rPoints.size() / 3, rTris.data(),
          rTris.size() / 3, options, result, error))
    {
      problem = "EmbeddedRemesh: " + error;
    }
    else
    {
      std::vector<char> kept(G->GetNumberOfCells(), 0);
      for (std::int64_t c : result.SourceCell)
      {
        if (c >= 0)
        {
          kept[c] = 1;
        }
      }
      auto* src = vtkIdTypeArray::SafeDownCast(G->GetCellData()->GetArray("ARSource"));
      for (vtkIdType c = 0; c < G->GetNumberOfCells(); ++c)
      {
        if (!kept[c])
        {
          removedCells.push_back(static_cast<double>(src->GetTypedComponent(c, 0)));
          removedCells.push_back(static_cast<double>(src->GetTypedComponent(c, 1)));
        }
      }
    }
  }
  if (failed())
  {
    return passThrough();
  }
  BroadcastDoubles(ctrl, removedCells);
  this->UpdateProgress(0.8);

  // ---- Output: this rank's kept owned cells; rank 0 adds the new ones.
  std::vector<char> gone(input->GetNumberOfCells(), 0);
  for (std::size_t k = 0; k < removedCells.size(); k += 2)
  {
    if (static_cast<int>(removedCells[k]) == rank)
    {
      gone[static_cast<vtkIdType>(removedCells[k + 1])] = 1;
    }
  }
  std::vector<vtkIdType> outOfInput(nPoints, -1);
  std::vector<vtkIdType> pointSource; // input point of each output point, -1: from G (rank 0)
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (std::size_t t = 0; t < nT; ++t)
  {
    for (int k = 0; owned[t] && !gone[tetCell[t]] && k < 4; ++k)
    {
      const std::int64_t v = V.Tetrahedra[4 * t + k];
      if (outOfInput[v] < 0)
      {
        outOfInput[v] = 0;
      }
    }
  }
  std::map<Coord, vtkIdType> byCoord;
  for (vtkIdType v = 0; v < nPoints; ++v)
  {
    if (outOfInput[v] == 0)
    {
      outOfInput[v] = points->InsertNextPoint(&V.Points[3 * v]);
      pointSource.push_back(v);
      if (rank == 0)
      {
        byCoord[Coord{ V.Points[3 * v], V.Points[3 * v + 1], V.Points[3 * v + 2] }] = outOfInput[v];
      }
    }
  }
  // Rank 0: the result's points in the output (kept input points by
  // coordinates, the others appended with their G point or -1 when new).
  std::vector<vtkIdType> outOfResult(result.SourcePoint.size(), -1), gSource;
  double newNodes = 0.0; // points of the refill that are no input point (rank 0)
  std::vector<char> needed(result.SourcePoint.size(), 0);
  for (std::size_t t = 0; t < result.SourceCell.size(); ++t)
  {
    for (int k = 0; result.SourceCell[t] < 0 && k < 4; ++k)
    {
      needed[result.Mesh.Tetrahedra[4 * t + k]] = 1;
    }
  }
  for (const std::int64_t id : result.Prisms)
  {
    needed[id] = 1;
  }
  for (const std::int64_t id : result.Pyramids)
  {
    needed[id] = 1;
  }
  const vtkIdType nInputOut = points->GetNumberOfPoints();
  for (std::size_t i = 0; i < result.SourcePoint.size(); ++i)
  {
    if (!needed[i])
    {
      continue;
    }
    const double* x = &result.Mesh.Points[3 * i];
    auto it = byCoord.find(Coord{ x[0], x[1], x[2] });
    if (it != byCoord.end())
    {
      outOfResult[i] = it->second;
      continue;
    }
    outOfResult[i] = points->InsertNextPoint(x);
    gSource.push_back(result.SourcePoint[i]);
    newNodes += result.SourcePoint[i] < 0 ? 1.0 : 0.0;
  }
  const vtkIdType nOut = points->GetNumberOfPoints();

  output->Initialize();
  output->GetFieldData()->ShallowCopy(input->GetFieldData());
  output->SetPoints(points);
  output->Allocate(static_cast<vtkIdType>(nT + result.SourceCell.size()));
  std::vector<vtkIdType> cellSource; // input cell of each output cell; -1: new
  vtkNew<vtkIntArray> region, layer, side;
  region->SetName("Region"); // 0 kept, 1 new tetrahedron of the refill, 2 layer cell
  layer->SetName("Layer");
  side->SetName("LayerSide");
  double kept = 0.0;                // kept cells
  double volumes[2] = { 0.0, 0.0 }; // before, after
  auto addCell = [&](int type, const vtkIdType* pts, vtkIdType src, int k, int s) {
    const ar::CellShape shape = type == VTK_TETRA ? ar::CellShape::Tetrahedron
      : type == VTK_WEDGE                         ? ar::CellShape::Wedge
                                                  : ar::CellShape::Pyramid;
    const int n = static_cast<int>(shape);
    output->InsertNextCell(type, n, pts);
    double x[6 * 3];
    for (int j = 0; j < n; ++j)
    {
      points->GetPoint(pts[j], x + 3 * j);
    }
    region->InsertNextValue(src >= 0 ? 0 : k >= 0 ? 2 : 1);
    layer->InsertNextValue(k);
    side->InsertNextValue(s);
    cellSource.push_back(src);
    volumes[1] += ar::CellVolume(shape, x);
    kept += src >= 0 ? 1.0 : 0.0;
  };
  auto addTet = [&](const vtkIdType pts[4], vtkIdType src, int k = -1, int s = 0) {
    addCell(VTK_TETRA, pts, src, k, s);
  };
  for (std::size_t t = 0; t < nT; ++t)
  {
    if (!owned[t])
    {
      continue;
    }
    const std::int64_t* v = &V.Tetrahedra[4 * t];
    volumes[0] += ar::TetSignedVolume(&V.Points[3 * v[0]], &V.Points[3 * v[1]], &V.Points[3 * v[2]], &V.Points[3 * v[3]]);
    if (gone[tetCell[t]])
    {
      continue;
    }
    const vtkIdType pts[4] = { outOfInput[v[0]], outOfInput[v[1]], outOfInput[v[2]], outOfInput[v[3]] };
    addTet(pts, tetCell[t]);
  }
  std::vector<vtkIdType> newCellOfResult(result.SourceCell.size(), -1);
  for (std::size_t t = 0; t < result.SourceCell.size(); ++t)
  {
    if (result.SourceCell[t] < 0)
    {
      const std::int64_t* v = &result.Mesh.Tetrahedra[4 * t];
      const vtkIdType pts[4] = { outOfResult[v[0]], outOfResult[v[1]], outOfResult[v[2]], outOfResult[v[3]] };
      newCellOfResult[t] = static_cast<vtkIdType>(cellSource.size());
      const bool closure = !result.TetrahedronLayer.empty() && result.TetrahedronLayer[t] >= 0;
      addTet(pts, -1, closure ? result.TetrahedronLayer[t] : -1, closure ? result.TetrahedronSide[t] : 0);
    }
  }
  for (std::size_t p = 0; p < result.Prisms.size() / 6; ++p)
  {
    vtkIdType pts[6];
    for (int k = 0; k < 6; ++k)
    {
      pts[k] = outOfResult[result.Prisms[6 * p + k]];
    }
    addCell(VTK_WEDGE, pts, -1, result.PrismLayer[p], result.PrismSide[p]);
  }
  for (std::size_t p = 0; p < result.Pyramids.size() / 5; ++p)
  {
    vtkIdType pts[5];
    for (int k = 0; k < 5; ++k)
    {
      pts[k] = outOfResult[result.Pyramids[5 * p + k]];
    }
    addCell(VTK_PYRAMID, pts, -1, result.PyramidLayer[p], result.PyramidSide[p]);
  }

  // ---- Fields: kept points and cells copy theirs; new ones interpolate in
  // the gathered cavity cells (rank 0), as the serial run does in the input.
  if (this->InterpolateFields)
  {
    vtkPointData* inPD = input->GetPointData();
    vtkCellData* inCD = input->GetCellData();
    vtkPointData* outPD = output->GetPointData();
    vtkCellData* outCD = output->GetCellData();
    vtkDataSetAttributes::FieldList pointList(rank == 0 ? 2 : 1), cellList(rank == 0 ? 2 : 1);
    pointList.InitializeFieldList(inPD);
    cellList.InitializeFieldList(inCD);
    if (rank == 0)
    {
      pointList.IntersectFieldList(G->GetPointData());
      cellList.IntersectFieldList(G->GetCellData());
    }
    const auto nCellsOut = static_cast<vtkIdType>(cellSource.size());
    outPD->InterpolateAllocate(pointList, nOut);
    outCD->CopyAllocate(cellList, nCellsOut);
    // Each output tuple from the input (kept points and cells: list index
    // 0) or from G (rank 0's new ones: index 1), as the serial run does.
    vtkARMeshKernels::TupleSources pointsFromInput(nOut, 1), pointsFromG(nOut, 4);
    vtkARMeshKernels::TupleSources cellsFromInput(nCellsOut, 1), cellsFromG(nCellsOut, 1);
    for (vtkIdType i = 0; i < nInputOut; ++i)
    {
      pointsFromInput.Copy(i, pointSource[i]);
    }
    vtkARMeshKernels::TetLocator locator;
    if (rank == 0 && G->GetNumberOfCells() > 0)
    {
      locator.Build(G);
    }
    // The new points (no G point) located in G's tetrahedra ...
    std::vector<vtkIdType> newPoint, queryOf(nOut, -1);
    for (vtkIdType i = nInputOut; i < nOut; ++i)
    {
      const std::int64_t g = gSource[i - nInputOut];
      if (g >= 0)
      {
        pointsFromG.Copy(i, g);
      }
      else
      {
        queryOf[i] = static_cast<vtkIdType>(newPoint.size());
        newPoint.push_back(i);
      }
    }
    const auto nNewPoints = static_cast<vtkIdType>(newPoint.size());
    std::vector<double> where(3 * newPoint.size()), weights(4 * newPoint.size());
    std::vector<vtkIdType> pointIn(newPoint.size());
    for (vtkIdType q = 0; q < nNewPoints; ++q)
    {
      points->GetPoint(newPoint[q], &where[3 * q]);
    }
    locator.Locate(nNewPoints, where.data(), nullptr, pointIn.data(), weights.data());
    for (vtkIdType q = 0; q < nNewPoints; ++q)
    {
      pointsFromG.Interpolate(newPoint[q], locator.CellPoints(pointIn[q]), &weights[4 * q]);
    }
    // ... and the new cells' centres, walked to from a corner's tetrahedron.
    std::vector<vtkIdType> newCell;
    for (vtkIdType k = 0; k < nCellsOut; ++k)
    {
      if (cellSource[k] >= 0)
      {
        cellsFromInput.Copy(k, cellSource[k]);
      }
      else
      {
        newCell.push_back(k);
      }
    }
    const auto nNewCells = static_cast<vtkIdType>(newCell.size());
    std::vector<double> centres(3 * newCell.size());
    std::vector<vtkIdType> starts(newCell.size(), -1), cellIn(newCell.size());
    vtkNew<vtkIdList> corners;
    for (vtkIdType q = 0; q < nNewCells; ++q)
    {
      vtkIdType npts;
      const vtkIdType* pts;
      output->GetCellPoints(newCell[q], npts, pts, corners);
      double* centre = &centres[3 * q];
      for (vtkIdType j = 0; j < npts; ++j)
      {
        double x[3];
        points->GetPoint(pts[j], x);
        for (int d = 0; d < 3; ++d)
        {
          centre[d] += x[d] / static_cast<double>(npts);
        }
        if (starts[q] < 0 && pts[j] >= nInputOut)
        {
          starts[q] = queryOf[pts[j]] >= 0 ? pointIn[queryOf[pts[j]]]
                                           : locator.CellOfPoint(gSource[pts[j] - nInputOut]);
        }
      }
    }
    locator.Locate(nNewCells, centres.data(), starts.data(), cellIn.data(), nullptr);
    for (vtkIdType q = 0; q < nNewCells; ++q)
    {
      cellsFromG.Copy(newCell[q], cellIn[q]);
    }
    vtkARMeshKernels::TransferData(pointList, 0, inPD, outPD, pointsFromInput);
    vtkARMeshKernels::TransferData(cellList, 0, inCD, outCD, cellsFromInput);
    if (rank == 0)
    {
      vtkARMeshKernels::TransferData(pointList, 1, G->GetPointData(), outPD, pointsFromG);
      vtkARMeshKernels::TransferData(cellList, 1, G->GetCellData(), outCD, cellsFromG);
    }
    outPD->RemoveArray(vtkDataSetAttributes::GhostArrayName());
    outCD->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  }
  output->GetCellData()->AddArray(region);
  output->GetCellData()->AddArray(layer);
  output->GetCellData()->AddArray(side);
  vtkEmbeddedRemeshQuality quality = vtkEmbeddedRemeshAddQualityArrays(output, region);

  // ---- Field data, equal on every rank and to the serial run's.
  double surfaceTriangles = static_cast<double>(result.Surface.size() / 3);
  double removedNodes = static_cast<double>(result.RemovedNodes);
  double limited = static_cast<double>(result.LimitedColumns);
  vtkEmbeddedRemeshReduceQuality(quality);
  vtkARMeshKernels::AllReduceSum(&kept, 1);
  vtkARMeshKernels::AllReduceSum(&limited, 1);
  vtkARMeshKernels::AllReduceSum(volumes, 2);
  vtkARMeshKernels::AllReduceSum(&surfaceTriangles, 1);
  vtkARMeshKernels::AllReduceSum(&removedNodes, 1);
  // The node counts, as the serial run gives them: the input's nodes, each
  // counted by the rank that owns it (not a ghost copy of another rank's
  // point); every node not removed is kept, so the output has the input's
  // less the removed ones plus the new ones.
  double inputNodes = 0.0;
  {
    vtkUnsignedCharArray* pointGhosts = input->GetPointGhostArray();
    for (vtkIdType v = 0; v < nPoints; ++v)
    {
      inputNodes += pointGhosts && (pointGhosts->GetValue(v) & vtkDataSetAttributes::DUPLICATEPOINT) ? 0.0 : 1.0;
    }
  }
  vtkARMeshKernels::AllReduceSum(&inputNodes, 1);
  vtkARMeshKernels::AllReduceSum(&newNodes, 1);
  auto field = [&](const char* name, double value) {
    output->GetFieldData()->AddArray(vtkARMeshKernels::FieldArray(name, &value, 1));
  };
  field("InputNodes", inputNodes);
  field("NewNodes", newNodes);
  field("OutputNodes", inputNodes - removedNodes + newNodes);
  field("KeptCells", kept);
  field("NewCells", quality.NewCells + quality.NewPrisms + quality.NewPyramids + quality.NewLayerTetrahedra);
  field("RemovedNodes", removedNodes);
  field("SurfaceTriangles", surfaceTriangles);
  field("SurfaceEdgeLength", edge);
  double outputSize = vtkEmbeddedRemeshOutputSizeAtSurface(result); // S and the new cells are on rank 0; 0 elsewhere
  vtkARMeshKernels::AllReduceMax(&outputSize, 1);
  vtkEmbeddedRemeshAddSizeFields(output, edge, inputSize, outputSize);
  vtkEmbeddedRemeshAddLayerFields(output, options.Layers, limited);
  vtkEmbeddedRemeshAddQualityFields(output, quality);
  field("RelativeVolumeChange", volumes[0] > 0.0 ? (volumes[1] - volumes[0]) / volumes[0] : 0.0);
  vtkNew<vtkCellArray> faces;
  for (std::size_t f = 0; f < result.Surface.size(); f += 3)
  {
    const vtkIdType tri[3] = { outOfResult[result.Surface[f]], outOfResult[result.Surface[f + 1]],
      outOfResult[result.Surface[f + 2]] };
    faces->InsertNextCell(3, tri);
  }
  if (rank == 0)
  {
    embedded->SetPoints(points);
  }
  else
  {
    vtkNew<vtkPoints> none;
    embedded->SetPoints(none);
  }
  embedded->SetPolys(faces);
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
