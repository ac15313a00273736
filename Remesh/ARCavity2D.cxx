// SPDX-License-Identifier: BSD-3-Clause
#include "ARCavity2D.h"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Arr_segment_traits_2.h>
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_no_edge_refinement_2.h>
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Fuzzy_sphere.h>
#include <CGAL/Kd_tree.h>
#include <CGAL/Search_traits_2.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/Surface_sweep_2_algorithms.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/property_map.h>

#include <boost/tuple/tuple.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <queue>
#include <set>
#include <sstream>

namespace ar
{
namespace
{
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point2 = K::Point_2;

// ---- The boundary of V as 3-D segments in the plane z = 0 (CGAL 5.5's AABB
// tree is three-dimensional): distances, visibility and "inside" queries.
using Point3 = K::Point_3;
using Segment3 = K::Segment_3;
using SegmentIterator = std::vector<Segment3>::const_iterator;
using SegmentPrimitive = CGAL::AABB_segment_primitive<K, SegmentIterator>;
using BoundaryTree = CGAL::AABB_tree<CGAL::AABB_traits<K, SegmentPrimitive>>;

// ---- Curve nodes in a kd-tree (the removal search).
using IndexedPoint = boost::tuple<Point2, std::size_t>;
using SearchTraits = CGAL::Search_traits_adapter<IndexedPoint,
  CGAL::Nth_of_tuple_property_map<0, IndexedPoint>, CGAL::Search_traits_2<K>>;
using KdTree = CGAL::Kd_tree<SearchTraits>;
using Circle = CGAL::Fuzzy_sphere<SearchTraits>;

// ---- The refill triangulation: vertex info = the node's index among the
// constrained nodes (-1 for the refinement's new points).
struct VertexInfo
{
  std::int64_t Id = -1;
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, K, CGAL::Delaunay_mesh_vertex_base_2<K>>;
using Fb = CGAL::Delaunay_mesh_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;

// ---- The size field's background: a Delaunay triangulation of the
// constrained nodes carrying their sizes, interpolated linearly.
using BVb = CGAL::Triangulation_vertex_base_with_info_2<double, K>;
using BTds = CGAL::Triangulation_data_structure_2<BVb>;
using Background = CGAL::Delaunay_triangulation_2<K, BTds>;

double SizeAt(const Background& bg, const Point2& p)
{
  const Background::Face_handle f = bg.locate(p);
  if (f == Background::Face_handle() || bg.is_infinite(f))
  {
    return bg.nearest_vertex(p)->info();
  }
  const Point2& a = f->vertex(0)->point();
  const Point2& b = f->vertex(1)->point();
  const Point2& c = f->vertex(2)->point();
  const double total = CGAL::area(a, b, c);
  if (!(total > 0.0))
  {
    return bg.nearest_vertex(p)->info();
  }
  const double wa = CGAL::area(p, b, c) / total;
  const double wb = CGAL::area(a, p, c) / total;
  const double wc = 1.0 - wa - wb;
  return wa * f->vertex(0)->info() + wb * f->vertex(1)->info() + wc * f->vertex(2)->info();
}

/// Mesh criteria: the squared sine of the smallest angle at least B, and the
/// longest edge at most Ratio times the size field at the centroid (the
/// quality type and its priority are those of CGAL's size criteria).
class GradedCriteria
{
public:
  using Quality = CGAL::Delaunay_mesh_size_criteria_2<CDT>::Quality;

  GradedCriteria(double b, const Background* background, double ratio)
    : B(b)
    , Bg(background)
    , Ratio(ratio)
  {
  }

  class Is_bad
  {
  public:
    Is_bad(double b, const Background* background, double ratio)
      : B(b)
      , Bg(background)
      , Ratio(ratio)
    {
    }

    CGAL::Mesh_2::Face_badness operator()(const Quality q) const
    {
      if (q.size() > 1)
      {
        return CGAL::Mesh_2::IMPERATIVELY_BAD;
      }
      return q.sine() < this->B ? CGAL::Mesh_2::BAD : CGAL::Mesh_2::NOT_BAD;
    }

    CGAL::Mesh_2::Face_badness operator()(const CDT::Face_handle& fh, Quality& q) const
    {
      const Point2& pa = fh->vertex(0)->point();
      const Point2& pb = fh->vertex(1)->point();
      const Point2& pc = fh->vertex(2)->point();
      std::array<double, 3> sq = { CGAL::squared_distance(pb, pc), CGAL::squared_distance(pc, pa),
        CGAL::squared_distance(pa, pb) };
      std::sort(sq.begin(), sq.end());
      const double h = this->Ratio * SizeAt(*this->Bg, CGAL::centroid(pa, pb, pc));
      q.second = sq[2] / (h * h);
      if (q.size() > 1)
      {
        q.first = 1;
        return CGAL::Mesh_2::IMPERATIVELY_BAD;
      }
      const double area2 = 2.0 * CGAL::area(pa, pb, pc);
      q.first = area2 * area2 / (sq[2] * sq[1]);
      return this->operator()(q);
    }

  private:
    double B;
    const Background* Bg;
    double Ratio;
  };

  Is_bad is_bad_object() const { return Is_bad(this->B, this->Bg, this->Ratio); }

private:
  double B;
  const Background* Bg;
  double Ratio;
};

double Distance(const double* a, const double* b)
{
  return std::hypot(a[0] - b[0], a[1] - b[1]);
}

bool Finite(const double* x, std::size_t n)
{
  return std::all_of(x, x + n, [](double v) { return std::isfinite(v); });
}

/// Parity of boundary crossings along three rays (majority), for "inside V".
bool Inside(const BoundaryTree& tree, const double* x)
{
  static const double dirs[3][2] = { { 0.5773, 0.8166 }, { -0.9123, 0.4095 }, { 0.2071, -0.9783 } };
  int votes = 0;
  for (const auto& d : dirs)
  {
    const K::Ray_3 ray(Point3(x[0], x[1], 0.0), K::Vector_3(d[0], d[1], 0.0));
    votes += (tree.number_of_intersected_primitives(ray) % 2 == 1) ? 1 : 0;
  }
  return votes >= 2;
}

/// True when two of the segments (pairs of 2-D points) cross or overlap
/// anywhere but at shared end points (CGAL's surface sweep, exact).
bool SegmentsCross(const std::vector<std::array<double, 4>>& segments)
{
  using EK = CGAL::Exact_predicates_exact_constructions_kernel;
  using Traits = CGAL::Arr_segment_traits_2<EK>;
  std::vector<Traits::Curve_2> curves;
  curves.reserve(segments.size());
  for (const auto& s : segments)
  {
    curves.emplace_back(EK::Point_2(s[0], s[1]), EK::Point_2(s[2], s[3]));
  }
  return CGAL::do_curves_intersect(curves.begin(), curves.end());
}

double SmallestAngle(const Point2& a, const Point2& b, const Point2& c)
{
  const Point2* p[3] = { &a, &b, &c };
  double smallest = 180.0;
  for (int k = 0; k < 3; ++k)
  {
    const K::Vector_2 u = *p[(k + 1) % 3] - *p[k], v = *p[(k + 2) % 3] - *p[k];
    const double angle = std::atan2(std::abs(u.x() * v.y() - u.y() * v.x()), u * v);
    smallest = std::min(smallest, angle * 180.0 / M_PI);
  }
  return smallest;
}

// ---- Layers (Cavity2DOptions::Layers): the band of quads around the curves.

/// One curve as an ordered list of curve nodes; Closed: the last joins the first.
struct Chain
{
  std::vector<std::int64_t> Nodes;
  bool Closed = false;
};

/// The curves' segments as chains; false with `error` for a node in three or
/// more segments (a branch) or a curve of one segment.
bool CurveChains(std::size_t nCurve, const std::vector<std::int64_t>& segs, std::vector<Chain>& chains,
  std::string& error)
{
  std::vector<std::vector<std::int64_t>> adjacent(nCurve);
  std::set<std::pair<std::int64_t, std::int64_t>> directed;
  for (std::size_t s = 0; s < segs.size(); s += 2)
  {
    adjacent[segs[s]].push_back(segs[s + 1]);
    adjacent[segs[s + 1]].push_back(segs[s]);
    directed.insert({ segs[s], segs[s + 1] });
  }
  for (std::size_t i = 0; i < nCurve; ++i)
  {
    if (adjacent[i].size() > 2)
    {
      error = "layers: the feature curve branches (a node in " + std::to_string(adjacent[i].size()) +
        " segments); layers need curves without branches.";
      return false;
    }
  }
  std::vector<char> visited(nCurve, 0);
  auto walk = [&](std::int64_t start, bool closed) {
    Chain chain;
    chain.Closed = closed;
    std::int64_t previous = -1, at = start;
    // Follow the segments' direction where it is consistent.
    if (adjacent[start].size() == 2 && !directed.count({ start, adjacent[start][0] }) &&
      directed.count({ start, adjacent[start][1] }))
    {
      previous = adjacent[start][0];
    }
    while (at >= 0 && !visited[at])
    {
      visited[at] = 1;
      chain.Nodes.push_back(at);
      std::int64_t next = -1;
      for (const std::int64_t b : adjacent[at])
      {
        if (b != previous && !visited[b])
        {
          next = b;
          break;
        }
      }
      previous = at;
      at = next;
    }
    chains.push_back(chain);
  };
  for (std::size_t i = 0; i < nCurve; ++i)
  {
    if (!visited[i] && adjacent[i].size() == 1)
    {
      // Start at the end a segment leaves from, when there is one.
      const std::int64_t other = adjacent[i][0];
      bool forward = directed.count({ static_cast<std::int64_t>(i), other }) > 0;
      if (!forward)
      {
        // the other end of this chain may be the start
        std::int64_t previous = static_cast<std::int64_t>(i), at = other;
        while (adjacent[at].size() == 2)
        {
          const std::int64_t next = adjacent[at][0] == previous ? adjacent[at][1] : adjacent[at][0];
          previous = at;
          at = next;
        }
        if (directed.count({ at, previous }))
        {
          walk(at, false);
          continue;
        }
      }
      walk(static_cast<std::int64_t>(i), false);
    }
  }
  for (std::size_t i = 0; i < nCurve; ++i)
  {
    if (!visited[i] && adjacent[i].size() == 2)
    {
      walk(static_cast<std::int64_t>(i), true);
    }
  }
  for (const Chain& c : chains)
  {
    if (c.Nodes.size() < 3)
    {
      error = "layers: a feature curve of " + std::to_string(c.Nodes.size() - 1) +
        " segment(s) after the trim cannot carry layers (they taper to nothing at its ends); use a "
        "shorter SurfaceEdgeLength or no layers.";
      return false;
    }
  }
  return true;
}

/// The band: ids 0 .. nCurve-1 are the curve nodes, nCurve + j layer point j.
struct Band
{
  std::vector<double> Points;                    ///< layer points, x y
  std::vector<std::int64_t> PointNode;           ///< per layer point: its curve node
  std::vector<double> Normal;                    ///< per curve node: x y (+ side)
  std::vector<double> Height;                    ///< per curve node: + side, then per curve node: - side
  std::vector<std::vector<std::int64_t>> Cells;  ///< counter-clockwise, band ids
  std::vector<int> CellLayer, CellSide;
  std::vector<std::array<std::int64_t, 2>> Walls; ///< the outermost polylines' segments, band ids
  std::size_t Quads = 0, Triangles = 0, Limited = 0;
  int Rounds = 0;
};

double Cross(const double* o, const double* a, const double* b)
{
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

/**
 * Builds the band around the chains (ARCavity2D.h: Normals, Heights): the
 * inputs, the state the stages share, and the stages in the order they run
 * (Execute): the normals, the heights (the full stack, the clearances, the
 * grading), then rounds of the cells and their check until no column fails.
 * `shell`: the cavity's boundary edges (x0 y0 x1 y1).
 */
class BandBuilder
{
public:
  BandBuilder(const std::vector<double>& x_, const std::vector<Chain>& chains_,
    const std::vector<std::array<double, 4>>& shell_, const PrismLayerOptions& o_, const std::vector<double>& z_,
    Band& band_, std::string& error_)
    : x(x_)
    , chains(chains_)
    , shell(shell_)
    , o(o_)
    , z(z_)
    , band(band_)
    , error(error_)
    , nCurve(x_.size() / 2)
    , N(o_.NumberOfLayers)
    , Z(z_.back())
  {
  }

  bool Execute();

private:
  void SegmentNormals(const Chain& c); ///< the unit normals of the segments at each node
  bool NodeNormals(const Chain& c);    ///< the mean of a node's segments' normals
  void SmoothNormals(const Chain& c);  ///< the Jacobi passes
  void CornerFloor();
  void FullHeights();            ///< the full stack, 0 at open ends (and on the - side without BothSides)
  void ClearanceAlongNormals();  ///< GapFraction of the free distance along the normals
  void ClearanceToOtherCurves(); ///< GapFraction of the distance to any other curve
  void Grade();                  ///< |H_u - H_v| <= MaxHeightGradient |x_u - x_v|
  void PlacePoints();            ///< the layer points of the current heights
  void BuildCells();             ///< the layer cells, each checked
  void CheckWalls();             ///< the outermost polylines cross nothing
  bool Shrink(int round);        ///< the failing columns by 0.7
  void CountLimited();

  /// The smallest dot of `n` with the normals of node i's segments.
  double Visibility(std::int64_t i, const double* n) const
  {
    double v = 1.0;
    for (int k = 0; k < segCount[i]; ++k)
    {
      v = std::min(v, n[0] * segNormals[i][2 * k] + n[1] * segNormals[i][2 * k + 1]);
    }
    return v;
  }
  /// The band id of node i's layer boundary k on side s (k = 0: the node).
  std::int64_t Id(std::int64_t i, int s, int k) const
  {
    return k == 0 || firstPoint[s * nCurve + i] < 0
      ? i
      : static_cast<std::int64_t>(nCurve) + firstPoint[s * nCurve + i] + k - 1;
  }
  const double* Position(std::int64_t b) const
  {
    return b < static_cast<std::int64_t>(nCurve) ? &x[2 * b] : &band.Points[2 * (b - nCurve)];
  }
  /// Columns a and b on side s fail (those of height > 0).
  void Fail(std::int64_t a, std::int64_t b, int s)
  {
    for (const std::int64_t i : { a, b })
    {
      if (band.Height[s * nCurve + i] > 0.0)
      {
        failing.insert(s * static_cast<std::int64_t>(nCurve) + i);
      }
    }
  }

  static constexpr double Visible = 0.3;            // as ARPrismLayers: the dot a normal keeps with its segments
  static constexpr double MinHeightFraction = 1e-3; // as ARPrismLayers
  static constexpr int MaxRounds = 60;

  // Inputs.
  const std::vector<double>& x;
  const std::vector<Chain>& chains;
  const std::vector<std::array<double, 4>>& shell;
  const PrismLayerOptions& o;
  const std::vector<double>& z;
  Band& band;
  std::string& error;
  const std::size_t nCurve;
  const int N;
  const double Z;
  // Normals: per node the normals of its (one or two) segments.
  std::vector<std::array<double, 4>> segNormals;
  std::vector<int> segCount;
  double cornerFloor = 0.05; // a layer quad's corner sine is at least this
  // The rounds: per column (s * nCurve + i) its first layer point or -1; the
  // failing columns; per wall its columns (a, b, side).
  std::vector<std::int64_t> firstPoint;
  std::set<std::int64_t> failing;
  std::vector<std::array<std::int64_t, 3>> wallColumns;
};

bool BandBuilder::Execute()
{
  band = Band();
  band.Normal.assign(2 * nCurve, 0.0);
  band.Height.assign(2 * nCurve, 0.0);
  segNormals.assign(nCurve, std::array<double, 4>{});
  segCount.assign(nCurve, 0);
  for (const Chain& c : chains)
  {
    SegmentNormals(c);
    if (!NodeNormals(c))
    {
      return false;
    }
    SmoothNormals(c);
  }
  CornerFloor();
  FullHeights();
  ClearanceAlongNormals();
  if (chains.size() > 1)
  {
    ClearanceToOtherCurves();
  }
  Grade();
  firstPoint.assign(2 * nCurve, -1);
  for (int round = 0;; ++round)
  {
    PlacePoints();
    BuildCells();
    CheckWalls();
    if (failing.empty())
    {
      break;
    }
    if (!Shrink(round))
    {
      return false;
    }
    Grade();
  }
  CountLimited();
  return true;
}

// ---- Normals.
void BandBuilder::SegmentNormals(const Chain& c)
{
  const std::size_t m = c.Nodes.size(), nSeg = c.Closed ? m : m - 1;
  for (std::size_t j = 0; j < nSeg; ++j)
  {
    const std::int64_t a = c.Nodes[j], b = c.Nodes[(j + 1) % m];
    const double dx = x[2 * b] - x[2 * a], dy = x[2 * b + 1] - x[2 * a + 1], l = std::hypot(dx, dy);
    for (const std::int64_t i : { a, b })
    {
      segNormals[i][2 * segCount[i]] = -dy / l;
      segNormals[i][2 * segCount[i] + 1] = dx / l;
      ++segCount[i];
    }
  }
}

bool BandBuilder::NodeNormals(const Chain& c)
{
  for (const std::int64_t i : c.Nodes)
  {
    double n[2] = { 0.0, 0.0 };
    for (int k = 0; k < segCount[i]; ++k)
    {
      n[0] += segNormals[i][2 * k];
      n[1] += segNormals[i][2 * k + 1];
    }
    const double l = std::hypot(n[0], n[1]);
    if (!(l > 1e-9) || !(Visibility(i, n) / l > 0.0))
    {
      std::ostringstream msg;
      msg << "layers: the feature curve turns back on itself at (" << x[2 * i] << ", " << x[2 * i + 1]
          << "): no direction there sees both of its segments.";
      error = msg.str();
      return false;
    }
    band.Normal[2 * i] = n[0] / l;
    band.Normal[2 * i + 1] = n[1] / l;
  }
  return true;
}

void BandBuilder::SmoothNormals(const Chain& c)
{
  const std::size_t m = c.Nodes.size();
  for (int pass = 0; pass < o.NormalSmoothingIterations; ++pass)
  {
    const std::vector<double> old = band.Normal;
    for (std::size_t j = 0; j < m; ++j)
    {
      if (!c.Closed && (j <= 1 || j + 2 >= m))
      {
        // An end is tapered to height 0 (its normal is not used); its
        // neighbour keeps the mean of its segments' normals, exact on a
        // circle, where a stencil through the end's would tilt it.
        continue;
      }
      const std::int64_t i = c.Nodes[j], p = c.Nodes[(j + m - 1) % m], q = c.Nodes[(j + 1) % m];
      double n[2] = { old[2 * p] + 2.0 * old[2 * i] + old[2 * q], old[2 * p + 1] + 2.0 * old[2 * i + 1] + old[2 * q + 1] };
      const double l = std::hypot(n[0], n[1]);
      if (!(l > 0.0))
      {
        continue;
      }
      n[0] /= l;
      n[1] /= l;
      if (Visibility(i, n) >= std::min(Visible, Visibility(i, &old[2 * i])))
      {
        band.Normal[2 * i] = n[0];
        band.Normal[2 * i + 1] = n[1];
      }
    }
  }
}

// The corner floor: min(0.05, half the layer-0 corner sine the normals set).
void BandBuilder::CornerFloor()
{
  cornerFloor = 0.05;
  for (const Chain& c : chains)
  {
    for (const std::int64_t i : c.Nodes)
    {
      cornerFloor = std::min(cornerFloor, 0.5 * Visibility(i, &band.Normal[2 * i]));
    }
  }
}

// ---- Heights.
void BandBuilder::FullHeights()
{
  for (const Chain& c : chains)
  {
    for (std::size_t j = 0; j < c.Nodes.size(); ++j)
    {
      const std::int64_t i = c.Nodes[j];
      const bool end = !c.Closed && (j == 0 || j + 1 == c.Nodes.size());
      band.Height[i] = end ? 0.0 : Z;
      band.Height[nCurve + i] = end || !o.BothSides ? 0.0 : Z;
    }
  }
}

// Clearance along the normals: GapFraction of the free distance to the
// cavity's boundary and to the curves (segments at the node skipped).
void BandBuilder::ClearanceAlongNormals()
{
  std::vector<Segment3> segments;
  std::vector<std::array<std::int64_t, 2>> ends; // curve segments' nodes; -1 for the shell
  for (const auto& e : shell)
  {
    segments.emplace_back(Point3(e[0], e[1], 0.0), Point3(e[2], e[3], 0.0));
    ends.push_back({ -1, -1 });
  }
  for (const Chain& c : chains)
  {
    const std::size_t m = c.Nodes.size(), nSeg = c.Closed ? m : m - 1;
    for (std::size_t j = 0; j < nSeg; ++j)
    {
      const std::int64_t a = c.Nodes[j], b = c.Nodes[(j + 1) % m];
      segments.emplace_back(Point3(x[2 * a], x[2 * a + 1], 0.0), Point3(x[2 * b], x[2 * b + 1], 0.0));
      ends.push_back({ a, b });
    }
  }
  BoundaryTree tree(segments.begin(), segments.end());
  std::vector<BoundaryTree::Primitive_id> hits;
  const double reach = Z / o.GapFraction;
  for (std::size_t i = 0; i < nCurve; ++i)
  {
    for (int s = 0; s < 2; ++s)
    {
      double& h = band.Height[s * nCurve + i];
      if (!(h > 0.0))
      {
        continue;
      }
      const double sign = s == 0 ? 1.0 : -1.0;
      const double d[2] = { sign * band.Normal[2 * i], sign * band.Normal[2 * i + 1] };
      const double* p = &x[2 * i];
      hits.clear();
      tree.all_intersected_primitives(
        Segment3(Point3(p[0], p[1], 0.0), Point3(p[0] + reach * d[0], p[1] + reach * d[1], 0.0)),
        std::back_inserter(hits));
      double free = reach;
      for (const auto& hit : hits)
      {
        const std::size_t k = static_cast<std::size_t>(hit - segments.begin());
        if (ends[k][0] == static_cast<std::int64_t>(i) || ends[k][1] == static_cast<std::int64_t>(i))
        {
          continue;
        }
        // p + t d on the segment a + u (b - a): t by Cramer's rule.
        const double ax = hit->source().x(), ay = hit->source().y();
        const double ex = hit->target().x() - ax, ey = hit->target().y() - ay;
        const double det = d[0] * (-ey) - d[1] * (-ex);
        if (std::abs(det) < 1e-300)
        {
          free = std::min(free, std::hypot(ax - p[0], ay - p[1])); // along the ray
          continue;
        }
        const double rx = ax - p[0], ry = ay - p[1];
        const double t = (rx * (-ey) - ry * (-ex)) / det;
        free = std::min(free, std::max(0.0, t));
      }
      h = std::min(h, o.GapFraction * free);
    }
  }
}

// And GapFraction of the distance to any other curve, in every direction:
// where two curves come close at a small angle, or one ends next to
// another, the rays along the normals can miss it, and the two bands'
// outlines would leave the refill only needles between them (0.001
// degrees, seen on a second cycle whose shock was fitted in two pieces).
void BandBuilder::ClearanceToOtherCurves()
{
  std::vector<std::vector<Segment3>> pieces(chains.size());
  for (std::size_t c = 0; c < chains.size(); ++c)
  {
    const std::vector<std::int64_t>& v = chains[c].Nodes;
    const std::size_t m = v.size(), nSeg = chains[c].Closed ? m : m - 1;
    for (std::size_t j = 0; j < nSeg; ++j)
    {
      const double* a = &x[2 * v[j]];
      const double* b = &x[2 * v[(j + 1) % m]];
      pieces[c].emplace_back(Point3(a[0], a[1], 0.0), Point3(b[0], b[1], 0.0));
    }
  }
  std::vector<BoundaryTree> trees(chains.size());
  for (std::size_t c = 0; c < chains.size(); ++c)
  {
    trees[c].insert(pieces[c].begin(), pieces[c].end());
    trees[c].build();
    trees[c].accelerate_distance_queries();
  }
  for (std::size_t c = 0; c < chains.size(); ++c)
  {
    for (const std::int64_t i : chains[c].Nodes)
    {
      const Point3 p(x[2 * i], x[2 * i + 1], 0.0);
      for (std::size_t d = 0; d < chains.size(); ++d)
      {
        if (d == c)
        {
          continue;
        }
        const double gap = o.GapFraction * std::sqrt(CGAL::to_double(trees[d].squared_distance(p)));
        band.Height[i] = std::min(band.Height[i], gap);
        band.Height[nCurve + i] = std::min(band.Height[nCurve + i], gap);
      }
    }
  }
}

// Grading along each chain (both directions until nothing changes; it only lowers).
void BandBuilder::Grade()
{
  for (const Chain& c : chains)
  {
    const std::size_t m = c.Nodes.size(), nSeg = c.Closed ? m : m - 1;
    for (int s = 0; s < 2; ++s)
    {
      double* H = &band.Height[s * nCurve];
      for (bool changed = true; changed;)
      {
        changed = false;
        for (int dir = 0; dir < 2; ++dir)
        {
          for (std::size_t jj = 0; jj < nSeg; ++jj)
          {
            const std::size_t j = dir == 0 ? jj : nSeg - 1 - jj;
            std::int64_t a = c.Nodes[j], b = c.Nodes[(j + 1) % m];
            if (dir == 1)
            {
              std::swap(a, b);
            }
            const double limit = H[a] + o.MaxHeightGradient * Distance(&x[2 * a], &x[2 * b]);
            if (H[b] > limit)
            {
              H[b] = limit;
              changed = true;
            }
          }
        }
      }
    }
  }
}

// ---- The rounds: the cells and the check; failing columns shrink by 0.7.
void BandBuilder::PlacePoints()
{
  band.Points.clear();
  band.PointNode.clear();
  std::fill(firstPoint.begin(), firstPoint.end(), -1);
  for (std::size_t i = 0; i < nCurve; ++i)
  {
    for (int s = 0; s < 2; ++s)
    {
      const double h = band.Height[s * nCurve + i];
      if (!(h > 0.0) || segCount[i] == 0)
      {
        continue;
      }
      firstPoint[s * nCurve + i] = static_cast<std::int64_t>(band.PointNode.size());
      const double sign = s == 0 ? 1.0 : -1.0;
      for (int k = 1; k <= N; ++k)
      {
        const double t = sign * h * z[k] / Z;
        band.Points.push_back(x[2 * i] + t * band.Normal[2 * i]);
        band.Points.push_back(x[2 * i + 1] + t * band.Normal[2 * i + 1]);
        band.PointNode.push_back(static_cast<std::int64_t>(i));
      }
    }
  }
}

void BandBuilder::BuildCells()
{
  band.Cells.clear();
  band.CellLayer.clear();
  band.CellSide.clear();
  band.Walls.clear();
  band.Quads = band.Triangles = 0;
  failing.clear();
  wallColumns.clear();
  for (const Chain& c : chains)
  {
    const std::size_t m = c.Nodes.size(), nSeg = c.Closed ? m : m - 1;
    for (std::size_t j = 0; j < nSeg; ++j)
    {
      const std::int64_t a = c.Nodes[j], b = c.Nodes[(j + 1) % m];
      for (int s = 0; s < 2; ++s)
      {
        band.Walls.push_back({ Id(a, s, N), Id(b, s, N) });
        wallColumns.push_back({ a, b, s });
        if (!(band.Height[s * nCurve + a] > 0.0) && !(band.Height[s * nCurve + b] > 0.0))
        {
          continue;
        }
        for (int k = 0; k < N; ++k)
        {
          std::vector<std::int64_t> ring = s == 0
            ? std::vector<std::int64_t>{ Id(a, 0, k), Id(b, 0, k), Id(b, 0, k + 1), Id(a, 0, k + 1) }
            : std::vector<std::int64_t>{ Id(a, 1, k), Id(a, 1, k + 1), Id(b, 1, k + 1), Id(b, 1, k) };
          std::vector<std::int64_t> cell;
          for (std::size_t r = 0; r < ring.size(); ++r)
          {
            if (ring[r] != ring[(r + 1) % ring.size()])
            {
              cell.push_back(ring[r]);
            }
          }
          const std::size_t n = cell.size();
          bool ok = n >= 3;
          for (std::size_t r = 0; ok && r < n; ++r)
          {
            const double* p = Position(cell[r]);
            const double* q = Position(cell[(r + 1) % n]);
            const double* w = Position(cell[(r + n - 1) % n]);
            const double scale = Distance(p, q) * Distance(p, w);
            const double sine = Cross(p, q, w) / scale;
            ok = n == 4 ? sine >= cornerFloor : (sine > 0.0 && scale > 0.0);
          }
          if (!ok)
          {
            Fail(a, b, s);
          }
          band.Cells.push_back(cell);
          band.CellLayer.push_back(k);
          band.CellSide.push_back(s == 0 ? 1 : -1);
          ++(n == 4 ? band.Quads : band.Triangles);
        }
      }
    }
  }
}

// The outermost polylines cross neither each other nor the cavity's boundary.
void BandBuilder::CheckWalls()
{
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 2, std::size_t>;
  std::vector<Box> boxes;
  std::vector<std::array<double, 4>> all;
  for (const auto& w : band.Walls)
  {
    const double* p = Position(w[0]);
    const double* q = Position(w[1]);
    all.push_back({ p[0], p[1], q[0], q[1] });
  }
  all.insert(all.end(), shell.begin(), shell.end());
  for (std::size_t k = 0; k < all.size(); ++k)
  {
    const auto& e = all[k];
    boxes.emplace_back(CGAL::Bbox_2(std::min(e[0], e[2]), std::min(e[1], e[3]), std::max(e[0], e[2]),
                         std::max(e[1], e[3])),
      k);
  }
  const std::size_t nWalls = band.Walls.size();
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& u, const Box& v) {
    std::size_t i = u.info(), j = v.info();
    if (i >= nWalls && j >= nWalls)
    {
      return; // two edges of the kept mesh
    }
    if (i > j)
    {
      std::swap(i, j);
    }
    if (j < nWalls)
    {
      const auto& a = band.Walls[i];
      const auto& b = band.Walls[j];
      if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1])
      {
        return; // neighbours along a polyline, or the two sides meeting at an end
      }
    }
    const K::Segment_2 si(Point2(all[i][0], all[i][1]), Point2(all[i][2], all[i][3]));
    const K::Segment_2 sj(Point2(all[j][0], all[j][1]), Point2(all[j][2], all[j][3]));
    if (CGAL::do_intersect(si, sj))
    {
      for (const std::size_t k : { i, j })
      {
        if (k < nWalls)
        {
          Fail(wallColumns[k][0], wallColumns[k][1], static_cast<int>(wallColumns[k][2]));
        }
      }
    }
  });
}

bool BandBuilder::Shrink(int round)
{
  if (round >= MaxRounds)
  {
    error = "layers: the layer cells could not be made valid in " + std::to_string(MaxRounds) + " rounds.";
    return false;
  }
  ++band.Rounds;
  for (const std::int64_t col : failing)
  {
    band.Height[col] *= 0.7;
    if (band.Height[col] < MinHeightFraction * Z)
    {
      const std::int64_t i = col % static_cast<std::int64_t>(nCurve);
      std::ostringstream msg;
      msg << "layers: the stack at (" << x[2 * i] << ", " << x[2 * i + 1] << ") on its "
          << (col < static_cast<std::int64_t>(nCurve) ? "+" : "-")
          << " side would have to shrink below 1e-3 of its height " << Z
          << " to stay valid (a fold, or the cavity's boundary or another curve in the way); lower the "
             "layers' thickness or raise RemovalFactor.";
      error = msg.str();
      return false;
    }
  }
  return true;
}

void BandBuilder::CountLimited()
{
  for (const Chain& c : chains)
  {
    for (const std::int64_t i : c.Nodes)
    {
      for (int s = 0; s < 2; ++s)
      {
        band.Limited += band.Height[s * nCurve + i] < Z * (1.0 - 1e-12) && (s == 0 || o.BothSides) ? 1 : 0;
      }
    }
  }
}

/// The band around the chains (BandBuilder).
bool BuildBand(const std::vector<double>& x, const std::vector<Chain>& chains,
  const std::vector<std::array<double, 4>>& shell, const PrismLayerOptions& o, const std::vector<double>& z,
  Band& band, std::string& error)
{
  BandBuilder builder(x, chains, shell, o, z, band, error);
  return builder.Execute();
}

/**
 * One RemeshLocalCavity2D run: the inputs, the state its stages share, and
 * the stages in the order they run (Execute), each a step of the header's
 * algorithm; as CavityRun does for the 3-D cavity.
 */
class Cavity2DRun
{
public:
  Cavity2DRun(const Mesh2D& v, const double* curvePoints_, std::size_t nCurvePoints_,
    const std::int64_t* curveSegments_, std::size_t nCurveSegments_, const Cavity2DOptions& options_,
    Cavity2DRemesh& out_, std::string& error_)
    : V(v)
    , curvePoints(curvePoints_)
    , nCurvePoints(nCurvePoints_)
    , curveSegments(curveSegments_)
    , nCurveSegments(nCurveSegments_)
    , options(options_)
    , out(out_)
    , error(error_)
    , nV(v.NumberOfPoints())
    , nC(v.NumberOfCells())
    , X(v.Points.data())
  {
  }

  bool Execute();

private:
  bool Validate();                ///< the inputs' sizes, coordinates and curve ids
  bool CheckLayerOptions();       ///< before any work
  bool ValidateCells();           ///< triangles and quads, convex and counter-clockwise
  bool MeasureEdges();            ///< the edges' cells (conforming), l_v and the mean edge at V's nodes
  void MeasureCurve();            ///< l_c at the curves' nodes
  void BuildBoundaryTree();       ///< V's boundary edges
  bool TrimCurves();              ///< inside V and BoundaryMargin from its boundary
  bool CheckCurvesCross();
  void MarkRemovedNodes();
  bool MarkCavity();              ///< cells touching removed nodes
  void BuildShell();              ///< the cavity's boundary edges and their nodes
  bool CheckCurvesInsideCavity(); ///< no curve crosses the cavity's boundary
  bool BuildLayers();             ///< the band (options.Layers on)
  void CollectConstraints();      ///< the constrained nodes and edges after the shell
  bool Triangulate();             ///< the constrained triangulation and the size field's background
  void MarkDomain();              ///< the faces inside the cavity
  bool CheckConstraintsInDomain();
  bool Refine();
  void OutputPoints();            ///< kept, the band's, the refinement's
  void OutputKeptCells();
  void OutputLayerCells();
  void OutputTriangles();         ///< the new triangles and the curve

  const double* BandPoint(std::int64_t b) const
  {
    return b < static_cast<std::int64_t>(nCurve) ? &cPoints[2 * b] : &band.Points[2 * (b - nCurve)];
  }
  std::int64_t BandNode(std::int64_t b) const
  {
    return b < static_cast<std::int64_t>(nCurve) ? b : band.PointNode[b - nCurve];
  }
  /// The output id of a vertex of the refined triangulation.
  std::int64_t OutputId(CDT::Vertex_handle v) const
  {
    const std::int64_t id = v->info().Id;
    if (id < nShellNodes)
    {
      return outIndex[plcNode[id]];
    }
    if (id < nConstrained)
    {
      return firstBand + extra[id - nShellNodes];
    }
    return firstSteiner + id - nConstrained;
  }

  // Inputs.
  const Mesh2D& V;
  const double* curvePoints;
  const std::size_t nCurvePoints;
  const std::int64_t* curveSegments;
  const std::size_t nCurveSegments;
  const Cavity2DOptions& options;
  Cavity2DRemesh& out;
  std::string& error;
  const std::size_t nV, nC;
  const double* X; // V's points
  // Layer options.
  bool layers = false;
  double stackHeight = 0.0; // z_N: added to the removal radius
  // Edges: the longest and the sum of the edges at each node of V and their
  // count; the longest at each curve node; edge (a < b) -> the cells holding it.
  std::vector<double> lv, sum, lc;
  std::vector<int> count;
  std::map<std::pair<std::int64_t, std::int64_t>, std::vector<std::int64_t>> edges;
  // V's boundary.
  std::vector<Segment3> boundary;
  BoundaryTree tree;
  // The trimmed curves: nodes, l_c there, segments (pairs of node ids), as 2-D segments.
  std::vector<double> cPoints, cSize;
  std::vector<std::int64_t> cSegs;
  std::size_t nCurve = 0;
  std::vector<std::array<double, 4>> curveList;
  // Removal and the cavity.
  std::vector<char> removed, cavity;
  std::vector<std::int64_t> plcIndex;                       // node -> index among the constrained nodes
  std::vector<std::int64_t> plcNode;                        // and back
  std::vector<std::pair<std::int64_t, std::int64_t>> shell; // cavity-boundary edges, constrained-node ids
  std::int64_t nShellNodes = 0;
  // Layers.
  Band band;
  // The constrained nodes after the cavity's boundary ("extra"), as band
  // ids (curve nodes 0 .. nCurve-1, then layer points): the curve nodes, or
  // with layers the outermost polylines' nodes; and the constraints that
  // bound the refill ("walls": the cavity's boundary, the band's outline).
  std::vector<std::int64_t> extra;
  std::vector<std::pair<std::int64_t, std::int64_t>> inner, walls; // band ids
  std::int64_t nBand = 0;
  std::vector<std::int64_t> extraOf; // band id -> CDT id
  std::int64_t nConstrained = 0;
  // The refill.
  CDT cdt;
  Background background;
  std::vector<CDT::Vertex_handle> handle;
  // Output: V's node -> output id; the first band point's and refinement point's output ids.
  std::vector<std::int64_t> outIndex;
  std::int64_t firstBand = 0, firstSteiner = 0;
};

bool Cavity2DRun::Execute()
{
  out = Cavity2DRemesh();
  if (!Validate() || !CheckLayerOptions() || !ValidateCells() || !MeasureEdges())
  {
    return false;
  }
  MeasureCurve();
  BuildBoundaryTree();
  if (!TrimCurves() || !CheckCurvesCross())
  {
    return false;
  }
  MarkRemovedNodes();
  if (!MarkCavity())
  {
    return false;
  }
  BuildShell();
  if (!CheckCurvesInsideCavity() || !BuildLayers())
  {
    return false;
  }
  CollectConstraints();
  if (!Triangulate())
  {
    return false;
  }
  MarkDomain();
  if (!CheckConstraintsInDomain() || !Refine())
  {
    return false;
  }
  OutputPoints();
  OutputKeptCells();
  if (layers)
  {
    OutputLayerCells();
  }
  OutputTriangles();
  return true;
}

// ---- Validation.
bool Cavity2DRun::Validate()
{
  if (nV < 3 || nC == 0 || V.Offsets.front() != 0 ||
    V.Offsets.back() != static_cast<std::int64_t>(V.Connectivity.size()))
  {
    error = "the planar mesh is empty (no cells).";
    return false;
  }
  if (nCurvePoints < 2 || nCurveSegments == 0)
  {
    error = "the feature curve is empty (no segments).";
    return false;
  }
  if (!Finite(V.Points.data(), V.Points.size()))
  {
    error = "the planar mesh has a non-finite coordinate.";
    return false;
  }
  if (!Finite(curvePoints, 2 * nCurvePoints))
  {
    error = "the feature curve has a non-finite coordinate.";
    return false;
  }
  for (std::size_t k = 0; k < 2 * nCurveSegments; ++k)
  {
    if (curveSegments[k] < 0 || static_cast<std::size_t>(curveSegments[k]) >= nCurvePoints)
    {
      error = "a segment of the feature curve refers to a point that does not exist.";
      return false;
    }
  }
  return true;
}

bool Cavity2DRun::CheckLayerOptions()
{
  layers = options.Layers.NumberOfLayers != 0;
  if (layers)
  {
    std::string why;
    if (!PrismLayerDistances(options.Layers, out.LayerDistances, why))
    {
      error = "layers: " + why;
      return false;
    }
    stackHeight = out.LayerDistances.back();
  }
  return true;
}

bool Cavity2DRun::ValidateCells()
{
  for (std::size_t c = 0; c < nC; ++c)
  {
    const std::int64_t n = V.Offsets[c + 1] - V.Offsets[c];
    if (n != 3 && n != 4)
    {
      error = "cell " + std::to_string(c) + " has " + std::to_string(n) +
        " points; the planar mesh takes triangles and quads.";
      return false;
    }
    const std::int64_t* v = &V.Connectivity[V.Offsets[c]];
    double area = 0.0;
    for (std::int64_t k = 0; k < n; ++k)
    {
      if (v[k] < 0 || static_cast<std::size_t>(v[k]) >= nV)
      {
        error = "cell " + std::to_string(c) + " refers to a point that does not exist.";
        return false;
      }
    }
    for (std::int64_t k = 0; k < n; ++k)
    {
      // Each corner's triangle must be positive: a convex, counter-clockwise cell.
      const double* a = &X[2 * v[k]];
      const double* b = &X[2 * v[(k + 1) % n]];
      const double* p = &X[2 * v[(k + n - 1) % n]];
      const double corner = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
      area = k == 0 ? corner : std::min(area, corner);
    }
    if (!(area > 0.0))
    {
      std::ostringstream msg;
      msg << "cell " << c << " of the planar mesh is inverted, flat or not convex (corner area " << area
          << "); the mesh must be valid before it is remeshed.";
      error = msg.str();
      return false;
    }
  }
  return true;
}

// ---- Edges: the longest and the mean edge at each node; adjacency.
bool Cavity2DRun::MeasureEdges()
{
  lv.assign(nV, 0.0);
  sum.assign(nV, 0.0);
  count.assign(nV, 0);
  for (std::size_t c = 0; c < nC; ++c)
  {
    const std::int64_t n = V.Offsets[c + 1] - V.Offsets[c];
    const std::int64_t* v = &V.Connectivity[V.Offsets[c]];
    for (std::int64_t k = 0; k < n; ++k)
    {
      const std::int64_t a = v[k], b = v[(k + 1) % n];
      auto& cells = edges[{ std::min(a, b), std::max(a, b) }];
      cells.push_back(static_cast<std::int64_t>(c));
      if (cells.size() > 2)
      {
        error = "the planar mesh is not conforming: an edge is shared by more than two cells.";
        return false;
      }
      if (cells.size() == 1)
      {
        const double l = Distance(&X[2 * a], &X[2 * b]);
        for (const std::int64_t i : { a, b })
        {
          lv[i] = std::max(lv[i], l);
          sum[i] += l;
          ++count[i];
        }
      }
    }
  }
  return true;
}

void Cavity2DRun::MeasureCurve()
{
  lc.assign(nCurvePoints, 0.0);
  for (std::size_t s = 0; s < nCurveSegments; ++s)
  {
    const std::int64_t a = curveSegments[2 * s], b = curveSegments[2 * s + 1];
    const double l = Distance(&curvePoints[2 * a], &curvePoints[2 * b]);
    lc[a] = std::max(lc[a], l);
    lc[b] = std::max(lc[b], l);
  }
}

void Cavity2DRun::BuildBoundaryTree()
{
  for (const auto& e : edges)
  {
    if (e.second.size() == 1)
    {
      const double* a = &X[2 * e.first.first];
      const double* b = &X[2 * e.first.second];
      boundary.emplace_back(Point3(a[0], a[1], 0.0), Point3(b[0], b[1], 0.0));
    }
  }
  tree.rebuild(boundary.begin(), boundary.end());
  tree.accelerate_distance_queries();
}

// ---- Trim the curves: inside V and at least BoundaryMargin * max(l_c, l_b)
// from its boundary, l_b the length of the nearest boundary edge (the kept
// mesh's size there, capped by V's longest edge), as the 3-D cavity does.
// With the curve finer than V next to the boundary (a second cycle: the
// first refined the cells at the curve but kept the long wall edges) a gap
// of BoundaryMargin curve edges against a wall edge five times longer left
// the refill only fans of needles there (1 degree), since no boundary edge
// may be split.
bool Cavity2DRun::TrimCurves()
{
  const double lvMax = *std::max_element(lv.begin(), lv.end());
  std::vector<char> usable(nCurvePoints, 0);
  std::size_t inside = 0;
  for (std::size_t i = 0; i < nCurvePoints; ++i)
  {
    const double* x = &curvePoints[2 * i];
    if (lc[i] <= 0.0 || !Inside(tree, x))
    {
      continue;
    }
    ++inside;
    const auto hit = tree.closest_point_and_primitive(Point3(x[0], x[1], 0.0));
    const double lb = std::min(lvMax, std::sqrt(CGAL::to_double(hit.second->squared_length())));
    const double d = std::sqrt(CGAL::to_double(CGAL::squared_distance(Point3(x[0], x[1], 0.0), hit.first)));
    usable[i] = d >= options.BoundaryMargin * std::max(lc[i], lb);
  }
  if (inside == 0)
  {
    error = "the feature curve lies entirely outside the mesh.";
    return false;
  }
  std::vector<std::int64_t> cIndex(nCurvePoints, -1);
  for (std::size_t s = 0; s < nCurveSegments; ++s)
  {
    const std::int64_t* e = curveSegments + 2 * s;
    if (!usable[e[0]] || !usable[e[1]] || e[0] == e[1])
    {
      continue;
    }
    for (int k = 0; k < 2; ++k)
    {
      if (cIndex[e[k]] < 0)
      {
        cIndex[e[k]] = static_cast<std::int64_t>(cSize.size());
        cPoints.insert(cPoints.end(), &curvePoints[2 * e[k]], &curvePoints[2 * e[k]] + 2);
        cSize.push_back(lc[e[k]]);
      }
      cSegs.push_back(cIndex[e[k]]);
    }
  }
  out.CurveSegmentsUsed = cSegs.size() / 2;
  if (cSegs.empty())
  {
    error = "nothing of the feature curve is left after trimming it back from the domain boundary "
            "(every segment has a point within BoundaryMargin edge lengths of it).";
    return false;
  }
  nCurve = cSize.size();
  return true;
}

bool Cavity2DRun::CheckCurvesCross()
{
  for (std::size_t s = 0; s < cSegs.size(); s += 2)
  {
    const double* a = &cPoints[2 * cSegs[s]];
    const double* b = &cPoints[2 * cSegs[s + 1]];
    curveList.push_back({ a[0], a[1], b[0], b[1] });
  }
  if (SegmentsCross(curveList))
  {
    error = "the feature curve intersects itself (or two curves cross).";
    return false;
  }
  return true;
}

// ---- Removal: V_j within RemovalFactor * max(l_ci, l_vj) of a visible C_i
// (plus the stack height with layers, as in 3-D).
void Cavity2DRun::MarkRemovedNodes()
{
  std::vector<IndexedPoint> indexed;
  double lcMax = 0.0;
  for (std::size_t i = 0; i < nCurve; ++i)
  {
    indexed.emplace_back(Point2(cPoints[2 * i], cPoints[2 * i + 1]), i);
    lcMax = std::max(lcMax, cSize[i]);
  }
  KdTree kd(indexed.begin(), indexed.end());
  kd.build();
  removed.assign(nV, 0);
  std::vector<IndexedPoint> found;
  const double rf = options.RemovalFactor;
  for (std::size_t j = 0; j < nV; ++j)
  {
    if (count[j] == 0)
    {
      continue; // not used by any cell
    }
    if (options.FullDomain)
    {
      removed[j] = 1;
      continue;
    }
    const double* xj = &X[2 * j];
    found.clear();
    kd.search(std::back_inserter(found),
      Circle(IndexedPoint(Point2(xj[0], xj[1]), 0), rf * std::max(lcMax, lv[j]) + stackHeight, 0.0));
    std::sort(found.begin(), found.end(),
      [](const IndexedPoint& a, const IndexedPoint& b) { return boost::get<1>(a) < boost::get<1>(b); });
    for (const IndexedPoint& q : found)
    {
      const std::size_t i = boost::get<1>(q);
      const double* xi = &cPoints[2 * i];
      if (Distance(xi, xj) >= rf * std::max(cSize[i], lv[j]) + stackHeight)
      {
        continue;
      }
      if (options.VisibilityTest)
      {
        // Stop just short of V_j, which may itself lie on the boundary.
        const double t = 1.0 - 1e-7;
        const Segment3 sight(Point3(xi[0], xi[1], 0.0),
          Point3(xi[0] + t * (xj[0] - xi[0]), xi[1] + t * (xj[1] - xi[1]), 0.0));
        if (tree.do_intersect(sight))
        {
          continue;
        }
      }
      removed[j] = 1;
      break;
    }
  }
}

// ---- The cavity: cells touching removed nodes; its boundary edges stay.
bool Cavity2DRun::MarkCavity()
{
  cavity.assign(nC, 0);
  for (std::size_t c = 0; c < nC; ++c)
  {
    for (std::int64_t k = V.Offsets[c]; k < V.Offsets[c + 1]; ++k)
    {
      cavity[c] = cavity[c] || removed[V.Connectivity[k]];
    }
  }
  out.RemovedCells = static_cast<std::size_t>(std::count(cavity.begin(), cavity.end(), char(1)));
  if (out.RemovedCells == 0)
  {
    error = "no node of the mesh lies near the feature curve: nothing to remesh.";
    return false;
  }
  return true;
}

void Cavity2DRun::BuildShell()
{
  plcIndex.assign(nV, -1);
  for (std::size_t c = 0; c < nC; ++c)
  {
    if (!cavity[c])
    {
      continue;
    }
    const std::int64_t n = V.Offsets[c + 1] - V.Offsets[c];
    const std::int64_t* v = &V.Connectivity[V.Offsets[c]];
    for (std::int64_t k = 0; k < n; ++k)
    {
      const std::int64_t a = v[k], b = v[(k + 1) % n];
      const auto& cells = edges.at({ std::min(a, b), std::max(a, b) });
      const bool interior = cells.size() == 2 && cavity[cells[0]] && cavity[cells[1]];
      if (interior)
      {
        continue;
      }
      for (const std::int64_t i : { a, b })
      {
        if (plcIndex[i] < 0)
        {
          plcIndex[i] = static_cast<std::int64_t>(plcNode.size());
          plcNode.push_back(i);
        }
      }
      shell.emplace_back(plcIndex[a], plcIndex[b]);
    }
  }
  nShellNodes = static_cast<std::int64_t>(plcNode.size());
}

// ---- The curves must stay inside the cavity: none may cross its boundary.
bool Cavity2DRun::CheckCurvesInsideCavity()
{
  std::vector<std::array<double, 4>> all = curveList;
  for (const auto& e : shell)
  {
    const double* a = &X[2 * plcNode[e.first]];
    const double* b = &X[2 * plcNode[e.second]];
    all.push_back({ a[0], a[1], b[0], b[1] });
  }
  if (SegmentsCross(all))
  {
    error = "the feature curve crosses the boundary of the cavity (the kept mesh is too close "
            "to it); raise RemovalFactor.";
    return false;
  }
  return true;
}

// ---- Layers: the band around the curves, built against the cavity's boundary.
bool Cavity2DRun::BuildLayers()
{
  if (!layers)
  {
    return true;
  }
  std::vector<Chain> chains;
  if (!CurveChains(nCurve, cSegs, chains, error))
  {
    return false;
  }
  std::vector<std::array<double, 4>> shellSegments;
  for (const auto& e : shell)
  {
    const double* a = &X[2 * plcNode[e.first]];
    const double* b = &X[2 * plcNode[e.second]];
    shellSegments.push_back({ a[0], a[1], b[0], b[1] });
  }
  return BuildBand(cPoints, chains, shellSegments, options.Layers, out.LayerDistances, band, error);
}

void Cavity2DRun::CollectConstraints()
{
  if (layers)
  {
    std::set<std::int64_t> nodes;
    for (const auto& w : band.Walls)
    {
      nodes.insert(w[0]);
      nodes.insert(w[1]);
      walls.emplace_back(w[0], w[1]);
    }
    extra.assign(nodes.begin(), nodes.end());
  }
  else
  {
    for (std::size_t i = 0; i < nCurve; ++i)
    {
      extra.push_back(static_cast<std::int64_t>(i));
    }
    for (std::size_t s = 0; s < cSegs.size(); s += 2)
    {
      inner.emplace_back(cSegs[s], cSegs[s + 1]);
    }
  }
  nBand = static_cast<std::int64_t>(nCurve + band.PointNode.size());
  extraOf.assign(nBand, -1);
  for (std::size_t k = 0; k < extra.size(); ++k)
  {
    extraOf[extra[k]] = nShellNodes + static_cast<std::int64_t>(k);
  }
  nConstrained = nShellNodes + static_cast<std::int64_t>(extra.size());
}

// ---- The constrained triangulation and the size field's background.
bool Cavity2DRun::Triangulate()
{
  handle.resize(nConstrained);
  for (std::int64_t k = 0; k < nConstrained; ++k)
  {
    const bool shellNode = k < nShellNodes;
    const double* x = shellNode ? &X[2 * plcNode[k]] : BandPoint(extra[k - nShellNodes]);
    const Point2 p(x[0], x[1]);
    handle[k] = cdt.insert(p);
    if (handle[k]->info().Id >= 0)
    {
      error = layers ? "two nodes of the refill coincide (a layer point on a kept node or on another layer point)."
                     : "two nodes of the refill coincide (a curve node on a kept node, or a repeated curve node).";
      return false;
    }
    handle[k]->info().Id = k;
    const std::int64_t v = shellNode ? plcNode[k] : -1;
    const double size = shellNode ? sum[v] / std::max(1, count[v]) : cSize[BandNode(extra[k - nShellNodes])];
    background.insert(p)->info() = size;
  }
  for (const auto& e : shell)
  {
    cdt.insert_constraint(handle[e.first], handle[e.second]);
  }
  for (const auto& e : inner)
  {
    cdt.insert_constraint(handle[extraOf[e.first]], handle[extraOf[e.second]]);
  }
  for (const auto& e : walls)
  {
    cdt.insert_constraint(handle[extraOf[e.first]], handle[extraOf[e.second]]);
  }
  if (static_cast<std::int64_t>(cdt.number_of_vertices()) != nConstrained)
  {
    error = layers ? "the layers touch the boundary of the cavity; raise RemovalFactor."
                   : "the feature curve touches the boundary of the cavity; raise RemovalFactor.";
    return false;
  }
  return true;
}

// Faces inside the cavity: parity of the walls crossed from the infinite
// face (a curve edge is crossed freely; the band is outside).
void Cavity2DRun::MarkDomain()
{
  std::set<std::pair<std::int64_t, std::int64_t>> wallKeys;
  for (const auto& e : shell)
  {
    wallKeys.insert({ std::min(e.first, e.second), std::max(e.first, e.second) });
  }
  for (const auto& e : walls)
  {
    const std::int64_t a = extraOf[e.first], b = extraOf[e.second];
    wallKeys.insert({ std::min(a, b), std::max(a, b) });
  }
  auto onWall = [&](CDT::Face_handle f, int i) {
    const std::int64_t a = f->vertex(CDT::cw(i))->info().Id, b = f->vertex(CDT::ccw(i))->info().Id;
    return a >= 0 && b >= 0 && wallKeys.count({ std::min(a, b), std::max(a, b) }) > 0;
  };
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f)
  {
    f->set_in_domain(false);
  }
  std::map<CDT::Face_handle, int> depth;
  std::queue<CDT::Face_handle> front;
  depth[cdt.infinite_face()] = 0;
  front.push(cdt.infinite_face());
  while (!front.empty())
  {
    const CDT::Face_handle f = front.front();
    front.pop();
    const int d = depth[f];
    f->set_in_domain(d % 2 == 1);
    for (int i = 0; i < 3; ++i)
    {
      const CDT::Face_handle g = f->neighbor(i);
      if (depth.count(g) == 0)
      {
        depth[g] = d + (onWall(f, i) ? 1 : 0);
        front.push(g);
      }
    }
  }
}

// Every curve segment must lie between two faces of the cavity; with
// layers every edge of the band's outline between the band and the cavity.
bool Cavity2DRun::CheckConstraintsInDomain()
{
  for (const auto& e : inner)
  {
    CDT::Face_handle f;
    int i;
    if (!cdt.is_edge(handle[extraOf[e.first]], handle[extraOf[e.second]], f, i) || !f->is_in_domain() ||
      !f->neighbor(i)->is_in_domain())
    {
      error = "the feature curve leaves the cavity (it passes over kept cells); raise RemovalFactor.";
      return false;
    }
  }
  for (const auto& e : walls)
  {
    CDT::Face_handle f;
    int i;
    if (!cdt.is_edge(handle[extraOf[e.first]], handle[extraOf[e.second]], f, i) ||
      f->is_in_domain() == f->neighbor(i)->is_in_domain())
    {
      error = "the layers leave the cavity (they pass over kept cells); raise RemovalFactor.";
      return false;
    }
  }
  return true;
}

// ---- Refinement: no constrained edge is split.
bool Cavity2DRun::Refine()
{
  const double sine = std::sin(options.MinAngle * M_PI / 180.0);
  GradedCriteria criteria(sine * sine, &background, options.SizeRatio);
  CGAL::Delaunay_mesher_no_edge_refinement_2<CDT, GradedCriteria> mesher(cdt, criteria);
  mesher.init(true); // the domain is marked above
  std::size_t inDomain = 0;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
  {
    inDomain += f->is_in_domain() ? 1 : 0;
  }
  const std::size_t maxSteps = 1000 * (inDomain + 10);
  std::size_t steps = 0;
  while (!mesher.is_refinement_done())
  {
    mesher.step_by_step_refine_mesh();
    if (++steps > maxSteps)
    {
      error = "the refinement of the cavity does not finish (" + std::to_string(steps) +
        " points inserted); lower the minimum angle.";
      return false;
    }
  }
  return true;
}

// ---- Output: kept points (input order), then the curve's, the layers'
// and the refinement's.
void Cavity2DRun::OutputPoints()
{
  outIndex.assign(nV, -1);
  for (std::size_t c = 0; c < nC; ++c)
  {
    for (std::int64_t k = V.Offsets[c]; !cavity[c] && k < V.Offsets[c + 1]; ++k)
    {
      outIndex[V.Connectivity[k]] = 0;
    }
  }
  for (const std::int64_t v : plcNode)
  {
    outIndex[v] = 0;
  }
  for (std::size_t v = 0; v < nV; ++v)
  {
    if (outIndex[v] == 0)
    {
      outIndex[v] = static_cast<std::int64_t>(out.SourcePoint.size());
      out.SourcePoint.push_back(static_cast<std::int64_t>(v));
      out.Mesh.Points.insert(out.Mesh.Points.end(), &X[2 * v], &X[2 * v] + 2);
    }
    else if (count[v] > 0)
    {
      ++out.RemovedNodes;
    }
  }
  firstBand = static_cast<std::int64_t>(out.SourcePoint.size()); // band id b is output id firstBand + b
  for (std::int64_t b = 0; b < nBand; ++b)
  {
    out.SourcePoint.push_back(-1);
    out.Mesh.Points.insert(out.Mesh.Points.end(), BandPoint(b), BandPoint(b) + 2);
  }
  // The refinement's points in canonical order (by coordinates).
  std::vector<CDT::Vertex_handle> steiner;
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
  {
    if (v->info().Id < 0)
    {
      steiner.push_back(v);
    }
  }
  std::sort(steiner.begin(), steiner.end(), [](CDT::Vertex_handle a, CDT::Vertex_handle b) {
    return a->point() < b->point();
  });
  firstSteiner = static_cast<std::int64_t>(out.SourcePoint.size());
  for (std::size_t k = 0; k < steiner.size(); ++k)
  {
    steiner[k]->info().Id = nConstrained + static_cast<std::int64_t>(k); // beyond the constrained nodes
    out.SourcePoint.push_back(-1);
    out.Mesh.Points.push_back(steiner[k]->point().x());
    out.Mesh.Points.push_back(steiner[k]->point().y());
  }
}

void Cavity2DRun::OutputKeptCells()
{
  out.Mesh.Offsets.assign(1, 0);
  for (std::size_t c = 0; c < nC; ++c)
  {
    if (cavity[c])
    {
      continue;
    }
    for (std::int64_t k = V.Offsets[c]; k < V.Offsets[c + 1]; ++k)
    {
      out.Mesh.Connectivity.push_back(outIndex[V.Connectivity[k]]);
    }
    out.Mesh.Offsets.push_back(static_cast<std::int64_t>(out.Mesh.Connectivity.size()));
    out.SourceCell.push_back(static_cast<std::int64_t>(c));
  }
}

void Cavity2DRun::OutputLayerCells()
{
  out.CellLayer.assign(out.SourceCell.size(), -1);
  out.CellSide.assign(out.SourceCell.size(), 0);
  for (std::size_t c = 0; c < band.Cells.size(); ++c)
  {
    for (const std::int64_t b : band.Cells[c])
    {
      out.Mesh.Connectivity.push_back(firstBand + b);
    }
    out.Mesh.Offsets.push_back(static_cast<std::int64_t>(out.Mesh.Connectivity.size()));
    out.SourceCell.push_back(-1);
    out.CellLayer.push_back(band.CellLayer[c]);
    out.CellSide.push_back(band.CellSide[c]);
  }
  out.FirstCurvePoint = static_cast<std::size_t>(firstBand);
  out.NumberOfCurvePoints = nCurve;
  out.Normals = band.Normal;
  out.Heights = band.Height;
  out.LayerQuads = band.Quads;
  out.LayerTriangles = band.Triangles;
  out.LimitedColumns = band.Limited;
  out.ShrinkRounds = band.Rounds;
}

// New triangles in canonical order (by their smallest output id, rotated).
void Cavity2DRun::OutputTriangles()
{
  std::vector<std::array<std::int64_t, 3>> triangles;
  out.MinAngleNew = 180.0;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
  {
    if (!f->is_in_domain())
    {
      continue;
    }
    std::array<std::int64_t, 3> t = { OutputId(f->vertex(0)), OutputId(f->vertex(1)),
      OutputId(f->vertex(2)) };
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    triangles.push_back(t);
    out.MinAngleNew = std::min(out.MinAngleNew,
      SmallestAngle(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point()));
  }
  std::sort(triangles.begin(), triangles.end());
  for (const auto& t : triangles)
  {
    out.Mesh.AddCell({ t[0], t[1], t[2] });
    out.SourceCell.push_back(-1);
    if (layers)
    {
      out.CellLayer.push_back(-1);
      out.CellSide.push_back(0);
    }
  }
  for (std::size_t s = 0; s < cSegs.size(); ++s)
  {
    out.Curve.push_back(firstBand + cSegs[s]);
  }
}
}

bool RemeshLocalCavity2D(const Mesh2D& V, const double* curvePoints, std::size_t nCurvePoints,
  const std::int64_t* curveSegments, std::size_t nCurveSegments, const Cavity2DOptions& options,
  Cavity2DRemesh& out, std::string& error)
{
  Cavity2DRun run(V, curvePoints, nCurvePoints, curveSegments, nCurveSegments, options, out, error);
  return run.Execute();
}
}
