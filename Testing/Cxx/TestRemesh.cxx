// Unit tests of the VTK-free meshing core: exact answers only.
#include "ARCGALTypes.h"
#include "ARDelaunay.h"
#include "ARHugePages.h"
#include "ARTetGen.h"
#include "ARTetGeometry.h"
#include "ARTestMeshes.h"

#include <gtest/gtest.h>

#include <sys/mman.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

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

// Every face of a Kuhn cube with a hole through it (so that the boundary
// has inner walls too): an interior face names its neighbour, which names
// it back through the same three corners; a boundary face lies on the cube's
// outer surface or on the hole's walls, and there are as many as the
// squares of those surfaces times two.
TEST(TetGeometry, FaceNeighboursOfACubeWithAHole)
{
  const int n = 30; // 162,000 tetrahedra less the hole's: two threads' worth
  const ar::TetMesh m = artest::KuhnCube(n, [](int i, int j, int) { return !(i >= 10 && i < 14 && j >= 10 && j < 20); });
  const std::size_t nT = m.NumberOfTetrahedra();
  std::vector<std::int64_t> one, two;
  std::string error;
  ASSERT_TRUE(ar::TetFaceNeighbors(m.Tetrahedra.data(), nT, m.NumberOfPoints(), one, error, 1)) << error;
  ASSERT_TRUE(ar::TetFaceNeighbors(m.Tetrahedra.data(), nT, m.NumberOfPoints(), two, error, 2)) << error;
  EXPECT_EQ(one, two);
  ASSERT_EQ(one.size(), 4 * nT);
  auto face = [&](std::size_t t, int f) {
    std::array<std::int64_t, 3> c;
    for (int k = 0; k < 3; ++k)
      c[k] = m.Tetrahedra[4 * t + ar::TetFaceVertex[f][k]];
    std::sort(c.begin(), c.end());
    return c;
  };
  auto onWall = [&](const std::array<std::int64_t, 3>& c) {
    // all three corners share a coordinate that is a wall of the cube or the hole
    for (int d = 0; d < 3; ++d)
    {
      const double x = m.Points[3 * c[0] + d];
      bool same = true;
      for (int k = 1; k < 3; ++k)
        same = same && m.Points[3 * c[k] + d] == x;
      const double g = x * n;
      const bool wall = d == 2 ? (g == 0 || g == n) : (g == 0 || g == n || (d == 0 ? g == 10 || g == 14 : g == 10 || g == 20));
      if (same && wall)
        return true;
    }
    return false;
  };
  std::size_t boundary = 0;
  for (std::size_t t = 0; t < nT; ++t)
  {
    for (int f = 0; f < 4; ++f)
    {
      const std::int64_t u = one[4 * t + f];
      if (u < 0)
      {
        ++boundary;
        EXPECT_TRUE(onWall(face(t, f))) << "tetrahedron " << t << " face " << f;
        continue;
      }
      ASSERT_LT(static_cast<std::size_t>(u), nT);
      int back = 0;
      for (int g = 0; g < 4; ++g)
        if (one[4 * u + g] == static_cast<std::int64_t>(t))
        {
          ++back;
          EXPECT_EQ(face(static_cast<std::size_t>(u), g), face(t, f));
        }
      EXPECT_EQ(back, 1);
    }
  }
  // outer: 6 n^2 squares less the hole's 4 x 10 on top and bottom; the
  // hole's walls: 2 (4 + 10) n; two triangles a square
  EXPECT_EQ(boundary, static_cast<std::size_t>(2 * (6 * n * n - 2 * 4 * 10 + 2 * (4 + 10) * n)));

  // A third tetrahedron on an interior face, and a point that does not exist.
  ar::TetMesh three = m;
  std::size_t t0 = 0;
  int f0 = 0;
  while (one[4 * t0 + f0] < 0)
    ++f0 == 4 ? (f0 = 0, ++t0) : 0;
  three.Points.insert(three.Points.end(), { 2.0, 2.0, 2.0 });
  const std::array<std::int64_t, 3> shared = face(t0, f0);
  three.Tetrahedra.insert(three.Tetrahedra.end(),
    { shared[0], shared[1], shared[2], static_cast<std::int64_t>(three.NumberOfPoints() - 1) });
  std::vector<std::int64_t> neighbor;
  EXPECT_FALSE(ar::TetFaceNeighbors(three.Tetrahedra.data(), nT + 1, three.NumberOfPoints(), neighbor, error, 2));
  EXPECT_NE(error.find("shared by 3 tetrahedra"), std::string::npos) << error;
  EXPECT_TRUE(neighbor.empty());
  error.clear();
  EXPECT_FALSE(ar::TetFaceNeighbors(m.Tetrahedra.data(), nT, m.NumberOfPoints() - 1, neighbor, error, 2));
  EXPECT_NE(error.find("does not exist"), std::string::npos) << error;
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

TEST(TetGen, LargeResultComesBackWhole)
{
  // About 10 MB of tetrahedra: the child process's result crosses the pipe
  // in many reads, straight into arrays allocated at their size.
  ar::TetGenOptions options;
  options.MaxVolume = 8e-6;
  options.PreserveSurface = false;
  ar::TetMesh mesh;
  std::string error;
  ASSERT_TRUE(ar::TetGenTetrahedralizeSurface(
    &CubePoints[0][0], 8, &CubeTriangles[0][0], 12, options, mesh, error))
    << error;
  EXPECT_GT(mesh.Tetrahedra.size() * sizeof(std::int64_t), std::size_t(8) << 20);
  const ar::TetMeshStatistics s = ar::ComputeStatistics(mesh);
  EXPECT_NEAR(s.TotalVolume, 1.0, 1e-11);
  EXPECT_EQ(s.NumberOfNonPositive, 0u);
  for (std::int64_t v : mesh.Tetrahedra)
  {
    ASSERT_TRUE(v >= 0 && static_cast<std::size_t>(v) < mesh.NumberOfPoints());
  }
}

namespace
{
/// The VmFlags of the mapping of this process that holds `address`
/// (/proc/self/smaps), or "" if none does.
std::string MappingFlags(const void* address)
{
  const auto a = reinterpret_cast<std::uintptr_t>(address);
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line))
  {
    std::uintptr_t first = 0, last = 0;
    char dash = 0;
    std::istringstream header(line);
    if (header >> std::hex >> first >> dash >> last && dash == '-')
    {
      inside = a >= first && a < last;
    }
    else if (inside && line.compare(0, 8, "VmFlags:") == 0)
    {
      return line.substr(8) + " ";
    }
  }
  return "";
}
}

TEST(HugePages, WholeHugePagesOfALargeRangeAreMarked)
{
  constexpr std::size_t mb = std::size_t(1) << 20;
  // Mappings of our own, so that each is its own VMA: 3 MB is too small to
  // mark, of 9 MB starting 1 MB past a 2 MB boundary the 8 MB of whole huge
  // pages are marked ("hg") and the first MB is not.
  void* small = mmap(nullptr, 3 * mb, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  void* big = mmap(nullptr, 12 * mb, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(small, MAP_FAILED);
  ASSERT_NE(big, MAP_FAILED);
  const std::uintptr_t aligned = (reinterpret_cast<std::uintptr_t>(big) + 2 * mb - 1) & ~(2 * mb - 1);
  char* start = reinterpret_cast<char*>(aligned) + mb;
  ASSERT_TRUE(start + 9 * mb <= static_cast<char*>(big) + 12 * mb);
  EXPECT_EQ(MappingFlags(small).find(" hg "), std::string::npos);
  ar::AdviseHugePages(small, 3 * mb);
  ar::AdviseHugePages(start, 9 * mb);
  EXPECT_EQ(MappingFlags(small).find(" hg "), std::string::npos) << MappingFlags(small);
  EXPECT_EQ(MappingFlags(start).find(" hg "), std::string::npos) << MappingFlags(start);
  EXPECT_NE(MappingFlags(start + mb).find(" hg "), std::string::npos) << MappingFlags(start + mb);
  EXPECT_NE(MappingFlags(start + 9 * mb - 1).find(" hg "), std::string::npos);
  EXPECT_EQ(MappingFlags(start + 9 * mb).find(" hg "), std::string::npos);
  munmap(small, 3 * mb);
  munmap(big, 12 * mb);

  // The vector helpers: the values as reserve, resize and assign give them.
  std::vector<double> v{ 1.0, 2.0, 3.0 };
  const std::size_t n = 3 * mb / sizeof(double) * 2; // 6 MB
  ar::ReserveHuge(v, n);
  EXPECT_GE(v.capacity(), n);
  ASSERT_EQ(v.size(), 3u);
  EXPECT_EQ(v[2], 3.0);
  ar::ResizeHuge(v, n);
  ASSERT_EQ(v.size(), n);
  EXPECT_EQ(v[0], 1.0);
  EXPECT_EQ(v[1], 2.0);
  EXPECT_EQ(std::count(v.begin() + 3, v.end(), 0.0), static_cast<std::ptrdiff_t>(n - 3));
  std::vector<std::int64_t> w{ 5, 6 };
  ar::AssignHuge(w, n, std::int64_t(-1));
  ASSERT_EQ(w.size(), n);
  EXPECT_EQ(std::count(w.begin(), w.end(), std::int64_t(-1)), static_cast<std::ptrdiff_t>(n));
  ar::AssignHuge(w, 4, std::int64_t(9)); // smaller: in place
  EXPECT_EQ(w, std::vector<std::int64_t>(4, 9));
}

namespace
{
/// The triangles of an nx x ny grid of squares, each cut along a diagonal.
ar::cgal::Soup GridSoup(std::size_t nx, std::size_t ny)
{
  ar::cgal::Soup soup;
  for (std::size_t j = 0; j < ny; ++j)
    for (std::size_t i = 0; i < nx; ++i)
    {
      const std::size_t a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      soup.push_back({ a, b, d });
      soup.push_back({ a, d, c });
    }
  return soup;
}
}

TEST(SoupToMesh, AgreesWithCGALOnWhatIsAPolygonMesh)
{
  namespace PMP = CGAL::Polygon_mesh_processing;
  const ar::cgal::Soup octahedron = { { 0, 2, 4 }, { 2, 1, 4 }, { 1, 3, 4 }, { 3, 0, 4 }, { 2, 0, 5 }, { 1, 2, 5 },
    { 3, 1, 5 }, { 0, 3, 5 } };
  std::vector<std::pair<std::string, ar::cgal::Soup>> cases;
  cases.push_back({ "a closed octahedron", octahedron });
  cases.push_back({ "an open grid", GridSoup(6, 4) });
  ar::cgal::Soup flipped = octahedron;
  std::swap(flipped[3][0], flipped[3][1]);
  cases.push_back({ "an octahedron with one triangle flipped", flipped });
  cases.push_back({ "three triangles on one edge", { { 0, 1, 2 }, { 1, 0, 3 }, { 0, 1, 4 } } });
  cases.push_back({ "two triangles meeting at a vertex only", { { 0, 1, 2 }, { 0, 3, 4 } } });
  ar::cgal::Soup twice = octahedron;
  for (const auto& t : octahedron)
    twice.push_back({ t[0] == 0 ? 0 : t[0] + 5, t[1] == 0 ? 0 : t[1] + 5, t[2] == 0 ? 0 : t[2] + 5 });
  cases.push_back({ "two octahedra sharing a vertex", twice });
  cases.push_back({ "a triangle with a repeated corner", { { 0, 1, 1 }, { 1, 0, 2 } } });
  cases.push_back({ "a triangle twice", { { 0, 1, 2 }, { 0, 1, 2 } } });
  cases.push_back({ "a closed fan and an open one at a vertex",
    { { 0, 1, 2 }, { 0, 2, 3 }, { 0, 3, 1 }, { 0, 4, 5 }, { 0, 5, 6 } } });
  cases.push_back({ "no triangle", {} });
  cases.push_back({ "a pillow: two triangles on the same corners, opposite ways", { { 0, 1, 2 }, { 0, 2, 1 } } });
  cases.push_back({ "four triangles on one edge, two each way",
    { { 0, 1, 2 }, { 1, 0, 3 }, { 0, 1, 4 }, { 1, 0, 5 } } });
  for (const auto& c : cases)
  {
    EXPECT_EQ(ar::cgal::IsTriangleSoupAMesh(c.second), PMP::is_polygon_soup_a_polygon_mesh(c.second)) << c.first;
  }
  EXPECT_TRUE(ar::cgal::IsTriangleSoupAMesh(octahedron));
  EXPECT_FALSE(ar::cgal::IsTriangleSoupAMesh(twice));
  // Random pieces of a grid, some triangles flipped: holes make vertices
  // where two fans meet, flips make edges used twice in one direction.
  std::mt19937 random(7);
  const ar::cgal::Soup grid = GridSoup(8, 8);
  int meshes = 0, soups = 0;
  for (int trial = 0; trial < 400; ++trial)
  {
    ar::cgal::Soup piece;
    const unsigned drop = 1 + trial % 40, flip = trial % 3 == 0 ? 100 : 100000; // in 1000
    for (auto t : grid)
    {
      if (random() % 1000 < drop)
        continue;
      if (random() % flip == 0)
        std::swap(t[0], t[1]);
      piece.push_back(t);
    }
    const bool expected = PMP::is_polygon_soup_a_polygon_mesh(piece);
    ASSERT_EQ(ar::cgal::IsTriangleSoupAMesh(piece), expected) << "trial " << trial;
    (expected ? meshes : soups) += 1;
  }
  EXPECT_GT(meshes, 10);
  EXPECT_GT(soups, 10);
}

TEST(SoupToMesh, SelfIntersectionFoundWhenBothTrianglesStraddleTheCut)
{
  // ar::cgal::DoesSelfIntersect tests two halves cut at the median of the
  // triangles' centres along x. 100 small triangles apart from each other
  // put the cut at x = 5.05; the one crossing pair, T1 over x 4 .. 6.2
  // (centre 5.1) and T2 over 3.8 .. 6 (centre 4.9), straddles it with its
  // centres on either side: a split by centre alone would miss it.
  std::vector<ar::cgal::Point> points;
  ar::cgal::Soup soup;
  for (int i = 0; i < 100; ++i)
  {
    const double x = 0.05 + 0.1 * i, y = 2.0; // (x the longest axis)
    const std::size_t first = points.size();
    points.emplace_back(x - 0.01, y, 0.0);
    points.emplace_back(x + 0.01, y, 0.0);
    points.emplace_back(x, y + 0.01, 0.0);
    soup.push_back({ first, first + 1, first + 2 });
  }
  ar::cgal::Mesh apart;
  ASSERT_TRUE(ar::cgal::SoupToMesh(points, soup, apart));
  EXPECT_FALSE(ar::cgal::DoesSelfIntersect(apart, 2));
  const std::size_t first = points.size();
  points.emplace_back(4.0, 0.0, 0.0); // T1, in z = 0
  points.emplace_back(6.2, 0.0, 0.0);
  points.emplace_back(5.1, 1.0, 0.0);
  points.emplace_back(3.8, 0.5, -1.0); // T2, in y = 0.5, through T1
  points.emplace_back(6.0, 0.5, -1.0);
  points.emplace_back(4.9, 0.5, 1.0);
  soup.push_back({ first, first + 1, first + 2 });
  soup.push_back({ first + 3, first + 4, first + 5 });
  ar::cgal::Mesh crossing;
  ASSERT_TRUE(ar::cgal::SoupToMesh(points, soup, crossing));
  namespace PMP = CGAL::Polygon_mesh_processing;
  ASSERT_TRUE(PMP::does_self_intersect(crossing)) << "the construction crosses";
  for (const std::size_t threads : { 1, 2 })
  {
    EXPECT_TRUE(ar::cgal::DoesSelfIntersect(crossing, threads)) << threads << " thread(s)";
  }
}
