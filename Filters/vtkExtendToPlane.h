// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkExtendToPlane
 * @brief Trims a feature surface near a plane and extends its open edges orthogonally onto it.
 *
 * Made for symmetry planes: a medial sheet or fitted shock surface that
 * degrades, or stops short, near a symmetry plane is cut back and then
 * continued straight down to the plane, so that it meets the plane at a
 * right angle (as a shock does at a plane of symmetry).
 *
 * Input: any vtkDataSet; it is reduced to its polygons (vtkGeometryFilter
 * for a non-polydata input), triangulated (vtkTriangleFilter) and exactly
 * coincident points are merged (vtkCleanPolyData, tolerance 0).
 *
 * Convention: s(x) = n . (x - PlaneOrigin), n = PlaneNormal / |PlaneNormal|.
 * The surface is kept where s > TrimDistance: the side the normal points to
 * (the inside of the domain for an inward normal), exactly clipped by
 * vtkClipPolyData (point arrays interpolated). When the surface lies mostly
 * on the other side (the area-weighted mean of s over the surface is
 * negative) the normal is flipped first, so that either orientation of the
 * plane works; the normal actually used is the field array
 * `ExtendPlaneNormal`.
 *
 * Then every open boundary edge (an edge used by exactly one polygon; edges
 * of three or more polygons of a non-manifold sheet are not open) whose two
 * end points lie within MaximumGap of the plane, and which makes an angle of
 * at most 30 degrees with the plane (|s(a) - s(b)| <= |ab| / 2: side edges
 * that leave the plane steeply are not extended), and whose polygon lies
 * farther from the plane than the edge (the surface ends towards the plane:
 * the far edge of a sheet narrower than the gap is left alone), gets a strip from the edge
 * to its orthogonal projection onto the plane (s = 0): each end point x
 * gets a column x - t s(x) n, t in [0, 1], divided into ceil(s(x) / h)
 * rows, h the mean edge length of the trimmed surface; columns are shared
 * by neighbouring edges and two columns with different row counts are
 * zipped together, so the strip conforms to itself and to the surface, and
 * each strip triangle contains the direction n (the surface meets the plane
 * orthogonally). Strip triangles are oriented like the polygon that owns
 * the edge. A boundary point already on the plane (s below 1e-9 h) gets no
 * column.
 *
 * MaximumGap 0 (default) is automatic: smin + h, smin the smallest s of an
 * open boundary point: the boundary nearest the plane (after a trim, the
 * cut, where s = TrimDistance) is extended, with its ragged parts up to one
 * edge length farther away.
 *
 * Output: vtkPolyData triangles; the trimmed surface first (cell array
 * `Extended` = 0), then the strips (`Extended` = 1). Point arrays of a strip
 * point are copied from the boundary point its column starts at; cell arrays
 * of a strip triangle from the polygon owning its edge. Field data
 * `ExtendPlaneNormal` (3), `ExtendMeanEdgeLength`, `ExtendMaximumGap` (the
 * gap used), `NumberOfExtendedEdges`.
 *
 * Errors (vtkErrorMacro naming the problem, empty output): no polygons, a
 * zero or non-finite PlaneNormal, a non-finite PlaneOrigin, non-finite point
 * coordinates, nothing left after trimming, a strip that would need more than
 * 10 million points.
 *
 * Serial: under MPI each rank extends its own piece (feature surfaces from
 * vtkQuadricFit live on rank 0).
 */
#ifndef vtkExtendToPlane_h
#define vtkExtendToPlane_h

#include "AdaptiveRedistributionFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

class ADAPTIVEREDISTRIBUTIONFILTERS_EXPORT vtkExtendToPlane : public vtkPolyDataAlgorithm
{
public:
  static vtkExtendToPlane* New();
  vtkTypeMacro(vtkExtendToPlane, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// A point on the plane. Default (0, 0, 0).
  vtkSetVector3Macro(PlaneOrigin, double);
  vtkGetVector3Macro(PlaneOrigin, double);
  ///@}

  ///@{
  /// The plane's normal (need not be unit length, must not be zero): the
  /// surface is kept on the side it points to (flipped automatically when
  /// the surface lies mostly on the other side). Default (0, 0, 1).
  vtkSetVector3Macro(PlaneNormal, double);
  vtkGetVector3Macro(PlaneNormal, double);
  ///@}

  ///@{
  /// The part of the surface within this distance of the plane (and beyond
  /// it) is cut away before extending. Default 0 (only the part beyond the
  /// plane is cut). Not clamped: a negative or non-finite value is refused
  /// with an error naming it.
  vtkSetMacro(TrimDistance, double);
  vtkGetMacro(TrimDistance, double);
  ///@}

  ///@{
  /// Open boundary edges with an end point farther than this from the plane
  /// are not extended. 0 (default): automatic, the smallest distance of an
  /// open boundary point plus the mean edge length. Not clamped: a negative
  /// or non-finite value is refused with an error naming it.
  vtkSetMacro(MaximumGap, double);
  vtkGetMacro(MaximumGap, double);
  ///@}

  /// Number of boundary edges extended by the last execution.
  vtkGetMacro(NumberOfExtendedEdges, vtkIdType);

protected:
  vtkExtendToPlane();
  ~vtkExtendToPlane() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkExtendToPlane(const vtkExtendToPlane&) = delete;
  void operator=(const vtkExtendToPlane&) = delete;

  double PlaneOrigin[3] = { 0.0, 0.0, 0.0 };
  double PlaneNormal[3] = { 0.0, 0.0, 1.0 };
  double TrimDistance = 0.0;
  double MaximumGap = 0.0;
  vtkIdType NumberOfExtendedEdges = 0;
};

#endif
