// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file ARTetMesh.h
 * @brief Plain-array tetrahedral mesh exchanged with the VTK-free meshing core.
 */
#ifndef ARTetMesh_h
#define ARTetMesh_h

#include <cstdint>
#include <vector>

namespace ar
{
/// A tetrahedron's faces, each as 3 of its corners (face f is opposite
/// corner f), oriented with its normal out of the tetrahedron for a
/// positively oriented one.
constexpr int TetFaceVertex[4][3] = { { 1, 2, 3 }, { 0, 3, 2 }, { 0, 1, 3 }, { 0, 2, 1 } };

/// Points as x0 y0 z0 x1 ...; tetrahedra as 4 point indices each, positively
/// oriented: (p1-p0).((p2-p0)x(p3-p0)) > 0, the VTK_TETRA convention.
struct TetMesh
{
  std::vector<double> Points;
  std::vector<std::int64_t> Tetrahedra;

  std::size_t NumberOfPoints() const { return this->Points.size() / 3; }
  std::size_t NumberOfTetrahedra() const { return this->Tetrahedra.size() / 4; }
};
}

#endif
