// SPDX-License-Identifier: BSD-3-Clause
#include "vtkMedialAxisDelaunay.h"

#include "ARMedialAxis.h"
#include "vtkARInputChecks.h"
#include "vtkARMeshKernels.h"
#include "vtkARParallel.h"

#include "vtkCellArray.h"
#include "vtkCallbackCommand.h"
#include "vtkCell.h"
#include "vtkCellData.h"
#include "vtkClipPolyData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkExtendToPlane.h"
#include "vtkFeatureEdges.h"
#include "vtkFieldData.h"
#include "vtkFillHolesFilter.h"
#include "vtkGeometryFilter.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPlane.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataNormals.h"
#include "vtkSmartPointer.h"
#include "vtkSmoothPolyDataFilter.h"
#include "vtkTriangle.h"
#include "vtkTriangleFilter.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWindowedSincPolyDataFilter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkMedialAxisDelaunay);

namespace
{
vtkMultiProcessController* Controller()
{
  vtkMultiProcessController* c = vtkMultiProcessController::GetGlobalController();
  return (c && c->GetNumberOfProcesses() > 1) ? c : nullptr;
}

/// This rank's surface without the triangles of ghost cells, as polydata.
vtkSmartPointer<vtkPolyData> LocalSurface(vtkDataSet* input)
{
  auto surface = vtkSmartPointer<vtkPolyData>::New();
  if (!input || input->GetNumberOfCells() == 0)
  {
    return surface;
  }
  vtkPolyData* pd = vtkPolyData::SafeDownCast(input);
  if (!pd)
  {
    vtkNew<vtkGeometryFilter> geometry;
    geometry->SetInputData(input);
    geometry->Update();
    surface->ShallowCopy(geometry->GetOutput());
    return surface;
  }
  vtkUnsignedCharArray* ghosts = pd->GetCellGhostArray();
  if (!ghosts)
  {
    surface->ShallowCopy(pd);
    return surface;
  }
  // The triangles of ghost cells belong to another rank (vtkGeometryFilter
  // keeps them for polydata input).
  vtkNew<vtkCellArray> owned;
  vtkIdType npts;
  const vtkIdType* ids;
  vtkCellArray* polys = pd->GetPolys();
  const vtkIdType offset = pd->GetNumberOfVerts() + pd->GetNumberOfLines();
  vtkIdType cell = offset;
  for (polys->InitTraversal(); polys->GetNextCell(npts, ids); ++cell)
  {
    if (!(ghosts->GetValue(cell) & vtkDataSetAttributes::DUPLICATECELL))
    {
      owned->InsertNextCell(npts, ids);
    }
  }
  surface->SetPoints(pd->GetPoints());
  surface->GetPointData()->ShallowCopy(pd->GetPointData());
  surface->SetPolys(owned);
  return surface;
}

const char* CellKind(int npts)
{
  return npts == 4 ? "quadrilateral" : "polygon";
}

/**
 * Symmetry planes picked from the domain's planar boundary patches: a patch
 * (boundary triangles sharing one plane, at least 0.5 % of the boundary's
 * area) is taken when at least 10 % of the feature surface's open-edge points
 * lie on it and the surface meets it at a right angle there (mean |n . N|
 * below sin 15 degrees over those points, n the surface normals): fields have
 * no normal gradient at a symmetry plane, so their isosurfaces stand on it
 * orthogonally, while a shock that leaves through an outlet or meets a wall
 * crosses it at an angle. (A zero-gradient outlet bends the isosurface to a
 * right angle in the last cell too: the 10 % keeps the few points where a
 * shock crosses it out.)
 */
std::vector<double> SymmetryPlanesFromBoundary(vtkPolyData* boundary, const std::vector<double>& points,
  const std::vector<double>& normals, const std::vector<std::int64_t>& triangles, double diagonal)
{
  struct Patch
  {
    double Area = 0.0;
    double Normal[3] = { 0.0, 0.0, 0.0 };
    double Offset = 0.0;
  };
  std::map<std::array<long long, 4>, Patch> patches;
  double total = 0.0;
  vtkIdType npts;
  const vtkIdType* ids;
  vtkCellArray* polys = boundary->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
  {
    if (npts != 3)
    {
      continue;
    }
    double a[3], b[3], c[3], n[3];
    boundary->GetPoint(ids[0], a);
    boundary->GetPoint(ids[1], b);
    boundary->GetPoint(ids[2], c);
    vtkTriangle::ComputeNormal(a, b, c, n);
    const double area = vtkTriangle::TriangleArea(a, b, c);
    if (!(area > 0.0))
    {
      continue;
    }
    int big = 0;
    for (int k = 1; k < 3; ++k)
    {
      big = std::abs(n[k]) > std::abs(n[big]) ? k : big;
    }
    if (n[big] < 0.0)
    {
      n[0] = -n[0];
      n[1] = -n[1];
      n[2] = -n[2];
    }
    const double d = vtkMath::Dot(n, a);
    const std::array<long long, 4> key = { std::llround(n[0] * 1e4), std::llround(n[1] * 1e4),
      std::llround(n[2] * 1e4), std::llround(d / (1e-5 * diagonal)) };
    Patch& p = patches[key];
    p.Area += area;
    for (int k = 0; k < 3; ++k)
    {
      p.Normal[k] += area * n[k];
    }
    p.Offset += area * d;
    total += area;
  }
  // The points on open edges of the feature surface.
  std::map<std::pair<std::int64_t, std::int64_t>, int> edgeUse;
  for (std::size_t t = 0; t < triangles.size(); t += 3)
  {
    for (int k = 0; k < 3; ++k)
    {
      const std::int64_t u = triangles[t + k], v = triangles[t + (k + 1) % 3];
      ++edgeUse[{ std::min(u, v), std::max(u, v) }];
    }
  }
  std::set<std::int64_t> open;
  for (const auto& e : edgeUse)
  {
    if (e.second == 1)
    {
      open.insert(e.first.first);
      open.insert(e.first.second);
    }
  }
  std::vector<double> planes;
  for (auto& entry : patches)
  {
    Patch& p = entry.second;
    if (p.Area < 0.005 * total)
    {
      continue;
    }
    vtkMath::Normalize(p.Normal);
    const double d = p.Offset / p.Area;
    int on = 0;
    double dots = 0.0;
    for (std::int64_t i : open)
    {
      if (std::abs(vtkMath::Dot(p.Normal, &points[3 * i]) - d) <= 1e-5 * diagonal)
      {
        ++on;
        dots += std::abs(vtkMath::Dot(p.Normal, &normals[3 * i]));
      }
    }
    if (on >= 3 && on >= 0.1 * static_cast<double>(open.size()) &&
      dots / on < std::sin(vtkMath::RadiansFromDegrees(15.0)))
    {
      planes.insert(planes.end(), { d * p.Normal[0], d * p.Normal[1], d * p.Normal[2], p.Normal[0],
                                    p.Normal[1], p.Normal[2] });
    }
  }
  return planes;
}
}

//------------------------------------------------------------------------------
vtkMedialAxisDelaunay::vtkMedialAxisDelaunay()
{
  this->SetNumberOfInputPorts(2);
}

//------------------------------------------------------------------------------
void vtkMedialAxisDelaunay::SetNumberOfSymmetryPlaneValues(int n)
{
  n = std::max(0, n);
  if (static_cast<int>(this->SymmetryPlanes.size()) != n)
  {
    this->SymmetryPlanes.resize(n, 0.0);
    this->Modified();
  }
}

void vtkMedialAxisDelaunay::SetSymmetryPlaneValue(int i, double value)
{
  if (i >= static_cast<int>(this->SymmetryPlanes.size()))
  {
    this->SymmetryPlanes.resize(i + 1, 0.0);
  }
  if (i >= 0 && this->SymmetryPlanes[i] != value)
  {
    this->SymmetryPlanes[i] = value;
    this->Modified();
  }
}

void vtkMedialAxisDelaunay::AddSymmetryPlane(const double origin[3], const double normal[3])
{
  this->SymmetryPlanes.insert(
    this->SymmetryPlanes.end(), { origin[0], origin[1], origin[2], normal[0], normal[1], normal[2] });
  this->Modified();
}

void vtkMedialAxisDelaunay::RemoveAllSymmetryPlanes()
{
  if (!this->SymmetryPlanes.empty())
  {
    this->SymmetryPlanes.clear();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
int vtkMedialAxisDelaunay::FillInputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  if (port == 1)
  {
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

//------------------------------------------------------------------------------
//------------------------------------------------------------------------------
/// The state of one execution, shared by the passes of RequestData.
struct vtkMedialAxisDelaunay::SheetState
{
  bool HasDomain = false;
  vtkPolyData* Output = nullptr;
  /// The input surface (gathered on rank 0) and the Domain's boundary.
  vtkSmartPointer<vtkPolyData> Surface;
  vtkSmartPointer<vtkPolyData> Boundary;
  vtkIdType NumberOfCells = 0;
  vtkIdType NumberOfPoints = 0;
  /// The (smoothed) surface; the input's normals, if any.
  vtkSmartPointer<vtkPolyData> Work;
  vtkDataArray* GivenNormals = nullptr;
  /// The core's input: points, oriented normals, triangles, domain, options.
  std::vector<double> Points;
  std::vector<double> Normals;
  std::vector<std::int64_t> Triangles;
  ar::ClosedSurface Closed;
  ar::MedialAxisOptions Options;
  /// The core's output and the polydata made of it.
  ar::MedialSheet Sheet;
  vtkIdType NumberOfTriangles = 0;
  vtkNew<vtkIntArray> SheetId;
  vtkNew<vtkPolyData> Result;
  std::vector<double> SheetAreas;
  double MedianEdge = 0.0;
};

//------------------------------------------------------------------------------
bool vtkMedialAxisDelaunay::Fail(SheetState& st, const std::string& message)
{
  vtkErrorMacro(<< message << " The output is empty.");
  st.Output->Initialize();
  return false;
}

int vtkMedialAxisDelaunay::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // The passes below share the state of this execution (SheetState).
  SheetState st;

  vtkDataSet* input = vtkDataSet::GetData(inputVector[0], 0);
  st.HasDomain = this->GetNumberOfInputConnections(1) > 0;
  vtkDataSet* domain = st.HasDomain ? vtkDataSet::GetData(inputVector[1], 0) : nullptr;
  st.Output = vtkPolyData::GetData(outputVector, 0);
  st.Output->Initialize();
  vtkMultiProcessController* ctrl = Controller();
  const bool root = !ctrl || ctrl->GetLocalProcessId() == 0;

  // Collective steps first, so that every rank reaches them.
  // Both ranks interpolate the contour points on the edges of their shared
  // faces, which can differ in the last bits: merge within 1e-9 of the
  // bounding-box diagonal.
  st.Surface = vtkARParallel::GatherPolyData(LocalSurface(input), 1e-9, false);
  if (st.HasDomain)
  {
    st.Boundary = vtkARParallel::GatherDomainBoundary(domain);
  }
  if (!root)
  {
    return 1;
  }

  vtkARInputChecks::Properties ranges;
  ranges.OneOf("Smoothing", this->Smoothing, { "None", "Windowed Sinc", "Laplacian" })
    .InRange("SmoothingIterations", this->SmoothingIterations, 0, 10000)
    .AboveAndAtMost("PassBand", this->PassBand, 0.0, 2.0)
    .InRange("RelaxationFactor", this->RelaxationFactor, 0.0, 1.0)
    .OneOf("FeatureRegion", this->FeatureRegion, { "Above Iso-Value", "Below Iso-Value" })
    .InRange("MinimumObjectAngle", this->MinimumObjectAngle, 0.0, 180.0, "degrees")
    .InRange("MinimumRadiusFactor", this->MinimumRadiusFactor, 0.0, 1e6)
    .InRange("MinimumAreaFraction", this->MinimumAreaFraction, 0.0, 1.0)
    .InRange("MaximumNumberOfSheets", this->MaximumNumberOfSheets, 0, VTK_INT_MAX, "0: no limit")
    .InRange("SymmetryTrimDistance", this->SymmetryTrimDistance, 0.0, VTK_DOUBLE_MAX)
    .InRange("MaximumHoleSize", this->MaximumHoleSize, 0.0, 1e6);
  if (!ranges.Ok())
  {
    std::string text = ranges.Message();
    text.pop_back();
    this->Fail(st, "MedialAxisDelaunay: " + text);
    return 1;
  }

  if (!this->CheckSurface(st))
  {
    return 1;
  }
  if (!this->SmoothSurface(st))
  {
    return 1;
  }
  if (!this->OrientNormals(st))
  {
    return 1;
  }
  if (!this->ReadDomain(st))
  {
    return 1;
  }
  if (!this->ComputeSheet(st))
  {
    return 1;
  }
  this->BuildSheet(st);
  this->FillSheetHoles(st);
  this->TrimAtSymmetryPlanes(st);
  this->WriteOutput(st);
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
bool vtkMedialAxisDelaunay::CheckSurface(SheetState& st)
{
  // ---- The surface: triangles only, finite coordinates.
  st.NumberOfCells = st.Surface->GetNumberOfCells();
  if (st.NumberOfCells == 0 || st.Surface->GetNumberOfPoints() == 0)
  {
    return this->Fail(st, "The input surface is empty (no cells): there is no region to take the medial "
                "axis of. Check the iso-value of the Contour upstream.");
  }
  if (st.Surface->GetNumberOfVerts() || st.Surface->GetNumberOfLines() || st.Surface->GetNumberOfStrips())
  {
    return this->Fail(st, "The input has vertices, lines or triangle strips; MedialAxisDelaunay needs a "
                "surface of triangles (apply Triangulate, or Extract Surface then Triangulate).");
  }
  {
    vtkIdType npts;
    const vtkIdType* ids;
    vtkCellArray* polys = st.Surface->GetPolys();
    vtkIdType cell = 0;
    for (polys->InitTraversal(); polys->GetNextCell(npts, ids); ++cell)
    {
      if (npts != 3)
      {
        std::ostringstream msg;
        msg << "Cell " << cell << " of the input surface is a " << CellKind(static_cast<int>(npts))
            << " with " << npts
            << " points; MedialAxisDelaunay needs triangles (apply the Triangulate filter first).";
        return this->Fail(st, msg.str());
      }
    }
  }
  st.NumberOfPoints = st.Surface->GetNumberOfPoints();
  const std::string nonFinite = vtkARInputChecks::NonFinitePoints(st.Surface, "the input surface");
  if (!nonFinite.empty())
  {
    return this->Fail(st, nonFinite.substr(0, nonFinite.size() - 1));
  }
  this->UpdateProgress(0.05);
  return true;
}

//------------------------------------------------------------------------------
bool vtkMedialAxisDelaunay::SmoothSurface(SheetState& st)
{
  // ---- Smoothing (points keep their ids).
  st.Work = vtkSmartPointer<vtkPolyData>::New();
  st.Work->CopyStructure(st.Surface);
  st.GivenNormals = st.Surface->GetPointData()->GetNormals();
  if (!st.GivenNormals)
  {
    st.GivenNormals = st.Surface->GetPointData()->GetArray("Normals");
  }
  if (st.GivenNormals && st.GivenNormals->GetNumberOfComponents() != 3)
  {
    st.GivenNormals = nullptr;
  }
  if (this->Smoothing != NO_SMOOTHING && this->SmoothingIterations > 0)
  {
    vtkSmartPointer<vtkPolyDataAlgorithm> smoother;
    if (this->Smoothing == WINDOWED_SINC)
    {
      auto sinc = vtkSmartPointer<vtkWindowedSincPolyDataFilter>::New();
      sinc->SetNumberOfIterations(this->SmoothingIterations);
      sinc->SetPassBand(this->PassBand);
      sinc->BoundarySmoothingOff(); // open edges at the domain boundary stay there
      sinc->FeatureEdgeSmoothingOff();
      sinc->NonManifoldSmoothingOn();
      sinc->NormalizeCoordinatesOn();
      smoother = sinc;
    }
    else
    {
      auto laplace = vtkSmartPointer<vtkSmoothPolyDataFilter>::New();
      laplace->SetNumberOfIterations(this->SmoothingIterations);
      laplace->SetRelaxationFactor(this->RelaxationFactor);
      laplace->BoundarySmoothingOff();
      laplace->FeatureEdgeSmoothingOff();
      smoother = laplace;
    }
    smoother->SetInputData(st.Work);
    smoother->Update();
    if (smoother->GetOutput()->GetNumberOfPoints() != st.NumberOfPoints)
    {
      return this->Fail(st, "Smoothing changed the number of surface points.");
    }
    st.Work = vtkSmartPointer<vtkPolyData>::New();
    st.Work->CopyStructure(smoother->GetOutput());
    // Points on a symmetry plane stay on it (a one-cell-thick 2-D mesh has all
    // its contour points there).
    std::vector<double> planes = this->SymmetryPlanes;
    planes.resize(6 * this->GetNumberOfSymmetryPlanes());
    if (this->UseSymmetryPlaneWidget)
    {
      planes.insert(planes.end(), this->SymmetryPlaneOrigin, this->SymmetryPlaneOrigin + 3);
      planes.insert(planes.end(), this->SymmetryPlaneNormal, this->SymmetryPlaneNormal + 3);
    }
    const double tol = 1e-6 * std::sqrt(st.Surface->GetLength2());
    vtkNew<vtkPoints> moved;
    moved->DeepCopy(st.Work->GetPoints());
    for (std::size_t k = 0; k + 5 < planes.size(); k += 6)
    {
      double n[3] = { planes[k + 3], planes[k + 4], planes[k + 5] };
      if (vtkMath::Normalize(n) <= 0.0)
      {
        continue;
      }
      for (vtkIdType i = 0; i < st.NumberOfPoints; ++i)
      {
        double x[3], y[3];
        st.Surface->GetPoint(i, x);
        if (std::abs(vtkPlane::Evaluate(n, &planes[k], x)) <= tol)
        {
          moved->GetPoint(i, y);
          const double d = vtkPlane::Evaluate(n, &planes[k], y);
          moved->SetPoint(i, y[0] - d * n[0], y[1] - d * n[1], y[2] - d * n[2]);
        }
      }
    }
    st.Work->SetPoints(moved);
  }
  this->UpdateProgress(0.1);
  return true;
}

//------------------------------------------------------------------------------
bool vtkMedialAxisDelaunay::OrientNormals(SheetState& st)
{
  // ---- Oriented point normals of the (smoothed) surface: the given ones
  // when the points did not move, else recomputed and oriented like the given ones.
  const bool smoothed = this->Smoothing != NO_SMOOTHING && this->SmoothingIterations > 0;
  vtkNew<vtkPolyDataNormals> normalsFilter;
  normalsFilter->SetInputData(st.Work);
  normalsFilter->ComputePointNormalsOn();
  normalsFilter->ComputeCellNormalsOff();
  normalsFilter->SplittingOff();
  if (st.GivenNormals)
  {
    normalsFilter->ConsistencyOff();
    normalsFilter->AutoOrientNormalsOff();
  }
  else
  {
    normalsFilter->ConsistencyOn();
    normalsFilter->AutoOrientNormalsOn(); // outward for closed surfaces
    vtkNew<vtkFeatureEdges> open;
    open->SetInputData(st.Work);
    open->BoundaryEdgesOn();
    open->FeatureEdgesOff();
    open->ManifoldEdgesOff();
    open->NonManifoldEdgesOff();
    open->Update();
    if (open->GetOutput()->GetNumberOfCells() > 0)
    {
      vtkWarningMacro(<< "The input surface is open and has no 'Normals' point array, so which "
                         "side is the feature region is a guess (normals oriented outwards per "
                         "connected piece). Use Contour with Compute Normals on.");
    }
  }
  vtkDataArray* computed = st.GivenNormals;
  if (smoothed || !st.GivenNormals)
  {
    normalsFilter->Update();
    computed = normalsFilter->GetOutput()->GetPointData()->GetNormals();
    if (!computed || normalsFilter->GetOutput()->GetNumberOfPoints() != st.NumberOfPoints)
    {
      return this->Fail(st, "Could not compute point normals of the input surface.");
    }
  }
  st.Points.assign(3 * st.NumberOfPoints, 0.0);
  st.Normals.assign(3 * st.NumberOfPoints, 0.0);
  for (vtkIdType i = 0; i < st.NumberOfPoints; ++i)
  {
    st.Work->GetPoint(i, &st.Points[3 * i]);
    double n[3];
    computed->GetTuple(i, n);
    if (st.GivenNormals)
    {
      // The geometry of the smoothed surface, the orientation of the given normals.
      double g[3];
      st.GivenNormals->GetTuple(i, g);
      if (n[0] * g[0] + n[1] * g[1] + n[2] * g[2] < 0.0)
      {
        n[0] = -n[0];
        n[1] = -n[1];
        n[2] = -n[2];
      }
    }
    std::copy(n, n + 3, &st.Normals[3 * i]);
  }
  st.Triangles.reserve(3 * st.NumberOfCells);
  {
    vtkIdType npts;
    const vtkIdType* ids;
    vtkCellArray* polys = st.Work->GetPolys();
    for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
    {
      st.Triangles.insert(st.Triangles.end(), { ids[0], ids[1], ids[2] });
    }
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkMedialAxisDelaunay::ReadDomain(SheetState& st)
{
  // ---- The domain boundary.
  if (st.HasDomain)
  {
    if (!st.Boundary || st.Boundary->GetNumberOfCells() == 0)
    {
      return this->Fail(st, "The Domain input has no boundary surface (is it an empty or 2-D dataset?).");
    }
    st.Closed.Points.resize(3 * st.Boundary->GetNumberOfPoints());
    for (vtkIdType i = 0; i < st.Boundary->GetNumberOfPoints(); ++i)
    {
      st.Boundary->GetPoint(i, &st.Closed.Points[3 * i]);
    }
    vtkIdType npts;
    const vtkIdType* ids;
    vtkCellArray* polys = st.Boundary->GetPolys();
    for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
    {
      if (npts == 3)
      {
        st.Closed.Triangles.insert(st.Closed.Triangles.end(), { ids[0], ids[1], ids[2] });
      }
    }
  }
  this->UpdateProgress(0.15);
  return true;
}

//------------------------------------------------------------------------------
bool vtkMedialAxisDelaunay::ComputeSheet(SheetState& st)
{
  // ---- The medial sheet.
  st.Options.MinimumObjectAngle = this->MinimumObjectAngle;
  st.Options.MinimumRadiusFactor = this->MinimumRadiusFactor;
  st.Options.MinimumAreaFraction = this->MinimumAreaFraction;
  st.Options.MaximumNumberOfSheets = this->MaximumNumberOfSheets;
  st.Options.RegionAgainstNormals = this->FeatureRegion == ABOVE_ISOVALUE;
  st.Options.SymmetryPlanes.assign(this->SymmetryPlanes.begin(),
    this->SymmetryPlanes.begin() + 6 * this->GetNumberOfSymmetryPlanes());
  if (this->UseSymmetryPlaneWidget)
  {
    st.Options.SymmetryPlanes.insert(st.Options.SymmetryPlanes.end(), this->SymmetryPlaneOrigin,
      this->SymmetryPlaneOrigin + 3);
    st.Options.SymmetryPlanes.insert(st.Options.SymmetryPlanes.end(), this->SymmetryPlaneNormal,
      this->SymmetryPlaneNormal + 3);
  }
  if (this->SymmetryPlanesFromDomain)
  {
    if (!st.HasDomain)
    {
      vtkWarningMacro(<< "SymmetryPlanesFromDomain needs a Domain input; no plane was picked.");
    }
    else
    {
      const std::vector<double> picked = SymmetryPlanesFromBoundary(
        st.Boundary, st.Points, st.Normals, st.Triangles, std::sqrt(st.Surface->GetLength2()) + std::sqrt(st.Boundary->GetLength2()));
      for (std::size_t k = 0; k < picked.size(); k += 6)
      {
        bool known = false; // the same plane given by hand
        for (std::size_t j = 0; j + 5 < st.Options.SymmetryPlanes.size(); j += 6)
        {
          double n[3] = { st.Options.SymmetryPlanes[j + 3], st.Options.SymmetryPlanes[j + 4],
            st.Options.SymmetryPlanes[j + 5] };
          vtkMath::Normalize(n);
          const double gap = vtkMath::Dot(n, &picked[k]) - vtkMath::Dot(n, &st.Options.SymmetryPlanes[j]);
          known = known || (std::abs(std::abs(vtkMath::Dot(n, &picked[k + 3])) - 1.0) < 1e-6 &&
                             std::abs(gap) <= 1e-6 * std::sqrt(st.Boundary->GetLength2()));
        }
        if (!known)
        {
          st.Options.SymmetryPlanes.insert(st.Options.SymmetryPlanes.end(), picked.begin() + k, picked.begin() + k + 6);
        }
      }
    }
  }
  std::string error;
  const bool ok = ar::ComputeMedialSheet(st.Points.data(), static_cast<std::size_t>(st.NumberOfPoints),
    st.Normals.data(), st.Triangles.data(), st.Triangles.size() / 3, st.Options,
    st.HasDomain ? &st.Closed : nullptr, st.Sheet, error, [this](double f) {
      this->UpdateProgress(0.15 + 0.75 * f);
      return this->GetAbortExecute() != 0;
    });
  if (!ok)
  {
    return this->Fail(st, "Medial axis: " + error);
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkMedialAxisDelaunay::BuildSheet(SheetState& st)
{
  // ---- Output.
  const auto nOut = static_cast<vtkIdType>(st.Sheet.Radius.size());
  vtkNew<vtkPoints> outPoints;
  outPoints->SetDataTypeToDouble();
  outPoints->SetNumberOfPoints(nOut);
  vtkNew<vtkDoubleArray> radius;
  radius->SetName("Radius");
  radius->SetNumberOfTuples(nOut);
  for (vtkIdType i = 0; i < nOut; ++i)
  {
    outPoints->SetPoint(i, &st.Sheet.Points[3 * i]);
    radius->SetValue(i, st.Sheet.Radius[i]);
  }
  st.NumberOfTriangles = static_cast<vtkIdType>(st.Sheet.SheetId.size());
  vtkNew<vtkCellArray> polys;
  polys->AllocateExact(st.NumberOfTriangles, 3 * st.NumberOfTriangles);
  st.SheetId->SetName("SheetId");
  st.SheetId->SetNumberOfTuples(st.NumberOfTriangles);
  for (vtkIdType t = 0; t < st.NumberOfTriangles; ++t)
  {
    const vtkIdType ids[3] = { st.Sheet.Triangles[3 * t], st.Sheet.Triangles[3 * t + 1],
      st.Sheet.Triangles[3 * t + 2] };
    polys->InsertNextCell(3, ids);
    st.SheetId->SetValue(t, st.Sheet.SheetId[t]);
  }
  st.Result->SetPoints(outPoints);
  st.Result->SetPolys(polys);
  st.Result->GetPointData()->AddArray(radius);
  st.Result->GetCellData()->AddArray(st.SheetId);
}

//------------------------------------------------------------------------------
void vtkMedialAxisDelaunay::FillSheetHoles(SheetState& st)
{
  // ---- Symmetry planes: the sheet of the mirrored union crosses each plane
  // orthogonally; keep the original side (cut SymmetryTrimDistance short of
  // the plane) and extend the open edges near the plane orthogonally onto
  // it, which also closes gaps that the pruning left next to the plane.
  st.SheetAreas = st.Sheet.SheetAreas;
  vtkNew<vtkIntArray> extended;
  extended->SetName("Extended");
  extended->SetNumberOfTuples(st.NumberOfTriangles);
  extended->FillValue(0);
  st.Result->GetCellData()->AddArray(extended);
  st.MedianEdge = 0.0;
  {
    std::vector<double> lengths;
    lengths.reserve(st.Triangles.size());
    for (std::size_t t = 0; t < st.Triangles.size(); t += 3)
    {
      for (int k = 0; k < 3; ++k)
      {
        lengths.push_back(std::sqrt(vtkMath::Distance2BetweenPoints(
          &st.Points[3 * st.Triangles[t + k]], &st.Points[3 * st.Triangles[t + (k + 1) % 3]])));
      }
    }
    std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
    st.MedianEdge = lengths[lengths.size() / 2];
  }
  if (this->FillHoles && this->MaximumHoleSize > 0.0 && st.NumberOfTriangles > 0)
  {
    vtkNew<vtkFillHolesFilter> fill;
    fill->SetInputData(st.Result);
    fill->SetHoleSize(this->MaximumHoleSize * st.MedianEdge);
    // The patches are polygons, one per hole: triangulate them (the input's
    // triangles come first, in order).
    vtkNew<vtkTriangleFilter> triangulate;
    triangulate->SetInputConnection(fill->GetOutputPort());
    triangulate->PassVertsOff();
    triangulate->PassLinesOff();
    triangulate->Update();
    vtkPolyData* filled = triangulate->GetOutput();
    const vtkIdType nNew = filled->GetNumberOfCells();
    if (nNew > st.NumberOfTriangles)
    {
      // The patches take the SheetId of a triangle at their first point.
      vtkNew<vtkPolyData> links;
      links->ShallowCopy(filled);
      links->BuildLinks();
      vtkNew<vtkIntArray> ids;
      ids->SetName("SheetId");
      ids->SetNumberOfTuples(nNew);
      vtkNew<vtkIntArray> ext;
      ext->SetName("Extended");
      ext->SetNumberOfTuples(nNew);
      ext->FillValue(0);
      for (vtkIdType t = 0; t < nNew; ++t)
      {
        int id = 0;
        if (t < st.NumberOfTriangles)
        {
          id = st.SheetId->GetValue(t);
        }
        else
        {
          vtkIdType npts;
          const vtkIdType* pts;
          links->GetCellPoints(t, npts, pts);
          vtkIdType ncells;
          vtkIdType* cellIds;
          links->GetPointCells(pts[0], ncells, cellIds);
          for (vtkIdType k = 0; k < ncells; ++k)
          {
            if (cellIds[k] < st.NumberOfTriangles)
            {
              id = st.SheetId->GetValue(cellIds[k]);
              break;
            }
          }
        }
        ids->SetValue(t, id);
      }
      st.Result->SetPolys(filled->GetPolys());
      st.Result->GetCellData()->Initialize();
      st.Result->GetCellData()->AddArray(ids);
      st.Result->GetCellData()->AddArray(ext);
    }
  }
}

//------------------------------------------------------------------------------
void vtkMedialAxisDelaunay::TrimAtSymmetryPlanes(SheetState& st)
{
  if (!st.Options.SymmetryPlanes.empty() && st.NumberOfTriangles > 0)
  {
    vtkSmartPointer<vtkPolyData> current = st.Result.Get();
    const std::size_t nPlanes = st.Options.SymmetryPlanes.size() / 6;
    for (std::size_t k = 0; k < nPlanes; ++k)
    {
      const double* v = st.Options.SymmetryPlanes.data() + 6 * k;
      double normal[3] = { v[3], v[4], v[5] };
      double side = 0.0; // the normal points to the side that holds the surface
      for (vtkIdType i = 0; i < st.NumberOfPoints; ++i)
      {
        const double* x = &st.Points[3 * i];
        const double d = (x[0] - v[0]) * normal[0] + (x[1] - v[1]) * normal[1] + (x[2] - v[2]) * normal[2];
        side += d > 0.0 ? 1.0 : (d < 0.0 ? -1.0 : 0.0);
      }
      if (side < 0.0)
      {
        normal[0] = -normal[0];
        normal[1] = -normal[1];
        normal[2] = -normal[2];
      }
      vtkNew<vtkPlane> plane;
      plane->SetOrigin(v[0], v[1], v[2]);
      plane->SetNormal(normal);
      vtkNew<vtkClipPolyData> clip;
      clip->SetInputData(current);
      clip->SetClipFunction(plane);
      clip->SetValue(this->SymmetryTrimDistance * vtkMath::Norm(normal));
      clip->Update();
      current = vtkSmartPointer<vtkPolyData>::New();
      current->ShallowCopy(clip->GetOutput());
      if (current->GetNumberOfCells() == 0)
      {
        break;
      }
      // Open edges within the trim distance plus two surface edge lengths of
      // the plane go down to it.
      vtkNew<vtkExtendToPlane> extend;
      // "Nothing to extend" is normal here (the sheet reaches the plane).
      vtkNew<vtkCallbackCommand> quiet;
      extend->AddObserver(vtkCommand::WarningEvent, quiet);
      extend->SetInputData(current);
      extend->SetPlaneOrigin(v[0], v[1], v[2]);
      extend->SetPlaneNormal(normal);
      extend->SetTrimDistance(0.0);
      extend->SetMaximumGap(this->SymmetryTrimDistance + 2.0 * st.MedianEdge);
      extend->Update();
      if (extend->GetOutput()->GetNumberOfCells() > 0)
      {
        current = vtkSmartPointer<vtkPolyData>::New();
        current->ShallowCopy(extend->GetOutput());
        current->GetFieldData()->Initialize();
      }
    }
    // Sheet areas of what is left.
    vtkDataArray* ids = current->GetCellData()->GetArray("SheetId");
    std::fill(st.SheetAreas.begin(), st.SheetAreas.end(), 0.0);
    for (vtkIdType t = 0; ids && t < current->GetNumberOfCells(); ++t)
    {
      const auto id = static_cast<std::size_t>(ids->GetComponent(t, 0));
      vtkCell* cell = current->GetCell(t);
      double a[3], b[3], c[3];
      cell->GetPoints()->GetPoint(0, a);
      cell->GetPoints()->GetPoint(1, b);
      cell->GetPoints()->GetPoint(2, c);
      if (id < st.SheetAreas.size())
      {
        st.SheetAreas[id] += vtkTriangle::TriangleArea(a, b, c);
      }
    }
    st.Result->ShallowCopy(current);
  }
}

//------------------------------------------------------------------------------
void vtkMedialAxisDelaunay::WriteOutput(SheetState& st)
{
  st.Output->ShallowCopy(st.Result);

  vtkNew<vtkDoubleArray> areas;
  areas->SetName("SheetAreas");
  for (double a : st.SheetAreas)
  {
    areas->InsertNextValue(a);
  }
  st.Output->GetFieldData()->AddArray(areas);
  auto count = [&](const char* name, std::size_t value) {
    const double v = static_cast<double>(value);
    st.Output->GetFieldData()->AddArray(vtkARMeshKernels::FieldArray(name, &v, 1));
  };
  count("DelaunayTetrahedra", st.Sheet.NumberOfTetrahedra);
  count("InteriorTetrahedra", st.Sheet.NumberOfInteriorTetrahedra);
  count("VoronoiFacets", st.Sheet.NumberOfFacets);
  count("MirrorCopies", st.Sheet.NumberOfMirrorCopies);
  vtkNew<vtkDoubleArray> used;
  used->SetName("SymmetryPlanesUsed");
  used->SetNumberOfComponents(6);
  for (std::size_t k = 0; k + 5 < st.Options.SymmetryPlanes.size(); k += 6)
  {
    used->InsertNextTuple(&st.Options.SymmetryPlanes[k]);
  }
  st.Output->GetFieldData()->AddArray(used);
  if (st.Output->GetNumberOfCells() == 0)
  {
    vtkWarningMacro(<< "No medial sheet survived the pruning (" << st.Sheet.NumberOfInteriorTetrahedra
                    << " of " << st.Sheet.NumberOfTetrahedra
                    << " Delaunay tetrahedra are interior). Check FeatureRegion (the side of "
                       "the normals), or lower MinimumObjectAngle / MinimumRadiusFactor.");
  }
}

//------------------------------------------------------------------------------
void vtkMedialAxisDelaunay::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Smoothing: " << this->Smoothing << "\n";
  os << indent << "SmoothingIterations: " << this->SmoothingIterations << "\n";
  os << indent << "PassBand: " << this->PassBand << "\n";
  os << indent << "RelaxationFactor: " << this->RelaxationFactor << "\n";
  os << indent << "FeatureRegion: " << this->FeatureRegion << "\n";
  os << indent << "MinimumObjectAngle: " << this->MinimumObjectAngle << "\n";
  os << indent << "MinimumRadiusFactor: " << this->MinimumRadiusFactor << "\n";
  os << indent << "MinimumAreaFraction: " << this->MinimumAreaFraction << "\n";
  os << indent << "MaximumNumberOfSheets: " << this->MaximumNumberOfSheets << "\n";
  os << indent << "SymmetryPlanes: " << this->GetNumberOfSymmetryPlanes() << "\n";
  os << indent << "UseSymmetryPlaneWidget: " << this->UseSymmetryPlaneWidget << "\n";
  os << indent << "SymmetryTrimDistance: " << this->SymmetryTrimDistance << "\n";
  os << indent << "SymmetryPlanesFromDomain: " << this->SymmetryPlanesFromDomain << "\n";
  os << indent << "FillHoles: " << this->FillHoles << "\n";
  os << indent << "MaximumHoleSize: " << this->MaximumHoleSize << "\n";
}
