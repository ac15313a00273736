// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file ARCavitySeparator.h
 * @brief A strip of triangles from S's open border to the cavity's boundary
 *        that, with S, cuts the cavity in two, so that its refill can run in
 *        two TetGen processes side by side (ARTetGenPieces.h).
 *
 * S is trimmed back from the cavity's boundary (ARCavity.h), so S alone never
 * separates the cavity, and a cavity around one shock is one piece: its
 * refill, most of a large adaptation's time, runs in one process. The strip
 * closes the gap between S's border and the boundary:
 *  - the boundary's triangles are classified by the side of S their centroid
 *    lies on (the nearest point of S and its triangle's normal);
 *  - the edges between the two classes form closed loops on the boundary,
 *    one per border loop of S where S is a sheet across the cavity (each
 *    loop vertex in exactly two loop edges, else there is no strip);
 *  - each border loop of S is matched with the boundary loop nearest to it
 *    (one to one), turned to run the same way, and the two are stitched
 *    (the monotone stitching with the least sum of new edges, by dynamic
 *    programming, as for optimal contour triangulations); the band is
 *    several of S's edges wide and its loops differ in spacing (S's edge,
 *    the input's size), so loops of new points are laid between them along
 *    the stitching's rungs (quadratic Bezier curves that reach the boundary
 *    along its inward normal, so that the strip meets it square), their
 *    spacing and the bands' widths growing geometrically from one loop's
 *    spacing to the other's, each pair of loops stitched in turn, oriented
 *    as S, and the new points smoothed within the strip (damped Laplacian
 *    passes, a move kept where its triangles' smallest angle does not fall);
 *  - refused (no strip) where a triangle of the strip has an angle under
 *    `minAngle` degrees, or crosses S, the boundary or another strip
 *    triangle (CGAL, exact predicates; triangles sharing a point: each
 *    one's edge away from it against the other; sharing an edge: folded
 *    onto each other). A crossing this misses makes TetGen fail, and the
 *    cavity is then refilled whole (ARCavity.cxx).
 * The strip's border is S's border and boundary edges; TetGen, which keeps
 * every facet (-Y), meets it alike from both sides. Its own points are new
 * points of the refill (free to move in the sliver smoothing afterwards:
 * the strip is no surface of the output).
 */
#ifndef ARCavitySeparator_h
#define ARCavitySeparator_h

#include <cstdint>
#include <string>
#include <vector>

namespace ar
{
/**
 * points: x y z per point of the complex. boundary: the cavity's boundary
 * triangles (3 ids each, a closed surface). surface: S's triangles (3 ids
 * each, consistently oriented, in the same point ids). On success `strip`
 * gets the strip's triangles (3 ids each; ids from points.size() / 3 on are
 * its own points inside, `newPoints`, x y z each) and true is returned;
 * false with `why` saying why there is none.
 */
bool CavitySeparatingStrip(const std::vector<double>& points, const std::vector<std::int64_t>& boundary,
  const std::vector<std::int64_t>& surface, double minAngle, std::vector<std::int64_t>& strip,
  std::vector<double>& newPoints, std::string& why);

/**
 * The strip's mending after its smoothing (CavitySeparatingStrip runs it): a
 * triangle of `strip` (3 ids each into `points`, x y z each) with an angle
 * under `minAngle` degrees and one of the strip's own points (id >=
 * firstNew) has that point merged into another corner of it, where the merge
 * keeps the strip a manifold (the two points' common neighbours are the
 * third corners of the triangles on their edge), turns no triangle over and
 * raises the smallest angle of the triangles that change; repeated while
 * one mends. The other points never move or go. A ring point laid a fifth
 * of an edge from a corner of S's jagged border left a 3.6 degree triangle
 * on the 5e6 cube, and the strip was refused (its refill then took 26 s
 * instead of 12). Points no triangle uses any more stay in `points`.
 */
void CollapseThinStripTriangles(
  const std::vector<double>& points, std::int64_t firstNew, double minAngle, std::vector<std::int64_t>& strip);
}

#endif
