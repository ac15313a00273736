// SPDX-License-Identifier: BSD-3-Clause
#include "vtkTrimSurface.h"
#include "vtkARInputChecks.h"

#include "vtkAbstractTransform.h"
#include "vtkAppendPolyData.h"
#include "vtkBox.h"
#include "vtkCleanPolyData.h"
#include "vtkExtractCells.h"
#include "vtkGenericCell.h"
#include "vtkGeometryFilter.h"
#include "vtkIdList.h"
#include "vtkMath.h"
#include "vtkPoints.h"
#include "vtkPolyDataPlaneClipper.h"
#include "vtkTriangleFilter.h"
#include "vtkClipPolyData.h"
#include "vtkImplicitFunction.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPlane.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <cmath>
#include <vector>

vtkStandardNewMacro(vtkTrimSurface);
vtkCxxSetObjectMacro(vtkTrimSurface, ClipFunction, vtkImplicitFunction);

vtkTrimSurface::~vtkTrimSurface()
{
  this->SetClipFunction(nullptr);
}

vtkMTimeType vtkTrimSurface::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  if (this->ClipFunction)
  {
    t = std::max(t, this->ClipFunction->GetMTime());
  }
  return t;
}

namespace
{
/// `input` clipped by `f`: keeps f < 0 when `negative`, else f > 0. A plane
/// (any vtkPlane, also with an offset or a transform: f is affine) is cut
/// with vtkPolyDataPlaneClipper, exactly; vtkClipPolyData would put the cut
/// about 1e-9 of the size off the plane (it interpolates in single
/// precision). Other functions go to vtkClipPolyData. Triangles out.
vtkSmartPointer<vtkPolyData> Clip(vtkPolyData* input, vtkImplicitFunction* f, bool negative)
{
  auto out = vtkSmartPointer<vtkPolyData>::New();
  if (input->GetNumberOfCells() == 0)
  {
    return out;
  }
  vtkNew<vtkTriangleFilter> triangles;
  if (vtkPlane::SafeDownCast(f))
  {
    // f(x) = g . x + c: the world plane g . x + c = 0, kept side by sign.
    const double zero[3] = { 0.0, 0.0, 0.0 };
    const double c = f->FunctionValue(zero);
    double g[3];
    for (int k = 0; k < 3; ++k)
    {
      double e[3] = { 0.0, 0.0, 0.0 };
      e[k] = 1.0;
      g[k] = f->FunctionValue(e) - c;
    }
    const double g2 = vtkMath::Dot(g, g);
    if (!(g2 > 0.0))
    {
      out->ShallowCopy(input);
      return out;
    }
    vtkNew<vtkPlane> plane;
    plane->SetOrigin(-c * g[0] / g2, -c * g[1] / g2, -c * g[2] / g2);
    const double sign = negative ? -1.0 : 1.0; // the clipper keeps the normal's side
    plane->SetNormal(sign * g[0], sign * g[1], sign * g[2]);
    vtkNew<vtkPolyDataPlaneClipper> clip;
    clip->SetInputData(input);
    clip->SetPlane(plane);
    clip->CappingOff();
    triangles->SetInputConnection(clip->GetOutputPort());
  }
  else
  {
    vtkNew<vtkClipPolyData> clip;
    clip->SetInputData(input);
    clip->SetClipFunction(f);
    clip->SetInsideOut(negative);
    triangles->SetInputConnection(clip->GetOutputPort());
  }
  triangles->Update();
  out->ShallowCopy(triangles->GetOutput());
  return out;
}
}

int vtkTrimSurface::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  if (!input)
  {
    return 1;
  }
  const std::string nonFinite = vtkARInputChecks::NonFinitePoints(input, "the surface");
  if (!nonFinite.empty())
  {
    vtkErrorMacro("TrimSurface: " << nonFinite << "The input is passed through.");
    output->ShallowCopy(input);
    return 1;
  }
  if (!this->ClipFunction)
  {
    vtkWarningMacro("TrimSurface: no plane or box is set; the input is passed through.");
    output->ShallowCopy(input);
    return 1;
  }
  auto surface = vtkSmartPointer<vtkPolyData>::New();
  surface->ShallowCopy(input);
  auto* box = vtkBox::SafeDownCast(this->ClipFunction);
  if (!box)
  {
    output->ShallowCopy(Clip(surface, this->ClipFunction, this->InsideOut));
    return 1;
  }

  // The box's six faces as outward planes in its own frame, each evaluated
  // through the box's transform: n . (T(x) - p), affine in x.
  double b[6];
  box->GetBounds(b);
  std::vector<vtkSmartPointer<vtkPlane>> faces;
  for (int axis = 0; axis < 3; ++axis)
  {
    for (int side = 0; side < 2; ++side)
    {
      auto plane = vtkSmartPointer<vtkPlane>::New();
      double normal[3] = { 0.0, 0.0, 0.0 }, origin[3] = { 0.0, 0.0, 0.0 };
      normal[axis] = side == 0 ? -1.0 : 1.0;
      origin[axis] = b[2 * axis + side];
      plane->SetNormal(normal);
      plane->SetOrigin(origin);
      plane->SetTransform(box->GetTransform());
      faces.push_back(plane);
    }
  }
  if (this->InsideOut)
  {
    for (std::size_t i = 0; i < faces.size() && surface->GetNumberOfCells() > 0; ++i)
    {
      surface = Clip(surface, faces[i], true);
      this->UpdateProgress((i + 1) / 6.0);
    }
    output->ShallowCopy(surface);
    return 1;
  }
  // Outside: split the surface by each face plane in turn, keeping both
  // sides (merged along the cut, so the mesh stays conforming: every cut
  // line is in the mesh before the next), then drop the triangles inside
  // the box (centroid behind all six faces).
  double bounds[6];
  input->GetBounds(bounds);
  const double diagonal = std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) +
    (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) +
    (bounds[5] - bounds[4]) * (bounds[5] - bounds[4]));
  for (std::size_t i = 0; i < faces.size(); ++i)
  {
    vtkNew<vtkAppendPolyData> append;
    for (bool side : { true, false })
    {
      vtkSmartPointer<vtkPolyData> piece = Clip(surface, faces[i], side);
      if (piece->GetNumberOfCells() > 0)
      {
        append->AddInputData(piece);
      }
    }
    vtkNew<vtkCleanPolyData> merge;
    merge->SetInputConnection(append->GetOutputPort());
    merge->ToleranceIsAbsoluteOn();
    merge->SetAbsoluteTolerance(1e-12 * diagonal);
    merge->ConvertLinesToPointsOff();
    merge->ConvertPolysToLinesOff();
    merge->ConvertStripsToPolysOff();
    merge->Update();
    surface = vtkSmartPointer<vtkPolyData>::New();
    surface->ShallowCopy(merge->GetOutput());
    this->UpdateProgress((i + 1) / 7.0);
  }
  vtkNew<vtkIdList> outside;
  vtkNew<vtkGenericCell> cell;
  for (vtkIdType c = 0; c < surface->GetNumberOfCells(); ++c)
  {
    surface->GetCell(c, cell);
    double centroid[3] = { 0.0, 0.0, 0.0 };
    const vtkIdType m = cell->GetNumberOfPoints();
    for (vtkIdType k = 0; k < m; ++k)
    {
      double x[3];
      cell->GetPoints()->GetPoint(k, x);
      for (int j = 0; j < 3; ++j)
      {
        centroid[j] += x[j] / m;
      }
    }
    double value = -VTK_DOUBLE_MAX;
    for (auto& face : faces)
    {
      value = std::max(value, face->FunctionValue(centroid));
    }
    if (value > 0.0)
    {
      outside->InsertNextId(c);
    }
  }
  if (outside->GetNumberOfIds() == 0)
  {
    output->Initialize();
    return 1;
  }
  vtkNew<vtkExtractCells> extract;
  extract->SetInputData(surface);
  extract->SetCellList(outside);
  vtkNew<vtkGeometryFilter> geometry;
  geometry->SetInputConnection(extract->GetOutputPort());
  geometry->Update();
  output->ShallowCopy(geometry->GetOutput());
  return 1;
}

void vtkTrimSurface::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "InsideOut: " << this->InsideOut << "\n";
  os << indent << "ClipFunction: " << this->ClipFunction << "\n";
}
