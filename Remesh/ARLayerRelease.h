// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file ARLayerRelease.h
 * @brief The prism layers an earlier adaptation left inside a hybrid mesh,
 *        split into tetrahedra so that the next adaptation's cavity may take
 *        them (the paper's cycles: the shock moves, and the new surface runs
 *        through the old stack).
 *
 * The cavity (ARCavity.h) removes tetrahedra only; every other cell is kept
 * and locks its nodes. A second cycle with layers then finds its surface
 * inside the first cycle's prisms and cannot remove them. This finds the
 * cells that can be released safely and splits them:
 *  - a group is a set of prisms and pyramids joined through their
 *    quadrilateral faces (one layer of one side of one stack, with the
 *    pyramids that close it);
 *  - a group is released when all its faces are interior: each quad shared
 *    by two cells of the group, each triangle shared with another 3-D cell
 *    (a tetrahedron, a cell of the group or of another group, an "other"
 *    cell). So its boundary towards the rest of the mesh is triangles only,
 *    and the cavity's boundary stays triangles whether it takes the group or
 *    not. Groups that touch the domain boundary (near-wall layers, a stack
 *    cut by a symmetry plane) or share a quad with a hexahedron or a
 *    polyhedron stay locked, as before;
 *  - each cell of a released group is split into positive tetrahedra, each
 *    quad by the diagonal from its smallest point id (Dompierre et al.,
 *    "How to subdivide pyramids, prisms and hexahedra into tetrahedra",
 *    1999: with that rule two cells sharing a quad split it alike, and
 *    every prism splits into three tetrahedra without a new point). A cell
 *    that does not split into three (two) positive tetrahedra locks its
 *    group.
 * The caller gives the split tetrahedra to the cavity with their group
 * (CavityOptions::CellGroups, removed whole or kept whole) and puts the cells
 * of the groups it kept back as they were.
 */
#ifndef ARLayerRelease_h
#define ARLayerRelease_h

#include <cstdint>
#include <vector>

namespace ar
{
/// Prisms and pyramids of a hybrid mesh in VTK's point order (VTK_WEDGE:
/// bottom triangle, top triangle, p_i - p_i+3 lateral edges; VTK_PYRAMID: the
/// quad, then the apex).
struct LayerCells
{
  std::vector<int> Sizes;          ///< per cell: 6 (prism) or 5 (pyramid)
  std::vector<std::int64_t> Ids;   ///< their point ids, cell after cell
};

struct LayerRelease
{
  std::vector<std::int64_t> Group;           ///< per cell: its group if released, else -1
  std::int64_t NumberOfGroups = 0;
  std::vector<std::int64_t> Tetrahedra;      ///< the released cells split, 4 ids each, positive (TetSignedVolume)
  std::vector<std::int64_t> TetrahedronCell; ///< per tetrahedron: its cell
};

/**
 * points: x y z per point. tets: the mesh's tetrahedra (4 ids each). cells:
 * its prisms and pyramids. otherFaces: the faces of its other 3-D cells
 * (hexahedra, polyhedra: per face its number of points, then the ids, as
 * CavityOptions::LockedCellFaces). Linear in the cells' faces apart from a
 * sort; the tetrahedra are only scanned for faces on the cells' points.
 */
LayerRelease ReleaseFloatingLayers(const double* points, const std::int64_t* tets, std::size_t nTets,
  const LayerCells& cells, const std::vector<std::int64_t>& otherFaces);
}

#endif
