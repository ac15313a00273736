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
 *
 * Anisotropic layers (Layers.NumberOfLayers > 0; the 2-D analogue of
 * ar::BuildPrismLayers, paper sections 4.1, 4.2 and Fig. 11): the curves'
 * nodes are offset on both sides along smoothed node normals by the layer
 * distances z_1 .. z_N of ar::PrismLayerDistances (FirstLayerThickness *
 * GrowthRatio^k, or TotalThickness split in that ratio: the same rule as in
 * 3-D), and consecutive offset polylines bound quadrilaterals, N per curve
 * segment and side. The + side is the left of the segment's direction (the
 * normal (-dy, dx)). Normals: the mean of the two segments' unit normals at
 * a node, then NormalSmoothingIterations Jacobi passes (a pass at a node is
 * refused where it would see either segment at a dot below 0.3). Heights
 * (per node and side, the whole column scaled, so the growth ratio stays):
 *  - an open curve's end nodes get height 0: the stack tapers to nothing
 *    there and the end segment's layer cells are triangles (the quads with
 *    their two corners at the end node merged);
 *  - along the normal, at most GapFraction of the free distance to the
 *    cavity's boundary and to the curves (the other side, other curves),
 *    and at most GapFraction of the distance to any other curve (in any
 *    direction: rays miss a curve that ends beside this one);
 *  - graded along the curve, |H_u - H_v| <= MaxHeightGradient |x_u - x_v|;
 *  - then every layer cell is checked (each quad corner's sine at least
 *    min(0.05, half its value at layer 0, set by the normals), each end
 *    triangle positive) and the outermost polylines must cross neither each
 *    other nor the cavity's boundary (CGAL's box intersection, exact
 *    predicates); the columns of failing cells shrink by 0.7 and the check
 *    repeats. A column that would have to go below 1e-3 of the stack makes
 *    the call fail.
 * The outermost polylines (closed around an open curve through its end
 * nodes; two loops around a closed one) are the constraints of the CDT in
 * place of the curves, the band between them is no part of the refill, and
 * the refill's size field takes the curve's edge length at their nodes. The
 * removal radius grows by the stack height z_N, as in 3-D. With BothSides
 * off the - side has height 0 (the curve itself bounds the band). Curves
 * with branches (a node in three segments) or of one segment are refused.
 */
#ifndef ARCavity2D_h
#define ARCavity2D_h

#include "ARPrismLayers.h"

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
  /// Layers of quads on both sides of the curves (NumberOfLayers 0: off);
  /// the fields mean what they mean for ar::BuildPrismLayers.
  PrismLayerOptions Layers;
};

struct Cavity2DRemesh
{
  /// Points: kept (input order), the curves' nodes, the layer points, the
  /// refinement's. Cells: kept (input order), the layer cells (quads, and
  /// triangles at a curve's tapered ends), then the new triangles.
  Mesh2D Mesh;
  std::vector<std::int64_t> SourcePoint; ///< per output point: input point id, or -1 (new)
  std::vector<std::int64_t> SourceCell;  ///< per output cell: input cell id (kept), or -1 (new)
  std::vector<std::int64_t> Curve;       ///< the embedded curve segments, pairs of output point ids
  std::size_t RemovedNodes = 0;          ///< nodes of V removed
  std::size_t RemovedCells = 0;          ///< cells of V in the cavity
  std::size_t CurveSegmentsUsed = 0;     ///< curve segments left after the trim
  double MinAngleNew = 0.0;              ///< smallest angle of the new (refill) triangles, degrees
  // ---- Layers (options.Layers on); empty or 0 otherwise.
  std::vector<int> CellLayer;            ///< per output cell: layer k (0 next to the curve) of a layer cell, else -1
  std::vector<int> CellSide;             ///< per output cell: +1 / -1 for layer cells, else 0
  std::size_t FirstCurvePoint = 0;       ///< output id of the first curve node (they are consecutive)
  std::size_t NumberOfCurvePoints = 0;
  std::vector<double> Normals;           ///< per curve node: the + side's unit column direction (x y)
  std::vector<double> Heights;           ///< per curve node: stack height on the + side, then (all nodes) on the - side
  std::vector<double> LayerDistances;    ///< the requested z_0 = 0 .. z_N
  std::size_t LayerQuads = 0;            ///< layer cells that are quads
  std::size_t LayerTriangles = 0;        ///< layer cells that are triangles (tapered ends)
  std::size_t LimitedColumns = 0;        ///< columns (node, side) lower than z_N, the tapered ends included
  int ShrinkRounds = 0;                  ///< rounds of the cell/crossing check that shrank columns
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
 * refinement that does not finish; with layers also bad layer options (as
 * ar::PrismLayerDistances names them), a branching or one-segment curve, a
 * curve turning too sharply for its normals, or a column that cannot be
 * made valid.
 */
bool RemeshLocalCavity2D(const Mesh2D& V, const double* curvePoints, std::size_t nCurvePoints,
  const std::int64_t* curveSegments, std::size_t nCurveSegments, const Cavity2DOptions& options,
  Cavity2DRemesh& out, std::string& error);
}

#endif
