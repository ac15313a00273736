// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkARParallel
 * @brief Private: every MPI helper of the AdaptiveRedistribution filters.
 *
 * Not part of the public API. Reductions, gathers and broadcasts over the
 * global controller, each a no-op (or the local value) on one rank, and the
 * gathering of surfaces (the domain boundary, the feature surfaces) to rank
 * 0. Every function is collective: all ranks call it, in the same order.
 */
#ifndef vtkARParallel_h
#define vtkARParallel_h

#include "vtkSmartPointer.h" // for the return types
#include "vtkType.h"

#include <cstdint>
#include <string>
#include <vector>

class vtkAbstractArray;
class vtkDataSet;
class vtkFieldData;
class vtkPolyData;
class vtkUnstructuredGrid;

class vtkARParallel
{
public:
  /// ar::AdviseHugePages on the array's allocated memory (ARHugePages.h):
  /// call it after sizing a large array and before writing it.
  static void AdviseHugePages(vtkAbstractArray* array);

  /// MPI reductions over the global controller (no-ops in serial).
  static void AllReduceMax(double* values, int n);
  static void AllReduceSum(double* values, int n);
  /// Every rank's `local` concatenated in rank order on rank 0 (empty on the
  /// other ranks; `local` itself in serial). Collective.
  static std::vector<double> GatherOnRoot(const std::vector<double>& local);
  static int NumberOfRanks();
  /// This process's rank in the global controller (0 in serial).
  static int Rank();

  /// The boundary surface of a (possibly distributed) volume mesh as
  /// triangles, whole on rank 0 and empty on the other ranks. Faces between
  /// two ranks' pieces are dropped. Collective: every rank must call it.
  static vtkSmartPointer<vtkPolyData> GatherDomainBoundary(vtkDataSet* domain);

  /// Rank 0 gets the union of the ranks' polydata (returned as is in serial,
  /// empty on the other ranks), points merged within `tolerance` times the
  /// bounding-box diagonal (0: exact duplicates only). A triangle present
  /// more than once is dropped altogether when `dropSharedTriangles` (faces
  /// between pieces), else kept once. Collective.
  static vtkSmartPointer<vtkPolyData> GatherPolyData(
    vtkPolyData* local, double tolerance, bool dropSharedTriangles);

  /// Every rank's `local` concatenated in rank order, on every rank
  /// (`local` itself in serial).
  static std::vector<double> AllGather(const std::vector<double>& local);
  /// Rank 0's `data` on every rank (integers travel as doubles: exact up to
  /// 2^53). Nothing in serial.
  static void BroadcastFromRoot(std::vector<double>& data);
  static void BroadcastFromRoot(std::vector<std::int64_t>& data);
  static void BroadcastFromRoot(std::string& text);
  /// Rank 0's field data into `fd` on the other ranks (rank 0's `fd` is
  /// left as it is). Nothing in serial.
  static void BroadcastFieldDataFromRoot(vtkFieldData* fd);

  /// The owned cells of every rank's piece in one mesh on rank 0 (ghost
  /// cells dropped, the points the pieces share merged: exact duplicates
  /// only), with rank 0's field data; an empty mesh on the other ranks. In
  /// serial, the piece's owned cells. Where the pieces carry point global
  /// ids (a partitioned dataset's), the points are put in their order, and
  /// the cells in the order of the cells' global ids where they have them
  /// too: the order of the serial mesh the ids number, whose work on rank 0
  /// (the 2-D remeshing) then gives the serial run's bits. Collective.
  static vtkSmartPointer<vtkUnstructuredGrid> GatherVolumeOnRoot(vtkUnstructuredGrid* piece);
  /// Every rank's `local` grid on rank 0, in rank order, coincident points
  /// merged (vtkAppendFilter, tolerance 0); an empty grid elsewhere. Under
  /// MPI only (a collective call).
  static vtkSmartPointer<vtkUnstructuredGrid> MergeOnRoot(vtkUnstructuredGrid* local);
};

#endif
