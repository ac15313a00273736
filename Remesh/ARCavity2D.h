// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file ARCavity2D.h
 * @brief LocalCavity remeshing of a planar mesh (paper section 2.4 in two
 *        dimensions): remove the nodes of a triangle/quad mesh near feature
 *        curves and refill the void with a constrained Delaunay mesh in which
 *        the curves are edges.
 *
 * This is the cross-section of a one-cell-deep ("2-D") finite-volume mesh,
 * e.g. an OpenFOAM 2-D case: the caller extrudes the result back into
 * hexahedra and wedges between the front and back planes.
 *
 * Removal as in 3-D: a node V_j goes when it lies within RemovalFactor *
 * max(l_ci, l_vj) of a curve node C_i (l = the longest edge at the node) and,
 * with VisibilityTest, the segment C_i V_j crosses no boundary edge of V. The
 * cells touching removed nodes form the cavity. Its boundary (the edges it
 * shares with kept cells and its edges on V's boundary) is kept exactly: the
 * nodes on it stay and its edges are never split, so the kept cells and the
 * domain boundary do not change. The curves are trimmed back: a curve node
 * outside V or closer than BoundaryMargin * max(l_ci, l_b) to V's boundary (l_b
 * the nearest boundary edge) is dropped
 * with its segments, so no boundary edge is cut.
 *
 * The refill: CGAL's Constrained_Delaunay_triangulation_2 of the cavity
 * boundary and the curves (both constraints), the faces inside the cavity
 * marked by parity across the cavity boundary (kept regions and holes of the
 * domain stay empty), then Delaunay_mesher_no_edge_refinement_2 (no
 * constrained edge is split) with a minimum-angle bound and a size field
 * interpolated linearly, over a Delaunay triangulation of the constrained
 * nodes, from the curves' edge length at the curve nodes to the mean edge
 * length of V at the cavity-boundary nodes. A face whose refinement point
 * would encroach a constrained edge is left as it is, so the angle bound is
 * what the refinement aims at; the smallest angle reached is reported.
 * Deterministic: the same input gives the same output.
 */
#ifndef ARCavity2D_h
#define ARCavity2D_h

#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

namespace ar
{
/// A planar mesh of triangles and quads: points as x0 y0 x1 y1 ...; cell c
/// is Connectivity[Offsets[c] .. Offsets[c + 1]), counter-clockwise (positive
/// area). Offsets has one entry more than there are cells.
struct Mesh2D
{
  std::vector<double> Points;
  std::vector<std::int64_t> Offsets{ 0 };
  std::vector<std::int64_t> Connectivity;

  std::size_t NumberOfPoints() const { return this->Points.size() / 2; }
  std::size_t NumberOfCells() const { return this->Offsets.empty() ? 0 : this->Offsets.size() - 1; }
  void AddCell(std::initializer_list<std::int64_t> ids)
  {
    this->Connectivity.insert(this->Connectivity.end(), ids.begin(), ids.end());
    this->Offsets.push_back(static_cast<std::int64_t>(this->Connectivity.size()));
  }
};

struct Cavity2DOptions
{
  double RemovalFactor = 3.0;  ///< radius of removal in max(l_ci, l_vj)
  bool VisibilityTest = true;  ///< a boundary edge between C_i and V_j keeps V_j
  double BoundaryMargin = 1.0; ///< curves trimmed this many max(l_ci, l_b) away from V's boundary
  double MinAngle = 25.0;      ///< degrees: the refinement's bound on the new triangles' angles
  /// A new triangle is refined when its longest edge exceeds SizeRatio times
  /// the size field at its centroid.
  double SizeRatio = 1.5;
  /// Remove every node: the whole cross-section is remeshed with the curves
  /// embedded (FullDomain); the domain boundary is still kept exactly.
  bool FullDomain = false;
};

struct Cavity2DRemesh
{
  Mesh2D Mesh;                           ///< kept points (input order) then new ones; kept cells (input order) then new triangles
  std::vector<std::int64_t> SourcePoint; ///< per output point: input point id, or -1 (new)
  std::vector<std::int64_t> SourceCell;  ///< per output cell: input cell id (kept), or -1 (new)
  std::vector<std::int64_t> Curve;       ///< the embedded curve segments, pairs of output point ids
  std::size_t RemovedNodes = 0;          ///< nodes of V removed
  std::size_t RemovedCells = 0;          ///< cells of V in the cavity
  std::size_t CurveSegmentsUsed = 0;     ///< curve segments left after the trim
  double MinAngleNew = 0.0;              ///< smallest angle of the new triangles, degrees
};

/**
 * Remeshes the cavity of V around the curves. V: counter-clockwise triangles
 * and quads (an inverted or flat cell is refused), conforming (an edge in at
 * most two cells). Curves: nodes (x y each) and segments (pairs of node ids),
 * ideally of nearly uniform length (the caller resamples them).
 *
 * Returns false with `error` naming the problem for: an empty V or curve set,
 * a cell that is not a triangle or quad, an inverted cell, a non-conforming
 * V, non-finite coordinates, curves entirely outside V (or nothing left after
 * the trim), curves crossing themselves or each other, a curve crossing the
 * cavity's boundary (raise RemovalFactor), nothing to remove, or a
 * refinement that does not finish.
 */
bool RemeshLocalCavity2D(const Mesh2D& V, const double* curvePoints, std::size_t nCurvePoints,
  const std::int64_t* curveSegments, std::size_t nCurveSegments, const Cavity2DOptions& options,
  Cavity2DRemesh& out, std::string& error);
}

#endif
