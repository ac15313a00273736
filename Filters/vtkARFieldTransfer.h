// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkARFieldTransfer
 * @brief Private: carrying fields from an input mesh to a remeshed one.
 *
 * Not part of the public API. Where each output tuple comes from
 * (TupleSources), the threaded copy and interpolation array by array
 * (TransferData, with vtkDataSetAttributes' own rules), and a reproducible
 * point location in tetrahedra (TetLocator). Used by EmbeddedRemesh's
 * drivers.
 */
#ifndef vtkARFieldTransfer_h
#define vtkARFieldTransfer_h

#include "ARHugePages.h" // for TupleSources
#include "vtkType.h"

#include <algorithm> // for TupleSources
#include <memory>    // for TetLocator's internals
#include <vector>

class vtkDataSetAttributes;
class vtkDataSetAttributesFieldList;
class vtkUnstructuredGrid;

class vtkARFieldTransfer
{
public:
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
    {
      ar::AssignHuge(this->Ids, static_cast<std::size_t>(n) * width, vtkIdType(-1));
      ar::AssignHuge(this->Weights, width > 1 ? static_cast<std::size_t>(n) * width : 0, 0.0);
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
   * point depends only on the point (and, for a walk that fails, on where
   * its search starts), never on the threads. A search walks from a start
   * tetrahedron towards the point, each step across the face whose
   * barycentric coordinate is the most negative (the neighbour found from
   * the corners' sorted cell links), until every coordinate is >= -1e-10;
   * where one is within 1e-10 of 0 (the point on a face, an edge or a
   * corner) the answer is, of the tetrahedra that hold it there, the one
   * that comes first by its sorted corners' coordinates, whichever side the
   * walk came from. The queries are taken in Morton
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

#endif
