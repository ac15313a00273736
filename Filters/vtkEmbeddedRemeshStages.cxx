// SPDX-License-Identifier: BSD-3-Clause
// The stages vtkEmbeddedRemesh's three drivers share (vtkEmbeddedRemeshStages.h).
#include "vtkEmbeddedRemeshStages.h"
#include "vtkEmbeddedRemesh.h"

#include "ARCavity.h"
#include "ARCavity2D.h"
#include "ARCellQuality.h"
#include "ARHugePages.h"
#include "ARMeshSize.h"
#include "ARPrismLayers.h"
#include "ARSurfaceRemesh.h"
#include "ARTetGeometry.h"
#include "vtkARInputChecks.h"
#include "vtkARMeshKernels.h"
#include "vtkARParallel.h"
#include "vtkARFieldTransfer.h"

#include "vtkAlgorithm.h"
#include "vtkAppendPolyData.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkGeometryFilter.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkMath.h"
#include "vtkMultiProcessController.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPThreadLocalObject.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkStaticCleanPolyData.h"
#include "vtkStaticPointLocator.h"
#include "vtkTriangleFilter.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <new>
#include <sstream>

namespace
{
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
std::string vtkEmbeddedRemeshFailure(const std::exception& e)
{
  if (dynamic_cast<const std::bad_alloc*>(&e))
  {
    return "EmbeddedRemesh ran out of memory (std::bad_alloc) while remeshing; raise SurfaceEdgeLength "
           "(or SurfaceSizeFactor), or remesh a smaller region (LocalCavity, a lower RemovalFactor).";
  }
  return std::string("EmbeddedRemesh failed: ") + e.what() + ".";
}

//------------------------------------------------------------------------------
/// NaN/Inf coordinates in the volume or a surface, or duplicated points (a
/// crack) in the volume: the problem (empty when there is none), checked
/// before any mesher sees the mesh (TetGen fails on, or corrupts its heap
/// with, a crack).
std::string vtkEmbeddedRemeshCheckCoordinates(vtkUnstructuredGrid* input, const std::vector<vtkDataSet*>& surfaces)
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

void vtkEmbeddedRemeshSurfaceAreaAndDiagonal(const vtkEmbeddedRemeshSoup& soup, double& area, double& diagonal)
{
  const std::vector<double>& points = soup.Points;
  const std::vector<std::int64_t>& tris = soup.Triangles;
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

//------------------------------------------------------------------------------
double vtkEmbeddedRemeshIdealStepLength(double edge, double layer, bool twoDimensional)
{
  if (!(edge > 0.0))
  {
    return 0.0;
  }
  // Built and measured as the output's cells are. 3-D: the regular
  // tetrahedron of edge e, the right prism over the equilateral triangle of
  // side e, `layer` high; 2-D (depth along z, left out): the equilateral
  // triangle, the e x layer rectangle.
  const double h = std::sqrt(3.0) / 2.0, e = edge, t = layer;
  if (t <= 0.0)
  {
    if (twoDimensional)
    {
      const double prism[18] = { 0, 0, 0, 0.5 * e, h * e, 0, e, 0, 0, 0, 0, e, 0.5 * e, h * e, e, e, 0, e };
      return ar::CellStepLength(ar::CellShape::Wedge, prism, 2);
    }
    const double tet[12] = { 0, 0, 0, e, 0, 0, 0.5 * e, h * e, 0, 0.5 * e, h * e / 3.0, e * std::sqrt(2.0 / 3.0) };
    return ar::CellStepLength(ar::CellShape::Tetrahedron, tet);
  }
  if (twoDimensional)
  {
    const double hex[24] = { 0, 0, 0, e, 0, 0, e, t, 0, 0, t, 0, 0, 0, e, e, 0, e, e, t, e, 0, t, e };
    return ar::CellStepLength(ar::CellShape::Hexahedron, hex, 2);
  }
  const double prism[18] = { 0, 0, 0, 0.5 * e, h * e, 0, e, 0, 0, 0, 0, t, 0.5 * e, h * e, t, e, 0, t };
  return ar::CellStepLength(ar::CellShape::Wedge, prism);
}

//------------------------------------------------------------------------------
vtkEmbeddedRemeshQuality vtkEmbeddedRemeshAddQualityArrays(
  vtkUnstructuredGrid* output, vtkIntArray* region, int depthAxis)
{
  const vtkIdType n = output->GetNumberOfCells();
  vtkNew<vtkDoubleArray> minAngle, maxAngle, aspect;
  minAngle->SetName("MinDihedralAngle");
  maxAngle->SetName("MaxDihedralAngle");
  aspect->SetName("AspectRatio");
  for (vtkDoubleArray* a : { minAngle.Get(), maxAngle.Get(), aspect.Get() })
  {
    a->SetNumberOfTuples(n);
    vtkARParallel::AdviseHugePages(a);
  }
  // On threads (vtkSMPTools) over fixed blocks of 20000 cells; the sums are
  // combined in block order, so the result depends neither on timing nor on
  // the number of threads.
  const vtkIdType blockSize = 20000;
  const vtkIdType nBlocks = (n + blockSize - 1) / blockSize;
  std::vector<vtkEmbeddedRemeshQuality> partial(static_cast<std::size_t>(nBlocks));
  // The output's points are doubles (the drivers make them so): read in place.
  vtkDoubleArray* xyz = vtkDoubleArray::SafeDownCast(output->GetPoints()->GetData());
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
        const vtkIdType p = pts[type == VTK_VOXEL ? voxelToHexahedron[k] : k];
        if (xyz)
        {
          std::copy(xyz->GetPointer(3 * p), xyz->GetPointer(3 * p) + 3, &x[3 * k]);
        }
        else
        {
          output->GetPoint(p, &x[3 * k]);
        }
      }
      const ar::CellQuality q = ar::ComputeCellQuality(shape, x, false); // (the scaled Jacobian is not reported)
      minAngle->SetValue(c, q.MinDihedralAngle);
      maxAngle->SetValue(c, q.MaxDihedralAngle);
      aspect->SetValue(c, q.AspectRatio);
      sums.NonPositiveJacobian += q.MinCornerJacobian > 0.0 ? 0.0 : 1.0;
      if (region->GetValue(c) != 0) // new cells only: the kept ones' steps are the input's
      {
        double& step = region->GetValue(c) == 1 ? sums.NewMinStep : sums.LayerMinStep;
        step = std::min(step, ar::CellStepLength(shape, x, depthAxis));
      }
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
    sums.NewMinStep = std::min(sums.NewMinStep, s.NewMinStep);
    sums.LayerMinStep = std::min(sums.LayerMinStep, s.LayerMinStep);
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

void vtkEmbeddedRemeshAddStepFields(vtkUnstructuredGrid* output, const vtkEmbeddedRemeshQuality& sums,
  double edge, const ar::PrismLayerOptions& layers, bool twoDimensional)
{
  auto field = [&](const char* name, double value) {
    output->GetFieldData()->AddArray(vtkARMeshKernels::FieldArray(name, &value, 1));
  };
  const bool anyNew = std::isfinite(sums.NewMinStep), anyLayer = std::isfinite(sums.LayerMinStep);
  field("StepLengthNew", anyNew ? sums.NewMinStep : 0.0);
  field("StepLengthLayerCells", anyLayer ? sums.LayerMinStep : 0.0);
  const double iso = vtkEmbeddedRemeshIdealStepLength(edge, 0.0, twoDimensional);
  field("StepLengthRatioNew", anyNew && iso > 0.0 ? sums.NewMinStep / iso : 0.0);
  std::vector<double> z;
  std::string unused;
  const bool on = layers.NumberOfLayers > 0 && ar::PrismLayerDistances(layers, z, unused);
  const double flat = on ? vtkEmbeddedRemeshIdealStepLength(edge, z[1], twoDimensional) : 0.0;
  field("StepLengthRatioLayerCells", anyLayer && flat > 0.0 ? sums.LayerMinStep / flat : 0.0);
}

void vtkEmbeddedRemeshReduceQuality(vtkEmbeddedRemeshQuality& q)
{
  double sums[8] = { q.NewCells, q.NewDihedralSum, q.NonPositiveJacobian, q.LayerCells, q.NewPrisms,
    q.NewPyramids, q.NewLayerTetrahedra, q.NewLayerHexahedra };
  double maxima[6] = { -q.NewMinDihedral, q.NewMaxAspectRatio, q.LayerMaxAspectRatio, -q.LayerMinDihedral,
    -q.NewMinStep, -q.LayerMinStep };
  vtkARParallel::AllReduceSum(sums, 8);
  vtkARParallel::AllReduceMax(maxima, 6);
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
  q.NewMinStep = -maxima[4];
  q.LayerMinStep = -maxima[5];
}

double vtkEmbeddedRemeshOutputSizeAtSurface(const ar::CavityRemesh& r)
{
  // l_v is read at S's nodes only: the cells without one of them (nearly
  // all of a large mesh) cannot change it and are skipped. (A maximum does
  // not depend on the order it is taken in: the value is the whole mesh's.)
  const std::size_t nPoints = r.Mesh.Points.size() / 3;
  std::vector<char> atSurface(nPoints, 0);
  for (const std::int64_t v : r.Surface)
  {
    atSurface[v] = 1;
  }
  std::vector<double> lv(nPoints, 0.0);
  auto accumulate = [&](ar::CellShape shape, const std::vector<std::int64_t>& cells) {
    const std::size_t nodes = static_cast<std::size_t>(ar::NumberOfNodes(shape));
    std::vector<std::int64_t> touching;
    for (std::size_t c = 0; c + nodes <= cells.size(); c += nodes)
    {
      if (std::any_of(&cells[c], &cells[c] + nodes, [&](std::int64_t v) { return atSurface[v] != 0; }))
      {
        touching.insert(touching.end(), &cells[c], &cells[c] + nodes);
      }
    }
    ar::AccumulateLongestEdges(shape, r.Mesh.Points.data(), touching.data(), touching.size() / nodes, lv);
  };
  accumulate(ar::CellShape::Tetrahedron, r.Mesh.Tetrahedra);
  accumulate(ar::CellShape::Wedge, r.Prisms);
  accumulate(ar::CellShape::Pyramid, r.Pyramids);
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
    who << "SurfaceSizeFactor is " << self->GetSurfaceSizeFactorUsed(dimension == 2) << " (S's edge length "
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
void vtkEmbeddedRemeshBroadcast(vtkEmbeddedRemeshSoup& soup)
{
  vtkARParallel::BroadcastFromRoot(soup.Points);
  vtkARParallel::BroadcastFromRoot(soup.Triangles);
}

//------------------------------------------------------------------------------
vtkEmbeddedRemeshSoup vtkEmbeddedRemeshCollectSurfaces(const std::vector<vtkDataSet*>& surfaces)
{
  vtkEmbeddedRemeshSoup soup;
  vtkNew<vtkAppendPolyData> append;
  AddSurfaceTriangles(surfaces, append);
  const bool distributed = vtkARParallel::NumberOfRanks() > 1;
  vtkSmartPointer<vtkPolyData> merged;
  if (distributed)
  {
    vtkNew<vtkPolyData> local;
    if (append->GetNumberOfInputConnections(0) > 0)
    {
      append->Update();
      local->ShallowCopy(append->GetOutput());
    }
    merged = vtkARParallel::GatherPolyData(local, 0.0, false); // rank 0 holds the union
  }
  else if (append->GetNumberOfInputConnections(0) > 0)
  {
    append->Update();
    merged = append->GetOutput();
  }
  if (merged && merged->GetNumberOfCells() > 0)
  {
    vtkNew<vtkStaticCleanPolyData> clean;
    clean->SetInputData(merged);
    clean->SetTolerance(0.0);
    clean->Update();
    vtkPolyData* surface = clean->GetOutput();
    soup.Points.resize(3 * surface->GetNumberOfPoints());
    for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
    {
      surface->GetPoint(i, &soup.Points[3 * i]);
    }
    vtkIdType npts;
    const vtkIdType* ids;
    vtkCellArray* polys = surface->GetPolys();
    for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
    {
      if (npts == 3)
      {
        soup.Triangles.insert(soup.Triangles.end(), { ids[0], ids[1], ids[2] });
      }
    }
  }
  if (distributed)
  {
    vtkARParallel::BroadcastFromRoot(soup.Points);
    vtkARParallel::BroadcastFromRoot(soup.Triangles);
  }
  return soup;
}

//------------------------------------------------------------------------------
double vtkEmbeddedRemeshInputSizeAt(const double* nodes, vtkIdType nNodes, int dim, const std::vector<double>& lv,
  const std::vector<char>* candidate, const double* query, std::size_t nQuery)
{
  vtkNew<vtkPoints> cloudPoints;
  cloudPoints->SetDataTypeToDouble();
  std::vector<vtkIdType> node; // cloud point -> node
  for (vtkIdType i = 0; i < nNodes; ++i)
  {
    if (!candidate || (*candidate)[i])
    {
      double x[3] = { 0.0, 0.0, 0.0 };
      std::copy(nodes + dim * i, nodes + dim * i + dim, x);
      cloudPoints->InsertNextPoint(x);
      node.push_back(i);
    }
  }
  // Per query point: the squared distance to the nearest candidate and l_v there.
  std::vector<double> mine(2 * nQuery, 0.0);
  for (std::size_t i = 0; i < nQuery; ++i)
  {
    mine[2 * i] = VTK_DOUBLE_MAX;
  }
  if (!node.empty())
  {
    vtkNew<vtkPolyData> cloud;
    cloud->SetPoints(cloudPoints);
    vtkNew<vtkStaticPointLocator> locator;
    locator->SetDataSet(cloud);
    locator->BuildLocator();
    for (std::size_t i = 0; i < nQuery; ++i)
    {
      double q[3] = { 0.0, 0.0, 0.0 };
      std::copy(query + dim * i, query + dim * i + dim, q);
      const vtkIdType j = locator->FindClosestPoint(q);
      if (j >= 0)
      {
        double x[3];
        cloudPoints->GetPoint(j, x);
        mine[2 * i] = vtkMath::Distance2BetweenPoints(q, x);
        mine[2 * i + 1] = lv[node[j]];
      }
    }
  }
  const std::vector<double> all = vtkARParallel::AllGather(mine); // rank order
  std::vector<double> near;
  for (std::size_t i = 0; i < nQuery; ++i)
  {
    double best = VTK_DOUBLE_MAX, size = 0.0;
    for (std::size_t r = 0; r < all.size() / (2 * nQuery); ++r)
    {
      const double* e = &all[2 * (r * nQuery + i)];
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
  return ar::Median(std::move(near));
}

//------------------------------------------------------------------------------
vtkEmbeddedRemeshSoup vtkEmbeddedRemeshRemeshSurface(vtkAlgorithm* self, const vtkEmbeddedRemeshSoup& s, double edge)
{
  vtkEmbeddedRemeshSoup r;
  std::string error;
  // (a large S in two pieces, side by side on the filter's threads)
  if (!ar::RemeshSurfaceIsotropic(
        s.Points, s.Triangles, edge, r.Points, r.Triangles, error, vtkSMPTools::GetEstimatedNumberOfThreads()))
  {
    vtkWarningWithObjectMacro(self, << "The feature surface is used as it is (not remeshed): " << error);
    r = s;
  }
  return r;
}

//------------------------------------------------------------------------------
namespace
{
template <typename Options>
void CommonCavityOptions(vtkEmbeddedRemesh* self, Options& options)
{
  options.RemovalFactor = self->GetRemovalFactor();
  options.VisibilityTest = self->GetVisibilityTest();
  options.BoundaryMargin = self->GetBoundaryMargin();
  options.FullDomain = self->GetMode() == vtkEmbeddedRemesh::FULL_DOMAIN;
}
}

bool vtkEmbeddedRemeshCavityOptions(
  vtkEmbeddedRemesh* self, double edge, ar::CavityOptions& options, std::string& problem)
{
  CommonCavityOptions(self, options);
  // The core's searches on as many threads as vtkSMPTools has here (the
  // filter's scope, vtkARMeshKernels::Threaded).
  options.Threads = vtkSMPTools::GetEstimatedNumberOfThreads();
  options.Quality.MaxRadiusEdgeRatio = self->GetMaxRadiusEdgeRatio();
  options.Quality.MinDihedralAngle = self->GetMinDihedralAngle();
  if (!vtkEmbeddedRemeshLayerOptions(self, edge, options.Layers, problem))
  {
    return false;
  }
  // Without layers the new cells at S should allow the time step of the
  // requested size: none under half the regular tetrahedron's step at S's
  // edge (the refill's points at smaller ones are moved). With layers the
  // layer cells set the step, by design.
  options.MinStepLength = options.Layers.NumberOfLayers > 0
    ? 0.0
    : vtkEmbeddedRemeshMinStepFraction * vtkEmbeddedRemeshIdealStepLength(edge, 0.0, false);
  return true;
}

bool vtkEmbeddedRemeshCavityOptions(
  vtkEmbeddedRemesh* self, double edge, ar::Cavity2DOptions& options, std::string& problem)
{
  CommonCavityOptions(self, options);
  options.MinAngle = self->GetMinTriangleAngle();
  return vtkEmbeddedRemeshLayerOptions(self, edge, options.Layers, problem);
}

//------------------------------------------------------------------------------
vtkEmbeddedRemeshCells::vtkEmbeddedRemeshCells(vtkUnstructuredGrid* output)
  : Output(output)
{
  this->Offsets->InsertNextValue(0);
  this->RegionArray->SetName("Region");
  this->LayerArray->SetName("Layer");
  this->SideArray->SetName("LayerSide");
}

vtkEmbeddedRemeshCells::~vtkEmbeddedRemeshCells() = default;

void vtkEmbeddedRemeshCells::Reserve(std::size_t cells, std::size_t points)
{
  const auto n = static_cast<vtkIdType>(cells);
  this->Types->Allocate(n);
  this->Offsets->Allocate(n + 1);
  this->Connectivity->Allocate(static_cast<vtkIdType>(points));
  this->RegionArray->Allocate(n);
  this->LayerArray->Allocate(n);
  this->SideArray->Allocate(n);
  for (vtkAbstractArray* a : std::initializer_list<vtkAbstractArray*>{ this->Types, this->Offsets,
         this->Connectivity, this->RegionArray, this->LayerArray, this->SideArray })
  {
    vtkARParallel::AdviseHugePages(a); // before the cells are written
  }
  this->Offsets->InsertNextValue(0);
  ar::ReserveHuge(this->Source, cells);
}

void vtkEmbeddedRemeshCells::Add(
  int type, vtkIdType n, const vtkIdType* pts, vtkIdType source, int region, int layer, int side, vtkPoints* points)
{
  if (points)
  {
    // The output's points are doubles (the drivers make them so): read them
    // in place, not point by point through vtkPoints::GetPoint.
    this->VolumeAfter += this->Volume(type, n, pts, static_cast<const double*>(points->GetVoidPointer(0)));
  }
  const vtkIdType c = this->AppendCells(1, n);
  std::copy(pts, pts + n, this->Connectivity->GetPointer(this->Offsets->GetValue(c)));
  this->Types->SetValue(c, static_cast<unsigned char>(type));
  this->Source.push_back(source);
  this->RegionArray->SetValue(c, region);
  this->LayerArray->SetValue(c, layer);
  this->SideArray->SetValue(c, side);
  this->NewCount += region > 0 ? 1 : 0;
}

void vtkEmbeddedRemeshCells::AddPolyhedron(vtkIdType source, vtkIdList* faces)
{
  // Its place (a type, no points) holds the order; Commit inserts the face
  // stream there, as vtkUnstructuredGrid derives the polyhedron's points
  // from it.
  vtkNew<vtkIdList> copy;
  copy->DeepCopy(faces);
  const vtkIdType c = this->AppendCells(1, 0);
  this->Polyhedra.emplace_back(c, copy);
  this->Types->SetValue(c, VTK_POLYHEDRON);
  this->Source.push_back(source);
  this->RegionArray->SetValue(c, 0);
  this->LayerArray->SetValue(c, -1);
  this->SideArray->SetValue(c, 0);
}

double vtkEmbeddedRemeshCells::Volume(int type, vtkIdType n, const vtkIdType* pts, const double* X) const
{
  if (type == VTK_TETRA)
  {
    return ar::TetSignedVolume(X + 3 * pts[0], X + 3 * pts[1], X + 3 * pts[2], X + 3 * pts[3]); // as ar::ComputeStatistics
  }
  const ar::CellShape shape = type == VTK_WEDGE ? ar::CellShape::Wedge : ar::CellShape::Pyramid;
  double x[6 * 3];
  for (vtkIdType j = 0; j < n; ++j)
  {
    std::copy(X + 3 * pts[j], X + 3 * pts[j] + 3, x + 3 * j);
  }
  return ar::CellVolume(shape, x);
}

namespace
{
/// `array` `extra` values longer, its capacity at least doubled when it
/// grows (vtkGenericDataArray::Resize), as InsertNextValue grows it.
template <typename A>
void Extend(A* array, vtkIdType extra)
{
  const vtkIdType n = array->GetNumberOfValues() + extra;
  if (n > array->GetSize())
  {
    array->Resize(n);
  }
  array->SetNumberOfValues(n);
}
}

vtkIdType vtkEmbeddedRemeshCells::AppendCells(vtkIdType count, vtkIdType points)
{
  // `count` cells of `points` points in all, after the last; their offsets
  // are the caller's to set but for one cell. Returns the first's index.
  const vtkIdType first = this->Types->GetNumberOfValues();
  const vtkIdType firstPoint = this->Connectivity->GetNumberOfValues();
  Extend(this->Types.Get(), count);
  Extend(this->Offsets.Get(), count);
  Extend(this->RegionArray.Get(), count);
  Extend(this->LayerArray.Get(), count);
  Extend(this->SideArray.Get(), count);
  Extend(this->Connectivity.Get(), points);
  if (count == 1)
  {
    this->Offsets->SetValue(first + 1, firstPoint + points);
  }
  return first;
}

void vtkEmbeddedRemeshCells::AddRefillTetrahedra(const ar::CavityRemesh& result,
  const std::vector<vtkIdType>* pointOf, const std::vector<vtkIdType>* keptSource, vtkPoints* points,
  const std::vector<char>* skipKept)
{
  // The result's tetrahedra to add, in order; each goes to its fixed place
  // (first + its index), so the threads' schedule changes nothing.
  std::vector<std::size_t> added;
  ar::ReserveHuge(added, result.SourceCell.size());
  for (std::size_t t = 0; t < result.SourceCell.size(); ++t)
  {
    const std::int64_t src = result.SourceCell[t];
    if (src < 0 || (keptSource && !(skipKept && (*skipKept)[src])))
    {
      added.push_back(t);
    }
  }
  const auto count = static_cast<vtkIdType>(added.size());
  const vtkIdType firstPoint = this->Connectivity->GetNumberOfValues();
  const vtkIdType first = this->AppendCells(count, 4 * count);
  this->Source.resize(this->Source.size() + added.size());
  std::vector<double> volume;
  ar::ResizeHuge(volume, points ? added.size() : 0);
  const double* X = points ? static_cast<const double*>(points->GetVoidPointer(0)) : nullptr;
  const bool layered = !result.TetrahedronLayer.empty();
  unsigned char* types = this->Types->GetPointer(0);
  vtkIdType* offsets = this->Offsets->GetPointer(0);
  int* region = this->RegionArray->GetPointer(0);
  int* layer = this->LayerArray->GetPointer(0);
  int* side = this->SideArray->GetPointer(0);
  vtkIdType* connectivity = this->Connectivity->GetPointer(0);
  vtkSMPTools::For(0, count, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType i = b; i < e; ++i)
    {
      const std::size_t t = added[i];
      const vtkIdType c = first + i;
      const std::int64_t src = result.SourceCell[t];
      const std::int64_t* v = &result.Mesh.Tetrahedra[4 * t];
      vtkIdType* pts = connectivity + firstPoint + 4 * i;
      for (int k = 0; k < 4; ++k)
      {
        pts[k] = pointOf ? (*pointOf)[v[k]] : static_cast<vtkIdType>(v[k]);
      }
      const int k = layered ? result.TetrahedronLayer[t] : -1;
      types[c] = VTK_TETRA;
      offsets[c + 1] = firstPoint + 4 * (i + 1);
      this->Source[c] = src >= 0 ? (*keptSource)[src] : -1;
      region[c] = src >= 0 ? 0 : k >= 0 ? 2 : 1;
      layer[c] = k;
      side[c] = k >= 0 ? result.TetrahedronSide[t] : 0;
      if (X)
      {
        volume[i] = this->Volume(VTK_TETRA, 4, pts, X);
      }
    }
  });
  for (vtkIdType i = 0; i < count; ++i) // in order, as the cells come
  {
    this->NewCount += region[first + i] > 0 ? 1 : 0;
    if (X)
    {
      this->VolumeAfter += volume[i];
    }
  }
}

void vtkEmbeddedRemeshCells::AddRefillLayers(
  const ar::CavityRemesh& result, const std::vector<vtkIdType>* pointOf, vtkPoints* points)
{
  auto add = [&](int type, int n, const std::vector<std::int64_t>& cells, const std::vector<int>& layer,
               const std::vector<int>& side) {
    for (std::size_t p = 0; p < cells.size() / n; ++p)
    {
      vtkIdType pts[6];
      for (int k = 0; k < n; ++k)
      {
        const std::int64_t id = cells[n * p + k];
        pts[k] = pointOf ? (*pointOf)[id] : static_cast<vtkIdType>(id);
      }
      this->Add(type, n, pts, -1, 2, layer[p], side[p], points);
    }
  };
  add(VTK_WEDGE, 6, result.Prisms, result.PrismLayer, result.PrismSide);
  add(VTK_PYRAMID, 5, result.Pyramids, result.PyramidLayer, result.PyramidSide);
}

void vtkEmbeddedRemeshCells::Commit()
{
  for (vtkDataArray* a : std::initializer_list<vtkDataArray*>{
         this->Types, this->Offsets, this->Connectivity, this->RegionArray, this->LayerArray, this->SideArray })
  {
    a->Squeeze(); // the room Reserve or the growth left
  }
  if (this->Polyhedra.empty())
  {
    vtkNew<vtkCellArray> cells;
    cells->SetData(this->Offsets, this->Connectivity);
    this->Output->SetCells(this->Types, cells);
  }
  else
  {
    // A polyhedron's points come from its face stream: insert the cells one
    // by one, as vtkUnstructuredGrid derives them (kept polyhedra are rare).
    const vtkIdType n = this->Types->GetNumberOfValues();
    this->Output->Allocate(n);
    auto poly = this->Polyhedra.begin();
    for (vtkIdType c = 0; c < n; ++c)
    {
      if (poly != this->Polyhedra.end() && poly->first == c)
      {
        this->Output->InsertNextCell(VTK_POLYHEDRON, poly->second);
        ++poly;
        continue;
      }
      const vtkIdType o = this->Offsets->GetValue(c);
      this->Output->InsertNextCell(
        this->Types->GetValue(c), this->Offsets->GetValue(c + 1) - o, this->Connectivity->GetPointer(o));
    }
  }
}

void vtkEmbeddedRemeshCells::Finish(bool layerArrays)
{
  this->Output->GetCellData()->AddArray(this->RegionArray);
  if (layerArrays)
  {
    this->Output->GetCellData()->AddArray(this->LayerArray);
    this->Output->GetCellData()->AddArray(this->SideArray);
  }
}

//------------------------------------------------------------------------------
vtkEmbeddedRemeshNewTuples vtkEmbeddedRemeshLocateNew(const vtkARFieldTransfer::TetLocator& locator,
  vtkUnstructuredGrid* output, const std::vector<char>& isNew, const std::vector<vtkIdType>& startOf,
  const std::vector<vtkIdType>& cellSource)
{
  vtkEmbeddedRemeshNewTuples n;
  // Only what a field needs is located: the new cells when the output has
  // cell arrays to fill, the new points when it has point arrays or needs
  // them as the cells' starts. (A mesh with point fields only, the usual
  // solution, has a million new cells at 1e6 tetrahedra: they took most of
  // the interpolation's time for nothing.)
  const bool cells = output->GetCellData()->GetNumberOfArrays() > 0;
  const bool points = cells || output->GetPointData()->GetNumberOfArrays() > 0;
  if (!points)
  {
    return n;
  }
  const vtkIdType nOut = output->GetNumberOfPoints();
  std::vector<vtkIdType> queryOf(nOut, -1); // new point -> its query
  for (vtkIdType i = 0; i < nOut; ++i)
  {
    if (isNew[i])
    {
      queryOf[i] = static_cast<vtkIdType>(n.Points.size());
      n.Points.push_back(i);
    }
  }
  const auto nNewPoints = static_cast<vtkIdType>(n.Points.size());
  std::vector<double> where(3 * n.Points.size());
  for (vtkIdType q = 0; q < nNewPoints; ++q)
  {
    output->GetPoint(n.Points[q], &where[3 * q]);
  }
  n.PointIn.resize(n.Points.size());
  n.Weights.resize(4 * n.Points.size());
  locator.Locate(nNewPoints, where.data(), nullptr, n.PointIn.data(), n.Weights.data());
  if (!cells)
  {
    return n;
  }

  // The new cells' centres, each walked to from the cell at one of its
  // corners (a new point's, else the first corner's startOf).
  for (std::size_t k = 0; k < cellSource.size(); ++k)
  {
    if (cellSource[k] < 0)
    {
      n.Cells.push_back(static_cast<vtkIdType>(k));
    }
  }
  const auto nNewCells = static_cast<vtkIdType>(n.Cells.size());
  std::vector<double> centres(3 * n.Cells.size());
  std::vector<vtkIdType> starts(n.Cells.size(), -1);
  n.CellIn.resize(n.Cells.size());
  vtkSMPThreadLocalObject<vtkIdList> scratch;
  vtkSMPTools::For(0, nNewCells, [&](vtkIdType b, vtkIdType e) {
    vtkIdList* corners = scratch.Local();
    for (vtkIdType q = b; q < e; ++q)
    {
      vtkIdType npts;
      const vtkIdType* pts;
      output->GetCellPoints(n.Cells[q], npts, pts, corners);
      double* centre = &centres[3 * q];
      std::fill(centre, centre + 3, 0.0);
      for (vtkIdType j = 0; j < npts; ++j)
      {
        double x[3];
        output->GetPoint(pts[j], x);
        for (int d = 0; d < 3; ++d)
        {
          centre[d] += x[d] / static_cast<double>(npts);
        }
        if (starts[q] < 0)
        {
          starts[q] = queryOf[pts[j]] >= 0 ? n.PointIn[queryOf[pts[j]]] : startOf[pts[j]];
        }
      }
    }
  });
  locator.Locate(nNewCells, centres.data(), starts.data(), n.CellIn.data(), nullptr);
  return n;
}

void vtkEmbeddedRemeshNewTuples::Fill(const vtkARFieldTransfer::TetLocator& locator,
  vtkARFieldTransfer::TupleSources& points, vtkARFieldTransfer::TupleSources& cells,
  const std::vector<vtkIdType>* cellOf) const
{
  for (std::size_t q = 0; q < this->Points.size(); ++q)
  {
    points.Interpolate(this->Points[q], locator.CellPoints(this->PointIn[q]), &this->Weights[4 * q]);
  }
  for (std::size_t q = 0; q < this->Cells.size(); ++q)
  {
    cells.Copy(this->Cells[q], cellOf ? (*cellOf)[this->CellIn[q]] : this->CellIn[q]);
  }
}

//------------------------------------------------------------------------------
void vtkEmbeddedRemeshSummary::AddRefill(const ar::CavityRemesh& result)
{
  this->RemovedNodes = static_cast<double>(result.RemovedNodes);
  this->SurfaceElements = static_cast<double>(result.Surface.size() / 3);
  this->SurfaceTrianglesAtLockedCells = static_cast<double>(result.SurfaceTrianglesAtLockedCells);
  this->OutputSize = vtkEmbeddedRemeshOutputSizeAtSurface(result);
  this->LimitedColumns = static_cast<double>(result.LimitedColumns);
  this->RefillAttempts = result.RefillAttempts;
  this->RefillPieces = static_cast<double>(result.RefillPieces);
  this->SeparatorTriangles = static_cast<double>(result.SeparatorTriangles);
  for (const auto& [name, seconds] : { std::make_pair("SecondsSetup", result.Seconds.Setup),
         std::make_pair("SecondsRemoval", result.Seconds.Removal), std::make_pair("SecondsCavity", result.Seconds.Cavity),
         std::make_pair("SecondsLayers", result.Seconds.Layers), std::make_pair("SecondsRefill", result.Seconds.Refill),
         std::make_pair("SecondsAssembly", result.Seconds.Assembly) })
  {
    this->Seconds.emplace_back(name, seconds);
  }
}

void vtkEmbeddedRemeshSummary::Reduce()
{
  if (vtkARParallel::NumberOfRanks() <= 1)
  {
    return;
  }
  double sums[] = { this->KeptCells, this->NewCells, this->InputNodes, this->NewNodes, this->RemovedNodes,
    this->SurfaceElements, this->SurfaceTrianglesAtLockedCells, this->LimitedColumns, this->PatchTrianglesNew,
    this->VolumeBefore, this->VolumeAfter };
  constexpr int nSums = sizeof(sums) / sizeof(sums[0]);
  vtkARParallel::AllReduceSum(sums, nSums);
  double* s = sums;
  for (double* v : { &this->KeptCells, &this->NewCells, &this->InputNodes, &this->NewNodes, &this->RemovedNodes,
         &this->SurfaceElements, &this->SurfaceTrianglesAtLockedCells, &this->LimitedColumns,
         &this->PatchTrianglesNew, &this->VolumeBefore, &this->VolumeAfter })
  {
    *v = *s++;
  }
  // Sizes and the refill's figures: known on rank 0 (S and the refill are
  // there), 0 elsewhere; timings: the slowest rank's.
  std::vector<double> maxima = { this->SurfaceEdgeLength, this->InputSize, this->OutputSize, this->RefillAttempts,
    this->MinTriangleAngleNew, this->RefillPieces };
  for (const auto& t : this->Seconds)
  {
    maxima.push_back(t.second);
  }
  vtkARParallel::AllReduceMax(maxima.data(), static_cast<int>(maxima.size()));
  this->SurfaceEdgeLength = maxima[0];
  this->InputSize = maxima[1];
  this->OutputSize = maxima[2];
  this->RefillAttempts = maxima[3];
  this->MinTriangleAngleNew = maxima[4];
  this->RefillPieces = maxima[5];
  for (std::size_t k = 0; k < this->Seconds.size(); ++k)
  {
    this->Seconds[k].second = maxima[6 + k];
  }
  vtkEmbeddedRemeshReduceQuality(this->Quality);
  // Every node not removed is kept: the output has the input's nodes less
  // the removed ones plus the new ones.
  this->OutputNodes = this->InputNodes - this->RemovedNodes + this->NewNodes;
}

void vtkEmbeddedRemeshSummary::Write(vtkUnstructuredGrid* output, const ar::PrismLayerOptions& layers) const
{
  auto field = [&](const char* name, double value) {
    output->GetFieldData()->AddArray(vtkARMeshKernels::FieldArray(name, &value, 1));
  };
  field("TwoDimensional", this->TwoDimensional ? 1.0 : 0.0);
  field("KeptCells", this->KeptCells);
  field("NewCells", this->NewCells);
  field("InputNodes", this->InputNodes);
  field("OutputNodes", this->OutputNodes);
  field("NewNodes", this->NewNodes);
  field("RemovedNodes", this->RemovedNodes);
  if (this->TwoDimensional)
  {
    field("SurfaceQuads", this->SurfaceElements);
  }
  else
  {
    field("SurfaceTriangles", this->SurfaceElements);
    field("SurfaceTrianglesAtLockedCells", this->SurfaceTrianglesAtLockedCells);
    field("RemovedLayerCells", this->RemovedLayerCells);
  }
  field("SurfaceEdgeLength", this->SurfaceEdgeLength);
  vtkEmbeddedRemeshAddSizeFields(output, this->SurfaceEdgeLength, this->InputSize, this->OutputSize);
  vtkEmbeddedRemeshAddLayerFields(output, layers, this->LimitedColumns);
  if (this->TwoDimensional)
  {
    field("MinTriangleAngleNew", this->NewCells > 0.0 ? this->MinTriangleAngleNew : 0.0);
    field("PatchTrianglesNew", this->PatchTrianglesNew);
  }
  else
  {
    field("RefillAttempts", this->RefillAttempts);
    field("RefillPieces", this->RefillPieces);
    field("SeparatorTriangles", this->SeparatorTriangles);
  }
  vtkEmbeddedRemeshAddQualityFields(output, this->Quality);
  vtkEmbeddedRemeshAddStepFields(output, this->Quality, this->SurfaceEdgeLength, layers, this->TwoDimensional);
  for (const auto& t : this->Seconds)
  {
    field(t.first.c_str(), t.second);
  }
  field("RelativeVolumeChange",
    this->VolumeBefore > 0.0 ? (this->VolumeAfter - this->VolumeBefore) / this->VolumeBefore : 0.0);
}

//------------------------------------------------------------------------------
void vtkEmbeddedRemeshSetEmbedded(vtkPolyData* embedded, vtkPoints* points, const std::vector<std::int64_t>& triangles,
  const std::vector<vtkIdType>* pointOf)
{
  vtkNew<vtkCellArray> faces;
  for (std::size_t f = 0; f + 2 < triangles.size(); f += 3)
  {
    vtkIdType tri[3];
    for (int k = 0; k < 3; ++k)
    {
      tri[k] = pointOf ? (*pointOf)[triangles[f + k]] : static_cast<vtkIdType>(triangles[f + k]);
    }
    faces->InsertNextCell(3, tri);
  }
  embedded->SetPoints(points);
  embedded->SetPolys(faces);
}

//------------------------------------------------------------------------------
void vtkEmbeddedRemeshCompleteCells(vtkUnstructuredGrid* output, vtkEmbeddedRemeshCells& cells,
  bool interpolateFields, const std::function<void()>& interpolate, vtkEmbeddedRemeshLap& lap,
  vtkEmbeddedRemeshSummary& summary)
{
  cells.Commit();
  summary.Seconds.emplace_back("SecondsOutput", lap());
  if (interpolateFields)
  {
    interpolate();
  }
  summary.Seconds.emplace_back("SecondsInterpolation", lap());
  cells.Finish(true);
  summary.Quality = vtkEmbeddedRemeshAddQualityArrays(output, cells.Region());
  summary.Seconds.emplace_back("SecondsQuality", lap());
  summary.KeptCells = static_cast<double>(cells.NumberOfKept());
  summary.NewCells = static_cast<double>(cells.NumberOfNew());
}
