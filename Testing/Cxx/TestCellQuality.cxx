// Unit tests of ar::ComputeCellQuality and its parts on cells whose
// dihedral angles, corner Jacobians and aspect ratios are known exactly.
#include "ARCellQuality.h"
#include "ARTetGeometry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace
{
constexpr double Deg = 180.0 / M_PI;

/// A right prism over the equilateral triangle of side 1, height h, in VTK
/// order: the triangle 0 1 2 (z = 0) runs clockwise seen from 3 4 5 (z = h).
std::vector<double> RightPrism(double h)
{
  const double r = std::sqrt(3.0) / 2.0;
  return { 0, 0, 0, 0.5, r, 0, 1, 0, 0, 0, 0, h, 0.5, r, h, 1, 0, h };
}

/// A square pyramid: base [-1,1]^2 at z = 0 (counterclockwise seen from the
/// apex), apex (0, 0, h).
std::vector<double> Pyramid(double h)
{
  return { -1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0, 0, 0, h };
}

/// A cube of side s with its corner at (x0, x0, x0), VTK hexahedron order.
std::vector<double> Cube(double s, double x0)
{
  std::vector<double> p = { 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1 };
  for (double& x : p)
  {
    x = x0 + s * x;
  }
  return p;
}

int Count(const double* values, int n, double target)
{
  return static_cast<int>(std::count_if(values, values + n, [&](double v) { return std::abs(v - target) < 1e-12; }));
}
}

TEST(CellQuality, Counts)
{
  EXPECT_EQ(ar::NumberOfEdges(ar::CellShape::Tetrahedron), 6);
  EXPECT_EQ(ar::NumberOfEdges(ar::CellShape::Pyramid), 8);
  EXPECT_EQ(ar::NumberOfEdges(ar::CellShape::Wedge), 9);
  EXPECT_EQ(ar::NumberOfEdges(ar::CellShape::Hexahedron), 12);
  EXPECT_EQ(ar::NumberOfFaces(ar::CellShape::Tetrahedron), 4);
  EXPECT_EQ(ar::NumberOfFaces(ar::CellShape::Pyramid), 5);
  EXPECT_EQ(ar::NumberOfFaces(ar::CellShape::Wedge), 5);
  EXPECT_EQ(ar::NumberOfFaces(ar::CellShape::Hexahedron), 6);
}

TEST(CellQuality, RightEquilateralPrism)
{
  const double h = 2.0;
  const std::vector<double> p = RightPrism(h);
  double a[9];
  ar::CellDihedralAngles(ar::CellShape::Wedge, p.data(), a);
  // Six edges between a triangle and a side quad: 90; three between side quads: 60.
  EXPECT_EQ(Count(a, 9, 90.0), 6);
  EXPECT_EQ(Count(a, 9, 60.0), 3);
  const ar::CellQuality q = ar::ComputeCellQuality(ar::CellShape::Wedge, p.data());
  EXPECT_NEAR(q.MinDihedralAngle, 60.0, 1e-12);
  EXPECT_NEAR(q.MaxDihedralAngle, 90.0, 1e-12);
  EXPECT_NEAR(q.AspectRatio, 2.0, 1e-15);
  // Every corner: |e1 x e2| h = sin(60) * h; scaled: sin(60).
  double j[6];
  ar::CellCornerJacobians(ar::CellShape::Wedge, p.data(), j);
  for (double v : j)
  {
    EXPECT_NEAR(v, std::sqrt(3.0) / 2.0 * h, 1e-14);
  }
  EXPECT_NEAR(q.MinScaledJacobian, std::sqrt(3.0) / 2.0, 1e-14);
}

TEST(CellQuality, InvertedPrism)
{
  // The two triangles swapped: the orientation of Gmsh's prism, inverted for VTK.
  std::vector<double> p = RightPrism(1.0);
  std::rotate(p.begin(), p.begin() + 9, p.end());
  double j[6];
  ar::CellCornerJacobians(ar::CellShape::Wedge, p.data(), j);
  for (double v : j)
  {
    EXPECT_NEAR(v, -std::sqrt(3.0) / 2.0, 1e-14);
  }
  EXPECT_LT(ar::ComputeCellQuality(ar::CellShape::Wedge, p.data()).MinCornerJacobian, 0.0);
  // One top node pushed below the bottom triangle: that corner and the one
  // below it are inverted, the far triangle's other corners are not.
  std::vector<double> q = RightPrism(1.0);
  q[3 * 3 + 2] = -0.5;
  ar::CellCornerJacobians(ar::CellShape::Wedge, q.data(), j);
  EXPECT_LT(j[0], 0.0);
  EXPECT_LT(j[3], 0.0);
  EXPECT_GT(j[1], 0.0);
  EXPECT_GT(j[2], 0.0);
  EXPECT_LT(ar::ComputeCellQuality(ar::CellShape::Wedge, q.data()).MinCornerJacobian, 0.0);
}

TEST(CellQuality, Cube)
{
  const std::vector<double> p = Cube(2.0, -3.0);
  double a[12], j[8];
  ar::CellDihedralAngles(ar::CellShape::Hexahedron, p.data(), a);
  EXPECT_EQ(Count(a, 12, 90.0), 12);
  ar::CellCornerJacobians(ar::CellShape::Hexahedron, p.data(), j);
  EXPECT_EQ(Count(j, 8, 8.0), 8);
  const ar::CellQuality q = ar::ComputeCellQuality(ar::CellShape::Hexahedron, p.data());
  EXPECT_NEAR(q.MinScaledJacobian, 1.0, 1e-15);
  EXPECT_NEAR(q.AspectRatio, 1.0, 1e-15);
  // Bottom and top swapped: every corner inverted.
  std::vector<double> r(p.begin() + 12, p.end());
  r.insert(r.end(), p.begin(), p.begin() + 12);
  ar::CellCornerJacobians(ar::CellShape::Hexahedron, r.data(), j);
  EXPECT_EQ(Count(j, 8, -8.0), 8);
}

TEST(CellQuality, NonPlanarQuadUsesItsAverageNormal)
{
  // Unit cube with node 6 raised by t: the top face is not planar. Its
  // average normal (diagonals' cross product) is (-t, -t, 2); the right face
  // stays the plane x = 1, so the angle at edge 5-6 is acos(t / sqrt(2t^2 + 4)).
  std::vector<double> p = Cube(1.0, 0.0);
  const double t = 1.0;
  p[3 * 6 + 2] += t;
  double a[12];
  ar::CellDihedralAngles(ar::CellShape::Hexahedron, p.data(), a);
  // Edges in order of (smaller node, larger node): 01 03 04 12 15 23 26 37 45 47 56 67.
  EXPECT_NEAR(a[10], std::acos(t / std::sqrt(2 * t * t + 4)) * Deg, 1e-12);
  EXPECT_NEAR(a[10], std::acos(1.0 / std::sqrt(6.0)) * Deg, 1e-12);
  EXPECT_NEAR(a[0], 90.0, 1e-12); // 01: bottom and front, both planar and untouched
}

TEST(CellQuality, RegularTetrahedron)
{
  // Edge length sqrt(8): corners of a cube of side 2.
  const double p[12] = { 1, 1, 1, -1, 1, -1, 1, -1, -1, -1, -1, 1 };
  ASSERT_GT(ar::TetSignedVolume(p, p + 3, p + 6, p + 9), 0.0);
  double a[6], b[6], j[4];
  ar::CellDihedralAngles(ar::CellShape::Tetrahedron, p, a);
  ar::TetDihedralAngles(p, p + 3, p + 6, p + 9, b);
  const double regular = std::acos(1.0 / 3.0) * Deg; // 70.5288 degrees
  for (int e = 0; e < 6; ++e)
  {
    EXPECT_NEAR(a[e], regular, 1e-12);
    EXPECT_NEAR(a[e], b[e], 1e-12);
  }
  EXPECT_NEAR(regular, 70.5288, 1e-4);
  // Every corner: 6 V = a^3 / sqrt(2) = 16 (a = sqrt(8)); scaled 1 / sqrt(2).
  ar::CellCornerJacobians(ar::CellShape::Tetrahedron, p, j);
  for (double v : j)
  {
    EXPECT_NEAR(v, 16.0, 1e-12);
    EXPECT_NEAR(v, 6.0 * ar::TetSignedVolume(p, p + 3, p + 6, p + 9), 1e-12);
  }
  const ar::CellQuality q = ar::ComputeCellQuality(ar::CellShape::Tetrahedron, p);
  EXPECT_NEAR(q.MinScaledJacobian, 1.0 / std::sqrt(2.0), 1e-14);
  EXPECT_NEAR(q.AspectRatio, 1.0, 1e-15);
}

TEST(CellQuality, TetrahedraAgreeWithTetDihedralAngles)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial)
  {
    double p[12];
    for (double& x : p)
    {
      x = u(rng);
    }
    if (ar::TetSignedVolume(p, p + 3, p + 6, p + 9) < 0.0)
    {
      std::swap_ranges(p + 3, p + 6, p + 6);
    }
    double a[6], b[6];
    ar::CellDihedralAngles(ar::CellShape::Tetrahedron, p, a);
    ar::TetDihedralAngles(p, p + 3, p + 6, p + 9, b);
    for (int e = 0; e < 6; ++e)
    {
      EXPECT_NEAR(a[e], b[e], 1e-9);
    }
  }
}

TEST(CellQuality, SquarePyramid)
{
  for (const double h : { std::sqrt(2.0), 3.0 })
  {
    // Base edges: atan(h / 1) between the base and a side; side edges:
    // 180 - acos(1 / (1 + h^2)) between two sides (outward normals (h, 0, 1)
    // and (0, h, 1)).
    const std::vector<double> p = Pyramid(h);
    double a[8], j[5];
    ar::CellDihedralAngles(ar::CellShape::Pyramid, p.data(), a);
    const double base = std::atan(h) * Deg, side = 180.0 - std::acos(1.0 / (1.0 + h * h)) * Deg;
    EXPECT_EQ(Count(a, 8, base), 4) << "h = " << h;
    EXPECT_EQ(Count(a, 8, side), 4) << "h = " << h;
    // Base corners: det((2,0,0), (0,2,0), (1,1,h)) = 4 h; the apex over each
    // quarter of the base (area 1): 6 V = 2 h.
    ar::CellCornerJacobians(ar::CellShape::Pyramid, p.data(), j);
    for (int k = 0; k < 4; ++k)
    {
      EXPECT_NEAR(j[k], 4.0 * h, 1e-12);
    }
    EXPECT_NEAR(j[4], 2.0 * h, 1e-12);
    const ar::CellQuality q = ar::ComputeCellQuality(ar::CellShape::Pyramid, p.data());
    EXPECT_NEAR(q.MinCornerJacobian, 2.0 * h, 1e-12);
    const double lateral = std::sqrt(2.0 + h * h); // base edges: 2
    EXPECT_NEAR(q.AspectRatio, std::max(lateral, 2.0) / std::min(lateral, 2.0), 1e-14);
  }
  // h = sqrt(2): all eight edges have length 2 (Johnson's J1): the angles
  // are acos(1/sqrt(3)) = 54.7356 and 180 - acos(1/3) = 109.4712.
  double a[8];
  ar::CellDihedralAngles(ar::CellShape::Pyramid, Pyramid(std::sqrt(2.0)).data(), a);
  EXPECT_NEAR(*std::min_element(a, a + 8), 54.7356, 1e-4);
  EXPECT_NEAR(*std::max_element(a, a + 8), 109.4712, 1e-4);
  EXPECT_NEAR(ar::CellAspectRatio(ar::CellShape::Pyramid, Pyramid(std::sqrt(2.0)).data()), 1.0, 1e-15);
  // The apex below the base: every corner inverted.
  double j[5];
  ar::CellCornerJacobians(ar::CellShape::Pyramid, Pyramid(-1.0).data(), j);
  for (double v : j)
  {
    EXPECT_LT(v, 0.0);
  }
}

TEST(CellQuality, Volumes)
{
  EXPECT_NEAR(ar::CellVolume(ar::CellShape::Hexahedron, Cube(2.0, -3.0).data()), 8.0, 1e-12);
  EXPECT_NEAR(ar::CellVolume(ar::CellShape::Wedge, RightPrism(0.7).data()), 0.7 * std::sqrt(3.0) / 4.0, 1e-15);
  EXPECT_NEAR(ar::CellVolume(ar::CellShape::Pyramid, Pyramid(3.0).data()), 4.0 * 3.0 / 3.0, 1e-14);
  const std::vector<double> tet = { 1e6, 0, 0, 1e6 + 1, 0, 0, 1e6, 1, 0, 1e6, 0, 1 };
  EXPECT_NEAR(ar::CellVolume(ar::CellShape::Tetrahedron, tet.data()), 1.0 / 6.0, 1e-12);
  // Two hexahedra stacked in the unit box, sharing a warped quad (its four
  // corners at heights 0.3, 0.6, 0.3, 0.6: not planar): the two volumes
  // depend on how the shared face is read, their sum does not.
  const double z[4] = { 0.3, 0.6, 0.3, 0.6 };
  std::vector<double> lower = Cube(1.0, 0.0), upper = Cube(1.0, 0.0);
  for (int k = 0; k < 4; ++k)
  {
    lower[3 * (k + 4) + 2] = z[k];
    upper[3 * k + 2] = z[k];
  }
  const double a = ar::CellVolume(ar::CellShape::Hexahedron, lower.data());
  const double b = ar::CellVolume(ar::CellShape::Hexahedron, upper.data());
  EXPECT_GT(a, 0.0);
  EXPECT_GT(b, 0.0);
  EXPECT_NEAR(a + b, 1.0, 1e-15);
  EXPECT_NEAR(a, 0.45, 1e-15); // the warped face split at its centroid (0.5, 0.5, 0.45)
}

// ComputeCellQuality takes the extreme angles from the extreme cosines; they
// must be CellDihedralAngles' extremes exactly, on perturbed cells of every
// shape and on cells with a face of zero area (that edge counts as 0).
TEST(CellQuality, ExtremeAnglesEqualThePerEdgeOnes)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  const std::vector<std::pair<ar::CellShape, std::vector<double>>> cells = {
    { ar::CellShape::Tetrahedron, { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1 } },
    { ar::CellShape::Pyramid, Pyramid(1.0) },
    { ar::CellShape::Wedge, RightPrism(0.7) },
    { ar::CellShape::Hexahedron, Cube(1.0, 0.0) },
  };
  int flats = 0;
  for (const auto& [shape, base] : cells)
  {
    const int nEdges = ar::NumberOfEdges(shape);
    for (int trial = 0; trial < 300; ++trial)
    {
      std::vector<double> p = base;
      for (double& x : p)
      {
        x += u(rng);
      }
      if (trial % 50 == 0)
      {
        // corner 1 onto corner 0: the faces through both have zero area (a
        // hexahedron's quads keep an area: their normals are the diagonals')
        std::copy(p.begin(), p.begin() + 3, p.begin() + 3);
      }
      double a[12];
      ar::CellDihedralAngles(shape, p.data(), a);
      const ar::CellQuality q = ar::ComputeCellQuality(shape, p.data(), false);
      EXPECT_EQ(q.MinDihedralAngle, *std::min_element(a, a + nEdges));
      EXPECT_EQ(q.MaxDihedralAngle, *std::max_element(a, a + nEdges));
      flats += q.MinDihedralAngle == 0.0 ? 1 : 0;
    }
  }
  EXPECT_GE(flats, 12); // the collapsed tetrahedra, pyramids and prisms
}

// The explicit step length 2 V / sum(face areas) on cells where both are
// known exactly, with and without the faces normal to a depth axis.
TEST(CellQuality, StepLength)
{
  // Regular tetrahedron of edge l: V = l^3 / (6 sqrt 2), faces sqrt(3) l^2 in
  // all: l / (3 sqrt 6).
  const double l = 0.3;
  const std::vector<double> tet = { 0, 0, 0, l, 0, 0, l / 2, l * std::sqrt(3.0) / 2, 0, l / 2,
    l * std::sqrt(3.0) / 6, l * std::sqrt(2.0 / 3.0) };
  EXPECT_NEAR(ar::CellStepLength(ar::CellShape::Tetrahedron, tet.data()), l / (3.0 * std::sqrt(6.0)), 1e-15);
  // Cube of side 2: 2 * 8 / 24; without the two faces normal to z (one cell
  // deep): 2 * 8 / 16, half the side; an axis none of its faces is normal to
  // changes nothing for the pyramid below.
  EXPECT_NEAR(ar::CellStepLength(ar::CellShape::Hexahedron, Cube(2.0, -3.0).data()), 2.0 / 3.0, 1e-14);
  EXPECT_NEAR(ar::CellStepLength(ar::CellShape::Hexahedron, Cube(2.0, -3.0).data(), 2), 1.0, 1e-14);
  EXPECT_NEAR(ar::CellStepLength(ar::CellShape::Hexahedron, Cube(2.0, -3.0).data(), 0), 1.0, 1e-14);
  // Right prism over the unit equilateral triangle, height h: V = h sqrt(3)
  // / 4, faces sqrt(3) / 2 + 3 h. One cell deep along z: the triangle's
  // inradius, 1 / (2 sqrt 3), whatever h.
  for (const double h : { 0.05, 1.0, 7.0 })
  {
    const std::vector<double> p = RightPrism(h);
    EXPECT_NEAR(ar::CellStepLength(ar::CellShape::Wedge, p.data()),
      2.0 * h * std::sqrt(3.0) / 4.0 / (std::sqrt(3.0) / 2.0 + 3.0 * h), 1e-14);
    EXPECT_NEAR(ar::CellStepLength(ar::CellShape::Wedge, p.data(), 2), 1.0 / (2.0 * std::sqrt(3.0)), 1e-14);
  }
  // Square pyramid, base 2 x 2, apex height 3: V = 4, four sides of
  // 2 * sqrt(1 + 9) / 2 each.
  const double side = std::sqrt(10.0);
  EXPECT_NEAR(ar::CellStepLength(ar::CellShape::Pyramid, Pyramid(3.0).data()), 8.0 / (4.0 + 4.0 * side), 1e-14);
  EXPECT_NEAR(ar::CellStepLength(ar::CellShape::Pyramid, Pyramid(3.0).data(), 0),
    ar::CellStepLength(ar::CellShape::Pyramid, Pyramid(3.0).data()), 1e-15);
  // A flat tetrahedron: no volume, step 0; a thin one: its height sets it.
  const std::vector<double> flat = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0 };
  EXPECT_EQ(ar::CellStepLength(ar::CellShape::Tetrahedron, flat.data()), 0.0);
  const std::vector<double> needle = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.3, 0.3, 1e-3 };
  EXPECT_LT(ar::CellStepLength(ar::CellShape::Tetrahedron, needle.data()), 1e-3);
}
