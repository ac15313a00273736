// Unit tests of ar::ComputeMedialSheet on closed surfaces whose medial axis is
// known exactly: a slab (its mid-plane), a thick spherical shell (its
// mid-sphere), a capped cylinder (its axis), plus every refused input.
#include "ARMedialAxis.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <map>

namespace
{
struct Surface
{
  std::vector<double> Points;
  std::vector<double> Normals;
  std::vector<std::int64_t> Triangles;
  double MaxEdge = 0.0;

  std::size_t NumberOfPoints() const { return Points.size() / 3; }
  std::size_t NumberOfTriangles() const { return Triangles.size() / 3; }

  /// Appends another surface (the points are not shared).
  void Append(const Surface& s)
  {
    const auto offset = static_cast<std::int64_t>(NumberOfPoints());
    Points.insert(Points.end(), s.Points.begin(), s.Points.end());
    Normals.insert(Normals.end(), s.Normals.begin(), s.Normals.end());
    for (std::int64_t id : s.Triangles)
      Triangles.push_back(id + offset);
    MaxEdge = std::max(MaxEdge, s.MaxEdge);
  }
};

/// The surface of the lattice box [0,n]^3 mapped through `map` (from
/// [-1,1]^3), triangulated with outward orientation; point normals are the
/// area-weighted triangle normals.
Surface MappedBoxSurface(std::array<int, 3> n,
  const std::function<std::array<double, 3>(double, double, double)>& map, bool flip = false)
{
  Surface s;
  std::map<std::array<int, 3>, std::int64_t> ids;
  auto id = [&](std::array<int, 3> ijk) {
    auto it = ids.find(ijk);
    if (it != ids.end())
      return it->second;
    const auto p = map(2.0 * ijk[0] / n[0] - 1.0, 2.0 * ijk[1] / n[1] - 1.0, 2.0 * ijk[2] / n[2] - 1.0);
    const auto newId = static_cast<std::int64_t>(s.Points.size() / 3);
    s.Points.insert(s.Points.end(), p.begin(), p.end());
    ids[ijk] = newId;
    return newId;
  };
  for (int a = 0; a < 3; ++a)
  {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int side = 0; side < 2; ++side)
    {
      for (int i = 0; i < n[b]; ++i)
        for (int j = 0; j < n[c]; ++j)
        {
          std::array<std::array<int, 3>, 4> q;
          const int di[4] = { 0, 1, 1, 0 }, dj[4] = { 0, 0, 1, 1 };
          for (int k = 0; k < 4; ++k)
          {
            q[k][a] = side ? n[a] : 0;
            q[k][b] = i + di[k];
            q[k][c] = j + dj[k];
          }
          std::int64_t v[4];
          for (int k = 0; k < 4; ++k)
            v[k] = id(q[k]);
          // e_b x e_c = e_a: counter-clockwise seen from outside on the + side.
          const bool outward = (side == 1) != flip;
          if (outward)
            s.Triangles.insert(s.Triangles.end(), { v[0], v[1], v[2], v[0], v[2], v[3] });
          else
            s.Triangles.insert(s.Triangles.end(), { v[0], v[2], v[1], v[0], v[3], v[2] });
        }
    }
  }
  s.Normals.assign(s.Points.size(), 0.0);
  for (std::size_t t = 0; t < s.NumberOfTriangles(); ++t)
  {
    const double* p[3];
    for (int k = 0; k < 3; ++k)
      p[k] = &s.Points[3 * s.Triangles[3 * t + k]];
    const double u[3] = { p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2] };
    const double w[3] = { p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2] };
    const double nrm[3] = { u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0] };
    for (int k = 0; k < 3; ++k)
    {
      for (int d = 0; d < 3; ++d)
        s.Normals[3 * s.Triangles[3 * t + k] + d] += nrm[d];
      const double* e0 = p[k];
      const double* e1 = p[(k + 1) % 3];
      s.MaxEdge = std::max(s.MaxEdge,
        std::sqrt((e0[0] - e1[0]) * (e0[0] - e1[0]) + (e0[1] - e1[1]) * (e0[1] - e1[1]) +
          (e0[2] - e1[2]) * (e0[2] - e1[2])));
    }
  }
  for (std::size_t i = 0; i < s.NumberOfPoints(); ++i)
  {
    double* nrm = &s.Normals[3 * i];
    const double l = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
    for (int d = 0; d < 3; ++d)
      nrm[d] /= l;
  }
  return s;
}

ar::MedialSheet Medial(const Surface& s, const ar::MedialAxisOptions& options = {},
  const ar::ClosedSurface* domain = nullptr)
{
  ar::MedialSheet sheet;
  std::string error;
  EXPECT_TRUE(ar::ComputeMedialSheet(s.Points.data(), s.NumberOfPoints(), s.Normals.data(),
    s.Triangles.data(), s.NumberOfTriangles(), options, domain, sheet, error))
    << error;
  return sheet;
}

std::string Refusal(const Surface& s, const ar::ClosedSurface* domain = nullptr,
  const ar::MedialAxisOptions& options = {})
{
  ar::MedialSheet sheet;
  std::string error;
  EXPECT_FALSE(ar::ComputeMedialSheet(s.Points.data(), s.NumberOfPoints(), s.Normals.data(),
    s.Triangles.data(), s.NumberOfTriangles(), options, domain, sheet, error));
  EXPECT_TRUE(sheet.Triangles.empty());
  return error;
}

double SheetArea(const ar::MedialSheet& m, const std::function<bool(const double*)>& where)
{
  double area = 0.0;
  for (std::size_t t = 0; t < m.Triangles.size() / 3; ++t)
  {
    const double* a = &m.Points[3 * m.Triangles[3 * t]];
    const double* b = &m.Points[3 * m.Triangles[3 * t + 1]];
    const double* c = &m.Points[3 * m.Triangles[3 * t + 2]];
    const double g[3] = { (a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3 };
    if (!where(g))
      continue;
    const double u[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
    const double w[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
    const double n[3] = { u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0] };
    area += 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  }
  return area;
}

// Slab [-4,4]^2 x [-0.5,0.5], edge length 0.25 on the large faces.
Surface Slab()
{
  return MappedBoxSurface({ 32, 32, 4 }, [](double u, double v, double w) {
    return std::array<double, 3>{ 4.0 * u, 4.0 * v, 0.5 * w };
  });
}
}

TEST(MedialAxis, SlabGivesItsMidPlane)
{
  const Surface slab = Slab();
  const ar::MedialSheet m = Medial(slab);
  ASSERT_FALSE(m.Triangles.empty());
  const double e = slab.MaxEdge;
  // Away from the rim (where the medial axis of a box branches to its edges),
  // every sheet point is on the mid-plane within one surface edge length, and
  // the radius is the half thickness.
  for (std::size_t i = 0; i < m.Radius.size(); ++i)
  {
    const double* x = &m.Points[3 * i];
    if (std::abs(x[0]) < 3.0 && std::abs(x[1]) < 3.0)
    {
      EXPECT_LE(std::abs(x[2]), e) << "point " << i;
      EXPECT_NEAR(m.Radius[i], 0.5, e) << "point " << i;
    }
  }
  // The mid-plane is covered: the area of the sheet inside |x|,|y| < 3 is the
  // 6 x 6 square (fan triangles are flat on z = 0 there).
  const double inner = SheetArea(m, [](const double* g) { return std::abs(g[0]) < 3.0 && std::abs(g[1]) < 3.0; });
  EXPECT_NEAR(inner, 36.0, 0.05 * 36.0);
  EXPECT_EQ(m.SheetAreas.size(), 1u);
}

TEST(MedialAxis, SphericalShellGivesItsMidSphere)
{
  // Shell between r = 2 and r = 3: the outer sphere with outward normals, the
  // inner one with normals pointing to the centre (out of the shell region).
  auto sphere = [](double r) {
    return [r](double u, double v, double w) {
      const double l = std::sqrt(u * u + v * v + w * w);
      return std::array<double, 3>{ r * u / l, r * v / l, r * w / l };
    };
  };
  Surface shell = MappedBoxSurface({ 16, 16, 16 }, sphere(3.0));
  shell.Append(MappedBoxSurface({ 12, 12, 12 }, sphere(2.0), /*flip=*/true));
  for (std::size_t i = 0; i < shell.NumberOfPoints(); ++i)
  {
    // The set-up itself: normals point out of the shell region.
    const double* x = &shell.Points[3 * i];
    const double* n = &shell.Normals[3 * i];
    const double radial = (n[0] * x[0] + n[1] * x[1] + n[2] * x[2]) / std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    ASSERT_GT(std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) > 2.5 ? radial : -radial, 0.9);
  }
  const ar::MedialSheet m = Medial(shell);
  ASSERT_FALSE(m.Triangles.empty());
  const double e = shell.MaxEdge;
  for (std::size_t i = 0; i < m.Radius.size(); ++i)
  {
    const double* x = &m.Points[3 * i];
    const double r = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    EXPECT_NEAR(r, 2.5, e) << "point " << i;
    EXPECT_NEAR(m.Radius[i], 0.5, e) << "point " << i;
  }
  const double area = SheetArea(m, [](const double*) { return true; });
  EXPECT_NEAR(area, 4.0 * M_PI * 2.5 * 2.5, 0.1 * 4.0 * M_PI * 2.5 * 2.5);
  EXPECT_EQ(m.SheetAreas.size(), 1u);
}

TEST(MedialAxis, CylinderGivesItsAxis)
{
  // Capped cylinder of radius 1 and length 8 along z: the square section is
  // mapped to the disk (elliptical grid mapping).
  // The points are jittered along the surface: with exactly circular rings
  // every two neighbouring rings are cospherical, the Voronoi vertices fall
  // on the axis and the medial axis degenerates to a curve with no facets.
  const Surface cyl = MappedBoxSurface({ 8, 8, 32 }, [](double u, double v, double w) {
    const double t = std::atan2(v * std::sqrt(1.0 - 0.5 * u * u), u * std::sqrt(1.0 - 0.5 * v * v));
    const double r = std::hypot(u * std::sqrt(1.0 - 0.5 * v * v), v * std::sqrt(1.0 - 0.5 * u * u));
    const double jt = 0.05 * std::sin(12.9898 * u + 78.233 * v + 37.719 * w);
    const double jz = std::abs(w) < 1.0 ? 0.05 * std::cos(93.989 * u + 67.345 * v + 11.135 * w) : 0.0;
    return std::array<double, 3>{ r * std::cos(t + jt), r * std::sin(t + jt), 4.0 * w + jz };
  });
  // A tube's medial axis is a curve: the Voronoi facets around it are thin
  // slivers in many small pieces, so the sheet filter by area is switched off.
  ar::MedialAxisOptions o;
  o.MinimumAreaFraction = 0.0;
  const ar::MedialSheet m = Medial(cyl, o);
  ASSERT_FALSE(m.Triangles.empty());
  const double e = cyl.MaxEdge;
  std::size_t alongAxis = 0;
  double zmin = 1e9, zmax = -1e9;
  for (std::size_t i = 0; i < m.Radius.size(); ++i)
  {
    const double* x = &m.Points[3 * i];
    if (std::abs(x[2]) < 3.0)
    {
      EXPECT_LE(std::hypot(x[0], x[1]), e) << "point " << i;
      EXPECT_NEAR(m.Radius[i], 1.0, e) << "point " << i;
      ++alongAxis;
      zmin = std::min(zmin, x[2]);
      zmax = std::max(zmax, x[2]);
    }
  }
  // The sheet follows the whole axis, not a piece of it.
  EXPECT_GT(alongAxis, 10u);
  EXPECT_LT(zmin, -3.0 + e);
  EXPECT_GT(zmax, 3.0 - e);
}

TEST(MedialAxis, DomainClipsTheSheet)
{
  // A domain box that ends at x = 2: no medial point beyond it.
  const Surface box = MappedBoxSurface({ 2, 2, 2 }, [](double u, double v, double w) {
    return std::array<double, 3>{ -5.0 + 3.5 * (u + 1.0), 5.0 * v, 5.0 * w };
  });
  ar::ClosedSurface domain{ box.Points, box.Triangles };
  const ar::MedialSheet m = Medial(Slab(), {}, &domain);
  ASSERT_FALSE(m.Triangles.empty());
  double xmax = -1e9;
  for (std::size_t i = 0; i < m.Radius.size(); ++i)
    xmax = std::max(xmax, m.Points[3 * i]);
  EXPECT_LE(xmax, 2.0);
  EXPECT_GT(xmax, 2.0 - Slab().MaxEdge);
}

TEST(MedialAxis, PruningOptionsAct)
{
  const Surface slab = Slab();
  ar::MedialAxisOptions strict;
  strict.MinimumRadiusFactor = 10.0; // every pole (r = 0.5, edges 0.25) is too small
  ar::MedialSheet m = Medial(slab, strict);
  EXPECT_TRUE(m.Triangles.empty());
  ar::MedialAxisOptions loose;
  loose.MinimumObjectAngle = 0.0; // keeps the spikes to the rim as well
  const ar::MedialSheet all = Medial(slab, loose);
  const ar::MedialSheet pruned = Medial(slab);
  EXPECT_GT(all.NumberOfFacets, pruned.NumberOfFacets);
}

TEST(MedialAxis, RefusesBadInput)
{
  Surface empty;
  EXPECT_NE(Refusal(empty).find("at least 4"), std::string::npos);

  Surface noTriangles = Slab();
  noTriangles.Triangles.clear();
  EXPECT_NE(Refusal(noTriangles).find("no triangles"), std::string::npos);

  Surface nan = Slab();
  nan.Points[7] = std::nan("");
  EXPECT_NE(Refusal(nan).find("non-finite"), std::string::npos);

  Surface coincident = Slab();
  coincident.Points.insert(coincident.Points.end(), coincident.Points.begin(), coincident.Points.begin() + 3);
  coincident.Normals.insert(coincident.Normals.end(), coincident.Normals.begin(), coincident.Normals.begin() + 3);
  EXPECT_NE(Refusal(coincident).find("coincide"), std::string::npos);

  // A flat triangulated grid: no volume, no medial axis.
  Surface plane;
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 4; ++j)
    {
      plane.Points.insert(plane.Points.end(), { double(i), double(j), 0.0 });
      plane.Normals.insert(plane.Normals.end(), { 0.0, 0.0, 1.0 });
    }
  plane.Triangles = { 0, 1, 6 };
  EXPECT_NE(Refusal(plane).find("coplanar"), std::string::npos);

  Surface badIndex = Slab();
  badIndex.Triangles[4] = 1000000;
  EXPECT_NE(Refusal(badIndex).find("does not exist"), std::string::npos);

  ar::ClosedSurface open{ { 0, 0, 0, 1, 0, 0, 0, 1, 0 }, { 0, 1, 2 } };
  EXPECT_NE(Refusal(Slab(), &open).find("not closed"), std::string::npos);

  // Options out of range: refused by name (they were clamped).
  ar::MedialAxisOptions wide;
  wide.MinimumObjectAngle = 200.0;
  EXPECT_NE(Refusal(Slab(), nullptr, wide).find("MinimumObjectAngle is 200"), std::string::npos);
  ar::MedialAxisOptions negative;
  negative.MinimumRadiusFactor = -1.0;
  EXPECT_NE(Refusal(Slab(), nullptr, negative).find("MinimumRadiusFactor is -1"), std::string::npos);
}

namespace
{
/// The slab's surface without the triangles on the planes y = y0 and (if
/// `twoPlanes`) y = y1: open where a symmetry plane cuts the domain.
Surface OpenSlab(double y0, double y1, int ny, bool twoPlanes)
{
  Surface s = MappedBoxSurface({ 32, ny, 4 }, [=](double u, double v, double w) {
    return std::array<double, 3>{ 4.0 * u, y0 + 0.5 * (v + 1.0) * (y1 - y0), 0.5 * w };
  });
  std::vector<std::int64_t> kept;
  for (std::size_t t = 0; t < s.NumberOfTriangles(); ++t)
  {
    bool onPlane0 = true, onPlane1 = true;
    for (int k = 0; k < 3; ++k)
    {
      const double y = s.Points[3 * s.Triangles[3 * t + k] + 1];
      onPlane0 = onPlane0 && y == y0;
      onPlane1 = onPlane1 && y == y1;
    }
    if (!onPlane0 && !(twoPlanes && onPlane1))
      kept.insert(kept.end(), s.Triangles.begin() + 3 * t, s.Triangles.begin() + 3 * t + 3);
  }
  // Drop the points that only the removed triangles used (the inside of the
  // open faces): they would close the region again.
  std::vector<std::int64_t> newId(s.NumberOfPoints(), -1);
  Surface open;
  open.MaxEdge = s.MaxEdge;
  for (std::int64_t& id : kept)
  {
    if (newId[id] < 0)
    {
      newId[id] = static_cast<std::int64_t>(open.NumberOfPoints());
      open.Points.insert(open.Points.end(), s.Points.begin() + 3 * id, s.Points.begin() + 3 * id + 3);
      open.Normals.insert(open.Normals.end(), s.Normals.begin() + 3 * id, s.Normals.begin() + 3 * id + 3);
    }
    open.Triangles.push_back(newId[id]);
  }
  return open;
}
}

TEST(MedialAxis, SymmetryPlaneMakesTheSheetMeetItOrthogonally)
{
  // Half a slab, y in [0, 4], open at the symmetry plane y = 0. Mirrored, the
  // union is the whole slab: its sheet is z = 0 right up to (and across) y = 0.
  const Surface half = OpenSlab(0.0, 4.0, 16, false);
  ar::MedialAxisOptions o;
  o.SymmetryPlanes = { 0.0, 0.0, 0.0, 0.0, -3.0, 0.0 }; // normal sense and length do not matter
  const ar::MedialSheet m = Medial(half, o);
  EXPECT_EQ(m.NumberOfMirrorCopies, 1u);
  ASSERT_FALSE(m.Triangles.empty());
  const double e = half.MaxEdge;
  double ymin = 1e9;
  for (std::size_t i = 0; i < m.Radius.size(); ++i)
  {
    const double* x = &m.Points[3 * i];
    if (std::abs(x[0]) < 3.0 && x[1] > -3.0 && x[1] < 3.0)
    {
      EXPECT_LE(std::abs(x[2]), e) << "point " << i;
      if (x[1] >= 0.0)
        ymin = std::min(ymin, x[1]);
    }
  }
  EXPECT_LE(ymin, e); // reaches the plane
  // Symmetric: the sheet's area on the mirrored side is the original side's
  // (not to round-off: CGAL resolves the cospherical points of the lattice
  // differently on the two sides).
  const double plus = SheetArea(m, [](const double* g) { return std::abs(g[0]) < 3.0 && g[1] > 0.0 && g[1] < 3.0; });
  const double minus = SheetArea(m, [](const double* g) { return std::abs(g[0]) < 3.0 && g[1] < 0.0 && g[1] > -3.0; });
  EXPECT_NEAR(plus, 18.0, 0.05 * 18.0);
  EXPECT_NEAR(minus, plus, 0.05 * plus);
}

TEST(MedialAxis, TwoParallelSymmetryPlanesLikeATwoDimensionalMesh)
{
  // A slab one "cell" deep in y (as an OpenFOAM 2-D case is), open at both
  // y = 0 and y = 0.25: without symmetry planes every surface point is on the
  // convex hull and no Voronoi facet is interior; with them the copies stack
  // up and the sheet is z = 0 across the whole depth.
  const Surface thin = OpenSlab(0.0, 0.25, 1, true);
  EXPECT_TRUE(Medial(thin).Triangles.empty());
  ar::MedialAxisOptions o;
  o.SymmetryPlanes = { 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.25, 0.0, 0.0, 1.0, 0.0 };
  const ar::MedialSheet m = Medial(thin, o);
  EXPECT_EQ(m.NumberOfMirrorCopies, 8u);
  ASSERT_FALSE(m.Triangles.empty());
  for (std::size_t i = 0; i < m.Radius.size(); ++i)
  {
    const double* x = &m.Points[3 * i];
    if (std::abs(x[0]) < 3.0)
      EXPECT_LE(std::abs(x[2]), thin.MaxEdge) << "point " << i;
  }
  const double inside = SheetArea(m, [](const double* g) { return std::abs(g[0]) < 3.0 && g[1] > 0.0 && g[1] < 0.25; });
  EXPECT_NEAR(inside, 6.0 * 0.25, 0.05 * 6.0 * 0.25);
}
