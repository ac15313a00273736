// Unit tests of ar::BuildPrismLayers and of RemeshLocalCavity with prism
// layers: right prisms with the requested thicknesses on a plane, positive
// corner Jacobians for every prism, pyramid and tetrahedron, a conforming
// and watertight hybrid mesh that conserves the volume, layers that shrink
// without inverting on a cone and between two close surfaces, bad options.
// Floating layers of an earlier cycle released as conforming tetrahedra (ARLayerRelease.h).
// The checks below (corner tetrahedra, faces, volumes) are written here from
// the VTK cell conventions, independently of the code under test.
#include "ARCavity.h"
#include "ARLayerRelease.h"
#include "ARPrismLayers.h"
#include "ARTetGeometry.h"
#include "ARTestMeshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <map>
#include <set>
#include <vector>

namespace
{
using artest::BoxTriangles;
using artest::ClosureAndRefillAngles;
using artest::Grid;
using artest::KuhnCube;
using artest::Surface;

enum CellType
{
  Tetra = 4,
  Pyramid = 5,
  Wedge = 6
};

struct Cell
{
  CellType Type;
  std::array<std::int64_t, 6> V;
  int Layer;  // -1: not a layer cell
  int Side;   // 0, +1, -1
  std::int64_t Source; // kept tets: the input tet; else -1
};

struct Hybrid
{
  std::vector<double> Points;
  std::vector<Cell> Cells;
};

Hybrid FromStack(const ar::PrismStack& s)
{
  Hybrid h;
  h.Points = s.Points;
  for (std::size_t c = 0; c < s.Prisms.size() / 6; ++c)
  {
    Cell cell{ Wedge, {}, s.PrismLayer[c], s.PrismSide[c], -1 };
    std::copy(&s.Prisms[6 * c], &s.Prisms[6 * c] + 6, cell.V.begin());
    h.Cells.push_back(cell);
  }
  for (std::size_t c = 0; c < s.Pyramids.size() / 5; ++c)
  {
    Cell cell{ Pyramid, {}, s.PyramidLayer[c], s.PyramidSide[c], -1 };
    std::copy(&s.Pyramids[5 * c], &s.Pyramids[5 * c] + 5, cell.V.begin());
    h.Cells.push_back(cell);
  }
  for (std::size_t c = 0; c < s.Tetrahedra.size() / 4; ++c)
  {
    Cell cell{ Tetra, {}, s.TetrahedronLayer[c], s.TetrahedronSide[c], -1 };
    std::copy(&s.Tetrahedra[4 * c], &s.Tetrahedra[4 * c] + 4, cell.V.begin());
    h.Cells.push_back(cell);
  }
  return h;
}

Hybrid FromCavity(const ar::CavityRemesh& r)
{
  Hybrid h;
  h.Points = r.Mesh.Points;
  for (std::size_t c = 0; c < r.Mesh.NumberOfTetrahedra(); ++c)
  {
    const int layer = r.TetrahedronLayer.empty() ? -1 : r.TetrahedronLayer[c];
    Cell cell{ Tetra, {}, layer, r.TetrahedronSide.empty() ? 0 : r.TetrahedronSide[c], r.SourceCell[c] };
    std::copy(&r.Mesh.Tetrahedra[4 * c], &r.Mesh.Tetrahedra[4 * c] + 4, cell.V.begin());
    h.Cells.push_back(cell);
  }
  for (std::size_t c = 0; c < r.Prisms.size() / 6; ++c)
  {
    Cell cell{ Wedge, {}, r.PrismLayer[c], r.PrismSide[c], -1 };
    std::copy(&r.Prisms[6 * c], &r.Prisms[6 * c] + 6, cell.V.begin());
    h.Cells.push_back(cell);
  }
  for (std::size_t c = 0; c < r.Pyramids.size() / 5; ++c)
  {
    Cell cell{ Pyramid, {}, r.PyramidLayer[c], r.PyramidSide[c], -1 };
    std::copy(&r.Pyramids[5 * c], &r.Pyramids[5 * c] + 5, cell.V.begin());
    h.Cells.push_back(cell);
  }
  return h;
}

/// The faces of a cell, each oriented outward (VTK conventions: a wedge's
/// bottom 0 1 2 has its normal away from the top, a pyramid's quad towards its apex).
std::vector<std::vector<int>> LocalFaces(CellType t)
{
  switch (t)
  {
    case Tetra:
      return { { 1, 2, 3 }, { 0, 3, 2 }, { 0, 1, 3 }, { 0, 2, 1 } };
    case Pyramid:
      return { { 0, 3, 2, 1 }, { 0, 1, 4 }, { 1, 2, 4 }, { 2, 3, 4 }, { 3, 0, 4 } };
    case Wedge:
      return { { 0, 1, 2 }, { 3, 5, 4 }, { 0, 3, 4, 1 }, { 1, 4, 5, 2 }, { 2, 5, 3, 0 } };
  }
  return {};
}

/// The corner tetrahedra whose volume is the Jacobian's sign at each corner.
std::vector<std::array<int, 4>> Corners(CellType t)
{
  switch (t)
  {
    case Tetra:
      return { { 0, 1, 2, 3 } };
    case Pyramid:
      return { { 0, 1, 3, 4 }, { 1, 2, 0, 4 }, { 2, 3, 1, 4 }, { 3, 0, 2, 4 } };
    case Wedge:
      return { { 0, 2, 1, 3 }, { 1, 0, 2, 4 }, { 2, 1, 0, 5 }, { 3, 4, 5, 0 }, { 4, 5, 3, 1 }, { 5, 3, 4, 2 } };
  }
  return {};
}

const double* X(const Hybrid& h, std::int64_t i)
{
  return &h.Points[3 * i];
}

/// Smallest corner volume of a cell (positive everywhere for a valid cell).
double MinCorner(const Hybrid& h, const Cell& c)
{
  double m = 1e300;
  for (const auto& k : Corners(c.Type))
    m = std::min(m, ar::TetSignedVolume(X(h, c.V[k[0]]), X(h, c.V[k[1]]), X(h, c.V[k[2]]), X(h, c.V[k[3]])));
  return m;
}

/// Volume by the divergence theorem: flat triangles, bilinear quads (2x2
/// Gauss points integrate the bilinear patch exactly), relative to `o`.
double FaceFlux(const Hybrid& h, const std::vector<std::int64_t>& f, const double* o)
{
  auto at = [&](std::int64_t i, int d) { return X(h, i)[d] - o[d]; };
  if (f.size() == 3)
  {
    double a[3], b[3], c[3];
    for (int d = 0; d < 3; ++d)
      a[d] = at(f[0], d), b[d] = at(f[1], d), c[d] = at(f[2], d);
    return (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0;
  }
  const double g[2] = { 0.5 - 0.5 / std::sqrt(3.0), 0.5 + 0.5 / std::sqrt(3.0) };
  double sum = 0.0;
  for (double u : g)
    for (double v : g)
    {
      double x[3], xu[3], xv[3];
      for (int d = 0; d < 3; ++d)
      {
        const double p0 = at(f[0], d), p1 = at(f[1], d), p2 = at(f[2], d), p3 = at(f[3], d);
        x[d] = (1 - u) * (1 - v) * p0 + u * (1 - v) * p1 + u * v * p2 + (1 - u) * v * p3;
        xu[d] = (1 - v) * (p1 - p0) + v * (p2 - p3);
        xv[d] = (1 - u) * (p3 - p0) + u * (p2 - p1);
      }
      const double n[3] = { xu[1] * xv[2] - xu[2] * xv[1], xu[2] * xv[0] - xu[0] * xv[2], xu[0] * xv[1] - xu[1] * xv[0] };
      sum += 0.25 * (x[0] * n[0] + x[1] * n[1] + x[2] * n[2]) / 3.0;
    }
  return sum;
}

double CellVolume(const Hybrid& h, const Cell& c)
{
  double v = 0.0;
  const double* o = X(h, c.V[0]);
  for (const auto& lf : LocalFaces(c.Type))
  {
    std::vector<std::int64_t> f;
    for (int k : lf)
      f.push_back(c.V[k]);
    v += FaceFlux(h, f, o);
  }
  return v;
}

using Key = std::array<long long, 12>;

/// A face (3 or 4 corners) as its sorted, rounded corner coordinates.
Key FaceKey(const std::vector<double>& pts, const std::vector<std::int64_t>& f)
{
  std::vector<std::array<long long, 3>> c;
  for (std::int64_t i : f)
    c.push_back({ std::llround(pts[3 * i] * 1e9), std::llround(pts[3 * i + 1] * 1e9), std::llround(pts[3 * i + 2] * 1e9) });
  std::sort(c.begin(), c.end());
  Key k;
  k.fill(LLONG_MIN);
  for (std::size_t i = 0; i < c.size(); ++i)
    for (int d = 0; d < 3; ++d)
      k[3 * i + d] = c[i][d];
  return k;
}

/// Every face and the cells that have it.
std::map<Key, std::vector<std::size_t>> Faces(const Hybrid& h)
{
  std::map<Key, std::vector<std::size_t>> faces;
  for (std::size_t c = 0; c < h.Cells.size(); ++c)
    for (const auto& lf : LocalFaces(h.Cells[c].Type))
    {
      std::vector<std::int64_t> f;
      for (int k : lf)
        f.push_back(h.Cells[c].V[k]);
      faces[FaceKey(h.Points, f)].push_back(c);
    }
  return faces;
}

std::set<Key> BoundaryFaces(const std::map<Key, std::vector<std::size_t>>& faces)
{
  std::set<Key> b;
  for (const auto& f : faces)
    if (f.second.size() == 1)
      b.insert(f.first);
  return b;
}

/// Every corner of every cell positive, no face in more than two cells.
void ExpectValidCells(const Hybrid& h, const std::string& label)
{
  std::map<CellType, std::size_t> bad, count;
  for (const Cell& c : h.Cells)
  {
    ++count[c.Type];
    if (!(MinCorner(h, c) > 0.0))
      ++bad[c.Type];
  }
  EXPECT_EQ(bad[Wedge], 0u) << label << ": prisms with a non-positive corner Jacobian (of " << count[Wedge] << ")";
  EXPECT_EQ(bad[Pyramid], 0u) << label << ": pyramids with a non-positive corner Jacobian (of " << count[Pyramid] << ")";
  EXPECT_EQ(bad[Tetra], 0u) << label << ": tetrahedra with a non-positive volume (of " << count[Tetra] << ")";
  std::size_t overused = 0;
  for (const auto& f : Faces(h))
    overused += f.second.size() > 2 ? 1 : 0;
  EXPECT_EQ(overused, 0u) << label << ": faces in more than two cells";
}

/// The stack alone: valid cells whose boundary is exactly its outer surface,
/// a closed oriented surface enclosing the cells' total volume.
void ExpectValidStack(const ar::PrismStack& s, const std::string& label)
{
  const Hybrid h = FromStack(s);
  ExpectValidCells(h, label);
  std::set<Key> outer;
  std::map<std::pair<std::int64_t, std::int64_t>, int> edges;
  double enclosed = 0.0, cells = 0.0;
  const double* o = X(h, 0);
  for (std::size_t t = 0; t < s.OuterTriangles.size() / 3; ++t)
  {
    const std::vector<std::int64_t> f(&s.OuterTriangles[3 * t], &s.OuterTriangles[3 * t] + 3);
    outer.insert(FaceKey(h.Points, f));
    enclosed += FaceFlux(h, f, o);
    for (int k = 0; k < 3; ++k)
      ++edges[{ f[k], f[(k + 1) % 3] }];
  }
  std::size_t open = 0;
  for (const auto& e : edges)
    open += (e.second != 1 || edges.count({ e.first.second, e.first.first }) == 0) ? 1 : 0;
  EXPECT_EQ(open, 0u) << label << ": the outer surface is closed and consistently oriented";
  EXPECT_EQ(BoundaryFaces(Faces(h)), outer) << label << ": the cells' boundary is the outer surface";
  for (const Cell& c : h.Cells)
    cells += CellVolume(h, c);
  EXPECT_NEAR(cells, enclosed, 1e-9 * enclosed) << label << ": the cells fill the outer surface";
}

Hybrid FromTets(const ar::TetMesh& m)
{
  Hybrid h;
  h.Points = m.Points;
  for (std::size_t c = 0; c < m.NumberOfTetrahedra(); ++c)
  {
    Cell cell{ Tetra, {}, -1, 0, -1 };
    std::copy(&m.Tetrahedra[4 * c], &m.Tetrahedra[4 * c] + 4, cell.V.begin());
    h.Cells.push_back(cell);
  }
  return h;
}

std::set<Key> TetBoundary(const ar::TetMesh& m)
{
  return BoundaryFaces(Faces(FromTets(m)));
}

double TetVolume(const ar::TetMesh& m)
{
  double v = 0.0;
  for (std::size_t c = 0; c < m.NumberOfTetrahedra(); ++c)
    v += ar::TetSignedVolume(&m.Points[3 * m.Tetrahedra[4 * c]], &m.Points[3 * m.Tetrahedra[4 * c + 1]],
      &m.Points[3 * m.Tetrahedra[4 * c + 2]], &m.Points[3 * m.Tetrahedra[4 * c + 3]]);
  return v;
}

/// S is trimmed back from the domain boundary by BoundaryMargin x max(l_s,
/// l_b), l_b the boundary faces' size (plus one l_s with layers): the
/// patches here, well inside the cube or cut by it, keep a third of their
/// triangles or more (the FullDomain case is on a coarse 8^3 cube).
void ExpectMostlyKept(const ar::CavityRemesh& r, std::size_t given, const std::string& label)
{
  EXPECT_GT(3 * r.SurfaceTrianglesUsed, given) << label << ": " << r.SurfaceTrianglesUsed << " of " << given
                                               << " S triangles survive the trim";
}

/// The validity checks of EmbeddedRemesh for a hybrid result.
void ExpectValidCavity(const ar::TetMesh& in, const ar::CavityRemesh& r, std::size_t nTriangles,
  int layers, bool bothSides, const std::string& label, bool quality = true)
{
  const Hybrid h = FromCavity(r);
  ExpectValidCells(h, label);
  const auto faces = Faces(h);
  EXPECT_EQ(BoundaryFaces(faces), TetBoundary(in)) << label << ": watertight, the boundary is the input's face for face";
  double volume = 0.0;
  for (const Cell& c : h.Cells)
    volume += CellVolume(h, c);
  const double v0 = TetVolume(in);
  EXPECT_NEAR(volume, v0, 1e-9 * v0) << label << ": volume conserved";
  // Counts.
  EXPECT_EQ(r.Prisms.size() / 6, (bothSides ? 2u : 1u) * layers * nTriangles) << label;
  EXPECT_GT(r.Pyramids.size(), 0u) << label;
  // Kept tetrahedra are the input's, corner for corner.
  std::size_t moved = 0;
  for (std::size_t t = 0; t < r.SourceCell.size(); ++t)
    if (r.SourceCell[t] >= 0)
      for (int k = 0; k < 4; ++k)
        for (int d = 0; d < 3; ++d)
          moved += r.Mesh.Points[3 * r.Mesh.Tetrahedra[4 * t + k] + d] != in.Points[3 * in.Tetrahedra[4 * r.SourceCell[t] + k] + d];
  EXPECT_EQ(moved, 0u) << label << ": kept cells unchanged";
  // Every pyramid's quad is a prism's quad.
  std::size_t unmatched = 0;
  for (std::size_t c = 0; c < h.Cells.size(); ++c)
  {
    if (h.Cells[c].Type != Pyramid)
      continue;
    const std::vector<std::int64_t> q(h.Cells[c].V.begin(), h.Cells[c].V.begin() + 4);
    const auto& cells = faces.at(FaceKey(h.Points, q));
    unmatched += (cells.size() == 2 && h.Cells[cells[0] == c ? cells[1] : cells[0]].Type == Wedge) ? 0 : 1;
  }
  EXPECT_EQ(unmatched, 0u) << label << ": pyramid quads that are not a prism's quad";
  // S's triangles are faces between the two sides' innermost prisms.
  ASSERT_EQ(r.Surface.size(), 3 * nTriangles) << label;
  std::size_t wrong = 0;
  for (std::size_t f = 0; f < nTriangles; ++f)
  {
    const std::vector<std::int64_t> tri(&r.Surface[3 * f], &r.Surface[3 * f] + 3);
    const auto it = faces.find(FaceKey(h.Points, tri));
    if (it == faces.end() || it->second.size() != 2)
    {
      ++wrong;
      continue;
    }
    const Cell& a = h.Cells[it->second[0]];
    const Cell& b = h.Cells[it->second[1]];
    if (bothSides)
      wrong += (a.Type == Wedge && b.Type == Wedge && a.Layer == 0 && b.Layer == 0 && a.Side == -b.Side) ? 0 : 1;
    else
      wrong += ((a.Type == Wedge && a.Layer == 0) != (b.Type == Wedge && b.Layer == 0)) ? 0 : 1;
  }
  EXPECT_EQ(wrong, 0u) << label << ": S triangles that are not faces between the innermost prisms";
  // TetGen's tetrahedra: min dihedral >= 10 degrees.
  if (quality)
  {
    double worst = 180.0;
    for (const Cell& c : h.Cells)
    {
      if (c.Type != Tetra || c.Source >= 0 || c.Layer >= 0)
        continue;
      double a[6];
      ar::TetDihedralAngles(X(h, c.V[0]), X(h, c.V[1]), X(h, c.V[2]), X(h, c.V[3]), a);
      worst = std::min(worst, *std::min_element(a, a + 6));
    }
    EXPECT_GE(worst, 10.0) << label << ": TetGen's tetrahedra";
  }
}

bool Build(const Surface& s, const ar::PrismLayerOptions& o, ar::PrismStack& out, std::string& error,
  const std::vector<double>& obstacles = BoxTriangles())
{
  return ar::BuildPrismLayers(s.Points.data(), s.Points.size() / 3, s.Triangles.data(), s.Triangles.size() / 3,
    obstacles.data(), obstacles.size() / 9, o, out, error);
}

// The tilted plane patch of TestCavity, edge about 0.05; its unit normal.
Surface TiltedPatch()
{
  return Grid(10, 10, 0.25, 0.75, 0.25, 0.75, [](double u, double v) {
    return std::array<double, 3>{ u, v, 0.5 + 0.2 * (u - 0.5) - 0.1 * (v - 0.5) };
  });
}
/// TiltedPatch without its quarter u, v > 0.5: an L whose border turns
/// inward at its notch.
Surface TiltedL()
{
  const Surface full = TiltedPatch();
  Surface out;
  out.Points = full.Points;
  for (std::size_t t = 0; t < full.Triangles.size() / 3; ++t)
  {
    double u = 0.0, v = 0.0;
    for (int k = 0; k < 3; ++k)
    {
      u += full.Points[3 * full.Triangles[3 * t + k]] / 3.0;
      v += full.Points[3 * full.Triangles[3 * t + k] + 1] / 3.0;
    }
    if (u < 0.5 || v < 0.5)
      out.Triangles.insert(out.Triangles.end(), &full.Triangles[3 * t], &full.Triangles[3 * t] + 3);
  }
  return out;
}
const std::array<double, 3> TiltedNormal = [] {
  const double n = std::sqrt(0.04 + 0.01 + 1.0);
  return std::array<double, 3>{ -0.2 / n, 0.1 / n, 1.0 / n };
}();

/// Right prisms of the requested thickness: each lateral edge of a layer-k
/// prism lies within 5 degrees of S's normal and is First * Growth^k long (1 %).
void ExpectRightPrisms(const std::vector<double>& pts, const std::vector<std::int64_t>& prisms,
  const std::vector<int>& layer, double first, double growth, const std::string& label)
{
  std::size_t tilted = 0, thick = 0;
  double worstAngle = 0.0, worstThickness = 0.0;
  for (std::size_t c = 0; c < prisms.size() / 6; ++c)
    for (int k = 0; k < 3; ++k)
    {
      const double* a = &pts[3 * prisms[6 * c + k]];
      const double* b = &pts[3 * prisms[6 * c + k + 3]];
      const double e[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
      const double len = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
      // atan2(|e x n|, |e . n|): well-conditioned next to 0 degrees, where acos is not.
      const double* n = TiltedNormal.data();
      const double cr[3] = { e[1] * n[2] - e[2] * n[1], e[2] * n[0] - e[0] * n[2], e[0] * n[1] - e[1] * n[0] };
      const double angle = std::atan2(std::sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]),
                             std::abs(e[0] * n[0] + e[1] * n[1] + e[2] * n[2])) * 180.0 / M_PI;
      const double want = first * std::pow(growth, layer[c]);
      worstAngle = std::max(worstAngle, angle);
      worstThickness = std::max(worstThickness, std::abs(len / want - 1.0));
      tilted += angle > 5.0 ? 1 : 0;
      thick += std::abs(len / want - 1.0) > 0.01 ? 1 : 0;
    }
  EXPECT_EQ(tilted, 0u) << label << ": lateral edges more than 5 deg off S's normal (worst " << worstAngle << ")";
  EXPECT_EQ(thick, 0u) << label << ": layers off their thickness by more than 1 % (worst " << worstThickness << ")";
}

// A cone sector: apex (0.5, 0.5, 0.15), axis +z, half-angle 35 degrees,
// slant distance s in [0.08, 0.55], azimuth in [0, 200] degrees, edges about
// 0.04: rings of constant s, each with as many points as its arc needs,
// zipped together. Its normals point away from the axis (the concave side is
// the - side). At the tip ring the concave side's normals meet the axis
// 0.08 tan 35 = 0.056 away, within the requested stack.
const double ConeHalfAngle = 35.0 * M_PI / 180.0;
Surface ConeSector()
{
  Surface out;
  const double h = 0.04, s0 = 0.08, s1 = 0.55, span = 200.0 * M_PI / 180.0;
  const int rings = static_cast<int>(std::lround((s1 - s0) / (0.87 * h)));
  std::vector<std::int64_t> first;
  std::vector<int> count;
  for (int j = 0; j <= rings; ++j)
  {
    const double s = s0 + (s1 - s0) * j / rings, r = s * std::sin(ConeHalfAngle);
    const int n = std::max(1, static_cast<int>(std::lround(r * span / h)));
    first.push_back(static_cast<std::int64_t>(out.Points.size() / 3));
    count.push_back(n);
    for (int i = 0; i <= n; ++i)
      out.Points.insert(out.Points.end(), { 0.5 + r * std::cos(span * i / n), 0.5 + r * std::sin(span * i / n), 0.15 + s * std::cos(ConeHalfAngle) });
  }
  for (int j = 0; j < rings; ++j)
    for (int a = 0, b = 0; a < count[j] || b < count[j + 1];)
    {
      if (b == count[j + 1] || (a < count[j] && double(a + 1) / count[j] < double(b + 1) / count[j + 1]))
        out.Triangles.insert(out.Triangles.end(), { first[j] + a, first[j] + a + 1, first[j + 1] + b }), ++a;
      else
        out.Triangles.insert(out.Triangles.end(), { first[j] + a, first[j + 1] + b + 1, first[j + 1] + b }), ++b;
    }
  return out;
}

/// Groups of layers under one apex: the pyramids' apices per border edge of S.
double ClosureGroups(const ar::CavityRemesh& r)
{
  std::set<std::int64_t> apices;
  for (std::size_t c = 0; c < r.Pyramids.size() / 5; ++c)
    apices.insert(r.Pyramids[5 * c + 4]);
  std::map<std::pair<std::int64_t, std::int64_t>, int> edges;
  for (std::size_t f = 0; f < r.Surface.size() / 3; ++f)
    for (int k = 0; k < 3; ++k)
    {
      const std::int64_t a = r.Surface[3 * f + k], b = r.Surface[3 * f + (k + 1) % 3];
      ++edges[{ std::min(a, b), std::max(a, b) }];
    }
  std::size_t border = 0;
  for (const auto& e : edges)
    border += e.second == 1 ? 1 : 0;
  return static_cast<double>(apices.size()) / static_cast<double>(border);
}
}

TEST(PrismLayers, PlanarSurfaceGetsRightPrismsOfTheRequestedThickness)
{
  const Surface s = TiltedPatch();
  ar::PrismLayerOptions o;
  o.NumberOfLayers = 4;
  o.FirstLayerThickness = 0.01;
  o.GrowthRatio = 1.3;
  o.BorderHeight = 1e9; // full height up to the border (no taper): the thickness everywhere, the closure
  ar::PrismStack stack;
  std::string error;
  ASSERT_TRUE(Build(s, o, stack, error)) << error;
  const std::size_t nTri = s.Triangles.size() / 3;
  EXPECT_EQ(stack.Prisms.size() / 6, 2u * 4u * nTri);
  EXPECT_EQ(stack.LimitedColumns, 0u) << "nothing is in the way of a plane in the middle of the box";
  EXPECT_EQ(stack.Pyramids.size() / 5, 40u * 8u) << "one pyramid per border edge, layer and side";
  // The first points are S's.
  for (std::size_t i = 0; i < s.Points.size(); ++i)
    ASSERT_EQ(stack.Points[i], s.Points[i]);
  ExpectRightPrisms(stack.Points, stack.Prisms, stack.PrismLayer, 0.01, 1.3, "plane");
  ExpectValidStack(stack, "plane");
  // The sides: + along S's normal.
  for (std::size_t c = 0; c < stack.Prisms.size() / 6; ++c)
  {
    const double* a = &stack.Points[3 * stack.Prisms[6 * c]];
    const double* b = &stack.Points[3 * stack.Prisms[6 * c + 3]];
    const double along = (b[0] - a[0]) * TiltedNormal[0] + (b[1] - a[1]) * TiltedNormal[1] + (b[2] - a[2]) * TiltedNormal[2];
    ASSERT_GT(along * stack.PrismSide[c], 0.0) << "prism " << c;
  }
  // TotalThickness instead of the first layer: the same stack.
  ar::PrismLayerOptions total = o;
  total.FirstLayerThickness = 0.0;
  total.TotalThickness = 0.01 * (1 + 1.3 + 1.69 + 2.197);
  ar::PrismStack same;
  ASSERT_TRUE(Build(s, total, same, error)) << error;
  ExpectRightPrisms(same.Points, same.Prisms, same.PrismLayer, 0.01, 1.3, "plane, total thickness");
}

TEST(PrismLayers, CavityWithLayersOnAPlaneIsAValidHybridMesh)
{
  const ar::TetMesh cube = KuhnCube(12);
  const Surface s = TiltedPatch();
  ar::CavityOptions o;
  o.Layers.NumberOfLayers = 3;
  o.Layers.FirstLayerThickness = 0.01;
  o.Layers.GrowthRatio = 1.2;
  o.Layers.BorderHeight = 1e9; // no taper: the full stack's closure against TetGen
  ar::CavityRemesh r;
  std::string error;
  ASSERT_TRUE(ar::RemeshLocalCavity(cube, s.Points.data(), s.Points.size() / 3, s.Triangles.data(),
    s.Triangles.size() / 3, o, r, error)) << error;
  ExpectValidCavity(cube, r, r.SurfaceTrianglesUsed, 3, true, "plane in the cube");
  ExpectMostlyKept(r, s.Triangles.size() / 3, "plane in the cube");
  ExpectRightPrisms(r.Mesh.Points, r.Prisms, r.PrismLayer, 0.01, 1.2, "plane in the cube");
  EXPECT_EQ(r.LimitedColumns, 0u);
  EXPECT_NEAR(r.LayerStackHeight, 0.01 * (1 + 1.2 + 1.44), 1e-15);
  // The removal radius covers the stack: no kept node within 3 max(l_s, l_v) + z_N of S's nodes.
  std::set<std::int64_t> kept(r.SourcePoint.begin(), r.SourcePoint.end());
  const double lv = std::sqrt(3.0) / 12.0;
  for (std::size_t j = 0; j < cube.NumberOfPoints(); ++j)
  {
    const double* x = &cube.Points[3 * j];
    if (!(x[0] > 0 && x[0] < 1 && x[1] > 0 && x[1] < 1 && x[2] > 0 && x[2] < 1))
      continue;
    double dmin = 1e9;
    for (std::size_t i = 0; i < s.Points.size() / 3; ++i)
      dmin = std::min(dmin, std::hypot(x[0] - s.Points[3 * i], std::hypot(x[1] - s.Points[3 * i + 1], x[2] - s.Points[3 * i + 2])));
    if (dmin < 0.99 * (3.0 * lv + r.LayerStackHeight))
      EXPECT_EQ(kept.count(static_cast<std::int64_t>(j)), 0u) << "node " << j << " at " << dmin;
  }
  // FullDomain with layers: everything remeshed, still a valid hybrid mesh.
  ar::CavityOptions full = o;
  full.FullDomain = true;
  ar::CavityRemesh all;
  ASSERT_TRUE(ar::RemeshLocalCavity(KuhnCube(8), s.Points.data(), s.Points.size() / 3, s.Triangles.data(),
    s.Triangles.size() / 3, full, all, error)) << error;
  ExpectValidCavity(KuhnCube(8), all, all.SurfaceTrianglesUsed, 3, true, "plane, FullDomain");
  ExpectMostlyKept(all, s.Triangles.size() / 3, "plane, FullDomain");
  EXPECT_EQ(std::count(all.SourceCell.begin(), all.SourceCell.end(), -1), static_cast<long>(all.SourceCell.size()));
  // The tetrahedra-only path is untouched by the new option's default.
  ar::CavityRemesh plain;
  ASSERT_TRUE(ar::RemeshLocalCavity(cube, s.Points.data(), s.Points.size() / 3, s.Triangles.data(),
    s.Triangles.size() / 3, ar::CavityOptions(), plain, error)) << error;
  EXPECT_TRUE(plain.Prisms.empty() && plain.Pyramids.empty() && plain.TetrahedronLayer.empty());
}

// A piece of S with no interior point (a strip one triangle wide, as a trim
// can cut off beside the rest) is dropped, the rest keeps its layers; the
// largest piece stays even when it has no interior point.
TEST(PrismLayers, CavityWithLayersDropsAStripCutOffBesideS)
{
  const ar::TetMesh cube = KuhnCube(12);
  const Surface patch = TiltedPatch();
  // Columns 7 and 9 of the 10 x 10 grid's cells removed: the cells 0-6
  // (140 triangles) and a strip of column 8 (20 triangles, each point on its
  // border), 0.05 apart.
  Surface s = patch;
  s.Triangles.clear();
  for (std::size_t t = 0; t < patch.Triangles.size() / 3; ++t)
  {
    const int column = static_cast<int>(t / 2 % 10);
    if (column != 7 && column != 9)
      s.Triangles.insert(s.Triangles.end(), &patch.Triangles[3 * t], &patch.Triangles[3 * t] + 3);
  }
  ar::CavityOptions o;
  o.Layers.NumberOfLayers = 3;
  o.Layers.FirstLayerThickness = 0.004;
  o.Layers.GrowthRatio = 1.2;
  ar::CavityRemesh r;
  std::string error;
  ASSERT_TRUE(ar::RemeshLocalCavity(cube, s.Points.data(), s.Points.size() / 3, s.Triangles.data(),
    s.Triangles.size() / 3, o, r, error)) << error;
  EXPECT_EQ(r.SurfaceTrianglesUsed, 140u);
  ExpectValidCavity(cube, r, r.SurfaceTrianglesUsed, 3, true, "plane and a strip beside it");
  // The strip alone: the largest piece, kept.
  Surface strip = patch;
  strip.Triangles.clear();
  for (std::size_t t = 0; t < patch.Triangles.size() / 3; ++t)
    if (t / 2 % 10 == 8)
      strip.Triangles.insert(strip.Triangles.end(), &patch.Triangles[3 * t], &patch.Triangles[3 * t] + 3);
  ASSERT_TRUE(ar::RemeshLocalCavity(cube, strip.Points.data(), strip.Points.size() / 3, strip.Triangles.data(),
    strip.Triangles.size() / 3, o, r, error)) << error;
  EXPECT_EQ(r.SurfaceTrianglesUsed, 20u);
  ExpectValidCavity(cube, r, r.SurfaceTrianglesUsed, 3, true, "a strip alone", false);
}

TEST(PrismLayers, OneSidedLayersMeetTetrahedraOnS)
{
  const ar::TetMesh cube = KuhnCube(12);
  const Surface s = TiltedPatch();
  ar::CavityOptions o;
  o.Layers.NumberOfLayers = 2;
  o.Layers.TotalThickness = 0.03;
  o.Layers.GrowthRatio = 1.5;
  o.Layers.BothSides = false;
  o.Layers.BorderHeight = 1e9; // no taper
  ar::CavityRemesh r;
  std::string error;
  ASSERT_TRUE(ar::RemeshLocalCavity(cube, s.Points.data(), s.Points.size() / 3, s.Triangles.data(),
    s.Triangles.size() / 3, o, r, error)) << error;
  ExpectValidCavity(cube, r, r.SurfaceTrianglesUsed, 2, false, "one side");
  ExpectMostlyKept(r, s.Triangles.size() / 3, "one side");
  ExpectRightPrisms(r.Mesh.Points, r.Prisms, r.PrismLayer, 0.03 / 2.5, 1.5, "one side");
  for (int side : r.PrismSide)
    ASSERT_EQ(side, 1);
}

TEST(PrismLayers, ConeLayersShrinkWithoutFolding)
{
  const Surface s = ConeSector();
  ASSERT_GT(s.Triangles.size(), 400u);
  ar::PrismLayerOptions o;
  o.NumberOfLayers = 4;
  o.TotalThickness = 0.06;
  o.GrowthRatio = 1.2;
  o.BorderHeight = 1e9; // no taper: the curvature alone lowers the stack
  ar::PrismStack stack;
  std::string error;
  ASSERT_TRUE(Build(s, o, stack, error)) << error;
  ExpectValidStack(stack, "cone");
  const std::size_t nTri = s.Triangles.size() / 3, nS = s.Points.size() / 3;
  // The stack covers S: 2 N prisms on every triangle, layer 0 standing on it.
  std::vector<int> perTriangle(nTri, 0);
  for (std::size_t c = 0; c < stack.PrismTriangle.size(); ++c)
  {
    ++perTriangle[stack.PrismTriangle[c]];
    if (stack.PrismLayer[c] == 0)
    {
      std::set<std::int64_t> bottom(&stack.Prisms[6 * c], &stack.Prisms[6 * c] + 3);
      std::set<std::int64_t> tri(&s.Triangles[3 * stack.PrismTriangle[c]], &s.Triangles[3 * stack.PrismTriangle[c]] + 3);
      ASSERT_EQ(bottom, tri) << "prism " << c;
    }
  }
  for (std::size_t t = 0; t < nTri; ++t)
    ASSERT_EQ(perTriangle[t], 8) << "triangle " << t;
  // Concave side (towards the axis) at the tip ring: shrunk; convex side mid-cone: full height.
  std::size_t shrunkNearTip = 0, nearTip = 0, fullOutside = 0, outside = 0;
  for (std::size_t v = 0; v < nS; ++v)
  {
    const double* x = &s.Points[3 * v];
    const double* n = &stack.Normals[3 * v];
    const double radial[2] = { x[0] - 0.5, x[1] - 0.5 };
    const double slant = std::hypot(radial[0], radial[1]) / std::sin(ConeHalfAngle);
    const int concave = (n[0] * radial[0] + n[1] * radial[1]) < 0 ? 0 : 1; // the side facing the axis
    ASSERT_EQ(concave, 1) << "the cone's normals point away from its axis";
    ASSERT_GT(stack.Heights[2 * v], 0.0);
    ASSERT_GT(stack.Heights[2 * v + 1], 0.0);
    if (slant < 0.09)
    {
      ++nearTip;
      shrunkNearTip += stack.Heights[2 * v + concave] < 0.056 ? 1 : 0;
    }
    if (slant > 0.25 && slant < 0.45)
    {
      ++outside;
      fullOutside += stack.Heights[2 * v + 1 - concave] > 0.06 * (1 - 1e-12) ? 1 : 0;
    }
  }
  EXPECT_GT(nearTip, 3u);
  EXPECT_EQ(shrunkNearTip, nearTip) << "the concave side stays short of the axis where its normals meet";
  EXPECT_GT(outside, 50u);
  EXPECT_EQ(fullOutside, outside) << "the convex side keeps the full stack";
  EXPECT_GT(stack.LimitedColumns, 0u);

  // In the cavity: a valid hybrid mesh.
  const ar::TetMesh cube = KuhnCube(12);
  ar::CavityOptions co;
  co.Layers = o;
  ar::CavityRemesh r;
  ASSERT_TRUE(ar::RemeshLocalCavity(cube, s.Points.data(), nS, s.Triangles.data(), nTri, co, r, error)) << error;
  ExpectValidCavity(cube, r, r.SurfaceTrianglesUsed, 4, true, "cone in the cube");
  ExpectMostlyKept(r, nTri, "cone in the cube");
}

TEST(PrismLayers, CloseParallelSurfacesShrinkTheirFacingLayers)
{
  // Two planes 0.06 apart, each asking for 0.05 on each side (2 x 0.05 > 0.06).
  Surface s = Grid(10, 10, 0.3, 0.7, 0.3, 0.7, [](double u, double v) { return std::array<double, 3>{ u, v, 0.47 }; });
  const Surface upper = Grid(10, 10, 0.3, 0.7, 0.3, 0.7, [](double u, double v) { return std::array<double, 3>{ u, v, 0.53 }; });
  const auto offset = static_cast<std::int64_t>(s.Points.size() / 3);
  s.Points.insert(s.Points.end(), upper.Points.begin(), upper.Points.end());
  for (std::int64_t id : upper.Triangles)
    s.Triangles.push_back(id + offset);
  ar::PrismLayerOptions o;
  o.NumberOfLayers = 3;
  o.TotalThickness = 0.05;
  o.GrowthRatio = 1.25;
  o.BorderHeight = 1e9; // no taper: the facing sides alone lower the stack
  ar::PrismStack stack;
  std::string error;
  ASSERT_TRUE(Build(s, o, stack, error)) << error;
  ExpectValidStack(stack, "parallel planes");
  EXPECT_EQ(stack.HolePoints.size(), 6u) << "one hole point per piece";
  // Facing sides (+ of the lower, - of the upper) take at most GapFraction of the gap;
  // the outer sides keep the full stack.
  const std::size_t nS = s.Points.size() / 3;
  double facing = 0.0, outer = 1.0;
  for (std::size_t v = 0; v < nS; ++v)
  {
    const bool lower = static_cast<std::int64_t>(v) < offset;
    facing = std::max(facing, stack.Heights[2 * v + (lower ? 0 : 1)]);
    outer = std::min(outer, stack.Heights[2 * v + (lower ? 1 : 0)]);
  }
  EXPECT_LE(facing, 0.35 * 0.06 + 1e-12);
  EXPECT_NEAR(outer, 0.05, 1e-12);
  // No overlap: every point of the lower stack lies below every point of the upper one.
  double lowerTop = -1.0, upperBottom = 2.0;
  for (std::size_t c = 0; c < stack.Prisms.size() / 6; ++c)
  {
    const bool lower = stack.Prisms[6 * c] < offset || (stack.Prisms[6 * c] >= static_cast<std::int64_t>(nS) &&
      (stack.Prisms[6 * c] - static_cast<std::int64_t>(nS)) % static_cast<std::int64_t>(nS) < offset);
    for (int k = 0; k < 6; ++k)
    {
      const double zk = stack.Points[3 * stack.Prisms[6 * c + k] + 2];
      (lower ? lowerTop : upperBottom) = lower ? std::max(lowerTop, zk) : std::min(upperBottom, zk);
    }
  }
  EXPECT_LT(lowerTop, upperBottom) << "the two stacks do not overlap";
  EXPECT_GE(upperBottom - lowerTop, 0.3 * 0.06 - 1e-12) << "and leave a gap for the tetrahedra";

  const ar::TetMesh cube = KuhnCube(12);
  ar::CavityOptions co;
  co.Layers = o;
  ar::CavityRemesh r;
  ASSERT_TRUE(ar::RemeshLocalCavity(cube, s.Points.data(), nS, s.Triangles.data(), s.Triangles.size() / 3, co, r, error)) << error;
  ExpectValidCavity(cube, r, r.SurfaceTrianglesUsed, 3, true, "parallel planes in the cube", false);
  ExpectMostlyKept(r, s.Triangles.size() / 3, "parallel planes in the cube");
  EXPECT_GT(r.LimitedColumns, 0u);
}

// A stack twice as high as S's border edges (0.1 per side on edges of 0.05),
// with the default taper: the border columns are at most BorderHeight x their
// border edges high, the heights graded inward with MaxHeightGradient, the
// columns far enough inside at full height, and TetGen's tetrahedra around
// the tapered closure at least 10 degrees.
TEST(PrismLayers, StackTallerThanItsBorderEdgesTapersToItsClosure)
{
  const ar::TetMesh cube = KuhnCube(12);
  const Surface s = TiltedPatch();
  ar::CavityOptions o;
  o.Layers.NumberOfLayers = 3;
  o.Layers.TotalThickness = 0.1;
  o.Layers.GrowthRatio = 1.2;
  ar::CavityRemesh r;
  std::string error;
  ASSERT_TRUE(ar::RemeshLocalCavity(cube, s.Points.data(), s.Points.size() / 3, s.Triangles.data(),
    s.Triangles.size() / 3, o, r, error)) << error;
  ExpectValidCavity(cube, r, r.SurfaceTrianglesUsed, 3, true, "tapered stack");
  const std::size_t nS = s.Points.size() / 3;
  // The heights from the stack's points: each S point (u, v on the grid)
  // against its farthest layer point along the normal.
  const double* n = TiltedNormal.data();
  std::vector<double> height(2 * nS, 0.0);
  for (std::size_t i = r.FirstStackPoint + nS; i < r.FirstStackPoint + r.NumberOfStackPoints; ++i)
  {
    const double* x = &r.Mesh.Points[3 * i];
    // nearest S point in the plane of S (the columns stand along n)
    std::size_t best = 0;
    double bestD = 1e9;
    for (std::size_t j = 0; j < nS; ++j)
    {
      const double* p = &s.Points[3 * j];
      const double d[3] = { x[0] - p[0], x[1] - p[1], x[2] - p[2] };
      const double along = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
      const double across = std::sqrt(std::max(0.0, d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - along * along));
      if (across < bestD)
      {
        bestD = across;
        best = j;
      }
    }
    if (bestD > 1e-3)
      continue; // a closure apex, not a layer point
    const double* p = &s.Points[3 * best];
    const double along = (x[0] - p[0]) * n[0] + (x[1] - p[1]) * n[1] + (x[2] - p[2]) * n[2];
    double& h = height[2 * best + (along > 0 ? 0 : 1)];
    h = std::max(h, std::abs(along));
  }
  double borderMax = 0.0, innerMin = 1.0;
  for (std::size_t j = 0; j < nS; ++j)
  {
    const double u = s.Points[3 * j], v = s.Points[3 * j + 1];
    const double fromBorder = std::min({ u - 0.25, 0.75 - u, v - 0.25, 0.75 - v });
    for (int side = 0; side < 2; ++side)
    {
      if (fromBorder < 1e-9)
        borderMax = std::max(borderMax, height[2 * j + side]);
      else if (fromBorder > (0.1 - 0.5 * 0.05) / o.Layers.MaxHeightGradient + 1e-9)
        innerMin = std::min(innerMin, height[2 * j + side]);
    }
  }
  // (the border edges along u are 0.05 sqrt(1.04) long in 3-D: S is tilted)
  EXPECT_LE(borderMax, 0.5 * 0.05 * std::sqrt(1.04) * (1 + 1e-9)) << "the border columns are tapered to half their edge";
  EXPECT_NEAR(innerMin, 0.1, 1e-9) << "the columns inside are at the full height";
  EXPECT_GT(r.LimitedColumns, 0u);
  const double worst = ClosureAndRefillAngles(r)[1]; // TetGen's, not the closure's
  std::printf("tapered stack 2 edges high: border columns <= %.4f, inner >= %.4f, TetGen's tetrahedra >= %.2f deg\n",
    borderMax, innerMin, worst);
  EXPECT_GE(worst, 10.0);
}

TEST(PrismLayers, SurfaceTrimmedAtTheDomainBoundaryGetsAClosedStack)
{
  // A wavy surface across the whole cube, its grid turned by 0.5 rad: the
  // trim leaves a jagged border (notches and spikes) near the boundary.
  const double c = std::cos(0.5), sn = std::sin(0.5);
  const Surface s = Grid(20, 20, -0.2, 1.2, -0.2, 1.2, [c, sn](double u, double v) {
    const double x = 0.5 + c * (u - 0.5) - sn * (v - 0.5), y = 0.5 + sn * (u - 0.5) + c * (v - 0.5);
    return std::array<double, 3>{ x, y, 0.45 + 0.1 * x + 0.05 * std::sin(6 * y) };
  });
  const ar::TetMesh cube = KuhnCube(12);
  ar::CavityOptions o;
  o.Layers.NumberOfLayers = 4;
  o.Layers.TotalThickness = 0.03;
  o.Layers.GrowthRatio = 1.2;
  ar::CavityRemesh r;
  std::string error;
  ASSERT_TRUE(ar::RemeshLocalCavity(cube, s.Points.data(), s.Points.size() / 3, s.Triangles.data(),
    s.Triangles.size() / 3, o, r, error)) << error;
  ASSERT_LT(r.SurfaceTrianglesUsed, s.Triangles.size() / 3);
  ExpectValidCavity(cube, r, r.SurfaceTrianglesUsed, 4, true, "trimmed surface", false);
  // The stack stays inside the domain, clear of its boundary.
  double nearest = 1.0;
  for (std::size_t i = r.FirstStackPoint; i < r.FirstStackPoint + r.NumberOfStackPoints; ++i)
  {
    const double* x = &r.Mesh.Points[3 * i];
    nearest = std::min({ nearest, x[0], 1 - x[0], x[1], 1 - x[1], x[2], 1 - x[2] });
  }
  EXPECT_GT(nearest, 0.02) << "no stack point near the domain boundary";
}

// A second cycle's cavity through the first cycle's stack (ARLayerRelease.h):
// the stack of a cavity refill, floating in the cube, is released one layer
// and side at a time; its cells split into positive tetrahedra of the cells'
// volumes that conform with each other and with the kept tetrahedra; a
// cavity around a moved S takes the groups whole. A group with a face on the
// domain boundary or a quad shared with another cell stays locked.
TEST(PrismLayers, FloatingLayersAreReleasedAsConformingTetrahedra)
{
  const ar::TetMesh cube = KuhnCube(12);
  const Surface s = TiltedPatch();
  ar::CavityOptions o;
  o.Layers.NumberOfLayers = 3;
  o.Layers.FirstLayerThickness = 0.01;
  ar::CavityRemesh r;
  std::string error;
  ASSERT_TRUE(ar::RemeshLocalCavity(cube, s.Points.data(), s.Points.size() / 3, s.Triangles.data(),
    s.Triangles.size() / 3, o, r, error)) << error;
  ar::LayerCells cells;
  std::vector<int> layerOf, sideOf;
  for (std::size_t c = 0; c < r.Prisms.size() / 6; ++c)
  {
    cells.Sizes.push_back(6);
    cells.Ids.insert(cells.Ids.end(), &r.Prisms[6 * c], &r.Prisms[6 * c] + 6);
    layerOf.push_back(r.PrismLayer[c]);
    sideOf.push_back(r.PrismSide[c]);
  }
  for (std::size_t c = 0; c < r.Pyramids.size() / 5; ++c)
  {
    cells.Sizes.push_back(5);
    cells.Ids.insert(cells.Ids.end(), &r.Pyramids[5 * c], &r.Pyramids[5 * c] + 5);
    layerOf.push_back(r.PyramidLayer[c]);
    sideOf.push_back(r.PyramidSide[c]);
  }
  const std::size_t n = cells.Sizes.size();
  ASSERT_GT(r.Pyramids.size(), 0u);
  const ar::LayerRelease rel =
    ar::ReleaseFloatingLayers(r.Mesh.Points.data(), r.Mesh.Tetrahedra.data(), r.Mesh.NumberOfTetrahedra(), cells, {});
  // One group per layer and side, each of one layer and side only.
  EXPECT_EQ(rel.NumberOfGroups, 6);
  std::map<std::int64_t, std::set<std::pair<int, int>>> of;
  for (std::size_t c = 0; c < n; ++c)
  {
    ASSERT_GE(rel.Group[c], 0) << "cell " << c;
    of[rel.Group[c]].insert({ layerOf[c], sideOf[c] });
  }
  for (const auto& g : of)
    EXPECT_EQ(g.second.size(), 1u) << "group " << g.first;
  // Three tetrahedra a prism, two a pyramid, positive, of the cell's volume.
  Hybrid h = FromCavity(r);
  std::vector<double> split(n, 0.0);
  std::vector<int> count(n, 0);
  ar::TetMesh all = r.Mesh;
  for (std::size_t t = 0; t < rel.TetrahedronCell.size(); ++t)
  {
    const std::int64_t* v = &rel.Tetrahedra[4 * t];
    const double vol = ar::TetSignedVolume(&r.Mesh.Points[3 * v[0]], &r.Mesh.Points[3 * v[1]],
      &r.Mesh.Points[3 * v[2]], &r.Mesh.Points[3 * v[3]]);
    EXPECT_GT(vol, 0.0) << "tetrahedron " << t;
    split[rel.TetrahedronCell[t]] += vol;
    ++count[rel.TetrahedronCell[t]];
    all.Tetrahedra.insert(all.Tetrahedra.end(), v, v + 4);
  }
  const std::size_t nTets = r.Mesh.NumberOfTetrahedra();
  for (std::size_t c = 0; c < n; ++c)
  {
    EXPECT_EQ(count[c], cells.Sizes[c] == 6 ? 3 : 2) << "cell " << c;
    EXPECT_NEAR(split[c], CellVolume(h, h.Cells[nTets + c]), 1e-12 * CellVolume(h, h.Cells[nTets + c]))
      << "cell " << c;
  }
  // With the kept tetrahedra: a conforming tetrahedral mesh of the cube.
  ExpectValidCells(FromTets(all), "released stack");
  EXPECT_EQ(TetBoundary(all), TetBoundary(cube));
  EXPECT_NEAR(TetVolume(all), 1.0, 1e-12);

  // A cavity around a quarter of S, moved along its normal, reaches part of
  // every group and takes each whole.
  ar::CavityOptions o2 = o;
  o2.CellGroups.assign(nTets, -1);
  for (std::size_t t = 0; t < rel.TetrahedronCell.size(); ++t)
    o2.CellGroups.push_back(rel.Group[rel.TetrahedronCell[t]]);
  Surface moved = Grid(5, 5, 0.25, 0.5, 0.25, 0.5, [](double u, double v) {
    return std::array<double, 3>{ u, v, 0.5 + 0.2 * (u - 0.5) - 0.1 * (v - 0.5) };
  });
  for (std::size_t i = 0; i < moved.Points.size() / 3; ++i)
    for (int k = 0; k < 3; ++k)
      moved.Points[3 * i + k] += 0.012 * TiltedNormal[k];
  ar::CavityRemesh r2;
  ASSERT_TRUE(ar::RemeshLocalCavity(all, moved.Points.data(), moved.Points.size() / 3, moved.Triangles.data(),
    moved.Triangles.size() / 3, o2, r2, error)) << error;
  std::vector<int> keptOf(static_cast<std::size_t>(rel.NumberOfGroups), 0);
  for (const std::int64_t src : r2.SourceCell)
    if (src >= 0 && o2.CellGroups[src] >= 0)
      ++keptOf[o2.CellGroups[src]];
  for (std::int64_t g = 0; g < rel.NumberOfGroups; ++g)
    EXPECT_EQ(keptOf[g], 0) << "group " << g << ": the cavity around the moved S took it whole";
  ExpectValidCavity(all, r2, r2.SurfaceTrianglesUsed, 3, true, "moved S through the released stack");

  // Locked: without the tetrahedra every group is on the boundary; a quad of
  // another cell (here one pyramid's) locks that pyramid's group only.
  const ar::LayerRelease bare = ar::ReleaseFloatingLayers(r.Mesh.Points.data(), nullptr, 0, cells, {});
  EXPECT_EQ(bare.NumberOfGroups, 0);
  EXPECT_TRUE(bare.Tetrahedra.empty());
  const std::int64_t* q = &r.Pyramids[0];
  const ar::LayerRelease hex = ar::ReleaseFloatingLayers(r.Mesh.Points.data(), r.Mesh.Tetrahedra.data(), nTets,
    cells, { 4, q[0], q[1], q[2], q[3] });
  EXPECT_EQ(hex.NumberOfGroups, 5);
  for (std::size_t c = 0; c < n; ++c)
    EXPECT_EQ(hex.Group[c] < 0, rel.Group[c] == rel.Group[r.Prisms.size() / 6]) << "cell " << c;
  // Bad geometry: a prism flattened onto its bottom does not split; its group stays locked.
  std::vector<double> flat = r.Mesh.Points;
  for (int k = 3; k < 6; ++k)
    for (int d = 0; d < 3; ++d)
      flat[3 * r.Prisms[k] + d] = flat[3 * r.Prisms[k - 3] + d] + 1e-14 * (d + 1);
  const ar::LayerRelease bad = ar::ReleaseFloatingLayers(flat.data(), r.Mesh.Tetrahedra.data(), nTets, cells, {});
  EXPECT_EQ(bad.NumberOfGroups, 5);
  EXPECT_LT(bad.Group[0], 0);
}

TEST(PrismLayers, RefusesBadInput)
{
  const Surface s = TiltedPatch();
  ar::PrismStack stack;
  std::string error;
  auto refused = [&](const ar::PrismLayerOptions& o, const std::string& word) {
    EXPECT_FALSE(Build(s, o, stack, error)) << word;
    EXPECT_NE(error.find(word), std::string::npos) << error;
    EXPECT_TRUE(stack.Prisms.empty());
    // The cavity refuses the same options with the same message, before any work.
    ar::CavityOptions co;
    co.Layers = o;
    ar::CavityRemesh r;
    std::string cavityError;
    EXPECT_FALSE(ar::RemeshLocalCavity(KuhnCube(4), s.Points.data(), s.Points.size() / 3, s.Triangles.data(),
      s.Triangles.size() / 3, co, r, cavityError));
    EXPECT_NE(cavityError.find(word), std::string::npos) << cavityError;
    EXPECT_TRUE(r.Mesh.Tetrahedra.empty() && r.Prisms.empty());
  };
  ar::PrismLayerOptions o;
  o.NumberOfLayers = 3;
  o.FirstLayerThickness = 0.01;
  o.GrowthRatio = 1.2;
  ASSERT_TRUE(Build(s, o, stack, error)) << error;
  for (double bad : { 0.0, -0.01, std::nan("") })
  {
    ar::PrismLayerOptions b = o;
    b.FirstLayerThickness = bad;
    refused(b, "FirstLayerThickness");
  }
  for (double bad : { 0.0, -1.2, std::nan("") })
  {
    ar::PrismLayerOptions b = o;
    b.GrowthRatio = bad;
    refused(b, "GrowthRatio");
  }
  ar::PrismLayerOptions b = o;
  b.TotalThickness = -1.0;
  refused(b, "TotalThickness");
  b = o;
  b.NumberOfLayers = -2;
  refused(b, "NumberOfLayers");
  b = o;
  b.GapFraction = 0.8;
  refused(b, "GapFraction");
  // Surfaces prism layers cannot stand on.
  Surface threeWay = s; // an edge in three triangles
  threeWay.Points.insert(threeWay.Points.end(), { 0.5, 0.3, 0.9 });
  threeWay.Triangles.insert(threeWay.Triangles.end(), { 0, 1, static_cast<std::int64_t>(threeWay.Points.size() / 3 - 1) });
  EXPECT_FALSE(Build(threeWay, o, stack, error));
  EXPECT_NE(error.find("manifold"), std::string::npos) << error;
  Surface bowtie; // two triangles sharing one point only
  bowtie.Points = { 0.4, 0.4, 0.5, 0.5, 0.4, 0.5, 0.5, 0.5, 0.5, 0.6, 0.5, 0.5, 0.6, 0.6, 0.5 };
  bowtie.Triangles = { 0, 1, 2, 2, 3, 4 };
  EXPECT_FALSE(Build(bowtie, o, stack, error));
  EXPECT_NE(error.find("pinched"), std::string::npos) << error;
  Surface outside = s; // S crossing an obstacle (the box's top)
  for (std::size_t i = 2; i < outside.Points.size(); i += 3)
    outside.Points[i] += 0.45;
  EXPECT_FALSE(Build(outside, o, stack, error));
  EXPECT_NE(error.find("obstacle"), std::string::npos) << error;
}

TEST(PrismLayers, EachSideOfATallEnoughStackGetsItsOwnClosure)
{
  // The closure tetrahedra at S's border points are as thin as their layer
  // over their distance to the apices; with one group of apices at S's level
  // for both sides, the outer layers are a whole side's stack from them, with
  // a group per side at most half of one. Five layers on each side of the
  // tilted plane (border edges 0.051, the stack 0.025 per side at the border)
  // and of the cone sector (edges about 0.04): the closure tetrahedra were
  // 6.05 and 4.76 degrees with one group, 8.35 and 6.71 with one per side
  // and the apices half a border edge out, 14.0 and 11.2 with the apices
  // half the group's height out and the wedges' arcs no farther (their bound
  // is about 1/N radians for N layers in a group). The same plane cut to an
  // L: where its border turns inward the two fans' apices are far from the
  // notch's column, 9.4 degrees, 13.7 with a wedge point on the bisector.
  // Layers growing by 1.2 away from S: with the apices at the group's middle
  // its thinnest layers, next to S, are the farthest from them (8.8
  // degrees); the apices stand nearer the thin end.
  // Eight layers on 0.06 on the cone (tapered to half a border edge at the
  // border: one group per side; closure 6.5 degrees): TetGen's tetrahedra
  // against the band of triangles between the two sides' rows of apices,
  // whose quads must fold convexly seen from the void (folded the other way,
  // a band left TetGen the flat tetrahedron of four apices, 2.4 degrees on a
  // validation cone; that case, where the fold decides, is
  // TestValidationCase's THIN_STACKS: here both folds pass), and against
  // the cone's inner cap, a bowl seen from the void: without the free
  // points off the caps (CavityOptions::OffsetPointSpacing) TetGen left
  // slivers of four cap points there (3.9 degrees).
  const ar::TetMesh cube = KuhnCube(12);
  struct Case
  {
    const char* Label;
    Surface S;
    int Layers;
    double Total, Closure, Growth = 1.0;
  };
  for (const Case& c : { Case{ "plane", TiltedPatch(), 5, 0.025, 10.0 },
         Case{ "plane, growth 1.2", TiltedPatch(), 5, 0.025, 10.0, 1.2 }, Case{ "L", TiltedL(), 5, 0.025, 10.0 },
         Case{ "cone", ConeSector(), 5, 0.025, 10.0 }, Case{ "cone, 8 layers", ConeSector(), 8, 0.06, 6.0 } })
  {
    ar::CavityOptions o;
    o.Layers.NumberOfLayers = c.Layers;
    o.Layers.TotalThickness = c.Total;
    o.Layers.GrowthRatio = c.Growth;
    ar::CavityRemesh r;
    std::string error;
    ASSERT_TRUE(ar::RemeshLocalCavity(cube, c.S.Points.data(), c.S.Points.size() / 3, c.S.Triangles.data(),
      c.S.Triangles.size() / 3, o, r, error)) << c.Label << ": " << error;
    ExpectValidCavity(cube, r, r.SurfaceTrianglesUsed, c.Layers, true, c.Label);
    const auto worst = ClosureAndRefillAngles(r);
    std::printf("%s: closure tetrahedra >= %.2f deg, TetGen's >= %.2f\n", c.Label, worst[0], worst[1]);
    EXPECT_GE(worst[0], c.Closure) << c.Label;
    EXPECT_GE(ClosureGroups(r), 2.0) << c.Label;
    EXPECT_GE(worst[1], 10.0) << c.Label;
  }
  // A side lower than a quarter of its border edges keeps one group for
  // both: the band between two rows of apices would be a row of needles.
  ar::CavityOptions o;
  o.Layers.NumberOfLayers = 5;
  o.Layers.TotalThickness = 0.01;
  const Surface s = TiltedPatch();
  ar::CavityRemesh r;
  std::string error;
  ASSERT_TRUE(ar::RemeshLocalCavity(cube, s.Points.data(), s.Points.size() / 3, s.Triangles.data(),
    s.Triangles.size() / 3, o, r, error)) << error;
  ExpectValidCavity(cube, r, r.SurfaceTrianglesUsed, 5, true, "low stack");
  EXPECT_GE(ClosureAndRefillAngles(r)[1], 10.0);
  EXPECT_EQ(ClosureGroups(r), 1.0);
}
