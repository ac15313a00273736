// Unit tests of ar::LongestEdgeAtNodes and its relatives (ARMeshSize.h) on
// cells whose edges are known exactly.
#include "ARMeshSize.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace
{
// The corner tetrahedron 0, e_x, 2 e_y, 3 e_z: edges 1, 2, 3 from the origin,
// sqrt(5), sqrt(10), sqrt(13) between the others.
const std::vector<double> Corner = { 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 3 };
}

TEST(MeshSize, LongestEdgeAtTetrahedronNodes)
{
  const std::int64_t tet[4] = { 0, 1, 2, 3 };
  const std::vector<double> lv = ar::LongestEdgeAtNodes(Corner.data(), 5, tet, 1);
  ASSERT_EQ(lv.size(), 5u);
  EXPECT_DOUBLE_EQ(lv[0], 3.0);
  EXPECT_DOUBLE_EQ(lv[1], std::sqrt(10.0));
  EXPECT_DOUBLE_EQ(lv[2], std::sqrt(13.0));
  EXPECT_DOUBLE_EQ(lv[3], std::sqrt(13.0));
  EXPECT_EQ(lv[4], 0.0) << "a node no cell uses has no size";
}

TEST(MeshSize, HexahedronEdgesAreNotItsDiagonals)
{
  // The box [0,1] x [0,2] x [0,4] in VTK order: the longest edge at every
  // node is 4, not a face or body diagonal.
  const std::vector<double> p = { 0, 0, 0, 1, 0, 0, 1, 2, 0, 0, 2, 0, 0, 0, 4, 1, 0, 4, 1, 2, 4, 0, 2, 4 };
  const std::int64_t hex[8] = { 0, 1, 2, 3, 4, 5, 6, 7 };
  std::vector<double> lv(8, 0.0);
  ar::AccumulateLongestEdges(ar::CellShape::Hexahedron, p.data(), hex, 1, lv);
  for (double l : lv)
  {
    EXPECT_DOUBLE_EQ(l, 4.0);
  }
  // A wedge and a pyramid on the same points: their own edges only.
  const std::int64_t wedge[6] = { 0, 1, 3, 4, 5, 7 }; // triangle (0,1,3) at z = 0, (4,5,7) at z = 4
  std::vector<double> lw(8, 0.0);
  ar::AccumulateLongestEdges(ar::CellShape::Wedge, p.data(), wedge, 1, lw);
  EXPECT_DOUBLE_EQ(lw[1], 4.0);
  EXPECT_EQ(lw[2], 0.0);
  const std::int64_t pyramid[5] = { 0, 1, 2, 3, 4 }; // apex (0, 0, 4) over the base z = 0
  std::vector<double> lp(8, 0.0);
  ar::AccumulateLongestEdges(ar::CellShape::Pyramid, p.data(), pyramid, 1, lp);
  EXPECT_DOUBLE_EQ(lp[0], 4.0);                 // edge 0-4
  EXPECT_DOUBLE_EQ(lp[2], std::sqrt(1.0 + 4.0 + 16.0)); // edge 2-4
  EXPECT_DOUBLE_EQ(lp[1], std::sqrt(1.0 + 16.0));       // edge 1-4 (longer than 1-2)
}

TEST(MeshSize, PolygonsIn2D)
{
  // A unit square and a triangle on its right side: the square's diagonal
  // is not one of its edges.
  const std::vector<double> p = { 0, 0, 1, 0, 1, 1, 0, 1, 3, 0.5 };
  const std::vector<std::int64_t> offsets = { 0, 4, 7 };
  const std::vector<std::int64_t> conn = { 0, 1, 2, 3, 1, 4, 2 };
  const std::vector<double> lv = ar::LongestPolygonEdgeAtNodes(p.data(), 2, 5, offsets.data(), conn.data(), 2);
  EXPECT_DOUBLE_EQ(lv[0], 1.0);
  EXPECT_DOUBLE_EQ(lv[3], 1.0);
  EXPECT_DOUBLE_EQ(lv[1], std::hypot(2.0, 0.5));
  EXPECT_DOUBLE_EQ(lv[2], std::hypot(2.0, 0.5));
  EXPECT_DOUBLE_EQ(lv[4], std::hypot(2.0, 0.5));
}

TEST(MeshSize, Medians)
{
  EXPECT_EQ(ar::Median({}), 0.0);
  EXPECT_EQ(ar::Median({ 3.0, 1.0, 2.0 }), 2.0);
  EXPECT_EQ(ar::Median({ 4.0, 1.0, 3.0, 2.0 }), 3.0) << "the upper median of an even count";
  // Over listed nodes: repeats count once, nodes without a size are left out.
  const std::vector<double> lv = { 5.0, 0.0, 1.0, 2.0, 9.0 };
  const std::int64_t tris[6] = { 0, 1, 2, 2, 3, 0 };
  EXPECT_EQ(ar::MedianAtNodes(lv, tris, 6), 2.0); // nodes 0, 2, 3 -> {5, 1, 2}
  const std::int64_t none[1] = { 1 };
  EXPECT_EQ(ar::MedianAtNodes(lv, none, 1), 0.0);
}
