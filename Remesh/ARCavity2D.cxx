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
}

bool RemeshLocalCavity2D(const Mesh2D& V, const double* curvePoints, std::size_t nCurvePoints,
  const std::int64_t* curveSegments, std::size_t nCurveSegments, const Cavity2DOptions& options,
  Cavity2DRemesh& out, std::string& error)
{
  out = Cavity2DRemesh();
  const std::size_t nV = V.NumberOfPoints();
  const std::size_t nC = V.NumberOfCells();
  // ---- Validation.
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
  const double* X = V.Points.data();
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

  // ---- Edges: the longest and the mean edge at each node; adjacency.
  std::vector<double> lv(nV, 0.0), sum(nV, 0.0), lc(nCurvePoints, 0.0);
  std::vector<int> count(nV, 0);
  // edge (a < b) -> the cells holding it
  std::map<std::pair<std::int64_t, std::int64_t>, std::vector<std::int64_t>> edges;
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
  for (std::size_t s = 0; s < nCurveSegments; ++s)
  {
    const std::int64_t a = curveSegments[2 * s], b = curveSegments[2 * s + 1];
    const double l = Distance(&curvePoints[2 * a], &curvePoints[2 * b]);
    lc[a] = std::max(lc[a], l);
    lc[b] = std::max(lc[b], l);
  }
  std::vector<Segment3> boundary;
  for (const auto& e : edges)
  {
    if (e.second.size() == 1)
    {
      const double* a = &X[2 * e.first.first];
      const double* b = &X[2 * e.first.second];
      boundary.emplace_back(Point3(a[0], a[1], 0.0), Point3(b[0], b[1], 0.0));
    }
  }
  BoundaryTree tree(boundary.begin(), boundary.end());
  tree.accelerate_distance_queries();

  // ---- Trim the curves: inside V and at least BoundaryMargin * max(l_c, l_b)
  // from its boundary, l_b the length of the nearest boundary edge (the kept
  // mesh's size there, capped by V's longest edge), as the 3-D cavity does.
  // With the curve finer than V next to the boundary (a second cycle: the
  // first refined the cells at the curve but kept the long wall edges) a gap
  // of BoundaryMargin curve edges against a wall edge five times longer left
  // the refill only fans of needles there (1 degree), since no boundary edge
  // may be split.
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
  std::vector<double> cPoints, cSize;
  std::vector<std::int64_t> cSegs;
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
  const std::size_t nCurve = cSize.size();
  std::vector<std::array<double, 4>> curveList;
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

  // ---- Removal: V_j within RemovalFactor * max(l_ci, l_vj) of a visible C_i.
  std::vector<IndexedPoint> indexed;
  double lcMax = 0.0;
  for (std::size_t i = 0; i < nCurve; ++i)
  {
    indexed.emplace_back(Point2(cPoints[2 * i], cPoints[2 * i + 1]), i);
    lcMax = std::max(lcMax, cSize[i]);
  }
  KdTree kd(indexed.begin(), indexed.end());
  kd.build();
  std::vector<char> removed(nV, 0);
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
      Circle(IndexedPoint(Point2(xj[0], xj[1]), 0), rf * std::max(lcMax, lv[j]), 0.0));
    std::sort(found.begin(), found.end(),
      [](const IndexedPoint& a, const IndexedPoint& b) { return boost::get<1>(a) < boost::get<1>(b); });
    for (const IndexedPoint& q : found)
    {
      const std::size_t i = boost::get<1>(q);
      const double* xi = &cPoints[2 * i];
      if (Distance(xi, xj) >= rf * std::max(cSize[i], lv[j]))
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

  // ---- The cavity: cells touching removed nodes; its boundary edges stay.
  std::vector<char> cavity(nC, 0);
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
  std::vector<std::int64_t> plcIndex(nV, -1); // node -> index among the constrained nodes
  std::vector<std::int64_t> plcNode;          // and back
  std::vector<std::pair<std::int64_t, std::int64_t>> shell; // cavity-boundary edges, constrained-node ids
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
      const bool inner = cells.size() == 2 && cavity[cells[0]] && cavity[cells[1]];
      if (inner)
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
  const auto nShellNodes = static_cast<std::int64_t>(plcNode.size());

  // ---- The curves must stay inside the cavity: none may cross its boundary.
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
  }

  // ---- The constrained triangulation and the size field's background.
  CDT cdt;
  Background background;
  std::vector<CDT::Vertex_handle> handle(nShellNodes + nCurve);
  for (std::int64_t k = 0; k < nShellNodes + static_cast<std::int64_t>(nCurve); ++k)
  {
    const bool shellNode = k < nShellNodes;
    const double* x = shellNode ? &X[2 * plcNode[k]] : &cPoints[2 * (k - nShellNodes)];
    const Point2 p(x[0], x[1]);
    handle[k] = cdt.insert(p);
    if (handle[k]->info().Id >= 0)
    {
      error = "two nodes of the refill coincide (a curve node on a kept node, or a repeated curve node).";
      return false;
    }
    handle[k]->info().Id = k;
    const std::int64_t v = shellNode ? plcNode[k] : -1;
    const double size = shellNode ? sum[v] / std::max(1, count[v]) : cSize[k - nShellNodes];
    background.insert(p)->info() = size;
  }
  for (const auto& e : shell)
  {
    cdt.insert_constraint(handle[e.first], handle[e.second]);
  }
  for (std::size_t s = 0; s < cSegs.size(); s += 2)
  {
    cdt.insert_constraint(handle[nShellNodes + cSegs[s]], handle[nShellNodes + cSegs[s + 1]]);
  }
  if (static_cast<std::int64_t>(cdt.number_of_vertices()) != nShellNodes + static_cast<std::int64_t>(nCurve))
  {
    error = "the feature curve touches the boundary of the cavity; raise RemovalFactor.";
    return false;
  }
  // Faces inside the cavity: parity of the cavity-boundary edges crossed
  // from the infinite face (a curve edge is crossed freely).
  std::set<std::pair<std::int64_t, std::int64_t>> shellKeys;
  for (const auto& e : shell)
  {
    shellKeys.insert({ std::min(e.first, e.second), std::max(e.first, e.second) });
  }
  auto onShell = [&](CDT::Face_handle f, int i) {
    const std::int64_t a = f->vertex(CDT::cw(i))->info().Id, b = f->vertex(CDT::ccw(i))->info().Id;
    return a >= 0 && b >= 0 && a < nShellNodes && b < nShellNodes &&
      shellKeys.count({ std::min(a, b), std::max(a, b) }) > 0;
  };
  {
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
          depth[g] = d + (onShell(f, i) ? 1 : 0);
          front.push(g);
        }
      }
    }
  }
  // Every curve segment must lie between two faces of the cavity.
  for (std::size_t s = 0; s < cSegs.size(); s += 2)
  {
    CDT::Face_handle f;
    int i;
    if (!cdt.is_edge(handle[nShellNodes + cSegs[s]], handle[nShellNodes + cSegs[s + 1]], f, i) ||
      !f->is_in_domain() || !f->neighbor(i)->is_in_domain())
    {
      error = "the feature curve leaves the cavity (it passes over kept cells); raise RemovalFactor.";
      return false;
    }
  }

  // ---- Refinement: no constrained edge is split.
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

  // ---- Output: kept points (input order), then the curve's and the refinement's.
  std::vector<std::int64_t> outIndex(nV, -1);
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
  std::vector<std::int64_t> curveOut(nCurve);
  for (std::size_t i = 0; i < nCurve; ++i)
  {
    curveOut[i] = static_cast<std::int64_t>(out.SourcePoint.size());
    out.SourcePoint.push_back(-1);
    out.Mesh.Points.insert(out.Mesh.Points.end(), &cPoints[2 * i], &cPoints[2 * i] + 2);
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
  for (const CDT::Vertex_handle& v : steiner)
  {
    v->info().Id = nShellNodes + static_cast<std::int64_t>(nCurve) +
      static_cast<std::int64_t>(out.SourcePoint.size()); // unique, beyond the constrained nodes
    out.SourcePoint.push_back(-1);
    out.Mesh.Points.push_back(v->point().x());
    out.Mesh.Points.push_back(v->point().y());
  }
  const std::int64_t steinerBase = nShellNodes + static_cast<std::int64_t>(nCurve);
  auto outputId = [&](CDT::Vertex_handle v) -> std::int64_t {
    const std::int64_t id = v->info().Id;
    if (id < nShellNodes)
    {
      return outIndex[plcNode[id]];
    }
    if (id < steinerBase)
    {
      return curveOut[id - nShellNodes];
    }
    return id - steinerBase;
  };
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
  // New triangles in canonical order (by their smallest output id, rotated).
  std::vector<std::array<std::int64_t, 3>> triangles;
  out.MinAngleNew = 180.0;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
  {
    if (!f->is_in_domain())
    {
      continue;
    }
    std::array<std::int64_t, 3> t = { outputId(f->vertex(0)), outputId(f->vertex(1)),
      outputId(f->vertex(2)) };
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
  }
  for (std::size_t s = 0; s < cSegs.size(); ++s)
  {
    out.Curve.push_back(curveOut[cSegs[s]]);
  }
  return true;
}
}
