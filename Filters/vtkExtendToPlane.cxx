// SPDX-License-Identifier: BSD-3-Clause
#include "vtkExtendToPlane.h"
#include "vtkARInputChecks.h"
#include "vtkARMeshKernels.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCleanPolyData.h"
#include "vtkPlane.h"
#include "vtkPolyDataPlaneClipper.h"
#include "vtkDataSet.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkGeometryFilter.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkTriangleFilter.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkExtendToPlane);

namespace
{
bool Finite3(const double v[3])
{
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

/// Polygons of `input` as triangles with exactly coincident points merged
/// (degenerate triangles dropped); verts and lines are dropped.
vtkSmartPointer<vtkPolyData> CleanTriangles(vtkPolyData* input)
{
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputData(input);
  triangles->PassVertsOff();
  triangles->PassLinesOff();
  vtkNew<vtkCleanPolyData> clean;
  clean->SetInputConnection(triangles->GetOutputPort());
  clean->PointMergingOn();
  clean->SetTolerance(0.0);
  clean->ConvertLinesToPointsOff();
  clean->ConvertPolysToLinesOff();
  clean->ConvertStripsToPolysOff();
  clean->Update();
  auto result = vtkSmartPointer<vtkPolyData>::New();
  result->ShallowCopy(clean->GetOutput());
  return result;
}

struct Edge
{
  vtkIdType lo, hi; // sorted point ids
  vtkIdType cell;   // a polygon using the edge
  vtkIdType from;   // the polygon's edge runs from -> to
  vtkIdType to;
};

//------------------------------------------------------------------------------
/**
 * ExtendToPlane's run: the stages of vtkExtendToPlane::RequestData over the
 * state they share (as Remesh2DRun in vtkEmbeddedRemesh2D.cxx; file-local,
 * so its members keep the names the stages had as locals). A stage returns
 * false when the run ends there, after an error (the output empty);
 * RequestData checks for cancelling between the stages.
 */
class ExtendRun
{
public:
  ExtendRun(vtkExtendToPlane* self_, vtkDataSet* input_, vtkPolyData* output_, vtkIdType& numberOfExtendedEdges_)
    : self(self_)
    , input(input_)
    , output(output_)
    , numberOfExtendedEdges(numberOfExtendedEdges_)
    , o(self_->GetPlaneOrigin())
  {
  }
  bool Parameters();   ///< the plane and the ranges checked
  bool Triangles();    ///< the input's polygons as clean triangles
  void Side();         ///< the normal towards the side the surface lies on
  bool Trim();         ///< what lies farther than TrimDistance from the plane
  void Edges();        ///< the open edges, the mean edge length, the gap
  bool Columns();      ///< the edges extended, the rows of their end points' columns
  void OutputPoints(); ///< the surface's points, then the columns'
  void OutputCells();  ///< the surface's polygons, then the strips; the field data

private:
  bool Fail(const std::string& message)
  {
    vtkErrorWithObjectMacro(self, << "ExtendToPlane: " << message);
    return false;
  }
  double SignedDistance(const double x[3]) const
  {
    return n[0] * (x[0] - o[0]) + n[1] * (x[1] - o[1]) + n[2] * (x[2] - o[2]);
  }

  vtkExtendToPlane* self;
  vtkDataSet* input;
  vtkPolyData* output;
  vtkIdType& numberOfExtendedEdges;
  const double* o;
  double n[3] = { 0.0, 0.0, 0.0 };
  // Triangles, Trim
  vtkSmartPointer<vtkPolyData> surface;
  vtkPoints* points = nullptr;
  // Edges
  vtkIdType numPoints = 0;
  std::vector<double> s;
  std::vector<Edge> open;
  double h = 0.0, onPlane = 0.0, gap = 0.0;
  // Columns, OutputPoints
  std::vector<Edge> extended;
  std::vector<vtkIdType> rows;
  double newPoints = 0.0;
  std::vector<std::vector<vtkIdType>> column;
};

//------------------------------------------------------------------------------
bool ExtendRun::Parameters()
{
  // ---- Parameters.
  const double* normal = self->GetPlaneNormal();
  if (!Finite3(normal) || !Finite3(o))
  {
    return Fail("PlaneOrigin or PlaneNormal is not finite (NaN or Inf); the output is empty.");
  }
  std::copy(normal, normal + 3, n);
  if (vtkMath::Normalize(n) <= 0.0)
  {
    return Fail("PlaneNormal is zero; the output is empty.");
  }
  vtkARInputChecks::Properties ranges;
  ranges.InRange("TrimDistance", self->GetTrimDistance(), 0.0, VTK_DOUBLE_MAX)
    .InRange("MaximumGap", self->GetMaximumGap(), 0.0, VTK_DOUBLE_MAX, "0 automatic");
  if (!ranges.Ok())
  {
    return Fail(ranges.Message() + "The output is empty.");
  }
  if (!input || input->GetNumberOfCells() == 0)
  {
    return Fail("the input has no cells; the output is empty.");
  }
  return true;
}

//------------------------------------------------------------------------------
bool ExtendRun::Triangles()
{
  // ---- Triangles of the input.
  auto asPoly = vtkSmartPointer<vtkPolyData>::New();
  if (auto* pd = vtkPolyData::SafeDownCast(input))
  {
    asPoly->ShallowCopy(pd);
  }
  else
  {
    vtkNew<vtkGeometryFilter> geometry;
    geometry->SetInputData(input);
    geometry->Update();
    asPoly->ShallowCopy(geometry->GetOutput());
  }
  surface = CleanTriangles(asPoly);
  if (surface->GetNumberOfPolys() == 0)
  {
    return Fail("the input has no polygons (a surface is needed); the output is empty.");
  }
  const std::string nonFinite = vtkARInputChecks::NonFinitePoints(surface, "the surface");
  if (!nonFinite.empty())
  {
    return Fail(nonFinite + "The output is empty.");
  }
  points = surface->GetPoints();
  return true;
}

//------------------------------------------------------------------------------
void ExtendRun::Side()
{
  // ---- Side: flip the normal when the surface lies mostly behind the plane
  // (area-weighted mean signed distance negative).
  double moment = 0.0;
  vtkIdType npts;
  const vtkIdType* ids;
  vtkCellArray* polys = surface->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
  {
    double a[3], b[3], c[3];
    points->GetPoint(ids[0], a);
    points->GetPoint(ids[1], b);
    points->GetPoint(ids[2], c);
    double u[3], v[3], w[3];
    for (int k = 0; k < 3; ++k)
    {
      u[k] = b[k] - a[k];
      v[k] = c[k] - a[k];
    }
    vtkMath::Cross(u, v, w);
    const double area = 0.5 * vtkMath::Norm(w);
    double centroid[3];
    for (int k = 0; k < 3; ++k)
    {
      centroid[k] = (a[k] + b[k] + c[k]) / 3.0 - o[k];
    }
    moment += area * vtkMath::Dot(centroid, n);
  }
  if (moment < 0.0)
  {
    n[0] = -n[0];
    n[1] = -n[1];
    n[2] = -n[2];
  }
}

//------------------------------------------------------------------------------
bool ExtendRun::Trim()
{
  // ---- Trim: keep s > TrimDistance.
  const double trim = self->GetTrimDistance();
  bool needsClip = false;
  for (vtkIdType i = 0; i < points->GetNumberOfPoints() && !needsClip; ++i)
  {
    double x[3];
    points->GetPoint(i, x);
    needsClip = SignedDistance(x) <= trim;
  }
  if (needsClip)
  {
    // vtkPolyDataPlaneClipper keeps the normal's side and cuts exactly
    // (vtkClipPolyData interpolates in single precision).
    vtkNew<vtkPlane> plane;
    plane->SetOrigin(o[0] + trim * n[0], o[1] + trim * n[1], o[2] + trim * n[2]);
    plane->SetNormal(n);
    vtkNew<vtkPolyDataPlaneClipper> clip;
    clip->SetInputData(surface);
    clip->SetPlane(plane);
    clip->CappingOff();
    clip->Update();
    surface = CleanTriangles(clip->GetOutput());
    points = surface->GetPoints();
    if (surface->GetNumberOfPolys() == 0)
    {
      vtkErrorWithObjectMacro(self, "ExtendToPlane: nothing of the surface lies farther than TrimDistance = "
        << trim << " from the plane on the normal's side; the output is empty.");
      return false;
    }
  }
  return true;
}

//------------------------------------------------------------------------------
void ExtendRun::Edges()
{
  // ---- Edges: sorted (lo, hi) pairs; open edges are used by one polygon.
  numPoints = surface->GetNumberOfPoints();
  s.resize(numPoints);
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    double x[3];
    points->GetPoint(i, x);
    s[i] = SignedDistance(x);
  }
  std::vector<Edge> edges;
  edges.reserve(3 * surface->GetNumberOfPolys());
  {
    vtkIdType npts;
    const vtkIdType* ids;
    vtkCellArray* polys = surface->GetPolys();
    vtkIdType cell = 0;
    for (polys->InitTraversal(); polys->GetNextCell(npts, ids); ++cell)
    {
      for (vtkIdType k = 0; k < npts; ++k)
      {
        const vtkIdType a = ids[k], b = ids[(k + 1) % npts];
        edges.push_back({ std::min(a, b), std::max(a, b), cell, a, b });
      }
    }
  }
  std::sort(edges.begin(), edges.end(),
    [](const Edge& p, const Edge& q) { return p.lo < q.lo || (p.lo == q.lo && p.hi < q.hi); });
  double lengthSum = 0.0;
  vtkIdType uniqueEdges = 0;
  for (std::size_t i = 0; i < edges.size();)
  {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi)
    {
      ++j;
    }
    double a[3], b[3];
    points->GetPoint(edges[i].lo, a);
    points->GetPoint(edges[i].hi, b);
    lengthSum += std::sqrt(vtkMath::Distance2BetweenPoints(a, b));
    ++uniqueEdges;
    if (j - i == 1)
    {
      open.push_back(edges[i]);
    }
    i = j;
  }
  h = lengthSum / static_cast<double>(uniqueEdges);
  onPlane = 1e-9 * h;
  double smin = VTK_DOUBLE_MAX;
  for (const Edge& e : open)
  {
    smin = std::min(smin, std::min(s[e.lo], s[e.hi]));
  }
  gap = self->GetMaximumGap() > 0.0 ? self->GetMaximumGap() : (open.empty() ? 0.0 : smin + h);
}

//------------------------------------------------------------------------------
bool ExtendRun::Columns()
{
  // ---- Columns at the end points of the extended edges.
  for (const Edge& e : open)
  {
    // Side edges leaving the plane at more than 30 degrees are not extended.
    double a[3], b[3];
    points->GetPoint(e.lo, a);
    points->GetPoint(e.hi, b);
    const double length = std::sqrt(vtkMath::Distance2BetweenPoints(a, b));
    // Only where the surface ends towards the plane: the polygon that owns the
    // edge lies farther from the plane than the edge (an edge at the far end
    // of a narrow sheet, within the gap as well, faces away from the plane).
    vtkIdType npts;
    const vtkIdType* ids;
    surface->GetPolys()->GetCellAtId(e.cell, npts, ids);
    double sPoly = 0.0;
    for (vtkIdType k = 0; k < npts; ++k)
    {
      sPoly += s[ids[k]];
    }
    sPoly /= static_cast<double>(npts);
    const bool facesPlane = sPoly > 0.5 * (s[e.lo] + s[e.hi]) + onPlane;
    if (facesPlane && s[e.lo] <= gap && s[e.hi] <= gap && (s[e.lo] > onPlane || s[e.hi] > onPlane) &&
      std::abs(s[e.lo] - s[e.hi]) <= 0.5 * length)
    {
      extended.push_back(e);
    }
  }
  numberOfExtendedEdges = static_cast<vtkIdType>(extended.size());
  rows.assign(numPoints, -1); // -1: no column
  for (const Edge& e : extended)
  {
    for (vtkIdType v : { e.lo, e.hi })
    {
      if (rows[v] < 0)
      {
        const double k = s[v] > onPlane ? std::max(1.0, std::ceil(s[v] / h - 1e-9)) : 0.0;
        newPoints += k;
        rows[v] = static_cast<vtkIdType>(std::min(k, 1e12));
      }
    }
  }
  if (newPoints > 1e7)
  {
    vtkErrorWithObjectMacro(self, "ExtendToPlane: the strips would need " << newPoints
                                                          << " points (over 10 million): the "
                                                             "surface is far from the plane for its "
                                                             "edge length; the output is empty.");
    numberOfExtendedEdges = 0;
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
void ExtendRun::OutputPoints()
{
  // ---- Output: the surface, then the columns' points.
  vtkNew<vtkPoints> outPoints;
  outPoints->SetDataType(VTK_DOUBLE);
  outPoints->Allocate(numPoints + static_cast<vtkIdType>(newPoints));
  vtkPointData* inPD = surface->GetPointData();
  vtkPointData* outPD = output->GetPointData();
  outPD->CopyAllocate(inPD, numPoints + static_cast<vtkIdType>(newPoints));
  for (vtkIdType i = 0; i < numPoints; ++i)
  {
    outPoints->InsertNextPoint(points->GetPoint(i));
    outPD->CopyData(inPD, i, i);
  }
  column.resize(numPoints);
  for (vtkIdType v = 0; v < numPoints; ++v)
  {
    if (rows[v] < 0)
    {
      continue;
    }
    column[v].push_back(v);
    double x[3];
    points->GetPoint(v, x);
    for (vtkIdType j = 1; j <= rows[v]; ++j)
    {
      const double t = j == rows[v] ? s[v] : s[v] * static_cast<double>(j) / rows[v];
      const double y[3] = { x[0] - t * n[0], x[1] - t * n[1], x[2] - t * n[2] };
      const vtkIdType id = outPoints->InsertNextPoint(y);
      outPD->CopyData(inPD, v, id);
      column[v].push_back(id);
    }
  }
  output->SetPoints(outPoints);
}

//------------------------------------------------------------------------------
void ExtendRun::OutputCells()
{
  vtkNew<vtkCellArray> outPolys;
  vtkCellData* inCD = surface->GetCellData();
  vtkCellData* outCD = output->GetCellData();
  const vtkIdType numCells = surface->GetNumberOfPolys();
  outCD->CopyAllocate(inCD, numCells);
  vtkNew<vtkUnsignedCharArray> flag;
  flag->SetName("Extended");
  flag->Allocate(numCells);
  {
    vtkIdType npts;
    const vtkIdType* ids;
    vtkCellArray* polys = surface->GetPolys();
    vtkIdType cell = 0;
    for (polys->InitTraversal(); polys->GetNextCell(npts, ids); ++cell)
    {
      const vtkIdType id = outPolys->InsertNextCell(npts, ids);
      outCD->CopyData(inCD, cell, id);
      flag->InsertNextValue(0);
    }
  }
  for (const Edge& e : extended)
  {
    // The owner runs from -> to; the strip runs to -> from beside it:
    // quad (to_0, from_0, from_end, to_end), zipped between the columns.
    const std::vector<vtkIdType>& A = column[e.from];
    const std::vector<vtkIdType>& B = column[e.to];
    const std::size_t ka = A.size() - 1, kb = B.size() - 1;
    std::size_t i = 0, j = 0;
    while (i < ka || j < kb)
    {
      vtkIdType tri[3];
      if (j == kb || (i < ka && (i + 1) * kb <= (j + 1) * ka))
      {
        tri[0] = B[j];
        tri[1] = A[i];
        tri[2] = A[i + 1];
        ++i;
      }
      else
      {
        tri[0] = B[j];
        tri[1] = A[i];
        tri[2] = B[j + 1];
        ++j;
      }
      const vtkIdType id = outPolys->InsertNextCell(3, tri);
      outCD->CopyData(inCD, e.cell, id);
      flag->InsertNextValue(1);
    }
  }
  output->SetPolys(outPolys);
  outCD->AddArray(flag);
  output->GetFieldData()->PassData(input->GetFieldData());
  output->GetFieldData()->AddArray(vtkARMeshKernels::FieldArray("ExtendPlaneNormal", n, 3));
  output->GetFieldData()->AddArray(vtkARMeshKernels::FieldArray("ExtendMeanEdgeLength", &h, 1));
  output->GetFieldData()->AddArray(vtkARMeshKernels::FieldArray("ExtendMaximumGap", &gap, 1));
  const double count = static_cast<double>(numberOfExtendedEdges);
  output->GetFieldData()->AddArray(vtkARMeshKernels::FieldArray("NumberOfExtendedEdges", &count, 1));
  if (extended.empty())
  {
    vtkWarningWithObjectMacro(self, "ExtendToPlane: no open boundary edge lies within MaximumGap = "
      << gap << " of the plane; nothing was extended.");
  }
}
}

vtkExtendToPlane::vtkExtendToPlane() = default;

int vtkExtendToPlane::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  return 1;
}

int vtkExtendToPlane::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* input = vtkDataSet::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  this->NumberOfExtendedEdges = 0;
  ExtendRun run(this, input, output, this->NumberOfExtendedEdges);
  // A stage that fails has said why; the output is then empty.
  auto proceed = [&](double progress, bool abortable) {
    this->UpdateProgress(progress);
    return !abortable || !this->CheckAbort();
  };
  if (!(run.Parameters() && run.Triangles() && proceed(0.2, false)))
  {
    return 1;
  }
  run.Side();
  if (!(run.Trim() && !this->CheckAbort() && proceed(0.4, false)))
  {
    return 1;
  }
  run.Edges();
  if (run.Columns())
  {
    run.OutputPoints();
    this->UpdateProgress(0.7);
    run.OutputCells();
    this->UpdateProgress(1.0);
  }
  return 1;
}

void vtkExtendToPlane::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "PlaneOrigin: " << this->PlaneOrigin[0] << " " << this->PlaneOrigin[1] << " "
     << this->PlaneOrigin[2] << "\n";
  os << indent << "PlaneNormal: " << this->PlaneNormal[0] << " " << this->PlaneNormal[1] << " "
     << this->PlaneNormal[2] << "\n";
  os << indent << "TrimDistance: " << this->TrimDistance << "\n";
  os << indent << "MaximumGap: " << this->MaximumGap << "\n";
}
