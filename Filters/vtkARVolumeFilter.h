// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkARVolumeFilter
 * @brief Abstract base of the filters that compute fields on a volume mesh.
 *
 * vtkShockSensor, vtkWeightFunction and vtkFeatureCluster share one frame,
 * the way vtkPointCloudFilter's subclasses do: the input, one or more ghost
 * levels more than the downstream asks for (gradients and graph rings at
 * partition boundaries need the neighbours), the work on threads
 * (vtkARMeshKernels::Threaded: vtkSMPTools in a local scope, the process's
 * backend left as the user has it), the output port 0 a shallow copy of the
 * input, and the mesh checked and indexed once (vtkARMeshKernels::MeshView),
 * its problem collected for the collective AgreeToProceed. A subclass
 * implements one hook, Execute, which validates its properties and arrays,
 * calls Proceed, and computes.
 *
 * @sa vtkShockSensor vtkWeightFunction vtkFeatureCluster
 */
#ifndef vtkARVolumeFilter_h
#define vtkARVolumeFilter_h

#include "AdaptiveRedistributionFiltersModule.h" // for export macro
#include "vtkUnstructuredGridAlgorithm.h"

class ADAPTIVEREDISTRIBUTIONFILTERS_EXPORT vtkARVolumeFilter : public vtkUnstructuredGridAlgorithm
{
public:
  vtkAbstractTypeMacro(vtkARVolumeFilter, vtkUnstructuredGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

protected:
  /// `task` names what the filter computes, for the messages ("the shock sensor").
  explicit vtkARVolumeFilter(const char* task);
  ~vtkARVolumeFilter() override = default;

  /// Ghost levels requested beyond the downstream's. Default 1.
  virtual int GetExtraGhostLevels() { return 1; }

  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  /// Runs Execute on threads, after the shared prologue.
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  /// One execution: input, output (the input, shallow-copied), the mesh
  /// view and the problem stream; defined in vtkARVolumeFilterExecution.h.
  struct Execution;

  /// The subclass's work: validation into run.Problem, then Proceed, then the
  /// computation. Returns RequestData's result.
  virtual int Execute(Execution& run) = 0;

  /// The collective check of run.Problem and the mesh over all ranks
  /// (vtkARMeshKernels::AgreeToProceed), then progress 0.1. False when the
  /// filter must stop (an error was reported on some rank, or the user
  /// cancelled a serial run): the output stays the input.
  bool Proceed(Execution& run);

  /// True when the user cancelled a serial run. Under MPI collective work
  /// runs to its end, so this is false there.
  bool Cancelled();

private:
  vtkARVolumeFilter(const vtkARVolumeFilter&) = delete;
  void operator=(const vtkARVolumeFilter&) = delete;

  const char* Task;
};

#endif
