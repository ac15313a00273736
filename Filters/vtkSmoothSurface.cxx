// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSmoothSurface.h"
#include "vtkARInputChecks.h"

#include "vtkCellArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkWindowedSincPolyDataFilter.h"

#include <algorithm>
#include <array>
#include <vector>

vtkStandardNewMacro(vtkSmoothSurface);

int vtkSmoothSurface::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  if (!input || input->GetNumberOfPoints() == 0)
  {
    return 1;
  }
  // A NaN point would spread to its neighbours with every iteration.
  vtkARInputChecks::Properties problem;
  problem.InRange("NumberOfIterations", this->NumberOfIterations, 0, VTK_INT_MAX)
    .InRange("PassBand", this->PassBand, 0.0, 2.0)
    .InRange("FeatureAngle", this->FeatureAngle, 0.0, 180.0, "degrees")
    .InRange("EdgeAngle", this->EdgeAngle, 0.0, 180.0, "degrees")
    .Add(vtkARInputChecks::NonFinitePoints(input, "the surface"));
  if (!problem.Ok())
  {
    vtkErrorMacro(<< "SmoothSurface: " << problem.Message() << "The input passes through unchanged.");
    output->ShallowCopy(input);
    return 1;
  }
  vtkNew<vtkPolyData> copy;
  copy->ShallowCopy(input);
  vtkNew<vtkWindowedSincPolyDataFilter> smooth;
  smooth->SetInputData(copy);
  smooth->SetNumberOfIterations(this->NumberOfIterations);
  smooth->SetPassBand(this->PassBand);
  smooth->SetBoundarySmoothing(this->BoundarySmoothing);
  smooth->SetFeatureEdgeSmoothing(this->FeatureEdgeSmoothing);
  smooth->SetFeatureAngle(this->FeatureAngle);
  smooth->SetEdgeAngle(this->EdgeAngle);
  smooth->SetNonManifoldSmoothing(this->NonManifoldSmoothing);
  smooth->SetNormalizeCoordinates(this->NormalizeCoordinates);
  smooth->Update();
  output->ShallowCopy(smooth->GetOutput());
  this->UpdateProgress(0.8);

  // The fixed points: on edges used by one polygon (BoundarySmoothing off)
  // or by three or more (NonManifoldSmoothing off).
  const vtkIdType n = input->GetNumberOfPoints();
  std::vector<std::array<vtkIdType, 2>> edges;
  vtkIdType npts;
  const vtkIdType* ids;
  vtkCellArray* polys = input->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
  {
    for (vtkIdType k = 0; k < npts; ++k)
    {
      const vtkIdType a = ids[k], b = ids[(k + 1) % npts];
      edges.push_back({ std::min(a, b), std::max(a, b) });
    }
  }
  std::sort(edges.begin(), edges.end());
  std::vector<char> fixed(n, 0);
  vtkIdType numFixed = 0;
  for (std::size_t i = 0; i < edges.size();)
  {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j] == edges[i])
    {
      ++j;
    }
    const std::size_t uses = j - i;
    if ((uses == 1 && !this->BoundarySmoothing) || (uses > 2 && !this->NonManifoldSmoothing))
    {
      for (vtkIdType v : edges[i])
      {
        numFixed += fixed[v] ? 0 : 1;
        fixed[v] = 1;
      }
    }
    i = j;
  }
  if (numFixed < 2)
  {
    return 1;
  }
  // Least squares y = a + s x over the fixed points (x input, y smoothed).
  vtkPoints* xp = input->GetPoints();
  vtkPoints* smoothed = output->GetPoints();
  vtkNew<vtkPoints> yp; // in the input's precision (the VTK filter may give floats)
  yp->SetDataType(xp->GetDataType());
  yp->SetNumberOfPoints(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    yp->SetPoint(i, smoothed->GetPoint(i));
  }
  double mx[3] = { 0, 0, 0 }, my[3] = { 0, 0, 0 };
  for (vtkIdType i = 0; i < n; ++i)
  {
    if (fixed[i])
    {
      double x[3], y[3];
      xp->GetPoint(i, x);
      yp->GetPoint(i, y);
      for (int k = 0; k < 3; ++k)
      {
        mx[k] += x[k] / numFixed;
        my[k] += y[k] / numFixed;
      }
    }
  }
  double sxy = 0.0, sxx = 0.0;
  for (vtkIdType i = 0; i < n; ++i)
  {
    if (fixed[i])
    {
      double x[3], y[3];
      xp->GetPoint(i, x);
      yp->GetPoint(i, y);
      for (int k = 0; k < 3; ++k)
      {
        sxy += (x[k] - mx[k]) * (y[k] - my[k]);
        sxx += (x[k] - mx[k]) * (x[k] - mx[k]);
      }
    }
  }
  const double s = sxx > 0.0 ? sxy / sxx : 1.0;
  if (!(s > 0.5 && s < 2.0))
  {
    return 1; // not the small scaling this corrects
  }
  for (vtkIdType i = 0; i < n; ++i)
  {
    double y[3];
    if (fixed[i])
    {
      xp->GetPoint(i, y);
    }
    else
    {
      yp->GetPoint(i, y);
      for (int k = 0; k < 3; ++k)
      {
        y[k] = mx[k] + (y[k] - my[k]) / s;
      }
    }
    yp->SetPoint(i, y);
  }
  output->SetPoints(yp);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkSmoothSurface::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfIterations: " << this->NumberOfIterations << "\n";
  os << indent << "PassBand: " << this->PassBand << "\n";
  os << indent << "BoundarySmoothing: " << this->BoundarySmoothing << "\n";
  os << indent << "NonManifoldSmoothing: " << this->NonManifoldSmoothing << "\n";
  os << indent << "NormalizeCoordinates: " << this->NormalizeCoordinates << "\n";
}
