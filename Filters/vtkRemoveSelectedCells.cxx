// SPDX-License-Identifier: BSD-3-Clause
#include "vtkRemoveSelectedCells.h"
#include "vtkARInputChecks.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkExtractCells.h"
#include "vtkExtractSelection.h"
#include "vtkGeometryFilter.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"
#include "vtkSelection.h"
#include "vtkSmartPointer.h"

vtkStandardNewMacro(vtkRemoveSelectedCells);

namespace
{
/// The input as polydata (a shallow copy of a polydata; the surface of any
/// other dataset).
vtkSmartPointer<vtkPolyData> AsPolyData(vtkDataSet* input)
{
  auto result = vtkSmartPointer<vtkPolyData>::New();
  if (auto* pd = vtkPolyData::SafeDownCast(input))
  {
    result->ShallowCopy(pd);
    return result;
  }
  vtkNew<vtkGeometryFilter> geometry;
  geometry->SetInputData(input);
  geometry->Update();
  result->ShallowCopy(geometry->GetOutput());
  return result;
}
}

vtkRemoveSelectedCells::vtkRemoveSelectedCells()
{
  this->SetNumberOfInputPorts(2);
}

int vtkRemoveSelectedCells::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  }
  else
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkSelection");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

int vtkRemoveSelectedCells::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* input = vtkDataSet::GetData(inputVector[0], 0);
  vtkSelection* selection = vtkSelection::GetData(inputVector[1], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  this->NumberOfRemovedCells = 0;
  if (!input || input->GetNumberOfCells() == 0)
  {
    vtkErrorMacro("RemoveSelectedCells: the input has no cells; the output is empty.");
    return 1;
  }
  const std::string nonFinite = vtkARInputChecks::NonFinitePoints(input, "the input");
  if (!nonFinite.empty())
  {
    vtkErrorMacro("RemoveSelectedCells: " << nonFinite << "The output is empty.");
    return 1;
  }
  if (!selection || selection->GetNumberOfNodes() == 0)
  {
    vtkWarningMacro("RemoveSelectedCells: no selection (or an empty one); the input is passed "
                    "through unchanged.");
    output->ShallowCopy(AsPolyData(input));
    return 1;
  }

  // Mark the selected cells: vtkExtractSelection with PreserveTopology adds
  // the cell array vtkInsidedness (1 = selected) and evaluates any selection
  // type and the selection's expression.
  vtkSmartPointer<vtkDataSet> copy;
  copy.TakeReference(input->NewInstance());
  copy->ShallowCopy(input);
  vtkNew<vtkExtractSelection> mark;
  mark->SetInputData(0, copy);
  mark->SetInputData(1, selection);
  mark->PreserveTopologyOn();
  mark->Update();
  this->UpdateProgress(0.4);
  auto* marked = vtkDataSet::SafeDownCast(mark->GetOutputDataObject(0));
  vtkDataArray* inside = marked ? marked->GetCellData()->GetArray("vtkInsidedness") : nullptr;
  if (!inside)
  {
    vtkWarningMacro("RemoveSelectedCells: the selection selects no cell of the input (is it a "
                    "point selection, or for another dataset?); the input is passed through "
                    "unchanged.");
    output->ShallowCopy(AsPolyData(input));
    return 1;
  }
  const vtkIdType n = input->GetNumberOfCells();
  vtkNew<vtkIdList> kept;
  kept->Allocate(n);
  for (vtkIdType c = 0; c < n; ++c)
  {
    if (inside->GetComponent(c, 0) <= 0.0)
    {
      kept->InsertNextId(c);
    }
  }
  this->NumberOfRemovedCells = n - kept->GetNumberOfIds();
  if (this->NumberOfRemovedCells == 0)
  {
    vtkWarningMacro("RemoveSelectedCells: the selection selects no cell of the input; the input "
                    "is passed through unchanged.");
    output->ShallowCopy(AsPolyData(input));
    return 1;
  }
  if (kept->GetNumberOfIds() == 0)
  {
    vtkWarningMacro("RemoveSelectedCells: every cell is selected; the output is empty.");
    return 1;
  }
  if (this->CheckAbort())
  {
    return 1;
  }

  // Keep the other cells (vtkExtractCells drops the unused points and keeps
  // the arrays, in input order), back to polydata.
  vtkNew<vtkExtractCells> extract;
  extract->SetInputData(copy);
  extract->SetCellList(kept);
  vtkNew<vtkGeometryFilter> geometry;
  geometry->SetInputConnection(extract->GetOutputPort());
  geometry->Update();
  output->ShallowCopy(geometry->GetOutput());
  this->UpdateProgress(1.0);
  return 1;
}

void vtkRemoveSelectedCells::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfRemovedCells: " << this->NumberOfRemovedCells << "\n";
}
