// SPDX-License-Identifier: BSD-3-Clause
#include "ARPrismLayers.h"
#include "ARCGALTypes.h"
#include "ARCellQuality.h"
#include "ARUnionFind.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <sstream>
#include <utility>

namespace ar
{
namespace
{
using cgal::Kernel;
using cgal::Point;
using Ray = Kernel::Ray_3;
using cgal::Triangle;
using Tree = cgal::TriangleTree;
using Vec = Eigen::Vector3d;

constexpr double Pi = 3.14159265358979323846;
/// The dot of a vertex normal with its triangles' unit normals aimed at.
constexpr double Visible = 0.3;
/// Smallest angle between the fans of two border edges at a border point.
constexpr double MinWedgeAngle = 20.0 * Pi / 180.0;
/// A column that must shrink below this fraction of the stack fails.
constexpr double MinHeightFraction = 1e-3;
constexpr int MaxRounds = 60;
/// No prism's top face may shrink below this fraction of its S triangle's
/// area: keeps a concave side's caps away from its focal line, where they
/// would pinch the space left for the tetrahedra.
constexpr double MinAreaRatio = 0.5;
/// Each side gets its own closure groups where every border column is at
/// least this many border edges high on both sides (NumberPoints).
constexpr double SideGroupsAbove = 0.25;
/// A wedge at a border point whose chord between the two fans' apices
/// passes farther than this many arc radii from the point gets a point on
/// its bisector (PlaceWedges).
constexpr double FarChord = 1.2;
/// A wedge's arc points stand at least this fraction of its fans' apices'
/// distance from the point (PlaceWedges). Where a border edge is much longer
/// than the stack, the apices stand half an edge along it, and an arc at the
/// apices' offsets hugs the point: the seam tetrahedra of the first and last
/// piece, (a_K, P_g, P_g+1, W_1), flattened (7.6 degrees on the 3-D bow
/// shock). Smallest closure / TetGen angle on the validation cases' layered
/// meshes and TestPrismLayers' tall stacks: 0 (the offsets alone) 7.6 / 10.1;
/// 0.3 10.9 / 10.2; 0.4 11.1 / 10.4 but a strip case of TestPrismLayers
/// fails; 0.5 9.6 / 7.5. Where the offsets are larger (stacks as tall as
/// the edges) nothing changes.
constexpr double ArcRadiusFloor = 0.3;

Vec At(const double* x)
{
  return Vec(x[0], x[1], x[2]);
}

Point P(const Vec& v)
{
  return Point(v.x(), v.y(), v.z());
}

double Det(const Vec& a, const Vec& b, const Vec& c)
{
  return a.dot(b.cross(c));
}

/// Distance from `origin` to the first hit of a ray, or +inf.
template <typename Result>
double HitDistance(const Result& hit, const Point& origin)
{
  if (!hit)
  {
    return std::numeric_limits<double>::infinity();
  }
  if (const Point* p = boost::get<Point>(&hit->first))
  {
    return std::sqrt(CGAL::to_double(CGAL::squared_distance(*p, origin)));
  }
  if (const Kernel::Segment_3* s = boost::get<Kernel::Segment_3>(&hit->first))
  {
    return std::sqrt(std::min(CGAL::to_double(CGAL::squared_distance(s->source(), origin)),
      CGAL::to_double(CGAL::squared_distance(s->target(), origin))));
  }
  return std::numeric_limits<double>::infinity();
}

bool AllFinite(const double* v, std::size_t n)
{
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!std::isfinite(v[i]))
    {
      return false;
    }
  }
  return true;
}

std::string Num(double v)
{
  std::ostringstream s;
  s << v;
  return s.str();
}
}

bool PrismLayerDistances(const PrismLayerOptions& o, std::vector<double>& z, std::string& error)
{
  z.clear();
  const int n = o.NumberOfLayers;
  if (n < 1 || n > 100)
  {
    error = "NumberOfLayers must be between 1 and 100 (got " + std::to_string(n) + ").";
    return false;
  }
  if (!(o.GrowthRatio > 0.0) || !std::isfinite(o.GrowthRatio))
  {
    error = "GrowthRatio must be a positive number (got " + Num(o.GrowthRatio) + ").";
    return false;
  }
  if (!(o.TotalThickness >= 0.0) || !std::isfinite(o.TotalThickness))
  {
    error = "TotalThickness must be positive, or 0 to use FirstLayerThickness (got " +
      Num(o.TotalThickness) + ").";
    return false;
  }
  double first = o.FirstLayerThickness;
  if (o.TotalThickness > 0.0)
  {
    double sum = 0.0, t = 1.0;
    for (int k = 0; k < n; ++k, t *= o.GrowthRatio)
    {
      sum += t;
    }
    first = o.TotalThickness / sum;
  }
  else if (!(first > 0.0) || !std::isfinite(first))
  {
    error = "FirstLayerThickness must be a positive number when no TotalThickness is given (got " +
      Num(first) + ").";
    return false;
  }
  if (!(o.MaxHeightGradient > 0.0) || !std::isfinite(o.MaxHeightGradient))
  {
    error = "MaxHeightGradient must be a positive number (got " + Num(o.MaxHeightGradient) + ").";
    return false;
  }
  if (!(o.BorderHeight > 0.0) || !std::isfinite(o.BorderHeight))
  {
    error = "BorderHeight must be a positive number (got " + Num(o.BorderHeight) + ").";
    return false;
  }
  if (!(o.GapFraction > 0.0 && o.GapFraction <= 0.5))
  {
    error = "GapFraction must lie in (0, 0.5] (got " + Num(o.GapFraction) + ").";
    return false;
  }
  if (o.NormalSmoothingIterations < 0)
  {
    error = "NormalSmoothingIterations must not be negative (got " +
      std::to_string(o.NormalSmoothingIterations) + ").";
    return false;
  }
  z.assign(1, 0.0);
  double t = first;
  for (int k = 0; k < n; ++k, t *= o.GrowthRatio)
  {
    z.push_back(z.back() + t);
  }
  if (!std::isfinite(z.back()) || !(z[1] > 0.0))
  {
    error = "the layer thicknesses overflow (FirstLayerThickness " + Num(first) + ", GrowthRatio " +
      Num(o.GrowthRatio) + ", " + std::to_string(n) + " layers).";
    z.clear();
    return false;
  }
  return true;
}

namespace
{
/**
 * One BuildPrismLayers call: the inputs, the state its stages share, and the
 * stages in the order they run (Execute): the surface's topology, the vertex
 * normals, the trees, the column heights, the border closure's sizes and the
 * point ids; then rounds of building the cells and the outer surface,
 * checking them and shrinking the columns and closure offsets that failed.
 */
class LayerBuild
{
public:
  LayerBuild(const double* xyz_, std::size_t nS_, const std::int64_t* tri_, std::size_t nT_,
    const double* obstacles_, std::size_t nObstacles_, const PrismLayerOptions& o_, PrismStack& out_,
    std::string& error_)
    : xyz(xyz_)
    , nS(nS_)
    , tri(tri_)
    , nT(nT_)
    , obstacles(obstacles_)
    , nObstacles(nObstacles_)
    , o(o_)
    , out(out_)
    , error(error_)
  {
  }

  bool Execute();

private:
  bool Validate();
  bool BuildTopology();
  bool ComputeNormals();
  bool BuildTrees();
  void ComputeHeights();
  void Grade();
  void ComputeBorderOffsets();
  void OffsetApices();
  void NumberPoints();
  bool ComputePrismFloors();
  bool CheckHeights();
  bool PlaceWedges();
  void PlaceApices();
  void WritePoints();
  void BuildCells();
  void BuildOuterSurface();
  bool CheckOuterSurface();
  void Shrink();
  void WriteResults();

  // Half-edge 3t+k goes from corner k of triangle t to corner k+1.
  std::int64_t tail(std::size_t he) const { return tri[he]; }
  std::int64_t head(std::size_t he) const { return tri[3 * (he / 3) + (he % 3 + 1) % 3]; }
  /// The smallest dot of `n` with the unit normals of v's triangles (and which).
  double minDot(std::size_t v, const Vec& n, std::int64_t* worst) const;
  // Free distance along a ray from x in direction d, skipping the S triangles
  // that contain one of the points in `skip`.
  double freeDistance(const Vec& x, const Vec& d, std::int64_t skipA, std::int64_t skipB) const;
  /// Point id of S point v at column index k in [lo, hi].
  std::int64_t id(std::int64_t v, int k) const;
  /// Signed distance from S of column index k in [lo, hi]: requested, and at point v.
  double requested(int k) const { return k >= 0 ? z[k] : -z[-k]; }
  double height(std::int64_t v, int k) const { return k >= 0 ? z[k] * H[2 * v] / Z : -z[-k] * H[2 * v + 1] / Z; }
  /// The height of group g's apices at point v's column (apexLevel[g] of
  /// the group's height there).
  double apexHeight(std::int64_t v, int g) const
  {
    return height(v, K[g]) + apexLevel[g] * (height(v, K[g + 1]) - height(v, K[g]));
  }
  /// Layer and side of the layer between column indices k and k + 1.
  static int layerOf(int k) { return k >= 0 ? k : -k - 1; }
  static int sideOf(int k) { return k >= 0 ? 1 : -1; }
  /// Point v's column at the height of group g's apices.
  Vec columnAt(std::int64_t v, int g) const { return Vec(X[v] + apexHeight(v, g) * normal[v]); }
  /// The apex beside the middle of edge (a, b) at its group's apex height: d_e
  /// out in the plane of the column points there.
  Vec apexOf(std::size_t edge, int g) const
  {
    const std::int64_t ea = tail(borderEdges[edge]), eb = head(borderEdges[edge]);
    const Vec ca = columnAt(ea, g), cb = columnAt(eb, g);
    return Vec(0.5 * (ca + cb) + dEdge[edge] * (cb - ca).cross(nEdge[edge]).normalized());
  }
  std::int64_t edgeApex(std::int64_t e, int g) const { return firstApex + e * nGroups + g; }
  /// The quad (w_j, w_j+1, u_j+1, u_j) between the wedge at head(e)'s rows
  /// of groups g and g + 1 is split along w_j+1 u_j (true) instead of w_j
  /// u_j+1: the diagonal that makes its fold convex seen from the void.
  bool bandFlipped(std::size_t e, int g, std::size_t j) const;
  Vec x(std::int64_t i) const { return At(&out.Points[3 * i]); }
  void addTet(const std::array<std::int64_t, 4>& q, int k, std::int64_t edge1, std::int64_t edge2,
    std::int64_t point);
  void addOuter(std::int64_t p, std::int64_t q, std::int64_t r, int kind, std::int64_t ref, int side);

  // Inputs.
  const double* xyz;
  const std::size_t nS;
  const std::int64_t* tri;
  const std::size_t nT;
  const double* obstacles;
  const std::size_t nObstacles;
  const PrismLayerOptions& o;
  PrismStack& out;
  std::string& error;

  // The layers' distances from S, their number and height, the sides.
  std::vector<double> z;
  int N = 0;
  double Z = 0.0;
  int sides = 1;
  // Topology: corners at each point, the twin of each half-edge, the border
  // (one fan per point), the used points' ranks, the neighbours.
  std::vector<std::int64_t> cStart, corners, twin, borderEdges, outBorder, rank, nStart, nbrs;
  std::size_t nUsed = 0;
  std::vector<Vec> X, faceNormal, faceUnit, normal;
  // The trees: obstacles and S itself.
  std::vector<Triangle> obstacleTris, surfaceTris;
  Tree obstacleTree, surfaceTree;
  // Column heights H[2 v + s] (s = 0 on the + side), the border edges'
  // closure offsets d_e, lengths, outward and normal directions.
  std::vector<double> H, dEdge, lEdge;
  std::vector<Vec> tEdge, nEdge;
  std::size_t nB = 0;
  // Point ids, the closure's groups of layers K_0 < .. < K_m, the prisms'
  // corner floors.
  std::int64_t firstApex = 0;
  int lo = 0, hi = 0, nGroups = 0;
  std::vector<int> K;
  std::vector<double> apexLevel, apexOut; // per group: the apices' level and offset, in group heights
  std::vector<double> prismFloor;
  // A round's state: the wedges at border points and their apices, what
  // must shrink, where each outer triangle comes from.
  struct Wedge
  {
    std::vector<double> Phi1, Gamma, Rho; // per group
    std::vector<Vec> XAxis, YAxis;        // per group
    int Pieces = 1;
  };
  struct Source
  {
    int Kind;
    std::int64_t Ref;
    int Side;
  };
  std::vector<Wedge> wedges;
  std::vector<std::vector<std::vector<std::int64_t>>> W; // W[e][g]: the wedge at head(e) in group g
  std::vector<Vec> apex;                 // apex positions, id firstApex + index
  std::vector<std::int64_t> apexSource;  // the S point each apex stands beside
  std::vector<char> shrinkH, shrinkD;
  std::vector<Source> outerSource;
  bool shrink = false;
  int round = 0;
};

bool LayerBuild::Execute()
{
  if (!Validate() || !BuildTopology() || !ComputeNormals() || !BuildTrees())
  {
    return false;
  }
  ComputeBorderOffsets(); // (the taper in ComputeHeights uses the border edges' lengths)
  ComputeHeights();
  NumberPoints();
  OffsetApices();
  if (!ComputePrismFloors())
  {
    return false;
  }
  shrinkH.assign(2 * nS, 0);
  shrinkD.assign(nB, 0);
  const std::size_t nPrisms = nT * static_cast<std::size_t>(sides * N);
  out.Prisms.reserve(6 * nPrisms);
  out.PrismLayer.reserve(nPrisms);
  out.PrismSide.reserve(nPrisms);
  out.PrismTriangle.reserve(nPrisms);
  out.OuterTriangles.reserve(6 * nT + 12 * nB);
  for (;; ++round)
  {
    if (round >= MaxRounds)
    {
      error = "the prism layers could not be made valid in " + std::to_string(MaxRounds) + " rounds.";
      return false;
    }
    if (!CheckHeights() || !PlaceWedges())
    {
      return false;
    }
    PlaceApices();
    WritePoints();
    BuildCells();
    BuildOuterSurface();
    if (!CheckOuterSurface())
    {
      return false;
    }
    if (!shrink)
    {
      break;
    }
    Shrink();
  }
  WriteResults();
  return true;
}

bool LayerBuild::Validate()
{
  out = PrismStack();
  if (!PrismLayerDistances(o, z, error))
  {
    return false;
  }
  N = o.NumberOfLayers;
  Z = z.back();
  sides = o.BothSides ? 2 : 1;
  if (nS < 3 || nT == 0)
  {
    error = "the surface is empty (no triangles).";
    return false;
  }
  if (!AllFinite(xyz, 3 * nS))
  {
    error = "the surface has a non-finite coordinate.";
    return false;
  }
  if (nObstacles > 0 && !AllFinite(obstacles, 9 * nObstacles))
  {
    error = "an obstacle triangle has a non-finite coordinate.";
    return false;
  }
  for (std::size_t k = 0; k < 3 * nT; ++k)
  {
    if (tri[k] < 0 || static_cast<std::size_t>(tri[k]) >= nS)
    {
      error = "triangle " + std::to_string(k / 3) + " refers to a point that does not exist.";
      return false;
    }
  }

  return true;
}

bool LayerBuild::BuildTopology()
{
  // ---- Topology: corners at each point, the twin of each directed edge.
  // Edge 3t+k goes from corner k of triangle t to corner k+1.
  cStart.assign(nS + 1, 0);
  corners.assign(3 * nT, 0);
  for (std::size_t k = 0; k < 3 * nT; ++k)
  {
    ++cStart[tri[k] + 1];
  }
  for (std::size_t v = 0; v < nS; ++v)
  {
    cStart[v + 1] += cStart[v];
  }
  {
    std::vector<std::int64_t> fill(cStart.begin(), cStart.end() - 1);
    for (std::size_t k = 0; k < 3 * nT; ++k)
    {
      corners[fill[tri[k]]++] = static_cast<std::int64_t>(k);
    }
  }
  X.resize(nS);
  for (std::size_t v = 0; v < nS; ++v)
  {
    X[v] = At(xyz + 3 * v);
  }
  faceNormal.resize(nT);
  faceUnit.resize(nT);
  for (std::size_t t = 0; t < nT; ++t)
  {
    const std::int64_t* f = tri + 3 * t;
    faceNormal[t] = (X[f[1]] - X[f[0]]).cross(X[f[2]] - X[f[0]]);
    const double n = faceNormal[t].norm();
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2] || !(n > 0.0))
    {
      error = "triangle " + std::to_string(t) + " of the surface has zero area.";
      return false;
    }
    faceUnit[t] = faceNormal[t] / n;
  }
  twin.assign(3 * nT, -1);
  for (std::size_t he = 0; he < 3 * nT; ++he)
  {
    const std::int64_t a = tail(he), b = head(he);
    int found = 0;
    for (std::int64_t i = cStart[b]; i < cStart[b + 1]; ++i)
    {
      if (head(corners[i]) == a)
      {
        twin[he] = corners[i];
        ++found;
      }
    }
    for (std::int64_t i = cStart[a]; i < cStart[a + 1]; ++i)
    {
      if (static_cast<std::size_t>(corners[i]) != he && head(corners[i]) == b)
      {
        found = 99;
      }
    }
    if (found > 1)
    {
      error = "the surface is not an oriented manifold at edge (" + std::to_string(a) + ", " +
        std::to_string(b) + "): it is used by more than two triangles or twice in the same direction.";
      return false;
    }
  }
  // Border edges, one fan per point.
  outBorder.assign(nS, -1);
  rank.assign(nS, -1);
  for (std::size_t v = 0; v < nS; ++v)
  {
    const std::int64_t deg = cStart[v + 1] - cStart[v];
    if (deg == 0)
    {
      continue;
    }
    rank[v] = static_cast<std::int64_t>(nUsed++);
    int nOut = 0, nIn = 0;
    std::int64_t start = corners[cStart[v]];
    for (std::int64_t i = cStart[v]; i < cStart[v + 1]; ++i)
    {
      const std::int64_t c = corners[i];
      if (twin[c] < 0)
      {
        ++nOut;
        start = c;
        outBorder[v] = static_cast<std::int64_t>(borderEdges.size());
        borderEdges.push_back(c);
      }
      if (twin[3 * (c / 3) + (c % 3 + 2) % 3] < 0)
      {
        ++nIn;
      }
    }
    // Walk around v from `start` through the edges coming into v.
    std::int64_t visited = 0;
    for (std::int64_t c = start;;)
    {
      ++visited;
      const std::int64_t in = 3 * (c / 3) + (c % 3 + 2) % 3;
      c = twin[in];
      if (c < 0 || c == start || visited > deg)
      {
        break;
      }
    }
    if (nOut > 1 || nIn != nOut || visited != deg)
    {
      error = "the surface is pinched at point " + std::to_string(v) +
        " (its triangles there form more than one fan); prism layers need a manifold surface.";
      return false;
    }
  }
  // Neighbours of each point (along S's edges).
  nStart.assign(nS + 1, 0);
  for (std::size_t v = 0; v < nS; ++v)
  {
    const std::size_t first = nbrs.size();
    for (std::int64_t i = cStart[v]; i < cStart[v + 1]; ++i)
    {
      const std::int64_t c = corners[i];
      nbrs.push_back(tri[3 * (c / 3) + (c % 3 + 1) % 3]);
      nbrs.push_back(tri[3 * (c / 3) + (c % 3 + 2) % 3]);
    }
    std::sort(nbrs.begin() + first, nbrs.end());
    nbrs.erase(std::unique(nbrs.begin() + first, nbrs.end()), nbrs.end());
    nStart[v + 1] = static_cast<std::int64_t>(nbrs.size());
  }

  return true;
}

double LayerBuild::minDot(std::size_t v, const Vec& n, std::int64_t* worst) const
{
  double m = 2.0;
  for (std::int64_t i = cStart[v]; i < cStart[v + 1]; ++i)
  {
    const double d = n.dot(faceUnit[corners[i] / 3]);
    if (d < m)
    {
      m = d;
      if (worst)
      {
        *worst = corners[i] / 3;
      }
    }
  }
  return m;
}

bool LayerBuild::ComputeNormals()
{
  // ---- Vertex normals: area-weighted, made visible from every incident triangle, smoothed.
  normal.assign(nS, Vec::Zero());
  for (std::size_t v = 0; v < nS; ++v)
  {
    if (rank[v] < 0)
    {
      continue;
    }
    Vec n = Vec::Zero();
    for (std::int64_t i = cStart[v]; i < cStart[v + 1]; ++i)
    {
      n += faceNormal[corners[i] / 3];
    }
    n = n.norm() > 0.0 ? Vec(n.normalized()) : faceUnit[corners[cStart[v]] / 3];
    for (int it = 0; it < 100; ++it)
    {
      std::int64_t worst = -1;
      const double d = minDot(v, n, &worst);
      if (d >= Visible)
      {
        break;
      }
      n = (n + (Visible - d + 0.05) * faceUnit[worst]).normalized();
    }
    if (!(minDot(v, n, nullptr) > 0.02))
    {
      error = "the surface folds back at point " + std::to_string(v) +
        ": no direction sees all its triangles, so no prism column can stand there.";
      return false;
    }
    normal[v] = n;
  }
  for (int pass = 0; pass < o.NormalSmoothingIterations; ++pass)
  {
    std::vector<Vec> next = normal;
    for (std::size_t v = 0; v < nS; ++v)
    {
      if (rank[v] < 0)
      {
        continue;
      }
      Vec mean = Vec::Zero();
      for (std::int64_t i = nStart[v]; i < nStart[v + 1]; ++i)
      {
        mean += normal[nbrs[i]];
      }
      const Vec cand = (normal[v] + mean / static_cast<double>(nStart[v + 1] - nStart[v])).normalized();
      if (minDot(v, cand, nullptr) >= std::min(minDot(v, normal[v], nullptr), Visible))
      {
        next[v] = cand;
      }
    }
    normal.swap(next);
  }

  return true;
}

bool LayerBuild::BuildTrees()
{
  // ---- The trees: obstacles and S itself.
  for (std::size_t k = 0; k < nObstacles; ++k)
  {
    const double* t = obstacles + 9 * k;
    obstacleTris.emplace_back(Point(t[0], t[1], t[2]), Point(t[3], t[4], t[5]), Point(t[6], t[7], t[8]));
  }
  for (std::size_t t = 0; t < nT; ++t)
  {
    surfaceTris.emplace_back(P(X[tri[3 * t]]), P(X[tri[3 * t + 1]]), P(X[tri[3 * t + 2]]));
  }
  obstacleTree.rebuild(obstacleTris.begin(), obstacleTris.end());
  surfaceTree.rebuild(surfaceTris.begin(), surfaceTris.end());
  if (!obstacleTris.empty())
  {
    obstacleTree.accelerate_distance_queries();
  }
  if (!obstacleTris.empty())
  {
    for (std::size_t t = 0; t < nT; ++t)
    {
      if (obstacleTree.do_intersect(surfaceTris[t]))
      {
        error = "triangle " + std::to_string(t) + " of the surface touches an obstacle.";
        return false;
      }
    }
  }
  return true;
}

double LayerBuild::freeDistance(const Vec& x, const Vec& d, std::int64_t skipA, std::int64_t skipB) const
{
  const Point origin = P(x);
  const Ray ray(origin, Kernel::Vector_3(d.x(), d.y(), d.z()));
  double dist = std::numeric_limits<double>::infinity();
  if (!obstacleTris.empty())
  {
    dist = HitDistance(obstacleTree.first_intersection(ray), origin);
  }
  auto skip = [&](const std::vector<Triangle>::const_iterator& it) {
    const std::int64_t* f = tri + 3 * (it - surfaceTris.begin());
    for (int k = 0; k < 3; ++k)
    {
      if (f[k] == skipA || f[k] == skipB)
      {
        return true;
      }
    }
    return false;
  };
  return std::min(dist, HitDistance(surfaceTree.first_intersection(ray, skip), origin));
}

void LayerBuild::ComputeHeights()
{
  // ---- Heights: H[2 v + s], s = 0 on the + side, 1 on the - side.
  H.assign(2 * nS, 0.0);
  for (std::size_t v = 0; v < nS; ++v)
  {
    if (rank[v] < 0)
    {
      continue;
    }
    for (int s = 0; s < sides; ++s)
    {
      const Vec d = s == 0 ? normal[v] : Vec(-normal[v]);
      H[2 * v + s] = std::min(Z, o.GapFraction * freeDistance(X[v], d, static_cast<std::int64_t>(v), -1));
    }
  }
  {
    // The taper: border columns no higher than BorderHeight x their border
    // edges (the mean of the one or more at the point).
    std::vector<double> borderLength(nS, 0.0);
    std::vector<int> borderCount(nS, 0);
    for (std::size_t e = 0; e < nB; ++e)
    {
      for (const std::int64_t v : { tail(borderEdges[e]), head(borderEdges[e]) })
      {
        borderLength[v] += lEdge[e];
        ++borderCount[v];
      }
    }
    for (std::size_t v = 0; v < nS; ++v)
    {
      if (borderCount[v] > 0 && rank[v] >= 0)
      {
        const double cap = o.BorderHeight * borderLength[v] / borderCount[v];
        for (int s = 0; s < sides; ++s)
        {
          H[2 * v + s] = std::min(H[2 * v + s], cap);
        }
      }
    }
  }
  Grade();
}

// |H_u - H_v| <= MaxHeightGradient |x_u - x_v| along S's edges: Dijkstra from the lowest columns.
void LayerBuild::Grade()
{
  using Item = std::pair<double, std::int64_t>;
  for (int s = 0; s < sides; ++s)
  {
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    for (std::size_t v = 0; v < nS; ++v)
    {
      if (rank[v] >= 0)
      {
        heap.emplace(H[2 * v + s], static_cast<std::int64_t>(v));
      }
    }
    while (!heap.empty())
    {
      const auto [h, v] = heap.top();
      heap.pop();
      if (h > H[2 * v + s])
      {
        continue;
      }
      for (std::int64_t i = nStart[v]; i < nStart[v + 1]; ++i)
      {
        const std::int64_t u = nbrs[i];
        const double cand = h + o.MaxHeightGradient * (X[u] - X[v]).norm();
        if (cand < H[2 * u + s])
        {
          H[2 * u + s] = cand;
          heap.emplace(cand, u);
        }
      }
    }
  }
}

void LayerBuild::ComputeBorderOffsets()
{
  // ---- Border closure: per border edge the apex offset d_e.
  nB = borderEdges.size();
  dEdge.assign(nB, 0.0);
  lEdge.assign(nB, 0.0);
  tEdge.resize(nB);
  nEdge.resize(nB);
  for (std::size_t e = 0; e < nB; ++e)
  {
    const std::int64_t a = tail(borderEdges[e]), b = head(borderEdges[e]);
    lEdge[e] = (X[b] - X[a]).norm();
    nEdge[e] = (normal[a] + normal[b]).normalized();
    tEdge[e] = (X[b] - X[a]).cross(nEdge[e]).normalized();
    const Vec m = 0.5 * (X[a] + X[b]);
    dEdge[e] = std::min(0.5 * lEdge[e], o.GapFraction * freeDistance(m, tEdge[e], a, b));
    if (!obstacleTris.empty())
    {
      // Not nearer to an obstacle than GapFraction of its distance in any direction.
      dEdge[e] = std::min(dEdge[e], o.GapFraction * std::sqrt(CGAL::to_double(obstacleTree.squared_distance(P(m)))));
    }
  }
}

void LayerBuild::OffsetApices()
{
  // A closure tetrahedron (a_k, a_k+1, W_j, W_j+1) at a border point is as
  // thin as its layer t seen from the apices: its angle at the edge W_j W_j+1
  // is about t d / (d^2 + dz^2), d the apices' offset and dz the layer's
  // height over them. Per group, the level and the offset (in group heights)
  // that make the thinnest of these angles largest: with uniform layers the
  // middle and about half the height (the outer layers 14 degrees with 5 in
  // a group a third of an edge high, 7.4 with the apices half an edge out);
  // with layers growing away from S nearer the thin ones (5 layers growing
  // by 1.2: 8.8 degrees at the middle, 13 near the thin end).
  apexLevel.assign(nGroups, 0.5);
  apexOut.assign(nGroups, 0.5);
  for (int g = 0; g < nGroups; ++g)
  {
    const double z0 = requested(K[g]), span = requested(K[g + 1]) - z0;
    double best = -1.0;
    for (int i = 1; i < 20; ++i)
    {
      for (int j = 4; j <= 20; ++j)
      {
        const double level = 0.05 * i, out = 0.05 * j, za = z0 + level * span, d = out * span;
        double worst = std::numeric_limits<double>::max();
        for (int k = K[g]; k < K[g + 1]; ++k)
        {
          const double t = requested(k + 1) - requested(k), dz = 0.5 * (requested(k + 1) + requested(k)) - za;
          worst = std::min(worst, t * d / (d * d + dz * dz));
        }
        // Ties (a symmetric group) keep the middle and the smaller offset.
        if (worst > best * (1.0 + 1e-9) ||
          (worst > best * (1.0 - 1e-9) && std::abs(level - 0.5) < std::abs(apexLevel[g] - 0.5)))
        {
          best = worst;
          apexLevel[g] = level;
          apexOut[g] = out;
        }
      }
    }
  }
  for (std::size_t e = 0; e < nB; ++e)
  {
    const std::int64_t a = tail(borderEdges[e]), b = head(borderEdges[e]);
    double out = 0.0;
    for (int g = 0; g < nGroups; ++g)
    {
      out = std::max(out,
        apexOut[g] * 0.5 * (height(a, K[g + 1]) - height(a, K[g]) + height(b, K[g + 1]) - height(b, K[g])));
    }
    dEdge[e] = std::min(dEdge[e], out);
  }
}

std::int64_t LayerBuild::id(std::int64_t v, int k) const
{
  if (k == 0)
  {
    return v;
  }
  const int s = k > 0 ? 0 : 1;
  const int layer = k > 0 ? k : -k;
  return static_cast<std::int64_t>(nS) + (static_cast<std::int64_t>(s * N + layer - 1) * static_cast<std::int64_t>(nUsed) + rank[v]);
}

void LayerBuild::NumberPoints()
{
  // ---- Point ids.
  const std::size_t nLayerPoints = static_cast<std::size_t>(sides) * N * nUsed;
  firstApex = static_cast<std::int64_t>(nS + nLayerPoints);
  lo = o.BothSides ? -N : 0;
  hi = N;
  // The border closure groups the layers of a column, K_0 = lo < .. < K_m =
  // hi, each group about one border edge high: one apex per group and edge,
  // so that the triangles the void sees are not needles on a tall stack.
  // With layers on both sides, each side at the border at least
  // SideGroupsAbove of a border edge high, each side has its own groups (S's
  // level is a group boundary): an apex then stands at most half a side's
  // stack from the layers it closes, not a whole side's as when one group
  // spans both (the closure tetrahedra 5.6 -> 7.5 degrees on the validation
  // cones). Lower stacks keep one group: the band of triangles between the
  // two sides' rows of apices would be as low as a side, and TetGen builds
  // thin tetrahedra against such needles.
  K = { lo };
  double meanEdge = 0.0;
  for (double l : lEdge)
  {
    meanEdge += l / static_cast<double>(nB);
  }
  bool perSide = o.BothSides && nB > 0;
  for (const std::int64_t he : borderEdges)
  {
    for (const std::int64_t v : { tail(he), head(he) })
    {
      perSide = perSide && std::min(height(v, hi), -height(v, lo)) >= SideGroupsAbove * meanEdge;
    }
  }
  const std::vector<std::array<int, 2>> spans =
    perSide ? std::vector<std::array<int, 2>>{ { lo, 0 }, { 0, hi } } : std::vector<std::array<int, 2>>{ { lo, hi } };
  for (const auto& range : spans)
  {
    const int k0 = range[0], k1 = range[1];
    if (nB > 0)
    {
      const double span = requested(k1) - requested(k0);
      // As many groups as the tallest border column (tapered: BorderHeight)
      // has border edges of height.
      double borderSpan = 0.0;
      for (const std::int64_t he : borderEdges)
      {
        for (const std::int64_t v : { tail(he), head(he) })
        {
          borderSpan = std::max(borderSpan, height(v, k1) - height(v, k0));
        }
      }
      const int m = std::max(1, std::min(k1 - k0, static_cast<int>(std::lround(borderSpan / meanEdge))));
      for (int g = 1; g < m; ++g)
      {
        const double target = requested(k0) + span * g / m;
        int best = K.back() + 1;
        for (int k = best; k <= k1 - (m - g); ++k)
        {
          best = std::abs(requested(k) - target) < std::abs(requested(best) - target) ? k : best;
        }
        K.push_back(best);
      }
    }
    K.push_back(k1);
  }
  nGroups = static_cast<int>(K.size()) - 1;
}

bool LayerBuild::ComputePrismFloors()
{
  // Prism corner floors from the normals (layer 0's bottom corners, which do not depend on height).
  prismFloor.resize(nT);
  for (std::size_t t = 0; t < nT; ++t)
  {
    const std::int64_t* f = tri + 3 * t;
    double j0 = 1.0;
    for (int k = 0; k < 3; ++k)
    {
      const Vec& a = X[f[k]];
      const Vec e1 = X[f[(k + 1) % 3]] - a, e2 = X[f[(k + 2) % 3]] - a;
      j0 = std::min(j0, Det(e1, e2, normal[f[k]]) / (e1.norm() * e2.norm()));
    }
    if (!(j0 > 0.0))
    {
      error = "the vertex normals do not see triangle " + std::to_string(t) + " of the surface.";
      return false;
    }
    prismFloor[t] = std::min(0.05, 0.5 * j0);
  }

  return true;
}

// ---- A round: every column still at least MinHeightFraction of the stack.
bool LayerBuild::CheckHeights()
{
  for (std::size_t v = 0; v < nS; ++v)
  {
    for (int s = 0; s < sides; ++s)
    {
      if (rank[v] >= 0 && H[2 * v + s] < MinHeightFraction * Z)
      {
        std::ostringstream msg;
        msg << "the prism layers cannot stand at point " << v << " of the surface on its "
            << (s == 0 ? "+" : "-") << " side: an obstacle or another part of the surface is "
            << "too close (the stack would have to shrink below " << MinHeightFraction
            << " of its height " << Z << ").";
        error = msg.str();
        return false;
      }
    }
  }
  return true;
}

bool LayerBuild::PlaceWedges()
{
  // Apices of the fans (one per border edge and group) and the wedges
  // between them at border points; d_e is lowered where the fans of a
  // border point come closer than MinWedgeAngle.
  wedges.assign(nB, Wedge());
  for (int pass = 0;; ++pass)
  {
    std::vector<char> lower(nB, 0);
    bool bad = false;
    for (std::size_t e = 0; e < nB; ++e)
    {
      // The wedge at a = head of edge e: between e (p -> a) and the outgoing edge f (a -> q).
      const std::int64_t a = head(borderEdges[e]);
      const std::int64_t f = outBorder[a];
      const std::int64_t p = tail(borderEdges[e]);
      const Vec n = normal[a];
      auto project = [&](const Vec& w) { return Vec(w - n.dot(w) * n); };
      Wedge& w = wedges[e];
      w.Phi1.assign(nGroups, 0.0);
      w.Gamma.assign(nGroups, 0.0);
      w.Rho.assign(nGroups, 0.0);
      w.XAxis.assign(nGroups, Vec::Zero());
      w.YAxis.assign(nGroups, Vec::Zero());
      w.Pieces = 1;
      for (int g = 0; g < nGroups; ++g)
      {
        // Angles around a's column in the plane normal to it, from the direction to p's column.
        w.XAxis[g] = project(columnAt(p, g) - columnAt(a, g)).normalized();
        w.YAxis[g] = n.cross(w.XAxis[g]);
        auto angle = [&](const Vec& x) {
          const Vec r = x - X[a];
          double phi = std::atan2(r.dot(w.YAxis[g]), r.dot(w.XAxis[g]));
          return phi < 0.0 ? phi + 2.0 * Pi : phi;
        };
        const Vec p1 = apexOf(e, g), p2 = apexOf(static_cast<std::size_t>(f), g);
        double phi1 = angle(p1);
        if (phi1 > 1.5 * Pi)
        {
          phi1 -= 2.0 * Pi;
        }
        w.Phi1[g] = phi1;
        w.Gamma[g] = angle(p2) - phi1;
        // The arc's points at the apices' offsets: a piece's tetrahedra see
        // a's layers from the chord W_j W_j+1 and flatten seen from farther.
        // But at least ArcRadiusFloor of the apices' distance: the seam
        // tetrahedra of the first and last piece flatten when the arc hugs a
        // while the fans' apices stand half a long edge away.
        const Vec r1 = project(p1 - X[a]), r2 = project(p2 - X[a]);
        const double far = 0.5 * (r1.norm() + r2.norm());
        w.Rho[g] =
          std::min(far, std::max(0.5 * (dEdge[e] + dEdge[static_cast<std::size_t>(f)]), ArcRadiusFloor * far));
        w.Pieces = std::max(w.Pieces, static_cast<int>(std::ceil(w.Gamma[g] / (0.5 * Pi) - 1e-9)));
        // A narrow wedge whose chord passes far out (a border turning inward)
        // gets a point on its bisector.
        if (r1.cross(r2).norm() > FarChord * w.Rho[g] * (r2 - r1).norm())
        {
          w.Pieces = std::max(w.Pieces, 2);
        }
        if (w.Gamma[g] < MinWedgeAngle)
        {
          lower[e] = lower[f] = 1;
          bad = true;
        }
      }
    }
    if (!bad)
    {
      break;
    }
    if (pass == 40)
    {
      for (std::size_t e = 0; e < nB; ++e)
      {
        if (*std::min_element(wedges[e].Gamma.begin(), wedges[e].Gamma.end()) < MinWedgeAngle)
        {
          error = "the border of the surface turns back too sharply at point " +
            std::to_string(head(borderEdges[e])) + " to close the prism layers there.";
          return false;
        }
      }
    }
    for (std::size_t e = 0; e < nB; ++e)
    {
      dEdge[e] *= lower[e] ? 0.7 : 1.0;
    }
  }
  return true;
}

void LayerBuild::PlaceApices()
{
  // Apex ids: edge e, group g -> firstApex + e * nGroups + g; then the wedges' inner points.
  apex.clear();
  apexSource.clear();
  for (std::size_t e = 0; e < nB; ++e)
  {
    for (int g = 0; g < nGroups; ++g)
    {
      apex.push_back(apexOf(e, g));
      apexSource.push_back(tail(borderEdges[e]));
    }
  }
  // W[e][g]: the wedge at head(e) in group g, W_0 = e's apex .. W_m = the outgoing edge's.
  W.assign(nB, {});
  for (std::size_t e = 0; e < nB; ++e)
  {
    const std::int64_t a = head(borderEdges[e]);
    const Wedge& w = wedges[e];
    W[e].resize(nGroups);
    for (int g = 0; g < nGroups; ++g)
    {
      W[e][g].push_back(edgeApex(static_cast<std::int64_t>(e), g));
      for (int j = 1; j < w.Pieces; ++j)
      {
        const double phi = w.Phi1[g] + j * w.Gamma[g] / w.Pieces;
        W[e][g].push_back(firstApex + static_cast<std::int64_t>(apex.size()));
        apexSource.push_back(a);
        apex.push_back(columnAt(a, g) + w.Rho[g] * (std::cos(phi) * w.XAxis[g] + std::sin(phi) * w.YAxis[g]));
      }
      W[e][g].push_back(edgeApex(outBorder[a], g));
    }
  }
}

void LayerBuild::WritePoints()
{
  // Points.
  out.Points.assign(3 * (static_cast<std::size_t>(firstApex) + apex.size()), 0.0);
  for (std::size_t v = 0; v < nS; ++v)
  {
    std::copy(xyz + 3 * v, xyz + 3 * v + 3, &out.Points[3 * v]);
    if (rank[v] < 0)
    {
      continue;
    }
    for (int k = lo; k <= hi; ++k)
    {
      if (k == 0)
      {
        continue;
      }
      const int s = k > 0 ? 0 : 1;
      const double h = z[k > 0 ? k : -k] * H[2 * v + s] / Z;
      const Vec x = X[v] + (k > 0 ? h : -h) * normal[v];
      const std::int64_t i = id(static_cast<std::int64_t>(v), k);
      out.Points[3 * i] = x.x();
      out.Points[3 * i + 1] = x.y();
      out.Points[3 * i + 2] = x.z();
    }
  }
  for (std::size_t i = 0; i < apex.size(); ++i)
  {
    for (int d = 0; d < 3; ++d)
    {
      out.Points[3 * (firstApex + i) + d] = apex[i][d];
    }
  }
}

void LayerBuild::addTet(const std::array<std::int64_t, 4>& q, int k, std::int64_t edge1, std::int64_t edge2,
  std::int64_t point)
{
  const Vec p0 = x(q[0]), p1 = x(q[1]), p2 = x(q[2]), p3 = x(q[3]);
  const double scale = std::max({ (p1 - p0).norm(), (p2 - p0).norm(), (p3 - p0).norm() });
  if (!(Det(p1 - p0, p2 - p0, p3 - p0) > 1e-12 * scale * scale * scale))
  {
    shrinkD[edge1] = shrinkD[edge2] = 1;
    shrinkH[2 * point + (k >= 0 ? 0 : 1)] = 1;
    shrink = true;
  }
  out.Tetrahedra.insert(out.Tetrahedra.end(), q.begin(), q.end());
  out.TetrahedronLayer.push_back(layerOf(k));
  out.TetrahedronSide.push_back(sideOf(k));
}

bool LayerBuild::bandFlipped(std::size_t e, int g, std::size_t j) const
{
  // Kept when u_j lies on a_K's side (the closure's) of the triangle (w_j,
  // w_j+1, u_j+1): the fold's ridge then points into the void. The other way
  // the void would see a dent that TetGen can only fill with the flat
  // tetrahedron of the four apices.
  const std::vector<std::int64_t>& w = W[e][g];
  const std::vector<std::int64_t>& u = W[e][g + 1];
  const Vec aK = x(id(head(borderEdges[e]), K[g + 1]));
  const Vec w0 = x(w[j]), w1 = x(w[j + 1]), u0 = x(u[j]), u1 = x(u[j + 1]);
  return Det(w1 - w0, u1 - w0, u0 - w0) * Det(w1 - w0, u1 - w0, aK - w0) < 0.0;
}

void LayerBuild::BuildCells()
{
  // Cells.
  out.Prisms.clear();
  out.PrismLayer.clear();
  out.PrismSide.clear();
  out.PrismTriangle.clear();
  out.Pyramids.clear();
  out.PyramidLayer.clear();
  out.PyramidSide.clear();
  out.Tetrahedra.clear();
  out.TetrahedronLayer.clear();
  out.TetrahedronSide.clear();
  std::fill(shrinkH.begin(), shrinkH.end(), 0);
  std::fill(shrinkD.begin(), shrinkD.end(), 0);
  shrink = false;
  for (std::size_t t = 0; t < nT; ++t)
  {
    const std::int64_t a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
    for (int s = 0; s < sides; ++s)
    {
      for (int k = 0; k < N; ++k)
      {
        std::array<std::int64_t, 6> w;
        if (s == 0)
        {
          w = { id(a, k), id(c, k), id(b, k), id(a, k + 1), id(c, k + 1), id(b, k + 1) };
        }
        else
        {
          w = { id(a, -k), id(b, -k), id(c, -k), id(a, -k - 1), id(b, -k - 1), id(c, -k - 1) };
        }
        double p[18], j[6];
        for (int i = 0; i < 6; ++i)
        {
          std::copy(&out.Points[3 * w[i]], &out.Points[3 * w[i]] + 3, p + 3 * i);
        }
        CellCornerJacobians(CellShape::Wedge, p, j, true);
        const double topArea = (At(p + 12) - At(p + 9)).cross(At(p + 15) - At(p + 9)).norm();
        if (*std::min_element(j, j + 6) < prismFloor[t] || topArea < MinAreaRatio * faceNormal[t].norm())
        {
          shrinkH[2 * a + s] = shrinkH[2 * b + s] = shrinkH[2 * c + s] = 1;
          shrink = true;
        }
        out.Prisms.insert(out.Prisms.end(), w.begin(), w.end());
        out.PrismLayer.push_back(k);
        out.PrismSide.push_back(s == 0 ? 1 : -1);
        out.PrismTriangle.push_back(static_cast<std::int64_t>(t));
      }
    }
  }
  for (std::size_t e = 0; e < nB; ++e)
  {
    // The fan of pyramids on edge e's column of quads, one apex per group,
    // and between groups a seam tetrahedron (a_K, b_K, P_g+1, P_g).
    const std::int64_t a = tail(borderEdges[e]), b = head(borderEdges[e]);
    const auto ee = static_cast<std::int64_t>(e);
    const double floor = std::min(0.05, 0.25 * dEdge[e] / std::hypot(dEdge[e], 0.5 * lEdge[e]));
    for (int g = 0; g < nGroups; ++g)
    {
      for (int k = K[g]; k < K[g + 1]; ++k)
      {
        const std::array<std::int64_t, 5> q = { id(a, k), id(b, k), id(b, k + 1), id(a, k + 1), edgeApex(ee, g) };
        double p[15], j[5]; // the four base corners, then the apex
        for (int i = 0; i < 5; ++i)
        {
          std::copy(&out.Points[3 * q[i]], &out.Points[3 * q[i]] + 3, p + 3 * i);
        }
        CellCornerJacobians(CellShape::Pyramid, p, j, true);
        if (*std::min_element(j, j + 4) < floor)
        {
          shrinkH[2 * a + (k >= 0 ? 0 : 1)] = shrinkH[2 * b + (k >= 0 ? 0 : 1)] = 1;
          shrink = true;
        }
        out.Pyramids.insert(out.Pyramids.end(), q.begin(), q.end());
        out.PyramidLayer.push_back(layerOf(k));
        out.PyramidSide.push_back(sideOf(k));
      }
      if (g + 1 < nGroups)
      {
        const int k = K[g + 1];
        addTet({ id(a, k), id(b, k), edgeApex(ee, g + 1), edgeApex(ee, g) }, k - 1, ee, ee, a);
      }
    }
  }
  for (std::size_t e = 0; e < nB; ++e)
  {
    // The wedge at a = head(e): per group and piece a tetrahedron per layer;
    // between groups two seam tetrahedra per piece.
    const std::int64_t a = head(borderEdges[e]);
    const auto ee = static_cast<std::int64_t>(e);
    const std::int64_t f = outBorder[a];
    for (int g = 0; g < nGroups; ++g)
    {
      const std::vector<std::int64_t>& w = W[e][g];
      for (std::size_t j = 0; j + 1 < w.size(); ++j)
      {
        for (int k = K[g]; k < K[g + 1]; ++k)
        {
          addTet({ id(a, k), id(a, k + 1), w[j], w[j + 1] }, k, ee, f, a);
        }
        if (g + 1 < nGroups)
        {
          const int k = K[g + 1];
          const std::vector<std::int64_t>& u = W[e][g + 1];
          if (bandFlipped(e, g, j))
          {
            addTet({ id(a, k), w[j], w[j + 1], u[j] }, k - 1, ee, f, a);
            addTet({ id(a, k), w[j + 1], u[j + 1], u[j] }, k - 1, ee, f, a);
          }
          else
          {
            addTet({ id(a, k), w[j], w[j + 1], u[j + 1] }, k - 1, ee, f, a);
            addTet({ id(a, k), w[j], u[j + 1], u[j] }, k - 1, ee, f, a);
          }
        }
      }
    }
  }
}

void LayerBuild::addOuter(std::int64_t p, std::int64_t q, std::int64_t r, int kind, std::int64_t ref, int side)
{
  out.OuterTriangles.insert(out.OuterTriangles.end(), { p, q, r });
  out.OuterTriangleKind.push_back(kind);
  outerSource.push_back(Source{ kind, ref, side });
}

void LayerBuild::BuildOuterSurface()
{
  // The outer surface.
  out.OuterTriangles.clear();
  out.OuterTriangleKind.clear();
  outerSource.clear();
  for (std::size_t t = 0; t < nT; ++t)
  {
    const std::int64_t a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
    addOuter(id(a, hi), id(b, hi), id(c, hi), 0, static_cast<std::int64_t>(t), 0);
    addOuter(id(a, lo), id(c, lo), id(b, lo), 1, static_cast<std::int64_t>(t), 1);
  }
  for (std::size_t e = 0; e < nB; ++e)
  {
    const std::int64_t a = tail(borderEdges[e]), b = head(borderEdges[e]);
    const auto ee = static_cast<std::int64_t>(e);
    addOuter(id(b, hi), id(a, hi), edgeApex(ee, nGroups - 1), 2, ee, 0);
    addOuter(id(a, lo), id(b, lo), edgeApex(ee, 0), 2, ee, 1);
  }
  for (std::size_t e = 0; e < nB; ++e)
  {
    const std::int64_t a = head(borderEdges[e]);
    const auto ee = static_cast<std::int64_t>(e);
    for (std::size_t j = 0; j + 1 < W[e][0].size(); ++j)
    {
      const std::vector<std::int64_t>& top = W[e][nGroups - 1];
      const std::vector<std::int64_t>& bottom = W[e][0];
      addOuter(id(a, hi), top[j], top[j + 1], 3, ee, 0);
      addOuter(id(a, lo), bottom[j + 1], bottom[j], 3, ee, 1);
      for (int g = 0; g + 1 < nGroups; ++g)
      {
        const std::vector<std::int64_t>& w = W[e][g];
        const std::vector<std::int64_t>& u = W[e][g + 1];
        const int side = K[g + 1] > 0 ? 0 : 1;
        if (bandFlipped(e, g, j))
        {
          addOuter(w[j], w[j + 1], u[j], 3, ee, side);
          addOuter(w[j + 1], u[j + 1], u[j], 3, ee, side);
        }
        else
        {
          addOuter(w[j], w[j + 1], u[j + 1], 3, ee, side);
          addOuter(w[j], u[j + 1], u[j], 3, ee, side);
        }
      }
    }
  }
}

bool LayerBuild::CheckOuterSurface()
{
  const std::size_t nOuter = out.OuterTriangleKind.size();
  std::vector<char> outerBad(nOuter, 0);
  // Against the obstacles.
  std::vector<Triangle> outerTris;
  outerTris.reserve(nOuter);
  for (std::size_t t = 0; t < nOuter; ++t)
  {
    const std::int64_t* f = &out.OuterTriangles[3 * t];
    outerTris.emplace_back(P(x(f[0])), P(x(f[1])), P(x(f[2])));
    if (!obstacleTris.empty() && obstacleTree.do_intersect(outerTris.back()))
    {
      outerBad[t] = 1;
    }
  }
  // Against itself (and the other pieces' stacks).
  {
    namespace PMP = CGAL::Polygon_mesh_processing;
    std::vector<std::int64_t> soupIndex(out.Points.size() / 3, -1);
    std::vector<Point> soupPoints;
    cgal::Soup soup(nOuter);
    for (std::size_t t = 0; t < nOuter; ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        const std::int64_t i = out.OuterTriangles[3 * t + k];
        if (soupIndex[i] < 0)
        {
          soupIndex[i] = static_cast<std::int64_t>(soupPoints.size());
          soupPoints.push_back(P(x(i)));
        }
        soup[t][k] = static_cast<std::size_t>(soupIndex[i]);
      }
    }
    cgal::Mesh mesh;
    if (!cgal::SoupToMesh(soupPoints, soup, mesh))
    {
      error = "internal error: the outer surface of the prism layers is not a closed manifold.";
      return false;
    }
    if (mesh.number_of_faces() != nOuter)
    {
      error = "internal error: the outer surface of the prism layers lost faces.";
      return false;
    }
    std::vector<std::pair<cgal::Mesh::Face_index, cgal::Mesh::Face_index>> pairs;
    PMP::self_intersections(faces(mesh), mesh, std::back_inserter(pairs));
    for (const auto& pr : pairs)
    {
      outerBad[static_cast<std::size_t>(pr.first)] = 1;
      outerBad[static_cast<std::size_t>(pr.second)] = 1;
    }
  }
  for (std::size_t t = 0; t < nOuter; ++t)
  {
    if (!outerBad[t])
    {
      continue;
    }
    shrink = true;
    const Source& src = outerSource[t];
    const int s = o.BothSides ? src.Side : 0;
    if (src.Kind <= 1)
    {
      for (int k = 0; k < 3; ++k)
      {
        shrinkH[2 * tri[3 * src.Ref + k] + s] = 1;
      }
    }
    else if (src.Kind == 2)
    {
      shrinkH[2 * tail(borderEdges[src.Ref]) + s] = shrinkH[2 * head(borderEdges[src.Ref]) + s] = 1;
      shrinkD[src.Ref] = 1;
    }
    else
    {
      const std::int64_t a = head(borderEdges[src.Ref]);
      shrinkH[2 * a + s] = 1;
      shrinkD[src.Ref] = shrinkD[outBorder[a]] = 1;
    }
  }
  return true;
}

// Columns and closure offsets of the cells that failed shrink, and the heights are graded again.
void LayerBuild::Shrink()
{
  for (std::size_t i = 0; i < 2 * nS; ++i)
  {
    H[i] *= shrinkH[i] ? 0.7 : 1.0;
  }
  for (std::size_t e = 0; e < nB; ++e)
  {
    dEdge[e] *= shrinkD[e] ? 0.8 : 1.0;
  }
  Grade();
}

// ---- Results.
void LayerBuild::WriteResults()
{
  out.NumberOfSurfacePoints = nS;
  out.PointSource.resize(out.Points.size() / 3);
  for (std::size_t v = 0; v < nS; ++v)
  {
    out.PointSource[v] = static_cast<std::int64_t>(v);
    for (int k = lo; k <= hi && rank[v] >= 0; ++k)
    {
      out.PointSource[id(static_cast<std::int64_t>(v), k)] = static_cast<std::int64_t>(v);
    }
  }
  for (std::size_t i = 0; i < apexSource.size(); ++i)
  {
    out.PointSource[firstApex + i] = apexSource[i];
  }
  out.ShrinkRounds = round;
  out.LayerDistances = z;
  out.Normals.resize(3 * nS);
  out.Heights.assign(2 * nS, 0.0);
  for (std::size_t v = 0; v < nS; ++v)
  {
    for (int d = 0; d < 3; ++d)
    {
      out.Normals[3 * v + d] = normal[v][d];
    }
    for (int s = 0; s < sides; ++s)
    {
      out.Heights[2 * v + s] = H[2 * v + s];
      out.LimitedColumns += (rank[v] >= 0 && H[2 * v + s] < Z * (1.0 - 1e-12)) ? 1 : 0;
    }
  }
  // A hole point per piece: the centroid of the + side's first prism there.
  UnionFind pieces(nT);
  for (std::size_t he = 0; he < 3 * nT; ++he)
  {
    if (twin[he] >= 0)
    {
      pieces.Union(static_cast<std::int64_t>(he / 3), twin[he] / 3);
    }
  }
  std::vector<char> done(nT, 0);
  for (std::size_t t = 0; t < nT; ++t)
  {
    const std::int64_t r = pieces.Find(static_cast<std::int64_t>(t));
    if (done[r])
    {
      continue;
    }
    done[r] = 1;
    Vec c = Vec::Zero();
    const std::int64_t* w = &out.Prisms[6 * (t * sides * N)];
    for (int i = 0; i < 6; ++i)
    {
      c += At(&out.Points[3 * w[i]]) / 6.0;
    }
    out.HolePoints.insert(out.HolePoints.end(), { c.x(), c.y(), c.z() });
  }
}

}

bool BuildPrismLayers(const double* xyz, std::size_t nS, const std::int64_t* tri, std::size_t nT,
  const double* obstacles, std::size_t nObstacles, const PrismLayerOptions& o, PrismStack& out,
  std::string& error)
{
  return LayerBuild(xyz, nS, tri, nT, obstacles, nObstacles, o, out, error).Execute();
}
}
