// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkARMeshKernels
 * @brief Private helpers shared by the AdaptiveRedistribution filters.
 *
 * Not part of the public API. Gives the per-cell loops of the sensors a flat,
 * read-only view of a vtkUnstructuredGrid (points as doubles, 64-bit offsets
 * and connectivity, cell types, ghost flags), the least-squares gradient
 * operator of any linear 3-D cell, a reproducible threaded cell-to-point
 * averaging, and the filters' pipeline helpers (the collective input check,
 * ghost levels, the scoped SMP backend, field arrays). The MPI helpers are
 * vtkARParallel, the field transfer to a remeshed mesh vtkARFieldTransfer.
 */
#ifndef vtkARMeshKernels_h
#define vtkARMeshKernels_h

#include "ARHugePages.h" // for the large arrays of CellsToPoints
#include "vtkDataSetAttributes.h" // for vtkDataSetAttributes::DUPLICATECELL
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h" // for the return type of FieldArray
#include "vtkType.h"

#include <algorithm>
#include <atomic>
#include <functional> // for Threaded
#include <cmath>
#include <string>
#include <vector>

class vtkAbstractArray;
class vtkAlgorithm;
class vtkDataSetAttributesFieldList;
class vtkInformationVector;
class vtkDataArray;
class vtkDoubleArray;
class vtkDataSet;
class vtkPolyData;
class vtkDataSetAttributes;
class vtkUnstructuredGrid;

class vtkARMeshKernels
{
public:
  /// Largest number of points of a cell the gradient operator accepts.
  static constexpr int MaxCellPoints = 64;

  /// Flat read-only view of an unstructured grid.
  struct MeshView
  {
    vtkIdType NumberOfPoints = 0;
    vtkIdType NumberOfCells = 0;
    const double* X = nullptr;
    const vtkIdType* Offsets = nullptr;
    const vtkIdType* Connectivity = nullptr;
    const unsigned char* Types = nullptr;
    const unsigned char* CellGhosts = nullptr;
    const unsigned char* PointGhosts = nullptr;

    /// Fills the view; copies only what is not already stored as doubles and
    /// 64-bit ids. Returns false (with a message) if there is nothing to view.
    bool Build(vtkUnstructuredGrid* grid, std::string& error);

    /// A linear 3-D cell the gradient operator handles.
    bool IsVolumeCell(vtkIdType c) const { return VolumeCellTable[this->Types[c]]; }
    /// A cell this rank owns (not a ghost copy of another rank's cell).
    bool IsOwnedCell(vtkIdType c) const
    {
      return !this->CellGhosts ||
        !(this->CellGhosts[c] & (vtkDataSetAttributes::DUPLICATECELL | vtkDataSetAttributes::HIDDENCELL));
    }
    bool IsOwnedPoint(vtkIdType p) const
    {
      return !this->PointGhosts || !(this->PointGhosts[p] & vtkDataSetAttributes::DUPLICATEPOINT);
    }
    int CellSize(vtkIdType c) const { return static_cast<int>(this->Offsets[c + 1] - this->Offsets[c]); }
    const vtkIdType* CellPoints(vtkIdType c) const { return this->Connectivity + this->Offsets[c]; }

  private:
    std::vector<double> XStore;
    std::vector<vtkIdType> OffsetStore, ConnectivityStore;
    static const bool* VolumeCellTable;
  };

  /// What a mesh is made of, for validation messages.
  struct CellCensus
  {
    vtkIdType VolumeCells = 0;     ///< linear 3-D cells (tet, pyramid, wedge, hex, voxel, prisms, polyhedra)
    vtkIdType LowerDimensional = 0; ///< vertices, lines, triangles, quads, polygons ...
    vtkIdType NonLinear = 0;       ///< quadratic, higher-order and other cells
    vtkIdType TooManyPoints = 0;   ///< polyhedra with more than MaxCellPoints points
  };
  static CellCensus Census(const MeshView& mesh);

  /**
   * Least-squares gradient operator of cell c: for any field f given at the
   * cell's points, grad f = sum_a W[a] f_a exactly for linear f (for a
   * tetrahedron this is the exact P1 gradient). W[a] = M^-1 (x_a - x_c), with
   * M = sum_a (x_a - x_c)(x_a - x_c)^T and x_c the vertex centroid.
   *
   * `measure` = sqrt(det M) / 3, which equals the volume of a tetrahedron and
   * is within 6% of the volume of a cube; it weights cell-to-point averages.
   * Returns false for a degenerate (flat) cell.
   */
  static bool GradientOperator(const MeshView& mesh, vtkIdType c, double W[][3], int& n, double& measure);

  /**
   * The tetrahedron case, inline for the hot loops: with J the matrix whose
   * rows are the edges x_a - x_0 (a = 1..3), fills Jinv = J^-1 so that
   * grad f = Jinv (f_1 - f_0, f_2 - f_0, f_3 - f_0), and the volume.
   * Returns false for a degenerate (flat) tetrahedron.
   */
  static bool TetInverseJacobian(const double* X, const vtkIdType* ids, double Jinv[3][3], double& volume)
  {
    const double* x0 = X + 3 * ids[0];
    const double* x1 = X + 3 * ids[1];
    const double* x2 = X + 3 * ids[2];
    const double* x3 = X + 3 * ids[3];
    const double a[3] = { x1[0] - x0[0], x1[1] - x0[1], x1[2] - x0[2] };
    const double b[3] = { x2[0] - x0[0], x2[1] - x0[1], x2[2] - x0[2] };
    const double c[3] = { x3[0] - x0[0], x3[1] - x0[1], x3[2] - x0[2] };
    // Columns of J^-1 are (b x c, c x a, a x b) / det.
    const double bc[3] = { b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2], b[0] * c[1] - b[1] * c[0] };
    const double ca[3] = { c[1] * a[2] - c[2] * a[1], c[2] * a[0] - c[0] * a[2], c[0] * a[1] - c[1] * a[0] };
    const double ab[3] = { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
    const double det = a[0] * bc[0] + a[1] * bc[1] + a[2] * bc[2];
    const double scale = a[0] * a[0] + a[1] * a[1] + a[2] * a[2] + b[0] * b[0] + b[1] * b[1] +
      b[2] * b[2] + c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    if (!(std::abs(det) > 1e-9 * scale * std::sqrt(scale)))
    {
      return false;
    }
    const double inv = 1.0 / det;
    for (int k = 0; k < 3; ++k)
    {
      Jinv[k][0] = bc[k] * inv;
      Jinv[k][1] = ca[k] * inv;
      Jinv[k][2] = ab[k] * inv;
    }
    volume = std::abs(det) / 6.0;
    return true;
  }

  /**
   * Average of per-cell values at the points: each cell for which
   * `cellFn(c, values, weight)` returns true adds weight*values to its points.
   * Ghost cells take part (they complete the stencils of partition-boundary
   * points). Points no cell reaches get 0. `out` gets npts*nComp values,
   * each point's sum taken over its cells in ascending order, so the result
   * does not depend on the threads. Returns false if aborted.
   */
  template <typename CellFn>
  static bool CellsToPoints(const MeshView& mesh, int nComp, CellFn&& cellFn,
    std::vector<double>& out, vtkAlgorithm* abortSource);

  /**
   * Collective check before any computation: every rank calls it once with
   * its own validation result (`problem` empty when fine). Reports the
   * problem, or an empty mesh / a mesh with no 3-D cells over all ranks, as an
   * error of `self`, and warns when a distributed mesh has no ghost cells.
   * Returns true when every rank can go on. `need` names what the filter
   * computes, for the messages.
   */
  static bool AgreeToProceed(vtkAlgorithm* self, const std::string& problem,
    const MeshView& mesh, const CellCensus& census, const char* need);

  /**
   * Averages columns of a per-cell table to the points (weighted by the cell
   * measure, over linear 3-D cells) and writes them into columns of a
   * per-point table: point[p * pointStride + pointColumns[k]] = average of
   * cell[c * cellStride + cellColumns[k]]. Returns false if aborted.
   */
  /// The cells at each point (CSR: point p's cells are
  /// cells[offsets[p] .. offsets[p + 1]]), each point's in ascending cell
  /// order whatever the threads (a serial counting sort); only the cells with
  /// use[c] != 0 when `use` is given.
  static void PointCells(const MeshView& mesh, const std::vector<char>* use, std::vector<vtkIdType>& offsets,
    std::vector<vtkIdType>& cells);

  static bool CellColumnsToPoints(const MeshView& mesh, const double* cellTable, int cellStride,
    const std::vector<int>& cellColumns, double* pointTable, int pointStride,
    const std::vector<int>& pointColumns, vtkAlgorithm* abortSource);

  /// RequestUpdateExtent of the filters: the downstream piece request plus
  /// `extra` ghost levels (gradients and graph rings at partition boundaries
  /// need the neighbours).
  static void RequestExtraGhostLevels(
    vtkInformationVector** inputVector, vtkInformationVector* outputVector, int extra, int port = 0);

  /// Runs `work` with vtkSMPTools on threads (STDThread) when VTK would
  /// otherwise run it sequentially (Debian's ParaView defaults to Sequential)
  /// and the user has not chosen a backend (VTK_SMP_BACKEND_IN_USE): a
  /// vtkSMPTools::LocalScope, so the process's backend, and every other
  /// filter of the user's session, is left as it is.
  static void Threaded(const std::function<void()>& work);

  /// Abort check that is cheap and safe to call from worker threads.
  static bool Aborted(vtkAlgorithm* self);

  /// Copies the components of `array` (point or cell data) into `dest` with
  /// stride `stride` starting at `offset`: dest[i*stride + offset + k].
  /// Returns the first tuple holding NaN or Inf, or -1.
  static vtkIdType PackComponents(vtkDataArray* array, double* dest, int stride, int offset);

  /// A named double field array holding `n` values.
  static vtkSmartPointer<vtkDoubleArray> FieldArray(const char* name, const double* values, int n);

};

//------------------------------------------------------------------------------
template <typename CellFn>
bool vtkARMeshKernels::CellsToPoints(const MeshView& mesh, int nComp, CellFn&& cellFn,
  std::vector<double>& out, vtkAlgorithm* abortSource)
{
  // Each cell's weighted values once (threaded over cells), then each
  // point's sum over its cells in ascending cell order (threaded over
  // points). No sum depends on how the cells were split among threads, so a
  // run is bit for bit reproducible (thread-local accumulators, summed over
  // the threads' ranges, gave NormalMach different in 4,229 of 15,746 points
  // of the bundled cone from one run to the next).
  const vtkIdType npts = mesh.NumberOfPoints;
  const vtkIdType ncells = mesh.NumberOfCells;
  const int stride = nComp + 1;
  std::vector<double> weighted;
  ar::AssignHuge(weighted, static_cast<size_t>(ncells) * stride, 0.0);
  std::atomic<bool> aborted(false);
  vtkSMPTools::For(0, ncells, [&](vtkIdType begin, vtkIdType end) {
    if (aborted || Aborted(abortSource))
    {
      aborted = true;
      return;
    }
    double values[16];
    std::vector<double> big(nComp > 16 ? nComp : 0);
    double* v = nComp > 16 ? big.data() : values;
    for (vtkIdType c = begin; c < end; ++c)
    {
      double w = 0.0;
      if (!cellFn(c, v, w) || !(w > 0.0))
      {
        continue;
      }
      double* dst = &weighted[static_cast<size_t>(c) * stride];
      for (int k = 0; k < nComp; ++k)
      {
        dst[k] = w * v[k];
      }
      dst[nComp] = w;
    }
  });
  if (aborted)
  {
    return false;
  }
  // The cells at each point, in ascending order.
  std::vector<char> used(static_cast<size_t>(ncells));
  for (vtkIdType c = 0; c < ncells; ++c)
  {
    used[c] = weighted[static_cast<size_t>(c) * stride + nComp] > 0.0 ? 1 : 0;
  }
  std::vector<vtkIdType> start, cells;
  PointCells(mesh, &used, start, cells);
  ar::AssignHuge(out, static_cast<size_t>(npts) * nComp, 0.0);
  vtkSMPTools::For(0, npts, [&](vtkIdType begin, vtkIdType end) {
    std::vector<double> sum(stride);
    for (vtkIdType p = begin; p < end; ++p)
    {
      std::fill(sum.begin(), sum.end(), 0.0);
      for (vtkIdType i = start[p]; i < start[p + 1]; ++i)
      {
        const double* src = &weighted[static_cast<size_t>(cells[i]) * stride];
        for (int k = 0; k < stride; ++k)
        {
          sum[k] += src[k];
        }
      }
      if (sum[nComp] > 0.0)
      {
        for (int k = 0; k < nComp; ++k)
        {
          out[static_cast<size_t>(p) * nComp + k] = sum[k] / sum[nComp];
        }
      }
    }
  });
  return true;
}

#endif
// VTK-HeaderTest-Exclude: vtkARMeshKernels.h
