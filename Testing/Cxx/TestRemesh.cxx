// Unit tests of the VTK-free meshing core: exact answers only.
#include "ARDelaunay.h"
#include "ARTetGen.h"
#include "ARTetGeometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace
{
// The unit cube's corners and its 12 outward-oriented boundary triangles.
const double CubePoints[8][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
  { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 } };
const std::int64_t CubeTriangles[12][3] = { { 0, 2, 1 }, { 0, 3, 2 }, { 4, 5, 6 }, { 4, 6, 7 },
  { 0, 1, 5 }, { 0, 5, 4 }, { 1, 2, 6 }, { 1, 6, 5 }, { 2, 3, 7 }, { 2, 7, 6 }, { 3, 0, 4 },
  { 3, 4, 7 } };
}

TEST(TetGeometry, CornerTetrahedron)
{
  const double p0[3] = { 0, 0, 0 }, p1[3] = { 1, 0, 0 }, p2[3] = { 0, 1, 0 }, p3[3] = { 0, 0, 1 };
  EXPECT_NEAR(ar::TetSignedVolume(p0, p1, p2, p3), 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(ar::TetSignedVolume(p0, p2, p1, p3), -1.0 / 6.0, 1e-15);
  double a[6];
  ar::TetDihedralAngles(p0, p1, p2, p3, a);
  // Edges 01, 02, 03 meet at the right-angled corner: 90 degrees each; the
  // other three are acos(1/sqrt(3)) = 54.7356 degrees.
  for (int e = 0; e < 3; ++e)
  {
    EXPECT_NEAR(a[e], 90.0, 1e-12);
  }
  const double expected = std::acos(1.0 / std::sqrt(3.0)) * 180.0 / M_PI;
  for (int e = 3; e < 6; ++e)
  {
    EXPECT_NEAR(a[e], expected, 1e-12);
  }
}

TEST(TetGeometry, RegularTetrahedron)
{
  const double p0[3] = { 1, 1, 1 }, p1[3] = { 1, -1, -1 }, p2[3] = { -1, 1, -1 },
               p3[3] = { -1, -1, 1 };
  double a[6];
  ar::TetDihedralAngles(p0, p1, p2, p3, a);
  for (double ai : a)
  {
    EXPECT_NEAR(ai, std::acos(1.0 / 3.0) * 180.0 / M_PI, 1e-12);
  }
  // Edge length 2 sqrt 2: volume a^3 / (6 sqrt 2) = 8/3, negative for this ordering.
  EXPECT_NEAR(std::abs(ar::TetSignedVolume(p0, p1, p2, p3)), 8.0 / 3.0, 1e-12);
}

TEST(Delaunay, CubeWithInteriorPointsFillsTheCube)
{
  std::vector<double> xyz(&CubePoints[0][0], &CubePoints[0][0] + 24);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  for (int i = 0; i < 200; ++i)
  {
    xyz.push_back(u(rng));
    xyz.push_back(u(rng));
    xyz.push_back(u(rng));
  }
  ar::TetMesh mesh;
  std::string error;
  ASSERT_TRUE(ar::DelaunayTetrahedralize(xyz.data(), xyz.size() / 3, mesh, error)) << error;
  const ar::TetMeshStatistics s = ar::ComputeStatistics(mesh);
  EXPECT_NEAR(s.TotalVolume, 1.0, 1e-12);
  EXPECT_EQ(s.NumberOfNonPositive, 0u);
  // Euler: every point is a vertex of the triangulation.
  std::vector<bool> used(mesh.NumberOfPoints(), false);
  for (auto v : mesh.Tetrahedra)
  {
    used[v] = true;
  }
  EXPECT_EQ(std::count(used.begin(), used.end(), true), 208);
}

TEST(Delaunay, RefusesCoplanarTooFewAndNonFinite)
{
  ar::TetMesh mesh;
  std::string error;
  const double flat[5][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 1, 1, 0 }, { 0.3, 0.6, 0 } };
  EXPECT_FALSE(ar::DelaunayTetrahedralize(&flat[0][0], 5, mesh, error));
  EXPECT_NE(error.find("coplanar"), std::string::npos) << error;
  EXPECT_EQ(mesh.NumberOfTetrahedra(), 0u);

  EXPECT_FALSE(ar::DelaunayTetrahedralize(&flat[0][0], 3, mesh, error));
  EXPECT_NE(error.find("at least 4"), std::string::npos) << error;

  double bad[4][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
  bad[2][1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(ar::DelaunayTetrahedralize(&bad[0][0], 4, mesh, error));
  EXPECT_NE(error.find("non-finite"), std::string::npos) << error;
}

TEST(TetGen, CubeSurfaceGivesQualityMeshOfUnitVolume)
{
  ar::TetGenOptions options;
  options.MaxVolume = 0.001;
  options.PreserveSurface = false; // let TetGen split the cube's faces too
  ar::TetMesh mesh;
  std::string error;
  ASSERT_TRUE(ar::TetGenTetrahedralizeSurface(
    &CubePoints[0][0], 8, &CubeTriangles[0][0], 12, options, mesh, error))
    << error;
  const ar::TetMeshStatistics s = ar::ComputeStatistics(mesh);
  EXPECT_NEAR(s.TotalVolume, 1.0, 1e-12);
  EXPECT_EQ(s.NumberOfNonPositive, 0u);
  EXPECT_GE(mesh.NumberOfTetrahedra(), 1000u); // volume bound 1e-3 forces refinement
  EXPECT_GT(s.MinDihedral, 5.0);
  // The input points come first, unchanged.
  for (int i = 0; i < 24; ++i)
  {
    EXPECT_EQ(mesh.Points[i], (&CubePoints[0][0])[i]);
  }
  EXPECT_EQ(ar::TetGenSwitches(options), "pq1.414/12a0.001Q");
}

TEST(TetGen, RefusesOpenSurfaceAndBadIndices)
{
  ar::TetGenOptions options;
  ar::TetMesh mesh;
  std::string error;
  EXPECT_FALSE(ar::TetGenTetrahedralizeSurface(
    &CubePoints[0][0], 8, &CubeTriangles[0][0], 11, options, mesh, error));
  EXPECT_NE(error.find("not closed"), std::string::npos) << error;

  std::int64_t tri[12][3];
  std::copy(&CubeTriangles[0][0], &CubeTriangles[0][0] + 36, &tri[0][0]);
  tri[5][2] = 42;
  EXPECT_FALSE(
    ar::TetGenTetrahedralizeSurface(&CubePoints[0][0], 8, &tri[0][0], 12, options, mesh, error));
  EXPECT_NE(error.find("does not exist"), std::string::npos) << error;
}

TEST(TetGen, SelfIntersectingSurfaceIsCaught)
{
  // Two closed cubes that overlap: a closed, manifold but self-intersecting
  // surface. It is refused before TetGen sees it.
  std::vector<double> xyz(&CubePoints[0][0], &CubePoints[0][0] + 24);
  for (int i = 0; i < 8; ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      xyz.push_back(CubePoints[i][k] + 0.5);
    }
  }
  std::vector<std::int64_t> tri(&CubeTriangles[0][0], &CubeTriangles[0][0] + 36);
  for (int t = 0; t < 12; ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      tri.push_back(CubeTriangles[t][k] + 8);
    }
  }
  ar::TetMesh mesh;
  std::string error;
  EXPECT_FALSE(ar::TetGenTetrahedralizeSurface(
    xyz.data(), 16, tri.data(), 24, ar::TetGenOptions(), mesh, error));
  EXPECT_NE(error.find("intersects itself"), std::string::npos) << error;
}
