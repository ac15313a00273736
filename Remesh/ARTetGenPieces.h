// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file ARTetGenPieces.h
 * @brief A piecewise linear complex split into the volume regions its
 *        triangles bound, and meshed region by region in parallel TetGen
 *        processes.
 *
 * Every triangle has two sides: the front (its right-hand normal's side)
 * and the back. Around every edge the triangles sharing it are sorted by
 * angle about the edge and each side is joined with the facing side of its
 * angular neighbour (two triangles: by their orientation alone; one, a free
 * border: its two sides). The joined sides are closed surfaces, or sheets
 * with both sides in one set (a surface with a free border). A set enclosing
 * positive volume is a region's outer boundary; the others (sheets, inner
 * boundaries, a layer stack's outer surface) float and join the smallest
 * outer boundary around them (winding number at one of their triangles).
 * The caller says which sides face the volume to mesh; the regions to mesh
 * are the pieces. Anything ambiguous (a set with sides to mesh and sides not
 * to, coincident angles about an edge, a floating set with no outer boundary
 * around it, a piece of fewer than 4 triangles) gives one piece, the whole.
 */
#ifndef ARTetGenPieces_h
#define ARTetGenPieces_h

#include "ARTetGen.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ar
{
/// Which sides of a complex's triangle face the volume to mesh (flags).
enum MeshedSide : std::uint8_t
{
  MeshedFront = 1, ///< the side the right-hand normal points to
  MeshedBack = 2,
  MeshedBoth = 3   ///< an internal facet (a surface embedded in the volume)
};

struct ComplexPiece
{
  PiecewiseLinearComplex Complex;   ///< its triangles, points (renumbered), sizes, markers and hole points
  std::vector<std::int64_t> Points; ///< per point of Complex: its index in the whole complex
};

/**
 * The regions of `plc` to mesh (meshedSides: per triangle, MeshedSide flags)
 * as complexes of their own, ordered by their smallest triangle index: the
 * triangles bounding a region (in the whole's order; one bounding two
 * regions is in both), their points and the free points (on no triangle)
 * within the piece's bounding box, in the whole's order with their sizes,
 * and the hole points within the piece's bounding box (the others lie
 * outside its convex hull, where TetGen ignores them: each piece carves
 * what the whole would have carved there), plus one inside each void of the
 * piece that is another piece (just behind a triangle of the void's
 * boundary, e.g. inside a closed S). Returns the number of pieces;
 * `pieces` is filled only when there are two or more (1: the complex is
 * one piece, or the split is ambiguous).
 */
std::size_t SplitComplex(const PiecewiseLinearComplex& plc, const std::vector<std::uint8_t>& meshedSides,
  std::vector<ComplexPiece>& pieces);

/**
 * TetGenMeshComplex on each piece of SplitComplex, at most `processes`
 * TetGen processes at once (0: std::thread::hardware_concurrency()), merged
 * into one result as TetGenMeshComplex would give it: the complex's points
 * first, in order, then each piece's new points in piece order; the
 * tetrahedra in piece order; Faces without duplicates (a triangle between
 * two pieces once, as its first piece has it). out.Pieces: the number of
 * pieces. With one piece this is TetGenMeshComplex itself; when a piece
 * fails the complex is meshed whole (and out.Pieces is 1).
 */
bool TetGenMeshComplexInPieces(const PiecewiseLinearComplex& plc, const std::vector<std::uint8_t>& meshedSides,
  const TetGenOptions& options, unsigned processes, TetGenResult& out, std::string& error);
}

#endif
