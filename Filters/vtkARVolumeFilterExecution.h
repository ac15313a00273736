// SPDX-License-Identifier: BSD-3-Clause
/**
 * The state of one execution of a vtkARVolumeFilter, handed to its
 * subclass's Execute (private header of the module).
 */
#ifndef vtkARVolumeFilterExecution_h
#define vtkARVolumeFilterExecution_h

#include "vtkARMeshKernels.h"
#include "vtkARVolumeFilter.h"

#include <sstream>

class vtkInformationVector;
class vtkUnstructuredGrid;

struct vtkARVolumeFilter::Execution
{
  vtkUnstructuredGrid* Input = nullptr;
  /// Port 0's output: the input, shallow-copied.
  vtkUnstructuredGrid* Output = nullptr;
  /// The output information (for the other ports).
  vtkInformationVector* OutputVector = nullptr;
  /// The input mesh, checked and indexed (its error, if any, is in Problem).
  vtkARMeshKernels::MeshView Mesh;
  /// What is wrong with the input or the properties; empty when fine.
  std::ostringstream Problem;
};

#endif
