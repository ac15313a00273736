// SPDX-License-Identifier: BSD-3-Clause
#include "ARCavity.h"
#include "ARCGALTypes.h"
#include "ARCavitySeparator.h"
#include "ARHugePages.h"

#include "ARMeshSize.h"
#include "ARParallelFor.h"
#include "ARTetGenPieces.h"
#include "ARUnionFind.h"

#include "ARTetGeometry.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Fuzzy_sphere.h>
#include <CGAL/Kd_tree.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/property_map.h>

#include <boost/optional.hpp>
#include <boost/tuple/tuple.hpp>

#include <algorithm>
#include <chrono>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_map>
#include <numeric>
#include <sstream>

namespace ar
{
namespace
{
using cgal::Kernel;
using cgal::Point;
using Segment = Kernel::Segment_3;
using Ray = Kernel::Ray_3;
using cgal::Triangle;
using Tree = cgal::TriangleTree;
using IndexedPoint = boost::tuple<Point, std::size_t>;
using SearchTraits = CGAL::Search_traits_adapter<IndexedPoint,
  CGAL::Nth_of_tuple_property_map<0, IndexedPoint>, CGAL::Search_traits_3<Kernel>>;
using KdTree = CGAL::Kd_tree<SearchTraits>;
using Sphere = CGAL::Fuzzy_sphere<SearchTraits>;


Point P(const double* x)
{
  return Point(x[0], x[1], x[2]);
}

double Distance(const double* a, const double* b)
{
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
    (a[2] - b[2]) * (a[2] - b[2]));
}

bool Finite(const std::vector<double>& v)
{
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

/// Parity of boundary crossings along three rays (majority), for "inside V".
/// Whether some triangle of `tree` reaches into the box of half-side `reach`
/// about p (widened a little, so that rounding cannot shrink it). False proves
/// every triangle farther than `reach` from p, which is what the trim needs
/// to know of most points, for about a hundredth of a closest-point query's
/// cost (against the 5e6 cube's 108k boundary triangles: 0.3 us against
/// 30 us, most of it AABB_tree's traversal from its kd-tree hint).
bool AnyWithin(const Tree& tree, const Point& p, double reach)
{
  const double r = reach * (1.0 + 1e-9) +
    4.0 * std::numeric_limits<double>::epsilon() * std::max({ std::abs(p.x()), std::abs(p.y()), std::abs(p.z()) });
  return tree.do_intersect(CGAL::Bbox_3(p.x() - r, p.y() - r, p.z() - r, p.x() + r, p.y() + r, p.z() + r));
}

bool Inside(const Tree& tree, const Point& p)
{
  static const double dirs[3][3] = { { 0.5773, 0.5774, 0.5775 }, { -0.3123, 0.8541, 0.4157 },
    { 0.7071, -0.1234, -0.6963 } };
  int votes = 0;
  for (const auto& d : dirs)
  {
    const Ray ray(p, Kernel::Vector_3(d[0], d[1], d[2]));
    votes += (tree.number_of_intersected_primitives(ray) % 2 == 1) ? 1 : 0;
  }
  return votes >= 2;
}
}

namespace
{
/// Drops triangles of S (keep[t] = 0) until the kept ones form a single fan
/// around each point: at a pinched point (two fans meeting at a point, as a
/// trim can leave) the largest fan stays. Prism columns need one normal per point.
void ClearPinches(const std::int64_t* tris, std::size_t nPoints, std::size_t nTris, std::vector<char>& keep)
{
  for (int pass = 0; pass < 100; ++pass)
  {
    std::vector<std::int64_t> start(nPoints + 1, 0);
    for (std::size_t t = 0; t < nTris; ++t)
    {
      for (int k = 0; k < 3 && keep[t]; ++k)
      {
        ++start[tris[3 * t + k] + 1];
      }
    }
    std::partial_sum(start.begin(), start.end(), start.begin());
    std::vector<std::int64_t> list(static_cast<std::size_t>(start.back()));
    std::vector<std::int64_t> fill(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t < nTris; ++t)
    {
      for (int k = 0; k < 3 && keep[t]; ++k)
      {
        list[fill[tris[3 * t + k]]++] = static_cast<std::int64_t>(t);
      }
    }
    bool changed = false;
    for (std::size_t v = 0; v < nPoints; ++v)
    {
      // (triangles dropped at an earlier point of this pass left out)
      const std::int64_t first = start[v];
      const std::int64_t deg = std::stable_partition(list.begin() + first, list.begin() + start[v + 1],
        [&](std::int64_t t) { return keep[t] != 0; }) - (list.begin() + first);
      if (deg < 2)
      {
        continue;
      }
      UnionFind fans(static_cast<std::size_t>(deg));
      for (std::int64_t i = 0; i < deg; ++i)
      {
        for (std::int64_t j = i + 1; j < deg; ++j)
        {
          const std::int64_t* a = tris + 3 * list[first + i];
          const std::int64_t* b = tris + 3 * list[first + j];
          bool shareEdge = false;
          for (int p = 0; p < 3; ++p)
          {
            for (int q = 0; q < 3; ++q)
            {
              shareEdge = shareEdge || (a[p] == b[q] && a[p] != static_cast<std::int64_t>(v));
            }
          }
          if (shareEdge)
          {
            fans.Union(i, j);
          }
        }
      }
      std::vector<std::int64_t> count(static_cast<std::size_t>(deg), 0);
      for (std::int64_t i = 0; i < deg; ++i)
      {
        ++count[fans.Find(i)];
      }
      const std::int64_t best = std::max_element(count.begin(), count.end()) - count.begin();
      if (count[best] == deg)
      {
        continue;
      }
      for (std::int64_t i = 0; i < deg; ++i)
      {
        if (fans.Find(i) != best)
        {
          keep[list[first + i]] = 0;
          changed = true;
        }
      }
    }
    if (!changed)
    {
      return;
    }
  }
}

/// The triangles t of `tris` (3 node ids each) with use(t) joined where they
/// share an edge; with `border`, the nodes of the edges only one of them uses
/// flagged there. With `manifoldOnly`, only across edges that no other
/// triangle of `tris` shares.
template <typename Use>
UnionFind JoinByEdges(
  const std::int64_t* tris, std::size_t nTris, Use use, std::vector<char>* border, bool manifoldOnly = false)
{
  std::vector<std::array<std::int64_t, 3>> edges; // (lower node, higher node, triangle)
  edges.reserve(3 * nTris);
  for (std::size_t t = 0; t < nTris; ++t)
  {
    for (int k = 0; k < 3 && (manifoldOnly || use(t)); ++k)
    {
      const std::int64_t a = tris[3 * t + k], b = tris[3 * t + (k + 1) % 3];
      edges.push_back({ std::min(a, b), std::max(a, b), static_cast<std::int64_t>(t) });
    }
  }
  std::sort(edges.begin(), edges.end());
  UnionFind joined(nTris);
  for (std::size_t e = 0, next = 0; e < edges.size(); e = next)
  {
    next = e + 1;
    while (next < edges.size() && edges[next][0] == edges[e][0] && edges[next][1] == edges[e][1])
    {
      ++next;
    }
    if (!manifoldOnly)
    {
      for (std::size_t i = e + 1; i < next; ++i)
      {
        joined.Union(edges[e][2], edges[i][2]);
      }
    }
    else if (next == e + 2 && use(static_cast<std::size_t>(edges[e][2])) && use(static_cast<std::size_t>(edges[e + 1][2])))
    {
      joined.Union(edges[e][2], edges[e + 1][2]);
    }
    if (border && next == e + 1)
    {
      (*border)[edges[e][0]] = (*border)[edges[e][1]] = 1;
    }
  }
  return joined;
}

/// Drops the pieces of S (edge-connected, keep[t] = 1) that have no
/// interior point, every point on the piece's border, apart from the
/// largest piece: a strip or a lone triangle that the trim cut off beside
/// the rest. A prism stack on such a piece is closure all round (no column
/// of full height), and beside another piece's border the two closures
/// leave TetGen a gap narrower than their triangles (on cone15Ma3o1 a lone
/// triangle next to the main piece's border left new tetrahedra of 4.2
/// degrees there).
void DropBorderOnlyPieces(const std::int64_t* tris, std::size_t nPoints, std::size_t nTris, std::vector<char>& keep)
{
  std::vector<char> onBorder(nPoints, 0);
  UnionFind pieces = JoinByEdges(tris, nTris, [&](std::size_t t) { return keep[t] != 0; }, &onBorder);
  std::vector<char> hasInterior(nTris, 0);
  std::vector<std::int64_t> size(nTris, 0);
  std::int64_t largest = -1;
  for (std::size_t t = 0; t < nTris; ++t)
  {
    if (!keep[t])
    {
      continue;
    }
    const std::int64_t r = pieces.Find(static_cast<std::int64_t>(t));
    for (int k = 0; k < 3; ++k)
    {
      hasInterior[r] |= onBorder[tris[3 * t + k]] ? 0 : 1;
    }
    ++size[r];
    largest = (largest < 0 || size[r] > size[largest]) ? r : largest;
  }
  for (std::size_t t = 0; t < nTris; ++t)
  {
    const std::int64_t r = keep[t] ? pieces.Find(static_cast<std::int64_t>(t)) : -1;
    keep[t] = keep[t] && (r == largest || hasInterior[r]);
  }
}

/**
 * One RemeshLocalCavity run: the inputs, the state its stages share, and the
 * stages in the order they run (Execute), each a step of the header's
 * algorithm; as vtkFlyingEdges3DAlgorithm keeps its passes over one state.
 */
class CavityRun
{
public:
  CavityRun(const TetMesh& v, const double* surfacePoints_, std::size_t nSurfacePoints_,
    const std::int64_t* surfaceTriangles_, std::size_t nSurfaceTriangles_, const CavityOptions& options_,
    CavityRemesh& out_, std::string& error_)
    : V(v)
    , surfacePoints(surfacePoints_)
    , nSurfacePoints(nSurfacePoints_)
    , surfaceTriangles(surfaceTriangles_)
    , nSurfaceTriangles(nSurfaceTriangles_)
    , options(options_)
    , out(out_)
    , error(error_)
    , nV(v.NumberOfPoints())
    , nT(v.NumberOfTetrahedra())
  {
  }

  /// RemeshLocalCavity; with `removedOnly`, stops after the removal test and
  /// returns its per-node flags there.
  bool Execute(std::vector<std::uint8_t>* removedOnly);

private:
  bool Validate();
  bool CheckLayerOptions();
  void ComputeSizes();
  void ComputeMeans(std::vector<char>& need);
  bool BuildAdjacency();
  bool BuildLockedRegion();
  bool TrimSurface();
  bool CheckSelfIntersection();
  bool MarkRemovedNodes();
  void AddSeparator(bool wanted);
  void AddOffsetPoints();
  std::size_t CloseOverGroups();
  bool MarkCavity();
  void BuildCavityBoundary();
  bool CheckSurfaceInsideCavity();
  bool AddSurfaceOrStack(int attempt);
  void AddHolePoints();
  bool Refill();
  bool GrowAtSlivers();
  void Assemble();

  /// The angle under which a refill's tetrahedron is a sliver (degrees):
  /// where the cavity grows at kept nodes, and where TetGen's points move.
  double SliverAngle() const { return std::max(0.0, options.Quality.MinDihedralAngle - 2.0); }
  /// Threads for the per-point searches (options.Threads, 0: the hardware's).
  std::size_t Threads() const { return static_cast<std::size_t>(std::max(0, options.Threads)); }
  /// Points per block of those searches (small, so that small inputs use the threads too).
  static constexpr std::size_t SearchGrain = 256;

  /// Adds the time since the last call to `stage`.
  void Lap(double& stage)
  {
    const auto now = Clock::now();
    stage += std::chrono::duration<double>(now - stageStart).count();
    stageStart = now;
  }

  using Clock = std::chrono::steady_clock;

  // Inputs.
  const TetMesh& V;
  const double* surfacePoints;
  const std::size_t nSurfacePoints;
  const std::int64_t* surfaceTriangles;
  const std::size_t nSurfaceTriangles;
  const CavityOptions& options;
  CavityRemesh& out;
  std::string& error;
  const std::size_t nV, nT;
  Clock::time_point stageStart = Clock::now();

  // Validation and options.
  std::vector<double> S;     // the surface's points
  bool layers = false;       // prism layers on
  double stackHeight = 0.0;  // z_N: added to the removal radius
  // Sizes: longest edge at V's and S's nodes; V's mean edge where needed.
  std::vector<double> lv, ls, meanV;
  std::vector<char> hasMean;
  // V's face adjacency, the domain boundary and the locked region (trees).
  std::vector<std::int64_t> neighbor;
  std::vector<Triangle> boundary, lockedFaces;
  Tree tree, lockedTree;
  // The trimmed S.
  double margin = 0.0;
  std::vector<double> sPoints, sSize;
  std::vector<std::int64_t> sTris;
  // Removal and the cavity.
  std::vector<char> removed, cavity;
  bool givenCavity = false;
  // The refill's complex: the cavity's boundary (canonical order), S or the
  // layer stack's outer surface, hole points; and its result.
  std::vector<std::int64_t> plcIndex;
  PiecewiseLinearComplex plc;
  std::vector<double> nodeSize;
  std::int64_t nBoundaryNodes = 0;
  std::size_t nShell = 0;
  std::size_t separatorPoints = 0;       // the separator's own points (AddSeparator), after S's
  std::size_t offsetPoints = 0;          // the last points of the complex: off S, free (AddOffsetPoints)
  std::vector<std::int64_t> keptBeyond; // per complex triangle: the kept cell beyond it, or -1
  TetGenResult refill;
  PrismStack stack;                      // the layer stack (options.Layers on)
  std::vector<std::int64_t> stackOuter;  // its outer nodes (stack ids), in the PLC after the cavity's
  std::vector<double> stackOuterSize;
};

bool CavityRun::Execute(std::vector<std::uint8_t>* removedOnly)
{
  out = CavityRemesh();
  stageStart = Clock::now();
  if (!Validate() || !CheckLayerOptions())
  {
    return false;
  }
  ComputeSizes();
  if (!BuildAdjacency())
  {
    return false;
  }
  Lap(out.Seconds.Setup);
  if (!BuildLockedRegion() || !TrimSurface() || !CheckSelfIntersection() || !MarkRemovedNodes())
  {
    return false;
  }
  if (removedOnly)
  {
    removedOnly->assign(removed.begin(), removed.end());
    return true;
  }
  Lap(out.Seconds.Removal);
  if (!MarkCavity())
  {
    return false;
  }
  // Nodes of the cavity's boundary faces stay; the other nodes of cavity cells
  // go. TetGen cannot place a point on a kept face (-Y), so where the
  // cavity's boundary has a pocket of nearly coplanar kept nodes it must make
  // a sliver from them: the kept cells at such slivers join the cavity and
  // the refill is repeated (at most twice).
  bool separator = true; // off once a refill failed with one
  for (int attempt = 0;; ++attempt)
  {
    BuildCavityBoundary();
    if (!CheckSurfaceInsideCavity() || !AddSurfaceOrStack(attempt))
    {
      return false;
    }
    AddSeparator(separator);
    AddOffsetPoints();
    AddHolePoints();
    if (!Refill())
    {
      if (out.SeparatorTriangles == 0)
      {
        return false;
      }
      // The strip made the complex fail (a crossing its test missed): this
      // attempt again, the cavity whole, as without it.
      separator = false;
      out.SeparatorSkipped = "the refill failed with it: " + error;
      error.clear();
      --attempt;
      continue;
    }
    // Slivers at TetGen's own points, which its -O2 smoothing left (a 9.07
    // degree tetrahedron of two kept and two new points on the 5e6 cube):
    // those points move within their stars. The complex's points stay, but
    // for the separator's own and the free points off S (the last of the
    // complex): the strip only splits the refill, it is no surface of the
    // output. First, so that a sliver the moves mend does not cost a refill.
    SmoothFreePointsAtSlivers(
      refill.Mesh, plc.Points.size() / 3 - separatorPoints - offsetPoints, SliverAngle(), 4, static_cast<int>(Threads()),
      options.MinStepLength);
    // Slivers still there with three kept nodes: grow the cavity there.
    if (attempt == 2 || !GrowAtSlivers())
    {
      break;
    }
  }
  out.RemovedCells = static_cast<std::size_t>(std::count(cavity.begin(), cavity.end(), char(1)));
  Lap(out.Seconds.Cavity);
  Assemble();
  Lap(out.Seconds.Assembly);
  return true;
}

// ---- Validation.
bool CavityRun::Validate()
{
  if (nV < 4 || nT == 0)
  {
    error = "the volume mesh is empty (no tetrahedra).";
    return false;
  }
  if (nSurfacePoints < 3 || nSurfaceTriangles == 0)
  {
    error = "the feature surface is empty (no triangles).";
    return false;
  }
  if (!options.CellGroups.empty() && options.CellGroups.size() != nT)
  {
    error = "CellGroups has " + std::to_string(options.CellGroups.size()) + " entries for " + std::to_string(nT) +
      " tetrahedra.";
    return false;
  }
  if (!Finite(V.Points))
  {
    error = "the volume mesh has a non-finite coordinate.";
    return false;
  }
  S.assign(surfacePoints, surfacePoints + 3 * nSurfacePoints);
  if (!Finite(S))
  {
    error = "the feature surface has a non-finite coordinate.";
    return false;
  }
  for (std::size_t k = 0; k < 3 * nSurfaceTriangles; ++k)
  {
    if (surfaceTriangles[k] < 0 || static_cast<std::size_t>(surfaceTriangles[k]) >= nSurfacePoints)
    {
      error = "a triangle of the feature surface refers to a point that does not exist.";
      return false;
    }
  }
  for (std::size_t t = 0; t < nT; ++t)
  {
    const std::int64_t* v = &V.Tetrahedra[4 * t];
    for (int k = 0; k < 4; ++k)
    {
      if (v[k] < 0 || static_cast<std::size_t>(v[k]) >= nV)
      {
        error = "tetrahedron " + std::to_string(t) + " refers to a point that does not exist.";
        return false;
      }
    }
    const double vol = TetSignedVolume(&V.Points[3 * v[0]], &V.Points[3 * v[1]],
      &V.Points[3 * v[2]], &V.Points[3 * v[3]]);
    if (!(vol > 0.0))
    {
      std::ostringstream msg;
      msg << "tetrahedron " << t << " of the volume mesh is inverted or flat (signed volume " << vol
          << "); the mesh must be valid before it is remeshed.";
      error = msg.str();
      return false;
    }
  }

  return true;
}

// ---- Prism layer options (checked before any work).
bool CavityRun::CheckLayerOptions()
{
  layers = options.Layers.NumberOfLayers != 0;
  if (layers)
  {
    std::vector<double> z;
    std::string why;
    if (!PrismLayerDistances(options.Layers, z, why))
    {
      error = "prism layers: " + why;
      return false;
    }
    stackHeight = z.back();
  }
  return true;
}

// ---- Longest edge at each node of V and of S (and room for the mean length
// of the edges of the tetrahedra at each node of V, the size the refill
// grades to at the cavity's boundary: ComputeMeans).
void CavityRun::ComputeSizes()
{
  lv = options.LongestEdges.size() == nV ? options.LongestEdges
                                         : LongestEdgeAtNodes(V.Points.data(), nV, V.Tetrahedra.data(), nT);
  ls.assign(nSurfacePoints, 0.0);
  meanV.assign(nV, 0.0);
  hasMean.assign(nV, 0);
  for (std::size_t t = 0; t < nSurfaceTriangles; ++t)
  {
    const std::int64_t* f = surfaceTriangles + 3 * t;
    for (int k = 0; k < 3; ++k)
    {
      const double l = Distance(&S[3 * f[k]], &S[3 * f[(k + 1) % 3]]);
      ls[f[k]] = std::max(ls[f[k]], l);
      ls[f[(k + 1) % 3]] = std::max(ls[f[(k + 1) % 3]], l);
    }
  }
}

// The mean edge at a node, for the nodes flagged in `need` that do not
// have it yet (only the cavity's boundary nodes need it: computed there,
// the cost follows the cavity). It is summed exactly (fixed point, scaled
// by the node's longest edge) so that it does not depend on the order of
// the cells: a rank that holds the cells around a node in another order
// gets the same bits.
void CavityRun::ComputeMeans(std::vector<char>& need)
{
  bool any = false;
  for (std::size_t v = 0; v < nV; ++v)
  {
    need[v] = need[v] && !hasMean[v];
    any = any || need[v];
  }
  if (!any)
  {
    return;
  }
  std::vector<__int128> sum(nV, 0);
  std::vector<std::int64_t> count(nV, 0);
  auto scale = [&](std::int64_t v) {
    int e = 0;
    std::frexp(lv[v], &e);
    return 100 - e; // every edge at v times 2^scale is below 2^100
  };
  for (std::size_t t = 0; t < nT; ++t)
  {
    const std::int64_t* v = &V.Tetrahedra[4 * t];
    if (!(need[v[0]] || need[v[1]] || need[v[2]] || need[v[3]]))
    {
      continue;
    }
    for (int a = 0; a < 4; ++a)
    {
      for (int b = a + 1; b < 4; ++b)
      {
        if (!need[v[a]] && !need[v[b]])
        {
          continue;
        }
        const double l = Distance(&V.Points[3 * v[a]], &V.Points[3 * v[b]]);
        for (const std::int64_t n : { v[a], v[b] })
        {
          if (need[n])
          {
            sum[n] += static_cast<__int128>(std::ldexp(l, scale(n)));
            ++count[n];
          }
        }
      }
    }
  }
  for (std::size_t v = 0; v < nV; ++v)
  {
    if (need[v])
    {
      meanV[v] = count[v] > 0
        ? std::ldexp(static_cast<double>(sum[v]), -scale(v)) / static_cast<double>(count[v])
        : lv[v];
      hasMean[v] = 1;
    }
  }
}

// ---- Face adjacency of V; its boundary faces (the domain boundary's tree).
bool CavityRun::BuildAdjacency()
{
  if (!TetFaceNeighbors(V.Tetrahedra.data(), nT, nV, neighbor, error, static_cast<int>(Threads())))
  {
    return false;
  }
  for (std::size_t t = 0; t < nT; ++t)
  {
    for (int f = 0; f < 4; ++f)
    {
      if (neighbor[4 * t + f] < 0)
      {
        const std::int64_t* v = &V.Tetrahedra[4 * t];
        const std::int64_t a = v[TetFaceVertex[f][0]], b = v[TetFaceVertex[f][1]], c = v[TetFaceVertex[f][2]];
        boundary.emplace_back(P(&V.Points[3 * a]), P(&V.Points[3 * b]), P(&V.Points[3 * c]));
      }
    }
  }
  if (!options.BoundaryTriangles.empty())
  {
    if (options.BoundaryTriangles.size() % 9 != 0 || !Finite(options.BoundaryTriangles))
    {
      error = "BoundaryTriangles must hold 9 finite coordinates per triangle.";
      return false;
    }
    boundary.clear();
    const std::vector<double>& b = options.BoundaryTriangles;
    for (std::size_t k = 0; k < b.size(); k += 9)
    {
      boundary.emplace_back(P(&b[k]), P(&b[k + 3]), P(&b[k + 6]));
    }
  }
  tree.rebuild(boundary.begin(), boundary.end());
  tree.accelerate_distance_queries();
  return true;
}

// ---- The region of the locked cells: the faces of its boundary (faces
// listed once), fanned into triangles.
bool CavityRun::BuildLockedRegion()
{
  if (!options.LockedCellFaces.empty())
  {
    const std::vector<std::int64_t>& F = options.LockedCellFaces;
    // Each face's ids sorted (same layout as F), then the faces sorted by
    // them: equal neighbours are a face between two locked cells.
    std::vector<std::int64_t> sortedIds(F.size());
    std::vector<std::size_t> start;
    for (std::size_t k = 0; k < F.size();)
    {
      const std::int64_t n = F[k];
      if (n < 3 || k + 1 + static_cast<std::size_t>(n) > F.size())
      {
        error = "LockedCellFaces is malformed at entry " + std::to_string(k) +
          " (each face: its number of nodes, at least 3, then the node ids).";
        return false;
      }
      for (std::size_t j = k + 1; j < k + 1 + static_cast<std::size_t>(n); ++j)
      {
        if (F[j] < 0 || static_cast<std::size_t>(F[j]) >= nV)
        {
          error = "LockedCellFaces refers to a point that does not exist (" + std::to_string(F[j]) + ").";
          return false;
        }
      }
      sortedIds[k] = n;
      std::copy(F.begin() + k + 1, F.begin() + k + 1 + n, sortedIds.begin() + k + 1);
      std::sort(sortedIds.begin() + k + 1, sortedIds.begin() + k + 1 + n);
      start.push_back(k);
      k += 1 + static_cast<std::size_t>(n);
    }
    auto key = [&](std::size_t k) { return sortedIds.begin() + k; };
    auto less = [&](std::size_t a, std::size_t b) {
      return std::lexicographical_compare(key(a), key(a) + 1 + sortedIds[a], key(b), key(b) + 1 + sortedIds[b]);
    };
    std::sort(start.begin(), start.end(), less);
    for (std::size_t i = 0; i < start.size();)
    {
      std::size_t j = i + 1;
      while (j < start.size() && !less(start[i], start[j]))
      {
        ++j;
      }
      if (j - i == 1)
      {
        const std::int64_t* f = &F[start[i] + 1];
        for (std::int64_t m = 1; m + 1 < F[start[i]]; ++m)
        {
          lockedFaces.emplace_back(P(&V.Points[3 * f[0]]), P(&V.Points[3 * f[m]]), P(&V.Points[3 * f[m + 1]]));
        }
      }
      i = j;
    }
  }
  lockedTree.rebuild(lockedFaces.begin(), lockedFaces.end());
  if (!lockedFaces.empty())
  {
    lockedTree.accelerate_distance_queries();
  }
  return true;
}

bool CavityRun::TrimSurface()
{
  // With prism layers the stack's closure reaches about half an edge beyond
  // S's border (the pyramids' apices): S is trimmed one edge further back,
  // so that a full edge of room stays between the closure and the kept
  // faces (with half an edge TetGen had to build slivers against both).
  margin = options.BoundaryMargin + (layers ? 1.0 : 0.0);
  // ---- Trim S: inside V and at least BoundaryMargin * max(l_s, l_b) from
  // its boundary, l_b the longest edge of the nearest boundary face (the kept
  // mesh's size there); outside the locked cells and at least
  // BoundaryMargin * l_s from them, and no triangle crossing them. With S
  // finer than V (the usual refinement) the gap left between S's border and
  // the kept boundary faces is then about one of those faces, room for the
  // refill to grade from S's size to theirs: a gap of one S edge against
  // faces four times larger left TetGen only slivers there.
  // (l_b is capped by V's largest l_v: BoundaryTriangles may describe the
  // domain by larger triangles than its mesh faces)
  const double lvMax = lv.empty() ? 0.0 : *std::max_element(lv.begin(), lv.end());
  auto boundaryClearance = [&](const Point& p, double lsi) {
    // The clearance asked for is at most `reach` (lb <= lvMax below): with no
    // boundary triangle that near, p passes without its closest point.
    const double reach = options.BoundaryMargin * std::max(lsi, lvMax) + (margin - options.BoundaryMargin) * lsi;
    if (!AnyWithin(tree, p, reach))
    {
      return true;
    }
    const auto hit = tree.closest_point_and_primitive(p);
    const Triangle& f = *hit.second;
    double lb = 0.0;
    for (int k = 0; k < 3; ++k)
    {
      lb = std::max(lb, std::sqrt(CGAL::to_double(CGAL::squared_distance(f.vertex(k), f.vertex((k + 1) % 3)))));
    }
    lb = std::min(lb, lvMax);
    // BoundaryMargin kept cells (or S edges, whichever is larger), plus with
    // layers the extra S edge that the stack's closure needs.
    return std::sqrt(CGAL::to_double(CGAL::squared_distance(p, hit.first))) >=
      options.BoundaryMargin * std::max(lsi, lb) + (margin - options.BoundaryMargin) * lsi;
  };
  // (per point on threads: each writes its own flags)
  std::vector<char> usable(nSurfacePoints, 0), clearOfLocked(nSurfacePoints, 1), insideV(nSurfacePoints, 0);
  ParallelFor(
    nSurfacePoints,
    [&](std::size_t first, std::size_t last) {
      for (std::size_t i = first; i < last; ++i)
      {
        const Point p = P(&S[3 * i]);
        if (!lockedFaces.empty())
        {
          clearOfLocked[i] = !Inside(lockedTree, p) &&
            (!AnyWithin(lockedTree, p, margin * ls[i]) ||
              std::sqrt(CGAL::to_double(lockedTree.squared_distance(p))) >= margin * ls[i]);
        }
        if (!Inside(tree, p))
        {
          continue;
        }
        insideV[i] = 1;
        usable[i] = boundaryClearance(p, ls[i]);
      }
    },
    Threads(), SearchGrain);
  const std::size_t inside = static_cast<std::size_t>(std::count(insideV.begin(), insideV.end(), char(1)));
  if (inside == 0)
  {
    error = "the feature surface lies entirely outside the volume mesh.";
    return false;
  }
  std::vector<std::int64_t> sIndex(nSurfacePoints, -1);
  std::vector<char> keepTriangle(nSurfaceTriangles, 0);
  for (std::size_t t = 0; t < nSurfaceTriangles; ++t)
  {
    const std::int64_t* f = surfaceTriangles + 3 * t;
    if (!lockedFaces.empty() &&
      (!clearOfLocked[f[0]] || !clearOfLocked[f[1]] || !clearOfLocked[f[2]] ||
        lockedTree.do_intersect(Triangle(P(&S[3 * f[0]]), P(&S[3 * f[1]]), P(&S[3 * f[2]])))))
    {
      ++out.SurfaceTrianglesAtLockedCells;
      continue;
    }
    keepTriangle[t] = usable[f[0]] && usable[f[1]] && usable[f[2]];
  }
  if (layers)
  {
    ClearPinches(surfaceTriangles, nSurfacePoints, nSurfaceTriangles, keepTriangle);
    DropBorderOnlyPieces(surfaceTriangles, nSurfacePoints, nSurfaceTriangles, keepTriangle);
  }
  for (std::size_t t = 0; t < nSurfaceTriangles; ++t)
  {
    const std::int64_t* f = surfaceTriangles + 3 * t;
    if (!keepTriangle[t])
    {
      continue;
    }
    for (int k = 0; k < 3; ++k)
    {
      if (sIndex[f[k]] < 0)
      {
        sIndex[f[k]] = static_cast<std::int64_t>(sSize.size());
        sPoints.insert(sPoints.end(), &S[3 * f[k]], &S[3 * f[k]] + 3);
        sSize.push_back(ls[f[k]]);
      }
      sTris.push_back(sIndex[f[k]]);
    }
  }
  out.SurfaceTrianglesUsed = sTris.size() / 3;
  if (sTris.empty())
  {
    error = "nothing of the feature surface is left after trimming it back from the domain "
            "boundary and the locked cells (every triangle has a point within BoundaryMargin "
            "edge lengths of them).";
    if (layers)
    {
      std::ostringstream msg;
      msg << " With prism layers it is trimmed one edge further, BoundaryMargin + 1 = " << margin
          << " edges, and pieces with no point off their border are dropped: the stack's closure needs "
             "that room, which the domain does not have here (a thin slab?). Tetrahedra (no layers) "
             "need only BoundaryMargin.";
      error += msg.str();
    }
    return false;
  }
  return true;
}

// S must not cross itself (a manifold S is checked with CGAL; TetGen catches the rest).
bool CavityRun::CheckSelfIntersection()
{
  {
    std::vector<Point> pts;
    for (std::size_t i = 0; i < sSize.size(); ++i)
    {
      pts.push_back(P(&sPoints[3 * i]));
    }
    cgal::Soup faces(sTris.size() / 3);
    for (std::size_t t = 0; t < faces.size(); ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        faces[t][k] = static_cast<std::size_t>(sTris[3 * t + k]);
      }
    }
    cgal::Mesh mesh;
    if (cgal::SoupToMesh(pts, faces, mesh))
    {
      // (in two halves on two threads, ARCGALTypes.h)
      if (cgal::DoesSelfIntersect(mesh, Threads()))
      {
        error = "the feature surface intersects itself.";
        return false;
      }
    }
  }
  return true;
}

// ---- Removal: V_j within RemovalFactor * max(l_si, l_vj) of a visible S_i.
bool CavityRun::MarkRemovedNodes()
{
  std::vector<IndexedPoint> indexed;
  const std::size_t nS = sSize.size();
  double lsMax = 0.0;
  for (std::size_t i = 0; i < nS; ++i)
  {
    indexed.emplace_back(P(&sPoints[3 * i]), i);
    lsMax = std::max(lsMax, sSize[i]);
  }
  KdTree kd(indexed.begin(), indexed.end());
  kd.build();
  removed.assign(nV, 0);
  if (!options.LockedNodes.empty() && options.LockedNodes.size() != nV)
  {
    error = "LockedNodes has " + std::to_string(options.LockedNodes.size()) + " entries for " +
      std::to_string(nV) + " nodes.";
    return false;
  }
  givenCavity = !options.CavityCells.empty();
  if (givenCavity && options.CavityCells.size() != nT)
  {
    error = "CavityCells has " + std::to_string(options.CavityCells.size()) + " entries for " +
      std::to_string(nT) + " tetrahedra.";
    return false;
  }
  if (givenCavity)
  {
    return true;
  }
  // S's bounding box: a node more than twice its search radius from it (in
  // one coordinate; twice, far beyond any rounding) has no S point within
  // that radius, and is skipped.
  double lo[3] = { 0.0, 0.0, 0.0 }, hi[3] = { 0.0, 0.0, 0.0 };
  for (int k = 0; k < 3 && nS > 0; ++k)
  {
    lo[k] = hi[k] = sPoints[k];
    for (std::size_t i = 1; i < nS; ++i)
    {
      lo[k] = std::min(lo[k], sPoints[3 * i + k]);
      hi[k] = std::max(hi[k], sPoints[3 * i + k]);
    }
  }
  const double rf = options.RemovalFactor;
  // V_j is removed when some S_i lies within rf * max(l_si, l_vj) + z_N of
  // it and sees it: the kd-tree's sphere of the largest such radius holds
  // every candidate. First any S point within the smallest radius, rf * l_vj
  // + z_N (a point of that sphere is in the larger one too): when it passes
  // both tests V_j goes at once (most nodes near S); otherwise every
  // candidate is tested. The result is the same either way (whether some
  // candidate passes), and each node writes its own flag (on threads).
  ParallelFor(
    nV,
    [&](std::size_t first, std::size_t last) {
      std::vector<IndexedPoint> found;
      auto passes = [&](const IndexedPoint& q, const double* xj, std::size_t j) {
        const std::size_t i = boost::get<1>(q);
        const double* xi = &sPoints[3 * i];
        if (Distance(xi, xj) >= rf * std::max(sSize[i], lv[j]) + stackHeight)
        {
          return false;
        }
        if (options.VisibilityTest)
        {
          // Stop just short of V_j, which may itself lie on the boundary.
          const double t = 1.0 - 1e-7;
          const Point end(xi[0] + t * (xj[0] - xi[0]), xi[1] + t * (xj[1] - xi[1]), xi[2] + t * (xj[2] - xi[2]));
          if (tree.do_intersect(Segment(boost::get<0>(q), end)))
          {
            return false;
          }
        }
        return true;
      };
      for (std::size_t j = first; j < last; ++j)
      {
        if (!options.LockedNodes.empty() && options.LockedNodes[j])
        {
          continue;
        }
        if (options.FullDomain)
        {
          removed[j] = 1;
          continue;
        }
        const double* xj = &V.Points[3 * j];
        const double radius = rf * std::max(lsMax, lv[j]) + stackHeight;
        const double reach = 2.0 * radius;
        if (xj[0] < lo[0] - reach || xj[0] > hi[0] + reach || xj[1] < lo[1] - reach || xj[1] > hi[1] + reach ||
          xj[2] < lo[2] - reach || xj[2] > hi[2] + reach)
        {
          continue;
        }
        const Point pj = P(xj);
        const boost::optional<IndexedPoint> any =
          kd.search_any_point(Sphere(IndexedPoint(pj, 0), rf * lv[j] + stackHeight, 0.0));
        if (any && passes(*any, xj, j))
        {
          removed[j] = 1;
          continue;
        }
        found.clear();
        kd.search(std::back_inserter(found), Sphere(IndexedPoint(pj, 0), radius, 0.0));
        for (const IndexedPoint& q : found)
        {
          if (passes(q, xj, j))
          {
            removed[j] = 1;
            break;
          }
        }
      }
    },
    Threads(), SearchGrain);
  return true;
}

// ---- The cavity: tetrahedra touching removed nodes (or the given one).
bool CavityRun::MarkCavity()
{
  cavity.assign(nT, 0);
  for (std::size_t t = 0; t < nT; ++t)
  {
    if (givenCavity)
    {
      cavity[t] = options.CavityCells[t] ? 1 : 0;
      continue;
    }
    for (int k = 0; k < 4; ++k)
    {
      cavity[t] = cavity[t] || removed[V.Tetrahedra[4 * t + k]];
    }
  }
  CloseOverGroups();
  out.RemovedCells = static_cast<std::size_t>(std::count(cavity.begin(), cavity.end(), char(1)));
  if (out.RemovedCells == 0)
  {
    error = "no node of the volume mesh lies near the feature surface: nothing to remesh.";
    return false;
  }
  return true;
}

// Every group the cavity touches joins it whole (CavityOptions::CellGroups);
// returns the tetrahedra added.
std::size_t CavityRun::CloseOverGroups()
{
  if (options.CellGroups.empty())
  {
    return 0;
  }
  std::int64_t nGroups = 0;
  for (const std::int64_t g : options.CellGroups)
  {
    nGroups = std::max(nGroups, g + 1);
  }
  std::vector<char> touched(static_cast<std::size_t>(nGroups), 0);
  for (std::size_t t = 0; t < nT; ++t)
  {
    const std::int64_t g = options.CellGroups[t];
    if (g >= 0 && cavity[t])
    {
      touched[g] = 1;
    }
  }
  std::size_t added = 0;
  for (std::size_t t = 0; t < nT; ++t)
  {
    const std::int64_t g = options.CellGroups[t];
    if (g >= 0 && touched[g] && !cavity[t])
    {
      cavity[t] = 1;
      ++added;
    }
  }
  return added;
}

// The refill's complex, first the cavity's boundary: its faces (kept faces
// marker 1, domain boundary 3) and nodes with their mean edge as size, in a
// canonical order; the kept regions next to the cavity (for hole points).
void CavityRun::BuildCavityBoundary()
{
  std::vector<char> need(nV, 0);
  for (std::size_t t = 0; t < nT; ++t)
  {
    if (cavity[t])
    {
      for (int k = 0; k < 4; ++k)
      {
        need[V.Tetrahedra[4 * t + k]] = 1;
      }
    }
  }
  ComputeMeans(need);
  plcIndex.assign(nV, -1);
  plc = PiecewiseLinearComplex();
  nodeSize.clear();
  keptBeyond.clear();
  for (std::size_t t = 0; t < nT; ++t)
  {
    for (int f = 0; f < 4 && cavity[t]; ++f)
    {
      const std::int64_t nb = neighbor[4 * t + f];
      if (nb >= 0 && cavity[nb])
      {
        continue;
      }
      for (int k = 0; k < 3; ++k)
      {
        const std::int64_t v = V.Tetrahedra[4 * t + TetFaceVertex[f][k]];
        if (plcIndex[v] < 0)
        {
          plcIndex[v] = static_cast<std::int64_t>(nodeSize.size());
          plc.Points.insert(plc.Points.end(), &V.Points[3 * v], &V.Points[3 * v] + 3);
          nodeSize.push_back(meanV[v]);
        }
        plc.Triangles.push_back(plcIndex[v]);
      }
      plc.TriangleMarkers.push_back(nb >= 0 ? 1 : 3); // 1 kept face, 3 domain boundary
      keptBeyond.push_back(nb);
    }
  }
  nBoundaryNodes = static_cast<std::int64_t>(nodeSize.size());
  {
    // Canonical order: nodes by coordinates, triangles by their (rotated)
    // node ids, so that the refill does not depend on V's numbering.
    std::vector<std::int64_t> order(nBoundaryNodes), rank(nBoundaryNodes);
    std::iota(order.begin(), order.end(), 0);
    const std::vector<double>& X = plc.Points;
    std::sort(order.begin(), order.end(), [&](std::int64_t a, std::int64_t b) {
      return std::lexicographical_compare(&X[3 * a], &X[3 * a] + 3, &X[3 * b], &X[3 * b] + 3);
    });
    std::vector<double> points(X.size()), sizes(nodeSize.size());
    for (std::int64_t k = 0; k < nBoundaryNodes; ++k)
    {
      rank[order[k]] = k;
      std::copy(&X[3 * order[k]], &X[3 * order[k]] + 3, &points[3 * k]);
      sizes[k] = nodeSize[order[k]];
    }
    plc.Points.swap(points);
    nodeSize.swap(sizes);
    for (std::int64_t& id : plcIndex)
    {
      id = id >= 0 ? rank[id] : id;
    }
    std::vector<std::array<std::int64_t, 5>> tris(plc.TriangleMarkers.size());
    for (std::size_t t = 0; t < tris.size(); ++t)
    {
      std::array<std::int64_t, 3> f = { rank[plc.Triangles[3 * t]], rank[plc.Triangles[3 * t + 1]],
        rank[plc.Triangles[3 * t + 2]] };
      std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
      tris[t] = { f[0], f[1], f[2], plc.TriangleMarkers[t], keptBeyond[t] };
    }
    std::sort(tris.begin(), tris.end());
    for (std::size_t t = 0; t < tris.size(); ++t)
    {
      std::copy(tris[t].begin(), tris[t].begin() + 3, &plc.Triangles[3 * t]);
      plc.TriangleMarkers[t] = static_cast<int>(tris[t][3]);
      keptBeyond[t] = tris[t][4];
    }
  }
}

// ---- S must lie inside the cavity: no S triangle may cross its boundary.
bool CavityRun::CheckSurfaceInsideCavity()
{
  nShell = plc.TriangleMarkers.size();
  {
    std::vector<Triangle> shell;
    for (std::size_t t = 0; t < nShell; ++t)
    {
      const std::int64_t* f = &plc.Triangles[3 * t];
      shell.emplace_back(P(&plc.Points[3 * f[0]]), P(&plc.Points[3 * f[1]]), P(&plc.Points[3 * f[2]]));
    }
    Tree shellTree(shell.begin(), shell.end());
    for (std::size_t t = 0; t < sTris.size() / 3; ++t)
    {
      const Triangle tri(P(&sPoints[3 * sTris[3 * t]]), P(&sPoints[3 * sTris[3 * t + 1]]),
        P(&sPoints[3 * sTris[3 * t + 2]]));
      if (shellTree.do_intersect(tri))
      {
        error = "the feature surface crosses the boundary of the cavity (the kept mesh is too "
                "close to it); raise RemovalFactor.";
        return false;
      }
    }
  }
  return true;
}

// S as internal facets (marker 2), or with prism layers the stack's outer
// surface (marker 4; the stack is built in the first attempt).
bool CavityRun::AddSurfaceOrStack(int attempt)
{
  if (!layers)
  {
    // S: internal facets, marker 2.
    plc.Points.insert(plc.Points.end(), sPoints.begin(), sPoints.end());
    nodeSize.insert(nodeSize.end(), sSize.begin(), sSize.end());
    for (std::int64_t id : sTris)
    {
      plc.Triangles.push_back(id + nBoundaryNodes);
    }
    plc.TriangleMarkers.insert(plc.TriangleMarkers.end(), sTris.size() / 3, 2);
  }
  else
  {
    if (attempt == 0)
    {
      // The layer stack, built against the cavity's boundary (the cavity
      // only grows in later attempts, so it stays clear of it).
      std::vector<double> obstacles(9 * nShell);
      for (std::size_t t = 0; t < nShell; ++t)
      {
        for (int k = 0; k < 3; ++k)
        {
          const double* x = &plc.Points[3 * plc.Triangles[3 * t + k]];
          std::copy(x, x + 3, &obstacles[9 * t + 3 * k]);
        }
      }
      std::string why;
      Lap(out.Seconds.Cavity);
      const bool built = BuildPrismLayers(sPoints.data(), sSize.size(), sTris.data(), sTris.size() / 3,
        obstacles.data(), nShell, options.Layers, stack, why);
      Lap(out.Seconds.Layers);
      if (!built)
      {
        error = "prism layers: " + why;
        return false;
      }
      // Its outer nodes in id order, with S's edge length at the point they stand on.
      const std::size_t nStack = stack.Points.size() / 3;
      std::vector<double> size(nStack, 0.0);
      std::vector<char> onOuter(nStack, 0);
      for (std::size_t i = 0; i < nStack; ++i)
      {
        size[i] = sSize[stack.PointSource[i]];
      }
      for (std::int64_t id : stack.OuterTriangles)
      {
        onOuter[id] = 1;
      }
      for (std::size_t i = 0; i < nStack; ++i)
      {
        if (onOuter[i])
        {
          stackOuter.push_back(static_cast<std::int64_t>(i));
          stackOuterSize.push_back(size[i]);
        }
      }
    }
    // Its outer surface: facets with marker 4, its nodes after the cavity's.
    std::vector<std::int64_t> stackPlc(stack.Points.size() / 3, -1);
    for (std::size_t j = 0; j < stackOuter.size(); ++j)
    {
      stackPlc[stackOuter[j]] = nBoundaryNodes + static_cast<std::int64_t>(j);
      plc.Points.insert(plc.Points.end(), &stack.Points[3 * stackOuter[j]], &stack.Points[3 * stackOuter[j]] + 3);
      nodeSize.push_back(stackOuterSize[j]);
    }
    for (std::int64_t id : stack.OuterTriangles)
    {
      plc.Triangles.push_back(stackPlc[id]);
    }
    plc.TriangleMarkers.insert(plc.TriangleMarkers.end(), stack.OuterTriangles.size() / 3, 4);
  }
  return true;
}

// A large cavity without layers: the strip that, with S, cuts it in two
// (ARCavitySeparator.h), as facets of marker 5 meshed on both sides. None
// when not `wanted` (SeparatorSkipped then says why).
void CavityRun::AddSeparator(bool wanted)
{
  out.SeparatorTriangles = 0;
  separatorPoints = 0;
  if (!wanted)
  {
    return;
  }
  out.SeparatorSkipped.clear();
  const auto cells = static_cast<std::size_t>(std::count(cavity.begin(), cavity.end(), char(1)));
  // (Whatever the threads: the output must not depend on them; with one
  // the two halves are refilled one after the other.)
  if (layers || cells < options.SplitRefillAbove)
  {
    return;
  }
  std::vector<std::int64_t> boundary(plc.Triangles.begin(), plc.Triangles.begin() + 3 * nShell), surface, strip;
  for (std::size_t t = nShell; t < plc.TriangleMarkers.size(); ++t)
  {
    if (plc.TriangleMarkers[t] == 2)
    {
      surface.insert(surface.end(), &plc.Triangles[3 * t], &plc.Triangles[3 * t] + 3);
    }
  }
  // The strip's triangles are kept as TetGen meets them (-Y): none under 5
  // degrees (on the 1e6 and 5e6 benchmark cubes its worst is 9-12 degrees,
  // 1 % under 24). Its own points may still move in the smoothing below.
  std::vector<double> added;
  if (!CavitySeparatingStrip(plc.Points, boundary, surface, 5.0, strip, added, out.SeparatorSkipped))
  {
    return;
  }
  // Its own points: sized as the strip's edges around them.
  const std::size_t first = plc.Points.size() / 3;
  plc.Points.insert(plc.Points.end(), added.begin(), added.end());
  nodeSize.resize(plc.Points.size() / 3, 0.0);
  std::vector<double> sum(added.size() / 3, 0.0);
  std::vector<int> count(added.size() / 3, 0);
  for (std::size_t t = 0; 3 * t < strip.size(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const std::int64_t a = strip[3 * t + k], b = strip[3 * t + (k + 1) % 3];
      const double len = Distance(&plc.Points[3 * a], &plc.Points[3 * b]);
      for (const std::int64_t v : { a, b })
      {
        if (static_cast<std::size_t>(v) >= first)
        {
          sum[v - first] += len;
          ++count[v - first];
        }
      }
    }
  }
  for (std::size_t i = 0; i < sum.size(); ++i)
  {
    nodeSize[first + i] = count[i] > 0 ? sum[i] / count[i] : 0.0;
  }
  plc.Triangles.insert(plc.Triangles.end(), strip.begin(), strip.end());
  plc.TriangleMarkers.insert(plc.TriangleMarkers.end(), strip.size() / 3, 5);
  out.SeparatorTriangles = strip.size() / 3;
  separatorPoints = added.size() / 3;
}

// Free points off S on both sides (with prism layers: off the stack's caps,
// outward), a regular tetrahedron's height above the centroids of the
// triangles, at least OffsetPointSpacing mean edges apart (see
// CavityOptions). Appended to the complex after every other point.
void CavityRun::AddOffsetPoints()
{
  offsetPoints = 0;
  const double spacing = options.OffsetPointSpacing;
  // The complex's triangles the points stand on: S's, on both sides, or
  // with layers the caps', on their outer side (their right-hand normal
  // points into the void).
  std::vector<std::size_t> base;
  std::vector<char> isBase(plc.TriangleMarkers.size(), 0);
  for (std::size_t t = nShell; t < plc.TriangleMarkers.size(); ++t)
  {
    const bool cap = layers && plc.TriangleMarkers[t] == 4 && stack.OuterTriangleKind[t - nShell] <= 1;
    if (cap || (!layers && plc.TriangleMarkers[t] == 2))
    {
      base.push_back(t);
      isBase[t] = 1;
    }
  }
  const int sides = layers ? 1 : 2;
  const std::size_t nTri = base.size();
  if (!(spacing > 0.0) || nTri == 0)
  {
    return;
  }
  const double heightFactor = std::sqrt(2.0 / 3.0); // a regular tetrahedron's apex over its base's centroid
  // Candidates, `sides` per triangle (+ side, then - side).
  std::vector<double> candidate(3 * sides * nTri), reach(nTri, 0.0), height(nTri, 0.0);
  for (std::size_t t = 0; t < nTri; ++t)
  {
    const std::int64_t* f = &plc.Triangles[3 * base[t]];
    const Point a = P(&plc.Points[3 * f[0]]), b = P(&plc.Points[3 * f[1]]), c = P(&plc.Points[3 * f[2]]);
    const Kernel::Vector_3 n = CGAL::cross_product(b - a, c - a);
    const double length = std::sqrt(n.squared_length());
    if (!(length > 0.0))
    {
      continue; // reach 0: no candidate
    }
    const double mean =
      (std::sqrt(CGAL::squared_distance(a, b)) + std::sqrt(CGAL::squared_distance(b, c)) +
        std::sqrt(CGAL::squared_distance(c, a))) / 3.0;
    reach[t] = spacing * mean;
    height[t] = heightFactor * mean;
    const Point centroid = CGAL::centroid(a, b, c);
    for (int side = 0; side < sides; ++side)
    {
      const Point x = centroid + n * ((side == 0 ? height[t] : -height[t]) / length);
      std::copy(x.cartesian_begin(), x.cartesian_end(), &candidate[3 * (sides * t + side)]);
    }
  }
  // In triangle order, a candidate stays when no earlier one is within the
  // larger of their spacings (a hash grid of cells as wide as the largest).
  const double cell = *std::max_element(reach.begin(), reach.end());
  if (!(cell > 0.0))
  {
    return;
  }
  struct KeyHash
  {
    std::size_t operator()(const std::array<std::int64_t, 3>& k) const
    {
      return static_cast<std::size_t>(k[0] * 73856093 ^ k[1] * 19349663 ^ k[2] * 83492791);
    }
  };
  std::unordered_map<std::array<std::int64_t, 3>, std::vector<std::size_t>, KeyHash> grid;
  std::vector<std::size_t> spaced; // candidate indices
  auto key = [&](const double* x) {
    return std::array<std::int64_t, 3>{ static_cast<std::int64_t>(std::floor(x[0] / cell)),
      static_cast<std::int64_t>(std::floor(x[1] / cell)), static_cast<std::int64_t>(std::floor(x[2] / cell)) };
  };
  for (std::size_t i = 0; i < sides * nTri; ++i)
  {
    if (!(reach[i / sides] > 0.0))
    {
      continue;
    }
    const double* x = &candidate[3 * i];
    const std::array<std::int64_t, 3> k = key(x);
    bool free = true;
    for (std::int64_t d0 = -1; d0 <= 1 && free; ++d0)
    {
      for (std::int64_t d1 = -1; d1 <= 1 && free; ++d1)
      {
        for (std::int64_t d2 = -1; d2 <= 1 && free; ++d2)
        {
          const auto it = grid.find({ k[0] + d0, k[1] + d1, k[2] + d2 });
          if (it == grid.end())
          {
            continue;
          }
          for (const std::size_t q : it->second)
          {
            if (Distance(x, &candidate[3 * q]) < std::max(reach[i / sides], reach[q / sides]))
            {
              free = false;
              break;
            }
          }
        }
      }
    }
    if (free)
    {
      grid[k].push_back(i);
      spaced.push_back(i);
    }
  }
  // Clear of the rest of the complex: no other face within a box of
  // half-width h around the point (it holds the segment from the centroid
  // out to the point), no triangle of S (of the caps) within half-width
  // 0.55 h (a plane at distance h stays outside such a box: 0.55 sqrt(3) <
  // 1; a concave surface or another piece closer than 0.55 h does not).
  std::vector<Triangle> others, surface;
  for (std::size_t t = 0; 3 * t < plc.Triangles.size(); ++t)
  {
    const std::int64_t* f = &plc.Triangles[3 * t];
    (isBase[t] ? surface : others).emplace_back(P(&plc.Points[3 * f[0]]), P(&plc.Points[3 * f[1]]), P(&plc.Points[3 * f[2]]));
  }
  const Tree othersTree(others.begin(), others.end()), surfaceTree(surface.begin(), surface.end());
  std::vector<char> clear(spaced.size(), 0);
  ParallelFor(
    spaced.size(),
    [&](std::size_t first, std::size_t last) {
      for (std::size_t k = first; k < last; ++k)
      {
        const std::size_t i = spaced[k];
        const Point x = P(&candidate[3 * i]);
        const double h = height[i / sides];
        clear[k] = !AnyWithin(othersTree, x, h) && !AnyWithin(surfaceTree, x, 0.55 * h) ? 1 : 0;
      }
    },
    Threads(), 2000);
  for (std::size_t k = 0; k < spaced.size(); ++k)
  {
    if (clear[k])
    {
      const std::size_t i = spaced[k];
      const std::int64_t* f = &plc.Triangles[3 * base[i / sides]];
      plc.Points.insert(plc.Points.end(), &candidate[3 * i], &candidate[3 * i] + 3);
      nodeSize.push_back((nodeSize[f[0]] + nodeSize[f[1]] + nodeSize[f[2]]) / 3.0);
      ++offsetPoints;
    }
  }
}

void CavityRun::AddHolePoints()
{
  // One hole point per patch of kept faces on the cavity's boundary (kept
  // faces joined across an edge where no other face of the complex meets
  // them: at an edge with more, kept regions that touch only along that
  // edge may meet, such as a kept tetrahedron the cavity surrounds, and each
  // needs its own hole point, or TetGen fills it; a region split into
  // several patches just gets several), inside the kept cell beyond the patch's
  // first face in the complex's canonical order: defined by the cavity's
  // boundary alone, whatever V's numbering or extent (the MPI driver refills
  // a gathered part of V). The first kept cell of each kept region in V's
  // order made TetGen's carving, and with it the refill's last flips, differ
  // between a serial run and a distributed one.
  const std::size_t nTriangles = keptBeyond.size();
  UnionFind patches =
    JoinByEdges(plc.Triangles.data(), nTriangles, [&](std::size_t t) { return keptBeyond[t] >= 0; }, nullptr, true);
  std::vector<char> holeDone(nTriangles, 0);
  for (std::size_t t = 0; t < nTriangles; ++t)
  {
    const std::int64_t r = keptBeyond[t] < 0 ? -1 : patches.Find(static_cast<std::int64_t>(t));
    if (r < 0 || holeDone[r])
    {
      continue;
    }
    holeDone[r] = 1;
    std::array<const double*, 4> corner; // summed in the order of their coordinates
    for (int k = 0; k < 4; ++k)
    {
      corner[k] = &V.Points[3 * V.Tetrahedra[4 * keptBeyond[t] + k]];
    }
    std::sort(corner.begin(), corner.end(), [](const double* a, const double* b) {
      return std::lexicographical_compare(a, a + 3, b, b + 3);
    });
    double c[3] = { 0.0, 0.0, 0.0 };
    for (const double* x : corner)
    {
      for (int d = 0; d < 3; ++d)
      {
        c[d] += 0.25 * x[d];
      }
    }
    plc.Holes.insert(plc.Holes.end(), c, c + 3);
  }
  // And one inside each piece of the layer stack.
  plc.Holes.insert(plc.Holes.end(), stack.HolePoints.begin(), stack.HolePoints.end());
  if (!plc.Holes.empty()) // no holes: both data() may be null, which memcpy must not get
  {
    std::vector<std::array<double, 3>> holes(plc.Holes.size() / 3);
    std::memcpy(holes.data(), plc.Holes.data(), plc.Holes.size() * sizeof(double));
    std::sort(holes.begin(), holes.end());
    std::memcpy(plc.Holes.data(), holes.data(), plc.Holes.size() * sizeof(double));
  }
  plc.PointSizes = nodeSize;
}

// ---- Refill (TetGen); one attempt.
bool CavityRun::Refill()
{
  Lap(out.Seconds.Cavity);
  ++out.RefillAttempts;
  if (!options.RefillFilesPrefix.empty() && !WriteTetGenFiles(plc, options.RefillFilesPrefix, error))
  {
    return false;
  }
  // In pieces: the cavity lies behind its boundary's faces (outward from
  // their cavity cell), on both sides of S, in front of the stack's outer
  // surface (oriented outward).
  std::vector<std::uint8_t> meshed(plc.TriangleMarkers.size());
  for (std::size_t t = 0; t < meshed.size(); ++t)
  {
    const int marker = plc.TriangleMarkers[t];
    meshed[t] = marker == 2 || marker == 5 ? MeshedBoth : (marker == 4 ? MeshedFront : MeshedBack);
  }
  const bool refilled = TetGenMeshComplexInPieces(plc, meshed, options.Quality, static_cast<unsigned>(Threads()), refill, error);
  out.RefillPieces = refill.Pieces;
  Lap(out.Seconds.Refill);
  if (!refilled)
  {
    error = "refilling the cavity: " + error;
    return false;
  }
  return true;
}

// Slivers of kept nodes only in the refill: the kept cells at them join the
// cavity. True when the cavity grew.
bool CavityRun::GrowAtSlivers()
{
  const double limit = SliverAngle();
  std::vector<std::int64_t> grow;
  for (std::size_t t = 0; t < refill.Mesh.NumberOfTetrahedra(); ++t)
  {
    const std::int64_t* v = &refill.Mesh.Tetrahedra[4 * t];
    int boundaryNodes = 0;
    for (int k = 0; k < 4; ++k)
    {
      boundaryNodes += v[k] < nBoundaryNodes ? 1 : 0;
    }
    if (boundaryNodes < 3)
    {
      continue;
    }
    double angles[6];
    TetDihedralAngles(&refill.Mesh.Points[3 * v[0]], &refill.Mesh.Points[3 * v[1]],
      &refill.Mesh.Points[3 * v[2]], &refill.Mesh.Points[3 * v[3]], angles);
    if (*std::min_element(angles, angles + 6) < limit)
    {
      for (int k = 0; k < 4; ++k)
      {
        if (v[k] < nBoundaryNodes)
        {
          grow.push_back(v[k]);
        }
      }
    }
  }
  if (grow.empty())
  {
    return false;
  }
  std::vector<char> atSliver(nV, 0);
  std::vector<std::int64_t> nodeOfPlc(nBoundaryNodes, -1);
  for (std::size_t v = 0; v < nV; ++v)
  {
    if (plcIndex[v] >= 0)
    {
      nodeOfPlc[plcIndex[v]] = static_cast<std::int64_t>(v);
    }
  }
  for (std::int64_t k : grow)
  {
    atSliver[nodeOfPlc[k]] = 1;
  }
  std::size_t added = 0;
  for (std::size_t t = 0; t < nT; ++t)
  {
    if (cavity[t])
    {
      continue;
    }
    for (int k = 0; k < 4; ++k)
    {
      const std::int64_t v = V.Tetrahedra[4 * t + k];
      if (atSliver[v] && (options.LockedNodes.empty() || !options.LockedNodes[v]))
      {
        cavity[t] = 1;
        ++added;
        break;
      }
    }
  }
  added += CloseOverGroups();
  return added > 0;
}

// ---- Output: V's points that are still used, then S's and TetGen's new points.
void CavityRun::Assemble()
{
  const std::size_t nRefillPoints = refill.Mesh.NumberOfPoints();
  std::vector<std::int64_t> outIndex(nV, -1);
  for (std::size_t t = 0; t < nT; ++t)
  {
    if (cavity[t])
    {
      continue;
    }
    for (int k = 0; k < 4; ++k)
    {
      outIndex[V.Tetrahedra[4 * t + k]] = 0;
    }
  }
  for (std::size_t v = 0; v < nV; ++v)
  {
    // Locked nodes stay even where no tetrahedron uses them: the caller's
    // kept non-tetrahedral cells do (e.g. the inner nodes of a layer stack).
    if (plcIndex[v] >= 0 || (!options.LockedNodes.empty() && options.LockedNodes[v]))
    {
      outIndex[v] = 0;
    }
  }
  // The output's sizes are known here: its arrays are allocated once (no
  // growth by doubling, which copies and faults in each new buffer).
  const std::size_t keptPoints = static_cast<std::size_t>(std::count(outIndex.begin(), outIndex.end(), 0));
  const std::size_t nStack = layers ? stack.Points.size() / 3 : 0;
  // TetGen's own points come after the complex's boundary nodes and the
  // stack's outer nodes.
  const std::size_t firstSteiner = static_cast<std::size_t>(nBoundaryNodes) + (layers ? stackOuter.size() : 0);
  // Free points of the complex TetGen did not use (AddOffsetPoints' outside
  // the region of their piece) are left out.
  std::vector<char> refillUsed(nRefillPoints, offsetPoints > 0 ? 0 : 1);
  if (offsetPoints > 0)
  {
    for (std::int64_t v : refill.Mesh.Tetrahedra)
    {
      refillUsed[v] = 1;
    }
  }
  std::size_t nSteiner = 0;
  for (std::size_t k = firstSteiner; k < nRefillPoints; ++k)
  {
    nSteiner += refillUsed[k] ? 1 : 0;
  }
  const std::size_t nOutPoints = keptPoints + nStack + nSteiner;
  const std::size_t keptTets =
    nT - static_cast<std::size_t>(std::count_if(cavity.begin(), cavity.end(), [](char c) { return c != 0; }));
  const std::size_t nOutTets =
    keptTets + refill.Mesh.NumberOfTetrahedra() + (layers ? stack.Tetrahedra.size() / 4 : 0);
  ReserveHuge(out.SourcePoint, nOutPoints);
  ReserveHuge(out.Mesh.Points, 3 * nOutPoints);
  ReserveHuge(out.Mesh.Tetrahedra, 4 * nOutTets);
  ReserveHuge(out.SourceCell, nOutTets);
  for (std::size_t v = 0; v < nV; ++v)
  {
    if (outIndex[v] == 0)
    {
      outIndex[v] = static_cast<std::int64_t>(out.SourcePoint.size());
      out.SourcePoint.push_back(static_cast<std::int64_t>(v));
      out.Mesh.Points.insert(out.Mesh.Points.end(), &V.Points[3 * v], &V.Points[3 * v] + 3);
    }
  }
  std::vector<char> used(nV, 0);
  for (std::int64_t v : V.Tetrahedra)
  {
    used[v] = 1;
  }
  for (std::size_t v = 0; v < nV; ++v)
  {
    out.RemovedNodes += (used[v] && outIndex[v] < 0) ? 1 : 0;
  }
  std::vector<std::int64_t> refillIndex(nRefillPoints, -1);
  for (std::size_t v = 0; v < nV; ++v)
  {
    if (plcIndex[v] >= 0)
    {
      refillIndex[plcIndex[v]] = outIndex[v];
    }
  }
  std::int64_t stackOffset = 0;
  if (layers)
  {
    // The stack's points (all of them), then TetGen's.
    stackOffset = static_cast<std::int64_t>(out.SourcePoint.size());
    out.SourcePoint.insert(out.SourcePoint.end(), stack.Points.size() / 3, -1);
    out.Mesh.Points.insert(out.Mesh.Points.end(), stack.Points.begin(), stack.Points.end());
    for (std::size_t j = 0; j < stackOuter.size(); ++j)
    {
      refillIndex[nBoundaryNodes + j] = stackOffset + stackOuter[j];
    }
  }
  for (std::size_t k = firstSteiner; k < nRefillPoints; ++k)
  {
    if (!refillUsed[k])
    {
      continue;
    }
    refillIndex[k] = static_cast<std::int64_t>(out.SourcePoint.size());
    out.SourcePoint.push_back(-1);
    out.Mesh.Points.insert(out.Mesh.Points.end(), &refill.Mesh.Points[3 * k], &refill.Mesh.Points[3 * k] + 3);
  }
  for (std::size_t t = 0; t < nT; ++t)
  {
    if (cavity[t])
    {
      continue;
    }
    for (int k = 0; k < 4; ++k)
    {
      out.Mesh.Tetrahedra.push_back(outIndex[V.Tetrahedra[4 * t + k]]);
    }
    out.SourceCell.push_back(static_cast<std::int64_t>(t));
  }
  for (std::size_t t = 0; t < refill.Mesh.NumberOfTetrahedra(); ++t)
  {
    for (int k = 0; k < 4; ++k)
    {
      out.Mesh.Tetrahedra.push_back(refillIndex[refill.Mesh.Tetrahedra[4 * t + k]]);
    }
    out.SourceCell.push_back(-1);
  }
  if (layers)
  {
    auto map = [&](std::vector<std::int64_t>& ids, const std::vector<std::int64_t>& from) {
      for (std::int64_t id : from)
      {
        ids.push_back(id + stackOffset);
      }
    };
    out.TetrahedronLayer.assign(out.SourceCell.size(), -1);
    out.TetrahedronSide.assign(out.SourceCell.size(), 0);
    map(out.Mesh.Tetrahedra, stack.Tetrahedra);
    out.SourceCell.insert(out.SourceCell.end(), stack.Tetrahedra.size() / 4, -1);
    out.TetrahedronLayer.insert(out.TetrahedronLayer.end(), stack.TetrahedronLayer.begin(), stack.TetrahedronLayer.end());
    out.TetrahedronSide.insert(out.TetrahedronSide.end(), stack.TetrahedronSide.begin(), stack.TetrahedronSide.end());
    map(out.Prisms, stack.Prisms);
    out.PrismLayer = stack.PrismLayer;
    out.PrismSide = stack.PrismSide;
    map(out.Pyramids, stack.Pyramids);
    out.PyramidLayer = stack.PyramidLayer;
    out.PyramidSide = stack.PyramidSide;
    out.FirstStackPoint = static_cast<std::size_t>(stackOffset);
    out.NumberOfStackPoints = stack.Points.size() / 3;
    out.LimitedColumns = stack.LimitedColumns;
    out.LayerStackHeight = stackHeight;
    // S: the faces between the two sides' innermost prisms (with one side,
    // between the prisms and TetGen's tetrahedra).
    map(out.Surface, sTris);
    return;
  }
  for (std::size_t f = 0; f < refill.FaceMarkers.size(); ++f)
  {
    if (refill.FaceMarkers[f] == 2)
    {
      for (int k = 0; k < 3; ++k)
      {
        out.Surface.push_back(refillIndex[refill.Faces[3 * f + k]]);
      }
    }
  }
}

}

bool RemeshLocalCavity(const TetMesh& V, const double* surfacePoints, std::size_t nSurfacePoints,
  const std::int64_t* surfaceTriangles, std::size_t nSurfaceTriangles, const CavityOptions& options,
  CavityRemesh& out, std::string& error)
{
  return CavityRun(V, surfacePoints, nSurfacePoints, surfaceTriangles, nSurfaceTriangles, options, out, error)
    .Execute(nullptr);
}

bool ComputeRemovedNodes(const TetMesh& V, const double* surfacePoints, std::size_t nSurfacePoints,
  const std::int64_t* surfaceTriangles, std::size_t nSurfaceTriangles, const CavityOptions& options,
  std::vector<std::uint8_t>& removed, std::string& error)
{
  CavityRemesh unused;
  removed.clear();
  return CavityRun(V, surfacePoints, nSurfacePoints, surfaceTriangles, nSurfaceTriangles, options, unused, error)
    .Execute(&removed);
}
}
