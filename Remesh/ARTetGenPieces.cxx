// SPDX-License-Identifier: BSD-3-Clause
#include "ARTetGenPieces.h"
#include "ARHugePages.h"

#include "ARUnionFind.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <numeric>
#include <system_error>
#include <thread>
#include <utility>

namespace ar
{
namespace
{
constexpr double Pi = 3.14159265358979323846;

/// The split's state: the complex, the sides (2 t the front of triangle t,
/// 2 t + 1 its back) joined into sets, and per set whether it faces the
/// volume to mesh.
class Splitter
{
public:
  Splitter(const PiecewiseLinearComplex& plc_, const std::vector<std::uint8_t>& meshed_)
    : plc(plc_)
    , meshed(meshed_)
    , nTri(plc_.Triangles.size() / 3)
    , sides(2 * nTri)
  {
  }

  /// The pieces (none: one piece or ambiguous).
  std::size_t Run(std::vector<ComplexPiece>& pieces);

private:
  bool JoinSides();
  bool LabelSets();
  bool AssignFloatingSets();
  bool BuildPieces(std::vector<ComplexPiece>& pieces);

  const double* X(std::int64_t id) const { return &plc.Points[3 * id]; }
  /// The centroid of the side's triangle moved off it to that side by 1e-4
  /// of the triangle's size.
  std::array<double, 3> OffTriangle(std::size_t side) const
  {
    const std::int64_t* v = &plc.Triangles[3 * (side / 2)];
    const double *a = X(v[0]), *b = X(v[1]), *c = X(v[2]);
    const double u[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
    const double w[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
    const double n[3] = { u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0] };
    const double twiceArea = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const double offset = (side % 2 == 0 ? 1e-4 : -1e-4) / std::sqrt(twiceArea);
    return { (a[0] + b[0] + c[0]) / 3.0 + offset * n[0], (a[1] + b[1] + c[1]) / 3.0 + offset * n[1],
      (a[2] + b[2] + c[2]) / 3.0 + offset * n[2] };
  }
  bool Meshed(std::size_t side) const
  {
    return (meshed[side / 2] & (side % 2 == 0 ? MeshedFront : MeshedBack)) != 0;
  }
  /// +1 when `side` (in a set bounding a region) has the region behind the
  /// triangle's normal, -1 in front: the sign that orients the triangle
  /// outward from that region.
  static double Outward(std::size_t side) { return side % 2 == 0 ? -1.0 : 1.0; }

  const PiecewiseLinearComplex& plc;
  const std::vector<std::uint8_t>& meshed;
  const std::size_t nTri;
  UnionFind sides;
  std::vector<std::int64_t> root;   // per side: its set
  std::vector<double> volume;       // per set (meshed ones): the volume it encloses, signed
  std::vector<std::int64_t> pieceOf; // per set (meshed ones): its piece, -1 none yet
  std::vector<std::int64_t> outer;  // the sets enclosing positive volume: one per piece
  std::vector<std::int64_t> floating;    // the other meshed sets
  std::vector<std::size_t> floatingSide; // per floating set: its first side
};

// Around every edge, each side joins the facing side of its angular neighbour.
bool Splitter::JoinSides()
{
  const std::int64_t* T = plc.Triangles.data();
  std::vector<std::array<std::int64_t, 5>> edges; // lower id, higher id, triangle, runs lower -> higher, third vertex
  edges.reserve(3 * nTri);
  for (std::size_t t = 0; t < nTri; ++t)
  {
    const std::int64_t* v = T + 3 * t;
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2])
    {
      return false;
    }
    for (int k = 0; k < 3; ++k)
    {
      const std::int64_t p = v[k], q = v[(k + 1) % 3];
      edges.push_back({ std::min(p, q), std::max(p, q), static_cast<std::int64_t>(t), p < q ? 1 : 0, v[(k + 2) % 3] });
    }
  }
  std::sort(edges.begin(), edges.end());
  // The side of a triangle facing increasing angle about the edge (lower ->
  // higher, right hand): its front when it runs lower -> higher.
  auto ahead = [&](std::size_t i) { return 2 * edges[i][2] + (edges[i][3] ? 0 : 1); };
  auto behind = [&](std::size_t i) { return 2 * edges[i][2] + (edges[i][3] ? 1 : 0); };
  std::vector<std::pair<double, std::size_t>> around;
  for (std::size_t e = 0, next = 0; e < edges.size(); e = next)
  {
    for (next = e + 1; next < edges.size() && edges[next][0] == edges[e][0] && edges[next][1] == edges[e][1]; ++next)
    {
    }
    const std::size_t m = next - e;
    if (m <= 2)
    {
      // One triangle (a free border): its two sides meet around the edge.
      // Two: whatever their angles, each side faces the other's.
      sides.Union(ahead(e), behind(next - 1));
      sides.Union(ahead(next - 1), behind(e));
      continue;
    }
    const double* a = X(edges[e][0]);
    const double* b = X(edges[e][1]);
    double axis[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
    const double length = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    if (!(length > 0.0))
    {
      return false;
    }
    for (double& x : axis)
    {
      x /= length;
    }
    double u[3] = { 0.0, 0.0, 0.0 }, w[3] = { 0.0, 0.0, 0.0 };
    around.clear();
    for (std::size_t i = e; i < next; ++i)
    {
      const double* c = X(edges[i][4]);
      double r[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
      const double along = r[0] * axis[0] + r[1] * axis[1] + r[2] * axis[2];
      const double full = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
      for (int d = 0; d < 3; ++d)
      {
        r[d] -= along * axis[d];
      }
      const double off = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
      if (!(off > 1e-9 * full))
      {
        return false; // a needle: no reliable angle
      }
      if (i == e)
      {
        for (int d = 0; d < 3; ++d)
        {
          u[d] = r[d] / off;
        }
        w[0] = axis[1] * u[2] - axis[2] * u[1];
        w[1] = axis[2] * u[0] - axis[0] * u[2];
        w[2] = axis[0] * u[1] - axis[1] * u[0];
      }
      around.emplace_back(std::atan2(r[0] * w[0] + r[1] * w[1] + r[2] * w[2], r[0] * u[0] + r[1] * u[1] + r[2] * u[2]), i);
    }
    std::sort(around.begin(), around.end());
    for (std::size_t j = 0; j < m; ++j)
    {
      const std::size_t k = (j + 1) % m;
      const double gap = around[k].first - around[j].first + (k == 0 ? 2.0 * Pi : 0.0);
      if (!(gap > 1e-9))
      {
        return false; // coincident half-planes
      }
      sides.Union(ahead(around[j].second), behind(around[k].second));
    }
  }
  return true;
}

// Each set faces the volume to mesh on all its sides or on none; the ones
// that do get the volume they enclose.
bool Splitter::LabelSets()
{
  root.resize(2 * nTri);
  std::vector<char> state(2 * nTri, 0); // per set: 1 meshed, 2 not
  for (std::size_t s = 0; s < 2 * nTri; ++s)
  {
    root[s] = sides.Find(static_cast<std::int64_t>(s));
    const char flag = Meshed(s) ? 1 : 2;
    if (state[root[s]] != 0 && state[root[s]] != flag)
    {
      return false;
    }
    state[root[s]] = flag;
  }
  // Volumes from the centre of the complex's box (smaller round-off); a
  // triangle with both sides in one set adds nothing.
  double lo[3], hi[3];
  for (int d = 0; d < 3; ++d)
  {
    lo[d] = hi[d] = plc.Points[d];
  }
  for (std::size_t i = 0; i < plc.Points.size(); ++i)
  {
    lo[i % 3] = std::min(lo[i % 3], plc.Points[i]);
    hi[i % 3] = std::max(hi[i % 3], plc.Points[i]);
  }
  const double o[3] = { 0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2]) };
  volume.assign(2 * nTri, 0.0);
  std::vector<double> scale(2 * nTri, 0.0);
  for (std::size_t t = 0; t < nTri; ++t)
  {
    if (root[2 * t] == root[2 * t + 1])
    {
      continue;
    }
    double p[3][3];
    for (int k = 0; k < 3; ++k)
    {
      for (int d = 0; d < 3; ++d)
      {
        p[k][d] = X(plc.Triangles[3 * t + k])[d] - o[d];
      }
    }
    const double det = p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) -
      p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) + p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0]);
    for (std::size_t s : { 2 * t, 2 * t + 1 })
    {
      if (state[root[s]] == 1)
      {
        volume[root[s]] += Outward(s) * det / 6.0;
        scale[root[s]] += std::abs(det) / 6.0;
      }
    }
  }
  pieceOf.assign(2 * nTri, -1);
  for (std::size_t s = 0; s < 2 * nTri; ++s)
  {
    if (root[s] == static_cast<std::int64_t>(s) && state[s] == 1 && volume[s] > 1e-9 * scale[s])
    {
      pieceOf[s] = static_cast<std::int64_t>(outer.size());
      outer.push_back(static_cast<std::int64_t>(s));
    }
  }
  for (std::size_t s = 0; s < 2 * nTri; ++s)
  {
    if (state[root[s]] == 2)
    {
      pieceOf[root[s]] = -2; // not meshed
    }
  }
  return !outer.empty();
}

/// Signed solid angle of triangle (a, b, c) seen from x (positive from behind its normal).
double SolidAngle(const double* a, const double* b, const double* c, const double* x)
{
  const double p[3] = { a[0] - x[0], a[1] - x[1], a[2] - x[2] };
  const double q[3] = { b[0] - x[0], b[1] - x[1], b[2] - x[2] };
  const double r[3] = { c[0] - x[0], c[1] - x[1], c[2] - x[2] };
  auto dot = [](const double* u, const double* v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; };
  const double lp = std::sqrt(dot(p, p)), lq = std::sqrt(dot(q, q)), lr = std::sqrt(dot(r, r));
  const double det = p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) +
    p[2] * (q[0] * r[1] - q[1] * r[0]);
  return 2.0 * std::atan2(det, lp * lq * lr + dot(p, q) * lr + dot(p, r) * lq + dot(q, r) * lp);
}

// The floating sets (sheets, inner boundaries) join the smallest outer
// boundary around them: the one of least volume whose winding number is
// about 1 at the centroid of the set's first triangle (moved off it to the
// set's side by 1e-4 of the triangle's size).
bool Splitter::AssignFloatingSets()
{
  std::vector<std::array<double, 3>> at;
  for (std::size_t t = 0; t < nTri; ++t)
  {
    for (std::size_t s : { 2 * t, 2 * t + 1 })
    {
      const std::int64_t r = root[s];
      if (pieceOf[r] != -1)
      {
        continue;
      }
      pieceOf[r] = -3; // listed
      floating.push_back(r);
      floatingSide.push_back(s);
      // Just off the triangle on this side (the triangle may bound an outer
      // set on its other side, where the winding number would be 1/2).
      at.push_back(OffTriangle(s));
    }
  }
  if (floating.size() * nTri > 50000000u)
  {
    return false; // too many to place; mesh the whole
  }
  std::vector<double> winding(floating.size() * outer.size(), 0.0);
  for (std::size_t t = 0; t < nTri; ++t)
  {
    const std::int64_t* v = &plc.Triangles[3 * t];
    for (std::size_t s : { 2 * t, 2 * t + 1 })
    {
      const std::int64_t r = root[s];
      if (root[2 * t] == root[2 * t + 1] || pieceOf[r] < 0)
      {
        continue;
      }
      for (std::size_t f = 0; f < floating.size(); ++f)
      {
        winding[f * outer.size() + pieceOf[r]] +=
          Outward(s) * SolidAngle(X(v[0]), X(v[1]), X(v[2]), at[f].data()) / (4.0 * Pi);
      }
    }
  }
  for (std::size_t f = 0; f < floating.size(); ++f)
  {
    std::int64_t best = -1;
    for (std::size_t o = 0; o < outer.size(); ++o)
    {
      if (winding[f * outer.size() + o] > 0.5 && (best < 0 || volume[outer[o]] < volume[outer[best]]))
      {
        best = static_cast<std::int64_t>(o);
      }
    }
    if (best < 0)
    {
      return false;
    }
    pieceOf[floating[f]] = best;
  }
  return true;
}

bool Splitter::BuildPieces(std::vector<ComplexPiece>& pieces)
{
  const std::size_t n = outer.size();
  std::vector<std::vector<std::int64_t>> triangles(n);
  for (std::size_t t = 0; t < nTri; ++t)
  {
    const std::int64_t front = Meshed(2 * t) ? pieceOf[root[2 * t]] : -1;
    const std::int64_t back = Meshed(2 * t + 1) ? pieceOf[root[2 * t + 1]] : -1;
    if (front >= 0)
    {
      triangles[front].push_back(static_cast<std::int64_t>(t));
    }
    if (back >= 0 && back != front)
    {
      triangles[back].push_back(static_cast<std::int64_t>(t));
    }
  }
  // Canonical order: by the smallest triangle.
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t(0));
  for (const auto& list : triangles)
  {
    if (list.size() < 4)
    {
      return false;
    }
  }
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return triangles[a][0] < triangles[b][0]; });
  const std::size_t nPoints = plc.Points.size() / 3;
  std::vector<std::int64_t> local(nPoints, -1);
  // Points on no triangle (free points to insert) go to every piece whose
  // box holds them; TetGen leaves them unused where they lie outside.
  std::vector<char> onTriangle(nPoints, 0);
  for (std::int64_t v : plc.Triangles)
  {
    onTriangle[v] = 1;
  }
  pieces.assign(n, ComplexPiece());
  for (std::size_t p = 0; p < n; ++p)
  {
    const std::vector<std::int64_t>& list = triangles[order[p]];
    ComplexPiece& piece = pieces[p];
    for (std::int64_t t : list)
    {
      for (int k = 0; k < 3; ++k)
      {
        piece.Points.push_back(plc.Triangles[3 * t + k]);
      }
    }
    std::sort(piece.Points.begin(), piece.Points.end());
    piece.Points.erase(std::unique(piece.Points.begin(), piece.Points.end()), piece.Points.end());
    if (piece.Points.size() < 4)
    {
      return false;
    }
    PiecewiseLinearComplex& c = piece.Complex;
    double lo[3] = { X(piece.Points[0])[0], X(piece.Points[0])[1], X(piece.Points[0])[2] };
    double hi[3] = { lo[0], lo[1], lo[2] };
    for (const std::int64_t id : piece.Points)
    {
      for (int d = 0; d < 3; ++d)
      {
        lo[d] = std::min(lo[d], X(id)[d]);
        hi[d] = std::max(hi[d], X(id)[d]);
      }
    }
    auto inBox = [&](const double* x) {
      return x[0] >= lo[0] && x[0] <= hi[0] && x[1] >= lo[1] && x[1] <= hi[1] && x[2] >= lo[2] && x[2] <= hi[2];
    };
    const std::size_t onTriangles = piece.Points.size();
    for (std::size_t id = 0; id < nPoints; ++id)
    {
      if (!onTriangle[id] && inBox(X(static_cast<std::int64_t>(id))))
      {
        piece.Points.push_back(static_cast<std::int64_t>(id));
      }
    }
    std::inplace_merge(piece.Points.begin(), piece.Points.begin() + onTriangles, piece.Points.end());
    for (std::size_t k = 0; k < piece.Points.size(); ++k)
    {
      const std::int64_t id = piece.Points[k];
      local[id] = static_cast<std::int64_t>(k);
      c.Points.insert(c.Points.end(), X(id), X(id) + 3);
      if (!plc.PointSizes.empty())
      {
        c.PointSizes.push_back(plc.PointSizes[id]);
      }
    }
    for (std::int64_t t : list)
    {
      for (int k = 0; k < 3; ++k)
      {
        c.Triangles.push_back(local[plc.Triangles[3 * t + k]]);
      }
      if (!plc.TriangleMarkers.empty())
      {
        c.TriangleMarkers.push_back(plc.TriangleMarkers[t]);
      }
    }
    for (std::size_t h = 0; h < plc.Holes.size() / 3; ++h)
    {
      const double* x = &plc.Holes[3 * h];
      if (inBox(x))
      {
        c.Holes.insert(c.Holes.end(), x, x + 3);
      }
    }
    // A void of this piece that is another piece (behind a floating set of
    // this one, e.g. the inside of a closed S): a hole point just inside it,
    // behind the set's first triangle. (A void not to mesh has its own.)
    for (std::size_t f = 0; f < floating.size(); ++f)
    {
      const std::size_t behind = floatingSide[f] ^ 1u;
      if (pieceOf[floating[f]] == static_cast<std::int64_t>(order[p]) && Meshed(behind) &&
        pieceOf[root[behind]] != pieceOf[floating[f]])
      {
        const std::array<double, 3> x = OffTriangle(behind);
        c.Holes.insert(c.Holes.end(), x.begin(), x.end());
      }
    }
  }
  return true;
}

std::size_t Splitter::Run(std::vector<ComplexPiece>& pieces)
{
  pieces.clear();
  if (nTri == 0 || meshed.size() != nTri || !JoinSides() || !LabelSets() || outer.size() < 2 ||
    !AssignFloatingSets() || !BuildPieces(pieces))
  {
    pieces.clear();
    return 1;
  }
  return pieces.size();
}

/// The pieces' results as one (ARTetGenPieces.h).
void Merge(const PiecewiseLinearComplex& plc, const std::vector<ComplexPiece>& pieces,
  std::vector<TetGenResult>& results, TetGenResult& out)
{
  out = TetGenResult();
  // Every array at its final size at once (no growth by doubling).
  std::size_t nPoints = plc.Points.size() / 3, nTets = 0, nFaces = 0;
  for (std::size_t p = 0; p < pieces.size(); ++p)
  {
    nPoints += results[p].Mesh.NumberOfPoints() - std::min(results[p].Mesh.NumberOfPoints(), pieces[p].Points.size());
    nTets += results[p].Mesh.NumberOfTetrahedra();
    nFaces += results[p].FaceMarkers.size();
  }
  ReserveHuge(out.Mesh.Points, 3 * nPoints);
  out.Mesh.Points = plc.Points;
  ReserveHuge(out.Mesh.Tetrahedra, 4 * nTets);
  ReserveHuge(out.Faces, 3 * nFaces);
  out.FaceMarkers.reserve(nFaces);
  std::vector<std::array<std::int64_t, 4>> faces; // sorted ids, then the order found
  faces.reserve(nFaces);
  for (std::size_t p = 0; p < pieces.size(); ++p)
  {
    TetGenResult& r = results[p];
    const std::size_t nIn = pieces[p].Points.size();
    std::vector<std::int64_t> global(r.Mesh.NumberOfPoints());
    for (std::size_t k = 0; k < global.size(); ++k)
    {
      if (k < nIn)
      {
        global[k] = pieces[p].Points[k];
        continue;
      }
      global[k] = static_cast<std::int64_t>(out.Mesh.Points.size() / 3);
      out.Mesh.Points.insert(out.Mesh.Points.end(), &r.Mesh.Points[3 * k], &r.Mesh.Points[3 * k] + 3);
    }
    for (std::int64_t v : r.Mesh.Tetrahedra)
    {
      out.Mesh.Tetrahedra.push_back(global[v]);
    }
    for (std::size_t f = 0; f < r.FaceMarkers.size(); ++f)
    {
      std::array<std::int64_t, 4> key;
      for (int k = 0; k < 3; ++k)
      {
        key[k] = global[r.Faces[3 * f + k]];
        out.Faces.push_back(key[k]);
      }
      std::sort(key.begin(), key.begin() + 3);
      key[3] = static_cast<std::int64_t>(faces.size());
      faces.push_back(key);
      out.FaceMarkers.push_back(r.FaceMarkers[f]);
    }
    r = TetGenResult(); // its memory back
  }
  // A face between two pieces: once, as its first piece has it.
  std::sort(faces.begin(), faces.end());
  std::vector<char> keep(faces.size(), 1);
  for (std::size_t i = 1; i < faces.size(); ++i)
  {
    if (std::equal(faces[i].begin(), faces[i].begin() + 3, faces[i - 1].begin()))
    {
      keep[faces[i][3]] = 0;
    }
  }
  std::size_t kept = 0;
  for (std::size_t f = 0; f < keep.size(); ++f)
  {
    if (keep[f])
    {
      std::copy(&out.Faces[3 * f], &out.Faces[3 * f] + 3, &out.Faces[3 * kept]);
      out.FaceMarkers[kept++] = out.FaceMarkers[f];
    }
  }
  out.Faces.resize(3 * kept);
  out.FaceMarkers.resize(kept);
  out.Pieces = pieces.size();
}
}

std::size_t SplitComplex(const PiecewiseLinearComplex& plc, const std::vector<std::uint8_t>& meshedSides,
  std::vector<ComplexPiece>& pieces)
{
  return Splitter(plc, meshedSides).Run(pieces);
}

bool TetGenMeshComplexInPieces(const PiecewiseLinearComplex& plc, const std::vector<std::uint8_t>& meshedSides,
  const TetGenOptions& options, unsigned processes, TetGenResult& out, std::string& error)
{
  std::vector<ComplexPiece> pieces;
  const std::size_t n = SplitComplex(plc, meshedSides, pieces);
  if (n < 2)
  {
    return TetGenMeshComplex(plc, options, out, error);
  }
  if (processes == 0)
  {
    processes = std::max(1u, std::thread::hardware_concurrency());
  }
  // One thread per running TetGen process (each waits on its pipe), the
  // largest pieces first; each result in its piece's place.
  std::vector<std::size_t> start(n);
  std::iota(start.begin(), start.end(), std::size_t(0));
  std::stable_sort(start.begin(), start.end(), [&](std::size_t a, std::size_t b) {
    return pieces[a].Complex.Triangles.size() > pieces[b].Complex.Triangles.size();
  });
  std::vector<TetGenResult> results(n);
  std::vector<std::string> errors(n);
  std::vector<char> ok(n, 0);
  std::atomic<std::size_t> next{ 0 };
  auto work = [&]() {
    for (std::size_t k = next++; k < n; k = next++)
    {
      const std::size_t p = start[k];
      ok[p] = TetGenMeshComplex(pieces[p].Complex, options, results[p], errors[p]) ? 1 : 0;
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t i = 1; i < std::min<std::size_t>(processes, n); ++i)
  {
    try
    {
      pool.emplace_back(work);
    }
    catch (const std::system_error&)
    {
      break; // fewer threads
    }
  }
  work();
  for (std::thread& t : pool)
  {
    t.join();
  }
  if (std::find(ok.begin(), ok.end(), 0) != ok.end())
  {
    return TetGenMeshComplex(plc, options, out, error); // never fail because of the split
  }
  Merge(plc, pieces, results, out);
  return true;
}
}
