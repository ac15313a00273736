// SPDX-License-Identifier: BSD-3-Clause
#include "vtkARVolumeFilter.h"

#include "vtkARVolumeFilterExecution.h"
#include "vtkARParallel.h"
#include "vtkExecutive.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <string>

//------------------------------------------------------------------------------
vtkARVolumeFilter::vtkARVolumeFilter(const char* task)
  : Task(task)
{
}

//------------------------------------------------------------------------------
int vtkARVolumeFilter::RequestUpdateExtent(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // The piece comes from the port that is asked: when only a second port
  // (vtkFeatureCluster's medial points) feeds a filter, port 0's request is
  // a stale "piece 0 of 1", which made every rank read the whole mesh.
  int port = 0;
  if (request && request->Has(vtkExecutive::FROM_OUTPUT_PORT()))
  {
    port = std::max(0, request->Get(vtkExecutive::FROM_OUTPUT_PORT()));
  }
  vtkARMeshKernels::RequestExtraGhostLevels(inputVector, outputVector, this->GetExtraGhostLevels(), port);
  return 1;
}

//------------------------------------------------------------------------------
int vtkARVolumeFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // Threads for this filter's own work only: the process's SMP backend is
  // left as the user has it.
  int result = 1;
  vtkARMeshKernels::Threaded([&]() {
    Execution run;
    run.Input = vtkUnstructuredGrid::GetData(inputVector[0], 0);
    run.Output = vtkUnstructuredGrid::GetData(outputVector, 0);
    run.OutputVector = outputVector;
    run.Output->ShallowCopy(run.Input);
    // Every rank reaches the same collective calls, in order: a mesh error
    // is collected, and reported by Proceed.
    std::string meshError;
    if (!run.Mesh.Build(run.Input, meshError))
    {
      run.Problem << meshError << ". ";
    }
    result = this->Execute(run);
  });
  return result;
}

//------------------------------------------------------------------------------
bool vtkARVolumeFilter::Proceed(Execution& run)
{
  if (!vtkARMeshKernels::AgreeToProceed(
        this, run.Problem.str(), run.Mesh, vtkARMeshKernels::Census(run.Mesh), this->Task))
  {
    return false;
  }
  this->UpdateProgress(0.1);
  return !this->Cancelled();
}

//------------------------------------------------------------------------------
bool vtkARVolumeFilter::Cancelled()
{
  return vtkARParallel::NumberOfRanks() == 1 && this->CheckAbort();
}

//------------------------------------------------------------------------------
void vtkARVolumeFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
