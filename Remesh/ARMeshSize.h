// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file ARMeshSize.h
 * @brief The local mesh size the paper uses everywhere (Eq. 4's l_j, section
 *        2.4's l_si and l_vj): the longest edge at a node, and the median of
 *        it over a set of nodes (the size of a mesh "at" a surface).
 *
 * One implementation for the 3-D and 2-D drivers of EmbeddedRemesh, serial
 * and distributed, and for the cavity core: the default size of the embedded
 * surface and the size reported on it come from the same measure.
 */
#ifndef ARMeshSize_h
#define ARMeshSize_h

#include "ARCellQuality.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ar
{
/// Raises lv[node] to the longest edge at each node of `nCells` cells of one
/// linear 3-D shape (`cells`: NumberOfNodes(shape) point ids each; `points`:
/// x y z per point). lv must hold every point id used.
void AccumulateLongestEdges(CellShape shape, const double* points, const std::int64_t* cells,
  std::size_t nCells, std::vector<double>& lv);

/// The longest edge at each of nPoints nodes of a tetrahedral mesh (0 at a
/// node no tetrahedron uses).
std::vector<double> LongestEdgeAtNodes(const double* points, std::size_t nPoints,
  const std::int64_t* tetrahedra, std::size_t nTetrahedra);

/// The same for polygons in `dimension` (2 or 3) coordinates, given as
/// VTK-style offsets (nCells + 1) and connectivity: the polygon's sides are
/// its edges.
std::vector<double> LongestPolygonEdgeAtNodes(const double* points, int dimension, std::size_t nPoints,
  const std::int64_t* offsets, const std::int64_t* connectivity, std::size_t nCells);

/// The median of `values` (the upper one for an even count: the element at
/// n / 2 in sorted order); 0 for none.
double Median(std::vector<double> values);

/// The median of lv over the distinct nodes listed in `nodes` (n ids, which
/// may repeat, as a triangle list does), nodes where lv is 0 left out; 0 for
/// none.
double MedianAtNodes(const std::vector<double>& lv, const std::int64_t* nodes, std::size_t n);
}

#endif
