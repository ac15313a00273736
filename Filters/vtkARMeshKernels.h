// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkARMeshKernels
 * @brief Private helpers shared by the AdaptiveRedistribution filters.
 *
 * Not part of the public API. Gives the per-cell loops of the sensors a flat,
 * read-only view of a vtkUnstructuredGrid (points as doubles, 64-bit offsets
 * and connectivity, cell types, ghost flags), the least-squares gradient
 * operator of any linear 3-D cell, a threaded cell-to-point averaging, MPI
 * reductions over the global controller, and input validation.
 */
#ifndef vtkARMeshKernels_h
#define vtkARMeshKernels_h

#include "vtkDataSetAttributes.h" // for vtkDataSetAttributes::DUPLICATECELL
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h" // for the return type of GatherDomainBoundary
#include "vtkType.h"

#include <algorithm> // for TupleSources
#include <atomic>
#include <functional> // for Threaded
#include <cmath>
#include <memory> // for TetLocator's internals
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

  /// MPI reductions over the global controller (no-ops in serial).
  static void AllReduceMax(double* values, int n);
  static void AllReduceSum(double* values, int n);
  /// Every rank's `local` concatenated in rank order on rank 0 (empty on the
  /// other ranks; `local` itself in serial). Collective.
  static std::vector<double> GatherOnRoot(const std::vector<double>& local);
  static int NumberOfRanks();

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

  /// A named double field array holding `n` values.
  static vtkSmartPointer<vtkDoubleArray> FieldArray(const char* name, const double* values, int n);

  /**
   * Where each tuple of a field transfer comes from: one source tuple
   * copied, or (Width > 1) up to Width source tuples weighted (linear
   * interpolation in a tetrahedron: 4; in a hexahedron: 8).
   */
  struct TupleSources
  {
    /// Source tuples per output tuple: 1 (copies only), or the most any
    /// interpolation uses.
    int Width = 1;
    /// Width ids per output tuple. Ids[Width*i] < 0: tuple i is not filled
    /// (another source fills it); with Width > 1, Ids[Width*i+1] < 0: a copy
    /// of tuple Ids[Width*i]; an interpolation of fewer than Width tuples
    /// ends at the first negative id.
    std::vector<vtkIdType> Ids;
    /// Width per output tuple with Width > 1 (empty with Width 1).
    std::vector<double> Weights;

    TupleSources(vtkIdType n, int width)
      : Width(width)
      , Ids(static_cast<std::size_t>(n) * width, -1)
      , Weights(width > 1 ? static_cast<std::size_t>(n) * width : 0, 0.0)
    {
    }
    vtkIdType Size() const { return static_cast<vtkIdType>(this->Ids.size()) / this->Width; }
    void Copy(vtkIdType i, vtkIdType from) { this->Ids[static_cast<std::size_t>(i) * this->Width] = from; }
    /// Tuple i interpolated from the `count` (at most Width; 0: Width)
    /// tuples `from` with `weights`.
    void Interpolate(vtkIdType i, const vtkIdType* from, const double* weights, int count = 0)
    {
      const std::size_t w = static_cast<std::size_t>(this->Width), n = count > 0 ? count : w;
      std::copy(from, from + n, &this->Ids[w * i]);
      std::copy(weights, weights + n, &this->Weights[w * i]);
    }
  };

  /**
   * Fills the arrays of `to` (just allocated from `from` by CopyAllocate or
   * InterpolateAllocate, sources.Size() tuples) as `sources` says: array by
   * array, on threads over the tuples, with the calls vtkDataSetAttributes'
   * CopyData and InterpolatePoint make for each array (InsertTuple,
   * InterpolateTuple, the nearest source tuple for an attribute flagged 2 for
   * interpolation), so the values are theirs. Arrays that are not numeric
   * (strings) are filled on one thread. Falls back to CopyData and
   * InterpolatePoint tuple by tuple when the arrays cannot be paired by
   * name (an unnamed array, or two with one name).
   */
  static void TransferData(vtkDataSetAttributes* from, vtkDataSetAttributes* to, const TupleSources& sources);
  /// The same for the arrays `list` pairs for its input `index` (`to` was
  /// allocated by the list's CopyAllocate or InterpolateAllocate).
  static void TransferData(const vtkDataSetAttributesFieldList& list, int index, vtkDataSetAttributes* from,
    vtkDataSetAttributes* to, const TupleSources& sources);

  /**
   * Point location in a set of tetrahedra, reproducible: the answer for a
   * point depends only on the point and on where its search starts, never on
   * the threads. A search walks from a start tetrahedron towards the point,
   * each step across the face whose barycentric coordinate is the most
   * negative (the neighbour found from the corners' sorted cell links),
   * until every coordinate is >= -1e-10. The queries are taken in Morton
   * order of their points (for the memory, not the result) in fixed blocks
   * of 256: a query's start is its own (given), else the previous query's
   * cell in its block, else (first of a block, or a walk that failed) the
   * cell of least id around its nearest vertex (vtkStaticPointLocator). A
   * walk that still fails (it leaves a concave cavity or takes 1000 steps)
   * is redone after the threaded pass, in query order, by
   * vtkStaticCellLocator::FindCell and, for a point outside every
   * tetrahedron (round-off at the boundary), FindClosestPoint, the weights
   * then those of the closest point.
   */
  class TetLocator
  {
  public:
    TetLocator();
    ~TetLocator();
    TetLocator(const TetLocator&) = delete;
    TetLocator& operator=(const TetLocator&) = delete;

    /// `tets` holds VTK_TETRA cells only; it is kept (not copied).
    void Build(vtkUnstructuredGrid* tets);
    /// Locates the n points x[3q..3q+2], on threads: cell[q] (a cell of
    /// `tets`) and its barycentric weights weights[4q..4q+3] (weights may be
    /// null). start: a cell to walk from per query, -1 (or start null) for
    /// the nearest vertex's.
    void Locate(vtkIdType n, const double* x, const vtkIdType* start, vtkIdType* cell, double* weights) const;
    /// The tetrahedron of least id using point p, -1 if none does.
    vtkIdType CellOfPoint(vtkIdType p) const;
    /// The four point ids of cell c.
    const vtkIdType* CellPoints(vtkIdType c) const;
    /// Queries the walk could not answer in the last Locate (for tests and timings).
    vtkIdType LastFallbacks() const;

  private:
    struct vtkInternals;
    std::unique_ptr<vtkInternals> Internals;
  };
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
  std::vector<double> weighted(static_cast<size_t>(ncells) * stride, 0.0);
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
  out.assign(static_cast<size_t>(npts) * nComp, 0.0);
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
