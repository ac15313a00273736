// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file ARTetGeometry.h
 * @brief Volume and dihedral angles of tetrahedra (no VTK).
 */
#ifndef ARTetGeometry_h
#define ARTetGeometry_h

#include "ARTetMesh.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ar
{
/// Signed volume: positive when (p1-p0).((p2-p0)x(p3-p0)) > 0.
double TetSignedVolume(const double p0[3], const double p1[3], const double p2[3], const double p3[3]);

/// The six interior dihedral angles in degrees, at edges 01 02 03 12 13 23.
/// A degenerate tetrahedron gives 0 or 180 for some angles.
void TetDihedralAngles(
  const double p0[3], const double p1[3], const double p2[3], const double p3[3], double angles[6]);

/// Summary over a whole mesh.
struct TetMeshStatistics
{
  double TotalVolume = 0.0;
  double MinVolume = 0.0;
  double MinDihedral = 0.0;
  double MaxDihedral = 0.0;
  std::size_t NumberOfNonPositive = 0;
};
TetMeshStatistics ComputeStatistics(const TetMesh& mesh);
/// The sum of the tetrahedra's signed volumes in their order: bit for bit
/// ComputeStatistics' TotalVolume, without its dihedral angles.
double TotalSignedVolume(const TetMesh& mesh);

/// Moves the free points (ids >= firstFree; the others stay where they are)
/// of tetrahedra whose smallest dihedral angle is below `minAngle` degrees,
/// each to where the smallest angle of its star (the tetrahedra at it) is
/// largest among a few tries: towards the centroid of its star's other
/// points, and small steps along the axes (a compass search, up to `passes`
/// rounds). A move is kept only if it raises the star's smallest angle and
/// every tetrahedron of the star stays positive, so the mesh stays valid and
/// no angle falls below the star's old smallest. Points of tetrahedra that
/// are not below `minAngle` never move: a mesh without such tetrahedra is
/// left bit for bit. Returns the number of points moved. (CGAL's sliver
/// perturbation works on a Mesh_3 complex, not on a mesh given as cells.)
/// The search for the thin tetrahedra runs on `threads` threads (0: the
/// hardware's; the same result on any number).
/// `minStep` > 0: tetrahedra whose explicit step length 2V / (sum of face
/// areas) (ar::CellStepLength) is below it are treated as slivers too (a
/// small cell sets an explicit solver's global time step): a star is then
/// scored by min over its tetrahedra of min(angle, minAngle * step /
/// minStep), a move is kept where it raises the star's score, and no angle
/// of the star falls below min(its old smallest, minAngle). 0 (the
/// default): the angles alone, as described above.
std::size_t SmoothFreePointsAtSlivers(
  TetMesh& mesh, std::size_t firstFree, double minAngle, int passes = 4, int threads = 1, double minStep = 0.0);

/// The tetrahedron across each face of `nT` tetrahedra (4 ids each, all
/// below nV): neighbor[4 t + f] for the face of t opposite its corner f
/// (TetFaceVertex), -1 where no other tetrahedron has that face (the mesh's
/// boundary). The faces are matched by a counting sort on their smallest id
/// and a sort of each small bucket, on `threads` threads (0: the
/// hardware's), in 12 bytes a face while the ids fit 32 bits; the result is
/// the same on any number. False, with `error` saying so, where a face is in
/// more than two tetrahedra (a mesh that is not conforming).
bool TetFaceNeighbors(const std::int64_t* tets, std::size_t nT, std::size_t nV,
  std::vector<std::int64_t>& neighbor, std::string& error, int threads = 0);
}

#endif
