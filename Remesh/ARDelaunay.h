// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file ARDelaunay.h
 * @brief Delaunay tetrahedralization of a point set with CGAL (exact predicates).
 */
#ifndef ARDelaunay_h
#define ARDelaunay_h

#include "ARTetMesh.h"

#include <string>

namespace ar
{
/**
 * Delaunay tetrahedralization of `n` points given as x y z triples. The
 * output keeps the input points in order (coincident points are merged by
 * CGAL: the later copies are simply not referenced) and lists the finite
 * Delaunay tetrahedra, positively oriented.
 *
 * Returns false, with `error` naming the problem, for fewer than four
 * points, a non-finite coordinate, or points that are all coplanar (CGAL's
 * triangulation then has dimension < 3 and no tetrahedra).
 */
bool DelaunayTetrahedralize(const double* xyz, std::size_t n, TetMesh& out, std::string& error);
}

#endif
