// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkARInputChecks
 * @brief Private validation helpers shared by the AdaptiveRedistribution
 *        filters: property ranges, NaN/Inf coordinates, duplicated points (a
 *        non-conforming volume) and the size of a remeshing job.
 *
 * Not part of the public API. Every check returns the sentence(s) that name
 * the problem (empty when the input is fine); the filter reports them with
 * its own vtkErrorMacro and passes its input through (or leaves its output
 * empty), as its other errors do. No check clamps or repairs anything.
 */
#ifndef vtkARInputChecks_h
#define vtkARInputChecks_h

#include "vtkType.h"

#include <initializer_list>
#include <sstream>
#include <string>

class vtkDataSet;
class vtkPoints;
class vtkUnstructuredGrid;

class vtkARInputChecks
{
public:
  /**
   * Property values checked against their valid ranges, one sentence per bad
   * property: "RemovalFactor is -1; it must lie in (0, 1000] (the radius of
   * removal ...)." NaN fails every range. Used instead of vtkSetClampMacro,
   * which hides the user's mistake. The ranges agree with the XML's domains.
   */
  class Properties
  {
  public:
    /// value in [lo, hi] (hi may be VTK_DOUBLE_MAX or VTK_INT_MAX: no upper bound).
    Properties& InRange(const char* name, double value, double lo, double hi, const char* meaning = nullptr);
    /// value in (lo, hi] (hi as above).
    Properties& AboveAndAtMost(const char* name, double value, double lo, double hi, const char* meaning = nullptr);
    /// value one of 0, 1, ..., names.size() - 1, named by `names`.
    Properties& OneOf(const char* name, int value, std::initializer_list<const char*> names);
    /// A problem found elsewhere, added as it is.
    Properties& Add(const std::string& sentence);

    bool Ok() const { return this->Text.str().empty(); }
    /// The sentences, each ending with ". " (empty when every value is valid).
    std::string Message() const { return this->Text.str(); }

  private:
    Properties& Range(const char* name, double value, double lo, bool loOpen, double hi, const char* meaning);
    std::ostringstream Text;
  };

  /// The lowest id of a point with a NaN or Inf coordinate, or -1.
  static vtkIdType FirstNonFinitePoint(vtkPoints* points);
  static vtkIdType FirstNonFinitePoint(const double* xyz, vtkIdType n);

  /// "" when every point of `data` (a vtkPointSet; other datasets are
  /// fine) is finite, else "Point 17 of <what> has a non-finite coordinate
  /// (NaN or Inf): (nan, 0.25, 0)[, and N more points too]: every coordinate
  /// must be finite. " — `what` e.g. "the volume mesh".
  static std::string NonFinitePoints(vtkDataSet* data, const char* what);
  static std::string NonFinitePoints(const double* xyz, vtkIdType n, const char* what);

  /**
   * A volume mesh whose cells do not share their faces across a crack:
   * distinct points used by 3-D cells at exactly the same location
   * (duplicated points), so that the faces on either side are each used by
   * one cell, although they are interior. "" when there are none, else a
   * message with the number of duplicated points, the number of such faces
   * and where the first one is. A mesher (TetGen) given such a mesh fails or
   * corrupts its heap, so this runs before it. O(n) with a static point
   * locator; cells are looked at only when duplicates exist.
   */
  static std::string DuplicatedPoints(vtkUnstructuredGrid* grid);

  /**
   * The largest number of elements (surface triangles plus volume cells) a
   * remeshing job may create: half the machine's physical memory at
   * BytesPerElement each, 2.5x the peak measured on EmbeddedRemesh FullDomain
   * runs (peak RSS over the elements made: 313 bytes on the oblique shock at
   * 1.8e6 elements, 400 on Kuhn cubes of 5.1e6 tetrahedra remeshed into
   * 11.1e6; TetGen's child process 336).
   */
  static double MaximumElements();
  static constexpr double BytesPerElement = 1024.0;
  /// The machine's physical memory in bytes (0 when unknown).
  static double PhysicalMemory();
};

#endif
// VTK-HeaderTest-Exclude: vtkARInputChecks.h
