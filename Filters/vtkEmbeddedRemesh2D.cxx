// SPDX-License-Identifier: BSD-3-Clause
// vtkEmbeddedRemesh's 2-D mode: a one-cell-deep mesh (OpenFOAM 2-D cases)
// remeshed on its cross-section and extruded back into hexahedra and wedges.
#include "vtkEmbeddedRemesh.h"
#include "vtkEmbeddedRemeshPlanes.h"
#include "vtkEmbeddedRemeshStages.h"

#include "ARCavity2D.h"
#include "ARMeshSize.h"
#include "vtkARMeshKernels.h"
#include "vtkARFieldTransfer.h"

#include "vtkAppendPolyData.h"
#include "vtkCell.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellTypes.h"
#include "vtkCleanPolyData.h"
#include "vtkCutter.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkGenericCell.h"
#include "vtkGeometryFilter.h"
#include "vtkIdList.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPlane.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPThreadLocalObject.h"
#include "vtkSMPTools.h"
#include "vtkSplineFilter.h"
#include "vtkStaticCellLocator.h"
#include "vtkStaticPointLocator.h"
#include "vtkStripper.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <numeric>
#include <sstream>

namespace
{
using Coord = std::array<double, 3>;

std::vector<vtkIdType> SortedKey(std::vector<vtkIdType> ids)
{
  std::sort(ids.begin(), ids.end());
  return ids;
}

/// The smallest angle of a triangle, degrees.
double TriangleMinAngle(const double* a, const double* b, const double* c)
{
  const double* p[3] = { a, b, c };
  double smallest = 180.0;
  for (int k = 0; k < 3; ++k)
  {
    double u[3], v[3];
    for (int d = 0; d < 3; ++d)
    {
      u[d] = p[(k + 1) % 3][d] - p[k][d];
      v[d] = p[(k + 2) % 3][d] - p[k][d];
    }
    smallest = std::min(smallest, vtkMath::DegreesFromRadians(vtkMath::AngleBetweenVectors(u, v)));
  }
  return smallest;
}

/// Copies point data at output point `i`: from input point `src`, or
/// interpolated in the cell of `locator`'s dataset that contains `x`
/// (the closest cell when none does).
void InterpolatePointData(vtkDataSet* from, vtkStaticCellLocator* locator, vtkPointData* out,
  vtkIdType src, const double* x, vtkIdType i, vtkGenericCell* cell, std::vector<double>& weights)
{
  if (src >= 0)
  {
    out->CopyData(from->GetPointData(), src, i);
    return;
  }
  double pcoords[3], closest[3], dist2;
  int subId;
  const double tol2 = 1e-12 * from->GetLength2();
  vtkIdType c = locator->FindCell(const_cast<double*>(x), tol2, cell, subId, pcoords, weights.data());
  if (c < 0)
  {
    locator->FindClosestPoint(x, closest, cell, c, subId, dist2);
    cell->EvaluatePosition(closest, nullptr, subId, pcoords, dist2, weights.data());
  }
  out->InterpolatePoint(from->GetPointData(), i, cell->PointIds, weights.data());
}

/// Points located in the cells of a vtkStaticCellLocator's dataset (the
/// one-cell-deep mesh: hexahedra and wedges): per point the cell that
/// contains it (the closest cell when none does) and, with weights, its
/// points and their interpolation weights there.
struct LocatedPoints
{
  static constexpr int Width = 8; ///< the hexahedron's points, the most a cell of the mesh has
  std::vector<vtkIdType> Cell;
  std::vector<vtkIdType> Ids;  ///< Width per point, the cell's points
  std::vector<double> Weights; ///< Width per point
  std::vector<int> Count;      ///< the cell's points
};

/// On threads (FindCell, as vtkProbeFilter does); the points no cell
/// contains (round-off at the boundary) then in order on one thread
/// (FindClosestPoint and, with weights, the weights at the closest point),
/// so the answer is the serial loop's.
LocatedPoints LocateInCells(vtkStaticCellLocator* locator, double tol2, const std::vector<double>& x, bool weights)
{
  const vtkIdType n = static_cast<vtkIdType>(x.size() / 3);
  const int W = LocatedPoints::Width;
  LocatedPoints out;
  out.Cell.assign(n, -1);
  if (weights)
  {
    out.Ids.assign(static_cast<std::size_t>(n) * W, -1);
    out.Weights.assign(static_cast<std::size_t>(n) * W, 0.0);
    out.Count.assign(n, 0);
  }
  auto keep = [&](vtkIdType q, vtkGenericCell* cell, const double* w) {
    const int m = std::min<int>(W, static_cast<int>(cell->GetNumberOfPoints()));
    out.Count[q] = m;
    for (int k = 0; k < m; ++k)
    {
      out.Ids[static_cast<std::size_t>(q) * W + k] = cell->GetPointId(k);
      out.Weights[static_cast<std::size_t>(q) * W + k] = w[k];
    }
  };
  vtkSMPThreadLocalObject<vtkGenericCell> cells;
  vtkSMPTools::For(0, n, [&](vtkIdType b, vtkIdType e) {
    vtkGenericCell* cell = cells.Local();
    std::vector<double> w(VTK_CELL_SIZE);
    double pcoords[3];
    int subId;
    for (vtkIdType q = b; q < e; ++q)
    {
      double p[3] = { x[3 * q], x[3 * q + 1], x[3 * q + 2] };
      out.Cell[q] = locator->FindCell(p, tol2, cell, subId, pcoords, w.data());
      if (out.Cell[q] >= 0 && weights)
      {
        keep(q, cell, w.data());
      }
    }
  });
  vtkNew<vtkGenericCell> cell;
  std::vector<double> w(VTK_CELL_SIZE);
  for (vtkIdType q = 0; q < n; ++q)
  {
    if (out.Cell[q] >= 0)
    {
      continue;
    }
    double closest[3], dist2, pcoords[3];
    int subId;
    locator->FindClosestPoint(&x[3 * q], closest, cell, out.Cell[q], subId, dist2);
    if (weights)
    {
      cell->EvaluatePosition(closest, nullptr, subId, pcoords, dist2, w.data());
      keep(q, cell, w.data());
    }
  }
  return out;
}
}

//------------------------------------------------------------------------------
bool vtkEmbeddedRemeshDetect2D(vtkUnstructuredGrid* input, vtkEmbeddedRemeshLayout& layout, std::string& why)
{
  layout = vtkEmbeddedRemeshLayout();
  const vtkIdType nPoints = input->GetNumberOfPoints();
  for (vtkIdType c = 0; c < input->GetNumberOfCells(); ++c)
  {
    const int type = input->GetCellType(c);
    const int dim = vtkCellTypes::GetDimension(type);
    if (type == VTK_HEXAHEDRON || type == VTK_WEDGE)
    {
      layout.VolumeCells.push_back(c);
    }
    else if (dim == 3 || !(type == VTK_TRIANGLE || type == VTK_QUAD || type == VTK_POLYGON))
    {
      why = "cell " + std::to_string(c) + " is a " + vtkCellTypes::GetClassNameFromTypeId(type) +
        " (a one-cell-deep mesh has hexahedra and wedges, and patch faces)";
      return false;
    }
  }
  if (layout.VolumeCells.empty())
  {
    why = "it has no hexahedra or wedges";
    return false;
  }
  // The two planes: one axis on which the cells' points take two values.
  std::vector<char> used(nPoints, 0);
  double lo[3] = { VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, VTK_DOUBLE_MAX };
  double hi[3] = { -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX };
  vtkIdType npts;
  const vtkIdType* pts;
  for (const vtkIdType c : layout.VolumeCells)
  {
    input->GetCellPoints(c, npts, pts);
    for (vtkIdType k = 0; k < npts; ++k)
    {
      used[pts[k]] = 1;
      double x[3];
      input->GetPoint(pts[k], x);
      for (int d = 0; d < 3; ++d)
      {
        lo[d] = std::min(lo[d], x[d]);
        hi[d] = std::max(hi[d], x[d]);
      }
    }
  }
  const double extentMax = std::max({ hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2] });
  const double tol = 1e-6 * extentMax;
  std::array<int, 3> axes = { 0, 1, 2 };
  std::sort(axes.begin(), axes.end(), [&](int a, int b) { return hi[a] - lo[a] < hi[b] - lo[b]; });
  int axis = -1;
  for (const int a : axes)
  {
    if (!(hi[a] - lo[a] > tol))
    {
      continue;
    }
    bool two = true;
    for (vtkIdType i = 0; i < nPoints && two; ++i)
    {
      if (used[i])
      {
        const double x = input->GetPoints()->GetPoint(i)[a];
        two = std::abs(x - lo[a]) <= tol || std::abs(x - hi[a]) <= tol;
      }
    }
    if (two)
    {
      axis = a;
      break;
    }
  }
  if (axis < 0)
  {
    why = "its points do not lie on two planes normal to a coordinate axis";
    return false;
  }
  layout.Axis = axis;
  layout.Lo = lo[axis];
  layout.Hi = hi[axis];
  auto side = [&](vtkIdType p) { return std::abs(input->GetPoints()->GetPoint(p)[axis] - lo[axis]) <= tol ? 0 : 1; };
  layout.Partner.assign(nPoints, -1);
  layout.Faces.resize(layout.VolumeCells.size());
  vtkNew<vtkGenericCell> cell;
  for (std::size_t k = 0; k < layout.VolumeCells.size(); ++k)
  {
    const vtkIdType c = layout.VolumeCells[k];
    input->GetCell(c, cell);
    const vtkIdType n = cell->GetNumberOfPoints();
    for (int f = 0; f < cell->GetNumberOfFaces(); ++f)
    {
      vtkIdList* ids = cell->GetFace(f)->GetPointIds();
      std::vector<vtkIdType> face(ids->GetPointer(0), ids->GetPointer(0) + ids->GetNumberOfIds());
      int onLo = 0;
      for (const vtkIdType p : face)
      {
        onLo += side(p) == 0 ? 1 : 0;
      }
      if (onLo == static_cast<int>(face.size()))
      {
        layout.Faces[k][0] = face;
      }
      else if (onLo == 0)
      {
        layout.Faces[k][1] = face;
      }
    }
    int depthEdges = 0;
    for (int e = 0; e < cell->GetNumberOfEdges(); ++e)
    {
      vtkIdList* ids = cell->GetEdge(e)->GetPointIds();
      vtkIdType a = ids->GetId(0), b = ids->GetId(1);
      if (side(a) == side(b))
      {
        continue;
      }
      if (side(a) == 1)
      {
        std::swap(a, b);
      }
      double xa[3], xb[3];
      input->GetPoint(a, xa);
      input->GetPoint(b, xb);
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      if (std::abs(xa[u] - xb[u]) > tol || std::abs(xa[v] - xb[v]) > tol ||
        (layout.Partner[a] >= 0 && layout.Partner[a] != b))
      {
        why = "cell " + std::to_string(c) + " has an edge between the planes that is not along the axis";
        return false;
      }
      layout.Partner[a] = b;
      ++depthEdges;
    }
    if (2 * static_cast<vtkIdType>(layout.Faces[k][0].size()) != n ||
      2 * static_cast<vtkIdType>(layout.Faces[k][1].size()) != n || 2 * depthEdges != n)
    {
      why = "cell " + std::to_string(c) + " does not span the two planes with one face on each";
      return false;
    }
  }
  return true;
}

//------------------------------------------------------------------------------
namespace
{
/// The 2-D mode's run: the stages of vtkEmbeddedRemesh::Remesh2D over the
/// state they share (as CavityRun in ARCavity.cxx; file-local, so its
/// members keep the names the stages had as locals). Each stage returns
/// false with Problem set when the input cannot be remeshed.
class Remesh2DRun
{
public:
  Remesh2DRun(vtkEmbeddedRemesh* self_, vtkUnstructuredGrid* input_, const vtkEmbeddedRemeshLayout& layout_,
    const std::vector<vtkDataSet*>& surfaces_, vtkUnstructuredGrid* output_, vtkPolyData* embedded_,
    vtkEmbeddedRemeshPlanes* planes_)
    : self(self_)
    , input(input_)
    , layout(layout_)
    , surfaces(surfaces_)
    , output(output_)
    , embedded(embedded_)
    , planes(planes_)
    , axis(layout_.Axis)
    , U((layout_.Axis + 1) % 3)
    , V((layout_.Axis + 2) % 3)
    , mid(0.5 * (layout_.Lo + layout_.Hi))
    , nPoints(input_->GetNumberOfPoints())
    , nVolume(layout_.VolumeCells.size())
  {
  }
  bool Section();       ///< the cross-section of the front faces, l_v at its nodes
  bool Curve();         ///< the feature curves at mid-depth, resampled at the edge length
  bool Cavity();        ///< the 2-D cavity and its refill
  bool OutputPoints();  ///< kept points, then a front and a back point per new 2-D point
  bool LocateCentres(); ///< the input cell holding each new cell's centre
  bool Cells();         ///< kept, new (extruded) and patch cells
  bool Fields();        ///< the point and cell data
  bool Summary();       ///< field data, the embedded surface, the planes for the patch leaves
  std::string Problem;

private:
  bool Fail(const std::string& problem)
  {
    this->Problem = problem;
    return false;
  }
  vtkEmbeddedRemesh* self;
  vtkUnstructuredGrid* input;
  const vtkEmbeddedRemeshLayout& layout;
  const std::vector<vtkDataSet*>& surfaces;
  vtkUnstructuredGrid* output;
  vtkPolyData* embedded;
  vtkEmbeddedRemeshPlanes* planes;
  const int axis, U, V;
  const double mid;
  const vtkIdType nPoints;
  const std::size_t nVolume;
  // Section
  std::vector<vtkIdType> node2d, frontPoint; ///< input point -> cross-section node; node -> input point
  ar::Mesh2D section;
  double areaBefore = 0.0;
  std::vector<double> lv;
  // Curve
  double inputSize = 0.0, edge = 0.0;
  std::vector<double> cPoints;
  std::vector<std::int64_t> cSegments;
  // Cavity
  ar::Cavity2DOptions options;
  bool layered = false;
  ar::Cavity2DRemesh result;
  // OutputPoints
  std::size_t n2 = 0;
  std::vector<vtkIdType> outOfInput, pointSource;
  std::vector<std::array<vtkIdType, 2>> pair; ///< per 2-D output point: its output ids on Lo, Hi
  vtkNew<vtkIdList> ids;
  std::vector<vtkIdType> planeCells, otherCells;
  std::map<std::vector<vtkIdType>, vtkIdType> planeCellOfKey;
  std::map<std::vector<vtkIdType>, std::pair<vtkIdType, int>> faceOwner; ///< key -> volume index, plane
  std::vector<char> isVolume;
  vtkNew<vtkPoints> points;
  vtkIdType nKeptPoints = 0, nOut = 0;
  // LocateCentres
  vtkNew<vtkStaticCellLocator> cellLocator;
  double tol2 = 0.0;
  std::vector<vtkIdType> newCellOf2D, newCells2D;
  LocatedPoints centreIn;
  // Cells
  std::unique_ptr<vtkEmbeddedRemeshCells> cellsPtr;
  std::vector<char> cellKept;
  double areaAfter = 0.0;
  vtkIdType newCount = 0, keptCount = 0;
  std::vector<vtkEmbeddedRemeshPlanes::Wedge> wedges;
  std::size_t patchTriangles = 0;
};

//------------------------------------------------------------------------------
bool Remesh2DRun::Section()
{
  // ---- The cross-section: the front (Lo) faces, counter-clockwise in (U, V).
  node2d.assign(nPoints, -1);
  section.Points.clear();
  for (std::size_t k = 0; k < nVolume; ++k)
  {
    for (const vtkIdType p : layout.Faces[k][0])
    {
      if (node2d[p] < 0)
      {
        node2d[p] = 0;
      }
    }
  }
  for (vtkIdType p = 0; p < nPoints; ++p)
  {
    if (node2d[p] == 0)
    {
      node2d[p] = static_cast<vtkIdType>(frontPoint.size());
      frontPoint.push_back(p);
      const double* x = input->GetPoints()->GetPoint(p);
      section.Points.push_back(x[U]);
      section.Points.push_back(x[V]);
    }
  }
  areaBefore = 0.0;
  for (std::size_t k = 0; k < nVolume; ++k)
  {
    std::vector<std::int64_t> face;
    for (const vtkIdType p : layout.Faces[k][0])
    {
      face.push_back(node2d[p]);
    }
    double area = 0.0;
    for (std::size_t j = 0; j < face.size(); ++j)
    {
      const double* a = &section.Points[2 * face[j]];
      const double* b = &section.Points[2 * face[(j + 1) % face.size()]];
      area += 0.5 * (a[0] * b[1] - a[1] * b[0]);
    }
    if (area < 0.0)
    {
      std::reverse(face.begin() + 1, face.end());
    }
    areaBefore += std::abs(area);
    section.Connectivity.insert(section.Connectivity.end(), face.begin(), face.end());
    section.Offsets.push_back(static_cast<std::int64_t>(section.Connectivity.size()));
  }
  // Longest 2-D edge at each node (the input's size at the curve).
  lv = ar::LongestPolygonEdgeAtNodes(section.Points.data(), 2, frontPoint.size(),
    section.Offsets.data(), section.Connectivity.data(), nVolume);
  return true;
}

//------------------------------------------------------------------------------
bool Remesh2DRun::Curve()
{
  // ---- The curves: the surfaces cut with the mid-depth plane.
  vtkNew<vtkAppendPolyData> append;
  for (vtkDataSet* ds : surfaces)
  {
    if (ds && ds->GetNumberOfCells() > 0)
    {
      vtkNew<vtkGeometryFilter> geometry;
      geometry->SetInputData(ds);
      geometry->Update();
      vtkNew<vtkPolyData> bare;
      bare->SetPoints(geometry->GetOutput()->GetPoints());
      bare->SetPolys(geometry->GetOutput()->GetPolys());
      append->AddInputData(bare);
    }
  }
  if (append->GetNumberOfInputConnections(0) == 0)
  {
    return this->Fail("The feature surface is empty (no Surfaces connected, or none has cells).");
  }
  vtkNew<vtkPlane> plane;
  double origin[3] = { 0.0, 0.0, 0.0 }, normal[3] = { 0.0, 0.0, 0.0 };
  origin[axis] = mid;
  normal[axis] = 1.0;
  plane->SetOrigin(origin);
  plane->SetNormal(normal);
  vtkNew<vtkCutter> cutter;
  cutter->SetInputConnection(append->GetOutputPort());
  cutter->SetCutFunction(plane);
  vtkNew<vtkCleanPolyData> clean; // merges the cut's duplicate points, drops degenerate segments
  clean->SetInputConnection(cutter->GetOutputPort());
  clean->ToleranceIsAbsoluteOn();
  clean->SetAbsoluteTolerance(1e-9 * std::sqrt(input->GetLength2()));
  vtkNew<vtkStripper> stripper;
  stripper->SetInputConnection(clean->GetOutputPort());
  stripper->JoinContiguousSegmentsOn();
  stripper->Update();
  vtkPolyData* cut = stripper->GetOutput();
  if (cut->GetNumberOfLines() == 0)
  {
    return this->Fail("The feature curve is empty: the feature surface does not cross the mid-depth "
                       "plane of the mesh.");
  }
  std::vector<double> cutPoints(2 * cut->GetNumberOfPoints());
  for (vtkIdType i = 0; i < cut->GetNumberOfPoints(); ++i)
  {
    const double* x = cut->GetPoint(i);
    cutPoints[2 * i] = x[U];
    cutPoints[2 * i + 1] = x[V];
  }
  inputSize = vtkEmbeddedRemeshInputSizeAt(section.Points.data(),
    static_cast<vtkIdType>(frontPoint.size()), 2, lv, nullptr, cutPoints.data(), cutPoints.size() / 2);
  edge = self->GetSurfaceEdgeLength() > 0.0 ? self->GetSurfaceEdgeLength() : self->GetSurfaceSizeFactorUsed(true) * inputSize;
  if (!(edge > 0.0))
  {
    return this->Fail("Could not find the mesh size near the feature curve; set SurfaceEdgeLength.");
  }
  {
    // The job's size, before the resampling and CGAL allocate it.
    double length = 0.0;
    vtkIdType n;
    const vtkIdType* ids;
    vtkCellArray* lines = cut->GetLines();
    for (lines->InitTraversal(); lines->GetNextCell(n, ids);)
    {
      for (vtkIdType k = 1; k < n; ++k)
      {
        double a[3], b[3]; // copies: GetPoint(id) returns one buffer for every call
        cut->GetPoint(ids[k - 1], a);
        cut->GetPoint(ids[k], b);
        length += std::hypot(a[U] - b[U], a[V] - b[V]);
      }
    }
    std::string tooLarge;
    if (!vtkEmbeddedRemeshJobFits(
          self, 2, length, length, edge, inputSize, areaBefore, static_cast<double>(nVolume), tooLarge))
    {
      return this->Fail(tooLarge.substr(std::string("EmbeddedRemesh: ").size()));
    }
  }
  vtkNew<vtkSplineFilter> resample;
  resample->SetInputData(cut);
  resample->SetSubdivideToLength();
  resample->SetLength(edge);
  resample->Update();
  vtkPolyData* curve = resample->GetOutput();
  {
    vtkIdType n;
    const vtkIdType* ids;
    vtkCellArray* lines = curve->GetLines();
    for (lines->InitTraversal(); lines->GetNextCell(n, ids);)
    {
      const auto first = static_cast<std::int64_t>(cPoints.size() / 2);
      vtkIdType count = n;
      double a[3], b[3]; // copies: GetPoint(id) returns one buffer for every call
      curve->GetPoint(ids[0], a);
      curve->GetPoint(ids[n - 1], b);
      const bool closed = n > 3 && std::hypot(a[U] - b[U], a[V] - b[V]) < 1e-9 * edge;
      if (closed)
      {
        --count; // a loop: the last point is the first
      }
      std::vector<double> line;
      for (vtkIdType k = 0; k < count; ++k)
      {
        const double* x = curve->GetPoint(ids[k]);
        line.push_back(x[U]);
        line.push_back(x[V]);
      }
      // An end segment of the resampled curve came out at 0.3 of the edge
      // on the validation wedge's outlet end (vtkSplineFilter spaces its
      // points evenly along each polyline it is given, so the short piece
      // comes from the cut's polylines; the cause is not pinned down): its
      // triangles were 0.19 of the requested size, and the solver's time
      // step with them. An end segment under half the edge shares the two
      // last segments' length with its neighbour (the middle point moves to
      // the midpoint of its neighbours: both between 0.5 and 1 edge).
      auto segment = [&line](vtkIdType i, vtkIdType j) {
        return std::hypot(line[2 * i] - line[2 * j], line[2 * i + 1] - line[2 * j + 1]);
      };
      if (!closed && count >= 3)
      {
        for (const vtkIdType end : { count - 1, vtkIdType(0) })
        {
          const vtkIdType mid = end == 0 ? 1 : end - 1, far = end == 0 ? 2 : end - 2;
          if (segment(end, mid) < 0.5 * edge)
          {
            line[2 * mid] = 0.5 * (line[2 * end] + line[2 * far]);
            line[2 * mid + 1] = 0.5 * (line[2 * end + 1] + line[2 * far + 1]);
          }
        }
      }
      cPoints.insert(cPoints.end(), line.begin(), line.end());
      for (vtkIdType k = 1; k < count; ++k)
      {
        cSegments.insert(cSegments.end(), { first + k - 1, first + k });
      }
      if (closed)
      {
        cSegments.insert(cSegments.end(), { first + count - 1, first });
      }
    }
  }
  if (cSegments.empty())
  {
    return this->Fail("The feature curve is empty after resampling.");
  }
  return true;
}

//------------------------------------------------------------------------------
bool Remesh2DRun::Cavity()
{
  // ---- The 2-D cavity and its refill.
  {
    std::string problem;
    if (!vtkEmbeddedRemeshCavityOptions(self, edge, options, problem))
    {
      return this->Fail(problem.substr(std::string("EmbeddedRemesh: ").size()));
    }
  }
  layered = options.Layers.NumberOfLayers > 0;
  std::string error;
  bool ok = false;
  try
  {
    ok = ar::RemeshLocalCavity2D(section, cPoints.data(), cPoints.size() / 2, cSegments.data(),
      cSegments.size() / 2, options, result, error);
  }
  catch (const std::exception& e)
  {
    error = std::string("CGAL failed: ") + e.what();
  }
  if (!ok)
  {
    return this->Fail(error);
  }
  return true;
}

//------------------------------------------------------------------------------
bool Remesh2DRun::OutputPoints()
{
  // ---- Output points: the kept input points (input order), then a front
  // and a back point per new 2-D point.
  n2 = result.SourcePoint.size();
  outOfInput.assign(nPoints, -1);
  pair.resize(n2);
  for (std::size_t i = 0; i < n2; ++i)
  {
    if (result.SourcePoint[i] >= 0)
    {
      const vtkIdType f = frontPoint[result.SourcePoint[i]];
      outOfInput[f] = 0;
      outOfInput[layout.Partner[f]] = 0;
    }
  }
  // 2-D cells off the planes (patch faces on the domain boundary) keep their points.
  for (std::size_t k = 0; k < nVolume; ++k)
  {
    for (int s = 0; s < 2; ++s)
    {
      faceOwner[SortedKey(layout.Faces[k][s])] = { static_cast<vtkIdType>(k), s };
    }
  }
  isVolume.assign(input->GetNumberOfCells(), 0);
  for (const vtkIdType c : layout.VolumeCells)
  {
    isVolume[c] = 1;
  }
  for (vtkIdType c = 0; c < input->GetNumberOfCells(); ++c)
  {
    if (isVolume[c])
    {
      continue;
    }
    input->GetCellPoints(c, ids);
    std::vector<vtkIdType> key(ids->GetPointer(0), ids->GetPointer(0) + ids->GetNumberOfIds());
    key = SortedKey(key);
    if (faceOwner.count(key))
    {
      planeCells.push_back(c);
      planeCellOfKey[key] = c;
    }
    else
    {
      otherCells.push_back(c);
      for (const vtkIdType p : key)
      {
        outOfInput[p] = 0;
      }
    }
  }
  points->SetDataTypeToDouble();
  for (vtkIdType p = 0; p < nPoints; ++p)
  {
    if (outOfInput[p] == 0)
    {
      outOfInput[p] = points->InsertNextPoint(input->GetPoint(p));
      pointSource.push_back(p);
    }
  }
  nKeptPoints = points->GetNumberOfPoints();
  for (std::size_t i = 0; i < n2; ++i)
  {
    if (result.SourcePoint[i] >= 0)
    {
      const vtkIdType f = frontPoint[result.SourcePoint[i]];
      pair[i] = { outOfInput[f], outOfInput[layout.Partner[f]] };
      continue;
    }
    double x[3];
    x[U] = result.Mesh.Points[2 * i];
    x[V] = result.Mesh.Points[2 * i + 1];
    for (int s = 0; s < 2; ++s)
    {
      x[axis] = s == 0 ? layout.Lo : layout.Hi;
      pair[i][s] = points->InsertNextPoint(x);
      pointSource.push_back(-1);
    }
  }
  nOut = points->GetNumberOfPoints();
  return true;
}

//------------------------------------------------------------------------------
bool Remesh2DRun::LocateCentres()
{
  // ---- The input cell holding each new cell's centre (at mid-depth): its
  // cell data, and the patch faces of its planes, go to the new cell.
  cellLocator->SetDataSet(input);
  cellLocator->BuildLocator();
  tol2 = 1e-12 * input->GetLength2();
  newCellOf2D.assign(result.SourceCell.size(), -1);
  for (std::size_t c = 0; c < result.SourceCell.size(); ++c)
  {
    if (result.SourceCell[c] < 0)
    {
      newCellOf2D[c] = static_cast<vtkIdType>(newCells2D.size());
      newCells2D.push_back(static_cast<vtkIdType>(c));
    }
  }
  std::vector<double> centres(3 * newCells2D.size(), 0.0);
  for (std::size_t q = 0; q < newCells2D.size(); ++q)
  {
    const std::size_t c = newCells2D[q];
    const std::int64_t* v = &result.Mesh.Connectivity[result.Mesh.Offsets[c]];
    const std::int64_t n = result.Mesh.Offsets[c + 1] - result.Mesh.Offsets[c];
    double* centre = &centres[3 * q];
    for (std::int64_t j = 0; j < n; ++j)
    {
      centre[U] += result.Mesh.Points[2 * v[j]] / static_cast<double>(n);
      centre[V] += result.Mesh.Points[2 * v[j] + 1] / static_cast<double>(n);
    }
    centre[axis] = mid;
  }
  centreIn = LocateInCells(cellLocator, tol2, centres, false);
  return true;
}

//------------------------------------------------------------------------------
bool Remesh2DRun::Cells()
{
  // ---- Cells: kept volume cells (their node order), new wedges, then the
  // 2-D cells (off the planes; on the planes kept with their cell, and the
  // new wedges' triangles where the input had a face).
  output->Initialize();
  output->GetFieldData()->ShallowCopy(input->GetFieldData());
  output->SetPoints(points);
  cellsPtr.reset(new vtkEmbeddedRemeshCells(output));
  vtkEmbeddedRemeshCells& cells = *cellsPtr; // Region 0 kept, 1 new triangle (wedge), 2 layer cell;
  // A 2-D cell gives a volume cell (at most 8 points) and at most two plane
  // faces; a kept cell at most 8 points.
  cells.Reserve(3 * result.SourceCell.size() + otherCells.size() + planeCells.size(),
    16 * result.SourceCell.size() + 8 * (otherCells.size() + planeCells.size()));
  // Layer, LayerSide: layer cells' k (0 next to the curve) and side (+1 on the
  // curve's left, ARCavity2D.h; -1 on its right)
  cellKept.assign(input->GetNumberOfCells(), 0);
  for (std::size_t c = 0; c < result.SourceCell.size(); ++c)
  {
    const std::int64_t* v = &result.Mesh.Connectivity[result.Mesh.Offsets[c]];
    const std::int64_t n = result.Mesh.Offsets[c + 1] - result.Mesh.Offsets[c];
    for (std::int64_t j = 0; j < n; ++j)
    {
      const double* a = &result.Mesh.Points[2 * v[j]];
      const double* b = &result.Mesh.Points[2 * v[(j + 1) % n]];
      areaAfter += 0.5 * (a[0] * b[1] - a[1] * b[0]);
    }
    const std::int64_t src = result.SourceCell[c];
    if (src >= 0)
    {
      const vtkIdType in = layout.VolumeCells[src];
      cellKept[in] = 1;
      input->GetCellPoints(in, ids);
      for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
      {
        ids->SetId(k, outOfInput[ids->GetId(k)]);
      }
      cells.Add(input->GetCellType(in), ids->GetNumberOfIds(), ids->GetPointer(0), in, 0, -1, 0);
      ++keptCount;
      continue;
    }
    vtkEmbeddedRemeshPlanes::Wedge w;
    const vtkIdType in = centreIn.Cell[newCellOf2D[c]];
    const bool layerCell = layered && result.CellLayer[c] >= 0;
    const int region = layerCell ? 2 : 1, k = layerCell ? result.CellLayer[c] : -1;
    const int side = layerCell ? result.CellSide[c] : 0;
    if (n == 3)
    {
      // A counter-clockwise triangle (a, b, c) in (U, V): its normal points to
      // Hi, so the wedge's base on Lo is (a, c, b) (VTK: the base's normal
      // points away from the top).
      const vtkIdType lo[3] = { pair[v[0]][0], pair[v[2]][0], pair[v[1]][0] };
      const vtkIdType hi[3] = { pair[v[0]][1], pair[v[2]][1], pair[v[1]][1] };
      const vtkIdType wedge[6] = { lo[0], lo[1], lo[2], hi[0], hi[1], hi[2] };
      cells.Add(VTK_WEDGE, 6, wedge, in, region, k, side);
      w.Face[0] = { lo[0], lo[1], lo[2] }; // normal -axis: out of the domain on Lo
      w.Face[1] = { hi[0], hi[2], hi[1] }; // normal +axis: out of the domain on Hi
    }
    else
    {
      // A layer quad (a, b, c, d), counter-clockwise: the hexahedron's base
      // on Lo is (a, b, c, d) (VTK: the base's normal points to the top).
      const vtkIdType hex[8] = { pair[v[0]][0], pair[v[1]][0], pair[v[2]][0], pair[v[3]][0], pair[v[0]][1],
        pair[v[1]][1], pair[v[2]][1], pair[v[3]][1] };
      cells.Add(VTK_HEXAHEDRON, 8, hex, in, region, k, side);
      w.Face[0] = { hex[0], hex[3], hex[2], hex[1] };
      w.Face[1] = { hex[4], hex[5], hex[6], hex[7] };
    }
    ++newCount;
    w.Source = in;
    wedges.push_back(w);
  }
  for (const vtkIdType c : otherCells)
  {
    input->GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      ids->SetId(k, outOfInput[ids->GetId(k)]);
    }
    cells.Add(input->GetCellType(c), ids->GetNumberOfIds(), ids->GetPointer(0), c, 0, -1, 0);
  }
  for (const vtkIdType c : planeCells)
  {
    input->GetCellPoints(c, ids);
    std::vector<vtkIdType> key(ids->GetPointer(0), ids->GetPointer(0) + ids->GetNumberOfIds());
    if (!cellKept[layout.VolumeCells[faceOwner.at(SortedKey(key)).first]])
    {
      continue;
    }
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      ids->SetId(k, outOfInput[ids->GetId(k)]);
    }
    cells.Add(input->GetCellType(c), ids->GetNumberOfIds(), ids->GetPointer(0), c, 0, -1, 0);
  }
  // Per input volume cell: its index among the volume cells.
  std::vector<vtkIdType> volumeIndex(input->GetNumberOfCells(), -1);
  for (std::size_t k = 0; k < nVolume; ++k)
  {
    volumeIndex[layout.VolumeCells[k]] = static_cast<vtkIdType>(k);
  }
  for (const auto& w : wedges)
  {
    const vtkIdType k = w.Source >= 0 ? volumeIndex[w.Source] : -1;
    for (int s = 0; k >= 0 && s < 2; ++s)
    {
      auto it = planeCellOfKey.find(SortedKey(layout.Faces[k][s]));
      if (it == planeCellOfKey.end())
      {
        continue;
      }
      const bool quad = w.Face[s].size() == 4;
      cells.Add(quad ? VTK_QUAD : VTK_TRIANGLE, static_cast<vtkIdType>(w.Face[s].size()), w.Face[s].data(),
        it->second, 1, -1, 0);
      ++patchTriangles;
    }
  }
  cells.Commit();
  return true;
}

//------------------------------------------------------------------------------
bool Remesh2DRun::Fields()
{
  const vtkEmbeddedRemeshCells& cells = *cellsPtr;
  // ---- Fields: kept points and cells copy theirs; new points interpolate
  // in the input cell that contains them, new cells take their source's.
  if (self->GetInterpolateFields())
  {
    vtkPointData* outPD = output->GetPointData();
    vtkCellData* outCD = output->GetCellData();
    const std::vector<vtkIdType>& sourceCell = cells.Sources();
    outPD->InterpolateAllocate(input->GetPointData(), nOut);
    outCD->CopyAllocate(input->GetCellData(), static_cast<vtkIdType>(sourceCell.size()));
    std::vector<double> where(3 * (nOut - nKeptPoints));
    for (vtkIdType i = nKeptPoints; i < nOut; ++i)
    {
      points->GetPoint(i, &where[3 * (i - nKeptPoints)]);
    }
    const LocatedPoints pointIn = LocateInCells(cellLocator, tol2, where, true);
    vtkARFieldTransfer::TupleSources pointSources(nOut, LocatedPoints::Width), cellSources(
      static_cast<vtkIdType>(sourceCell.size()), 1);
    for (vtkIdType i = 0; i < nKeptPoints; ++i)
    {
      pointSources.Copy(i, pointSource[i]);
    }
    for (vtkIdType i = nKeptPoints; i < nOut; ++i)
    {
      const std::size_t q = static_cast<std::size_t>(i - nKeptPoints);
      pointSources.Interpolate(i, &pointIn.Ids[LocatedPoints::Width * q], &pointIn.Weights[LocatedPoints::Width * q],
        pointIn.Count[q]);
    }
    for (std::size_t k = 0; k < sourceCell.size(); ++k)
    {
      cellSources.Copy(static_cast<vtkIdType>(k), sourceCell[k]);
    }
    vtkARFieldTransfer::TransferData(input->GetPointData(), outPD, pointSources);
    vtkARFieldTransfer::TransferData(input->GetCellData(), outCD, cellSources);
  }
  return true;
}

//------------------------------------------------------------------------------
bool Remesh2DRun::Summary()
{
  vtkEmbeddedRemeshCells& cells = *cellsPtr;
  cells.Finish(layered);
  vtkEmbeddedRemeshSummary summary;
  summary.Quality = vtkEmbeddedRemeshAddQualityArrays(output, cells.Region(), axis);

  // ---- Field data and the embedded surface (quads: the extruded curve segments).
  summary.TwoDimensional = true;
  summary.KeptCells = static_cast<double>(keptCount);
  summary.NewCells = static_cast<double>(newCount);
  summary.InputNodes = static_cast<double>(nPoints);
  summary.OutputNodes = static_cast<double>(nOut);
  summary.NewNodes = static_cast<double>(nOut - nKeptPoints);
  summary.RemovedNodes = static_cast<double>(nPoints - nKeptPoints);
  summary.SurfaceElements = static_cast<double>(result.Curve.size() / 2);
  summary.SurfaceEdgeLength = edge;
  summary.InputSize = inputSize;
  {
    const std::vector<double> lvOut = ar::LongestPolygonEdgeAtNodes(result.Mesh.Points.data(), 2,
      result.Mesh.NumberOfPoints(), result.Mesh.Offsets.data(), result.Mesh.Connectivity.data(),
      result.Mesh.NumberOfCells());
    summary.OutputSize = ar::MedianAtNodes(lvOut, result.Curve.data(), result.Curve.size());
  }
  summary.MinTriangleAngleNew = result.MinAngleNew;
  summary.PatchTrianglesNew = static_cast<double>(patchTriangles);
  summary.LimitedColumns = static_cast<double>(result.LimitedColumns);
  summary.VolumeBefore = areaBefore;
  summary.VolumeAfter = areaAfter;
  summary.Write(output, options.Layers);
  vtkNew<vtkCellArray> quads;
  for (std::size_t s = 0; s < result.Curve.size(); s += 2)
  {
    const std::int64_t a = result.Curve[s], b = result.Curve[s + 1];
    const vtkIdType quad[4] = { pair[a][0], pair[b][0], pair[b][1], pair[a][1] };
    quads->InsertNextCell(4, quad);
  }
  embedded->Initialize();
  embedded->SetPoints(points);
  embedded->SetPolys(quads);

  if (planes)
  {
    planes->Valid = true;
    planes->Input = input;
    planes->Output = output;
    planes->FaceOwner.clear();
    planes->CellFaceKey.assign(input->GetNumberOfCells(), {});
    for (std::size_t k = 0; k < nVolume; ++k)
    {
      for (int s = 0; s < 2; ++s)
      {
        const auto key = SortedKey(layout.Faces[k][s]);
        planes->FaceOwner[key] = layout.VolumeCells[k];
        planes->CellFaceKey[layout.VolumeCells[k]][s] = key;
      }
    }
    planes->CellKept = cellKept;
    for (vtkIdType c = 0; c < input->GetNumberOfCells(); ++c)
    {
      planes->CellKept[c] = planes->CellKept[c] || !isVolume[c];
    }
    planes->Wedges = wedges;
  }
  return true;
}
}

//------------------------------------------------------------------------------
int vtkEmbeddedRemesh::Remesh2D(vtkUnstructuredGrid* input, const vtkEmbeddedRemeshLayout& layout,
  const std::vector<vtkDataSet*>& surfaces, vtkUnstructuredGrid* output, vtkPolyData* embedded,
  vtkEmbeddedRemeshPlanes* planes)
{
  Remesh2DRun run(this, input, layout, surfaces, output, embedded, planes);
  bool cancelled = false;
  auto proceed = [&](double progress) {
    this->UpdateProgress(progress);
    cancelled = this->CheckAbort();
    return !cancelled;
  };
  const bool done = run.Section() && run.Curve() && proceed(0.3) && run.Cavity() && proceed(0.7) &&
    run.OutputPoints() && run.LocateCentres() && run.Cells() && run.Fields() && run.Summary();
  if (cancelled)
  {
    output->ShallowCopy(input);
    return 1;
  }
  if (!done)
  {
    vtkErrorMacro(<< "EmbeddedRemesh (2-D mode): " << run.Problem << " The input passes through unchanged.");
    output->ShallowCopy(input);
    embedded->Initialize();
    return 1;
  }
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkPolyData> vtkEmbeddedRemeshRebuildPatch(vtkPolyData* leaf, const vtkEmbeddedRemeshPlanes& planes)
{
  if (!planes.Valid || !leaf || leaf->GetNumberOfCells() == 0 || !leaf->GetPoints())
  {
    return nullptr;
  }
  // The leaf's points as input volume points (by coordinates).
  std::map<Coord, vtkIdType> inputPoint, leafPoint;
  for (vtkIdType i = 0; i < planes.Input->GetNumberOfPoints(); ++i)
  {
    double x[3];
    planes.Input->GetPoint(i, x);
    inputPoint.emplace(Coord{ x[0], x[1], x[2] }, i);
  }
  for (vtkIdType i = 0; i < leaf->GetNumberOfPoints(); ++i)
  {
    double x[3];
    leaf->GetPoint(i, x);
    leafPoint.emplace(Coord{ x[0], x[1], x[2] }, i);
  }
  std::vector<vtkIdType> keptFaces;
  std::map<std::vector<vtkIdType>, vtkIdType> removedFace; // key -> leaf cell
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < leaf->GetNumberOfCells(); ++c)
  {
    leaf->GetCellPoints(c, ids);
    std::vector<vtkIdType> key;
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      double x[3];
      leaf->GetPoint(ids->GetId(k), x);
      auto it = inputPoint.find(Coord{ x[0], x[1], x[2] });
      if (it == inputPoint.end())
      {
        break;
      }
      key.push_back(it->second);
    }
    std::sort(key.begin(), key.end());
    auto owner = key.size() == static_cast<std::size_t>(ids->GetNumberOfIds()) ? planes.FaceOwner.find(key)
                                                                               : planes.FaceOwner.end();
    if (owner != planes.FaceOwner.end() && !planes.CellKept[owner->second])
    {
      removedFace[key] = c;
    }
    else
    {
      keptFaces.push_back(c);
    }
  }
  if (removedFace.empty())
  {
    return nullptr;
  }
  // The new triangles of this leaf and their source faces.
  std::vector<std::pair<std::vector<vtkIdType>, vtkIdType>> added;
  for (const auto& w : planes.Wedges)
  {
    for (int s = 0; w.Source >= 0 && s < 2; ++s)
    {
      auto it = removedFace.find(planes.CellFaceKey[w.Source][s]);
      if (it != removedFace.end())
      {
        added.emplace_back(w.Face[s], it->second);
      }
    }
  }
  // Points: the leaf's points still used (its order), then new ones.
  auto out = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble(); // the new points exactly as in the volume
  std::vector<vtkIdType> outOfLeaf(leaf->GetNumberOfPoints(), -1), source;
  for (const vtkIdType c : keptFaces)
  {
    leaf->GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      outOfLeaf[ids->GetId(k)] = 0;
    }
  }
  std::map<vtkIdType, vtkIdType> outOfVolume; // remeshed volume point -> leaf output point
  for (const auto& a : added)
  {
    for (const vtkIdType p : a.first)
    {
      double x[3];
      planes.Output->GetPoint(p, x);
      auto it = leafPoint.find(Coord{ x[0], x[1], x[2] });
      if (it != leafPoint.end())
      {
        outOfLeaf[it->second] = 0;
      }
    }
  }
  for (vtkIdType i = 0; i < leaf->GetNumberOfPoints(); ++i)
  {
    if (outOfLeaf[i] == 0)
    {
      outOfLeaf[i] = points->InsertNextPoint(leaf->GetPoint(i));
      source.push_back(i);
    }
  }
  for (const auto& a : added)
  {
    for (const vtkIdType p : a.first)
    {
      double x[3];
      planes.Output->GetPoint(p, x);
      auto it = leafPoint.find(Coord{ x[0], x[1], x[2] });
      if (it == leafPoint.end() && outOfVolume.count(p) == 0)
      {
        outOfVolume[p] = points->InsertNextPoint(x);
        source.push_back(-1);
      }
    }
  }
  out->SetPoints(points);
  vtkNew<vtkCellArray> polys;
  std::vector<vtkIdType> cellSource;
  for (const vtkIdType c : keptFaces)
  {
    leaf->GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      ids->SetId(k, outOfLeaf[ids->GetId(k)]);
    }
    polys->InsertNextCell(ids);
    cellSource.push_back(c);
  }
  for (const auto& a : added)
  {
    std::vector<vtkIdType> face(a.first.size());
    for (std::size_t k = 0; k < face.size(); ++k)
    {
      double x[3];
      planes.Output->GetPoint(a.first[k], x);
      auto it = leafPoint.find(Coord{ x[0], x[1], x[2] });
      face[k] = it != leafPoint.end() ? outOfLeaf[it->second] : outOfVolume.at(a.first[k]);
    }
    polys->InsertNextCell(static_cast<vtkIdType>(face.size()), face.data());
    cellSource.push_back(a.second);
  }
  out->SetPolys(polys);
  // Fields: kept points and faces copy theirs; new points interpolate in the
  // leaf, new faces take the face they replace.
  out->GetPointData()->InterpolateAllocate(leaf->GetPointData(), points->GetNumberOfPoints());
  out->GetCellData()->CopyAllocate(leaf->GetCellData(), static_cast<vtkIdType>(cellSource.size()));
  vtkNew<vtkStaticCellLocator> locator;
  locator->SetDataSet(leaf);
  locator->BuildLocator();
  vtkNew<vtkGenericCell> cell;
  std::vector<double> weights(VTK_CELL_SIZE);
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
  {
    double x[3];
    points->GetPoint(i, x);
    InterpolatePointData(leaf, locator, out->GetPointData(), source[i], x, i, cell, weights);
  }
  for (std::size_t k = 0; k < cellSource.size(); ++k)
  {
    out->GetCellData()->CopyData(leaf->GetCellData(), cellSource[k], static_cast<vtkIdType>(k));
  }
  out->GetFieldData()->ShallowCopy(leaf->GetFieldData());
  return out;
}
