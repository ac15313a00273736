// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file ARSurfaceRemesh.h
 * @brief Isotropic remeshing of a triangulated surface at a target edge length (CGAL).
 */
#ifndef ARSurfaceRemesh_h
#define ARSurfaceRemesh_h

#include <cstdint>
#include <string>
#include <vector>

namespace ar
{
/**
 * Remeshes a triangulated surface (open or closed, one or several pieces)
 * to nearly equilateral triangles of edge length `edgeLength` with CGAL's
 * isotropic remeshing (8 iterations). Border edges are first split to the
 * target length (from a cut input, below: those over 4/3 of it) and then
 * kept in place, so the outline does not shrink.
 *
 * CGAL halves edges over 4/3 of the target and keeps shorter ones, so from
 * an input whose edges are 4.6 targets long it ends at 1.15 of the target:
 * the size asked for a refined S was not the size made. Where the result's
 * median edge is over 1.1 targets and the input's at least 1.5, the input
 * is cut into n x n per triangle (n its median edge over the target,
 * rounded up from a quarter below) and remeshed again, and of the two the
 * result whose median edge is nearer the target is returned.
 * The new points are projected on the input's triangles (their closest
 * point, as CGAL's own projection, but each query started from where the
 * point lay before instead of a kd-tree search).
 *
 * A surface that would have 60,000 triangles or more is cut in two pieces of
 * about equal area across its longest extent; the cut's edges are split to
 * the target length and kept as the border is, and the pieces are remeshed
 * side by side on `threads` threads (one: one after the other, the same
 * output) and joined at the cut. CGAL's remeshing runs on one thread and
 * took 8-10 s of a 5e6-tetrahedron adaptation (220,000 triangles); in two
 * pieces on two cores 3-4 s. Where a piece would not be a manifold (it
 * touches the other at a single point) the surface is remeshed whole.
 * `pieces` (optional) gets the number of pieces.
 *
 * The input must be an orientable manifold triangle soup (CGAL orients it);
 * returns false with `error` naming the problem otherwise (non-manifold
 * edges, a non-finite coordinate, a non-positive edge length).
 */
bool RemeshSurfaceIsotropic(const std::vector<double>& points, const std::vector<std::int64_t>& triangles,
  double edgeLength, std::vector<double>& outPoints, std::vector<std::int64_t>& outTriangles,
  std::string& error, int threads = 1, int* pieces = nullptr);

/**
 * Whether two triangulated surfaces (x y z per point, three point ids per
 * triangle) cross or touch: a triangle of one intersects a triangle of the
 * other (CGAL AABB tree of the first, exact predicates). Surfaces that
 * merely come close do not count.
 */
bool SurfacesIntersect(const std::vector<double>& pointsA, const std::vector<std::int64_t>& trianglesA,
  const std::vector<double>& pointsB, const std::vector<std::int64_t>& trianglesB);
}

#endif
