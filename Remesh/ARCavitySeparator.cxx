// SPDX-License-Identifier: BSD-3-Clause
#include "ARCavitySeparator.h"

#include "ARCGALTypes.h"
#include "ARParallelFor.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Box_intersection_d/Box_with_info_d.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace ar
{
namespace
{
using K = cgal::Kernel;
using Pt = K::Point_3;
using Tri = cgal::Triangle;
using Tree = cgal::TriangleTree;
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;
using Loop = std::vector<std::int64_t>;
using Edge = std::pair<std::int64_t, std::int64_t>;

struct Geometry
{
  const std::vector<double>& X;
  Pt At(std::int64_t i) const { return Pt(X[3 * i], X[3 * i + 1], X[3 * i + 2]); }
  double Distance2(std::int64_t a, std::int64_t b) const { return CGAL::squared_distance(At(a), At(b)); }
};

/// Directed edges chained into closed loops; false where a point starts or
/// ends more than one edge, or a chain does not close.
bool ChainLoops(const std::vector<Edge>& edges, std::vector<Loop>& loops)
{
  std::unordered_map<std::int64_t, std::int64_t> next, in;
  for (const Edge& e : edges)
  {
    if (!next.emplace(e.first, e.second).second || ++in[e.second] > 1)
    {
      return false;
    }
  }
  std::unordered_map<std::int64_t, char> seen;
  for (const Edge& e : edges)
  {
    if (seen.count(e.first))
    {
      continue;
    }
    Loop loop;
    std::int64_t v = e.first;
    do
    {
      loop.push_back(v);
      seen[v] = 1;
      const auto it = next.find(v);
      if (it == next.end())
      {
        return false;
      }
      v = it->second;
    } while (v != e.first && !seen.count(v));
    if (v != e.first)
    {
      return false;
    }
    loops.push_back(std::move(loop));
  }
  return true;
}

/// Triangles' edges that only one of them has, directed as in it (S's
/// border); false where an edge is in more than two.
bool BorderEdges(const std::vector<std::int64_t>& tris, std::vector<Edge>& border)
{
  std::vector<std::pair<Edge, Edge>> all; // (sorted key, directed)
  for (std::size_t t = 0; 3 * t < tris.size(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const std::int64_t a = tris[3 * t + k], b = tris[3 * t + (k + 1) % 3];
      all.push_back({ { std::min(a, b), std::max(a, b) }, { a, b } });
    }
  }
  std::sort(all.begin(), all.end());
  for (std::size_t i = 0; i < all.size();)
  {
    std::size_t j = i;
    while (j < all.size() && all[j].first == all[i].first)
    {
      ++j;
    }
    if (j - i > 2)
    {
      return false;
    }
    if (j - i == 1)
    {
      border.push_back(all[i].second);
    }
    i = j;
  }
  return true;
}

/// The boundary's edges between triangles on the two sides of S, directed
/// as in the triangle on the + side; false where an edge of the boundary is
/// not in exactly two of its triangles.
bool SideChangeEdges(const std::vector<std::int64_t>& tris, const std::vector<char>& plus, std::vector<Edge>& out)
{
  std::vector<std::pair<Edge, std::pair<std::size_t, int>>> all; // (key, (triangle, k))
  for (std::size_t t = 0; 3 * t < tris.size(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const std::int64_t a = tris[3 * t + k], b = tris[3 * t + (k + 1) % 3];
      all.push_back({ { std::min(a, b), std::max(a, b) }, { t, k } });
    }
  }
  std::sort(all.begin(), all.end());
  for (std::size_t i = 0; i < all.size(); i += 2)
  {
    if (i + 1 >= all.size() || all[i + 1].first != all[i].first ||
      (i + 2 < all.size() && all[i + 2].first == all[i].first))
    {
      return false;
    }
    const std::size_t t0 = all[i].second.first, t1 = all[i + 1].second.first;
    if (plus[t0] != plus[t1])
    {
      const auto& p = plus[t0] ? all[i].second : all[i + 1].second;
      out.push_back({ tris[3 * p.first + p.second], tris[3 * p.first + (p.second + 1) % 3] });
    }
  }
  return true;
}

/// Per point of `loop`, the nearest point of `other` (its index there).
std::vector<std::size_t> Nearest(const Geometry& g, const Loop& loop, const Loop& other)
{
  std::vector<std::size_t> near(loop.size(), 0);
  ParallelFor(
    loop.size(),
    [&](std::size_t first, std::size_t last) {
      for (std::size_t i = first; i < last; ++i)
      {
        double best = std::numeric_limits<double>::max();
        for (std::size_t j = 0; j < other.size(); ++j)
        {
          const double d = g.Distance2(loop[i], other[j]);
          if (d < best)
          {
            best = d;
            near[i] = j;
          }
        }
      }
    },
    0, 64);
  return near;
}

double MinAngle(const Geometry& g, std::int64_t a, std::int64_t b, std::int64_t c)
{
  const std::int64_t v[3] = { a, b, c };
  double smallest = 180.0;
  for (int k = 0; k < 3; ++k)
  {
    const Pt p = g.At(v[k]), q = g.At(v[(k + 1) % 3]), r = g.At(v[(k + 2) % 3]);
    const K::Vector_3 u = q - p, w = r - p;
    const double nu = std::sqrt(u.squared_length()), nw = std::sqrt(w.squared_length());
    if (!(nu > 0.0 && nw > 0.0))
    {
      return 0.0;
    }
    const double c = std::max(-1.0, std::min(1.0, (u * w) / (nu * nw)));
    smallest = std::min(smallest, std::acos(c) * 180.0 / M_PI);
  }
  return smallest;
}

/// CollapseThinStripTriangles (ARCavitySeparator.h).
void CollapseThinTriangles(const Geometry& g, std::int64_t firstNew, double minAngle, std::vector<std::int64_t>& strip)
{
  for (int round = 0; round < 100; ++round)
  {
    bool changed = false;
    std::unordered_map<std::int64_t, std::vector<std::size_t>> star; // point -> its triangles
    for (std::size_t t = 0; 3 * t < strip.size(); ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        star[strip[3 * t + k]].push_back(t);
      }
    }
    auto normal = [&](const std::int64_t* v) {
      return CGAL::cross_product(g.At(v[1]) - g.At(v[0]), g.At(v[2]) - g.At(v[0]));
    };
    auto neighbours = [&](std::int64_t v) {
      std::vector<std::int64_t> n;
      for (const std::size_t t : star[v])
      {
        for (int k = 0; k < 3; ++k)
        {
          if (strip[3 * t + k] != v)
          {
            n.push_back(strip[3 * t + k]);
          }
        }
      }
      std::sort(n.begin(), n.end());
      n.erase(std::unique(n.begin(), n.end()), n.end());
      return n;
    };
    for (std::size_t t = 0; 3 * t < strip.size() && !changed; ++t)
    {
      const std::int64_t* f = &strip[3 * t];
      if (MinAngle(g, f[0], f[1], f[2]) >= minAngle)
      {
        continue;
      }
      // The best merge of one of its own points v into another corner u.
      double best = MinAngle(g, f[0], f[1], f[2]);
      std::int64_t bestV = -1, bestU = -1;
      for (int a = 0; a < 3; ++a)
      {
        const std::int64_t v = f[a];
        if (v < firstNew)
        {
          continue;
        }
        const std::vector<std::int64_t> nv = neighbours(v);
        for (int b = 1; b < 3; ++b)
        {
          const std::int64_t u = f[(a + b) % 3];
          // Manifold: the common neighbours of v and u are the third
          // corners of the triangles on their edge.
          std::vector<std::int64_t> common, third;
          const std::vector<std::int64_t> nu = neighbours(u);
          std::set_intersection(nv.begin(), nv.end(), nu.begin(), nu.end(), std::back_inserter(common));
          for (const std::size_t s : star[v])
          {
            const std::int64_t* e = &strip[3 * s];
            if (e[0] == u || e[1] == u || e[2] == u)
            {
              third.push_back(e[0] != u && e[0] != v ? e[0] : e[1] != u && e[1] != v ? e[1] : e[2]);
            }
          }
          std::sort(third.begin(), third.end());
          if (common != third)
          {
            continue;
          }
          double smallest = 180.0;
          bool flips = false;
          for (const std::size_t s : star[v])
          {
            std::int64_t e[3] = { strip[3 * s], strip[3 * s + 1], strip[3 * s + 2] };
            if (e[0] == u || e[1] == u || e[2] == u)
            {
              continue; // goes
            }
            const K::Vector_3 before = normal(e);
            std::replace(e, e + 3, v, u);
            const K::Vector_3 after = normal(e);
            flips = flips || before * after <= 0.0;
            smallest = std::min(smallest, MinAngle(g, e[0], e[1], e[2]));
          }
          if (!flips && smallest > best)
          {
            best = smallest;
            bestV = v;
            bestU = u;
          }
        }
      }
      if (bestV < 0)
      {
        continue;
      }
      std::vector<std::int64_t> kept;
      for (std::size_t s = 0; 3 * s < strip.size(); ++s)
      {
        std::int64_t e[3] = { strip[3 * s], strip[3 * s + 1], strip[3 * s + 2] };
        const bool hasV = e[0] == bestV || e[1] == bestV || e[2] == bestV;
        const bool hasU = e[0] == bestU || e[1] == bestU || e[2] == bestU;
        if (hasV && hasU)
        {
          continue;
        }
        std::replace(e, e + 3, bestV, bestU);
        kept.insert(kept.end(), e, e + 3);
      }
      strip = std::move(kept);
      changed = true;
    }
    if (!changed)
    {
      return;
    }
  }
}

/// The band between S's border loop `b` and the boundary loop `l` (the
/// same way round), from b[0] and l[j0]: the monotone stitching of the two
/// loops with the least sum of new edges' lengths (dynamic programming over
/// the pairs (i, j), as Fuchs, Kedem and Uselton's optimal contour
/// triangulation; a greedy walk strays where one loop makes a detour, e.g.
/// round a corner of the domain).
void Stitch(const Geometry& g, const Loop& b, const Loop& l, std::size_t j0, std::vector<std::int64_t>& strip,
  std::vector<Edge>* rungs = nullptr)
{
  const std::size_t m = b.size(), k = l.size(), w = k + 1;
  auto B = [&](std::size_t i) { return b[i % m]; };
  auto L = [&](std::size_t j) { return l[(j0 + j) % k]; };
  const double inf = std::numeric_limits<double>::max();
  std::vector<double> cost((m + 1) * w, inf);
  std::vector<char> fromB((m + 1) * w, 0);
  cost[0] = 0.0;
  for (std::size_t i = 0; i <= m; ++i)
  {
    for (std::size_t j = 0; j <= k; ++j)
    {
      const double edge = std::sqrt(g.Distance2(B(i), L(j))); // the edge (b_i, l_j) the step ends on
      if (i > 0 && cost[(i - 1) * w + j] < inf && cost[(i - 1) * w + j] + edge < cost[i * w + j])
      {
        cost[i * w + j] = cost[(i - 1) * w + j] + edge;
        fromB[i * w + j] = 1;
      }
      if (j > 0 && cost[i * w + j - 1] < inf && cost[i * w + j - 1] + edge < cost[i * w + j])
      {
        cost[i * w + j] = cost[i * w + j - 1] + edge;
        fromB[i * w + j] = 0;
      }
    }
  }
  std::vector<std::array<std::int64_t, 3>> tris;
  for (std::size_t i = m, j = k; i > 0 || j > 0;)
  {
    if (fromB[i * w + j])
    {
      tris.push_back({ B(i), B(i - 1), L(j) });
      --i;
    }
    else
    {
      tris.push_back({ B(i), L(j - 1), L(j) });
      --j;
    }
  }
  for (auto it = tris.rbegin(); it != tris.rend(); ++it)
  {
    strip.insert(strip.end(), it->begin(), it->end());
    if (rungs)
    {
      // The edge (b_i, l_j) each step ends on: (first, last) of a step
      // along b, (first, last) of a step along l.
      rungs->push_back({ (*it)[0], (*it)[2] });
    }
  }
}

/// The closed polyline through `pts` (x y z each) resampled at `n` points
/// evenly spaced along it, from its first point.
std::vector<double> Resample(const std::vector<double>& pts, std::size_t n)
{
  const std::size_t m = pts.size() / 3;
  std::vector<double> at(m + 1, 0.0);
  for (std::size_t i = 0; i < m; ++i)
  {
    const double* p = &pts[3 * i];
    const double* q = &pts[3 * ((i + 1) % m)];
    at[i + 1] = at[i] + std::sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) + (q[2] - p[2]) * (q[2] - p[2]));
  }
  std::vector<double> out;
  std::size_t seg = 0;
  for (std::size_t k = 0; k < n; ++k)
  {
    const double s = at[m] * static_cast<double>(k) / static_cast<double>(n);
    while (seg + 1 < m && at[seg + 1] <= s)
    {
      ++seg;
    }
    const double len = at[seg + 1] - at[seg];
    const double f = len > 0.0 ? (s - at[seg]) / len : 0.0;
    const double* p = &pts[3 * seg];
    const double* q = &pts[3 * ((seg + 1) % m)];
    for (int d = 0; d < 3; ++d)
    {
      out.push_back(p[d] + f * (q[d] - p[d]));
    }
  }
  return out;
}

/// Whether a strip triangle crosses another triangle of the complex: apart,
/// they may not meet; sharing a point, each one's far edge must miss the
/// other (a crossing through the shared point's own edges goes unseen:
/// the refill then fails and is made without the strip); sharing an edge,
/// they may not fold onto each other.
bool StripCrosses(const Geometry& g, const std::vector<std::int64_t>& strip, const std::vector<std::int64_t>& others)
{
  auto tri = [&](const std::vector<std::int64_t>& v, std::size_t t) {
    return Tri(g.At(v[3 * t]), g.At(v[3 * t + 1]), g.At(v[3 * t + 2]));
  };
  std::vector<Box> a, b;
  const std::size_t nStrip = strip.size() / 3;
  for (std::size_t t = 0; t < nStrip; ++t)
  {
    a.emplace_back(tri(strip, t).bbox(), t);
    b.emplace_back(tri(strip, t).bbox(), t);
  }
  for (std::size_t t = 0; 3 * t < others.size(); ++t)
  {
    b.emplace_back(tri(others, t).bbox(), nStrip + t);
  }
  auto ids = [&](std::size_t t) {
    return t < nStrip ? &strip[3 * t] : &others[3 * (t - nStrip)];
  };
  bool crosses = false;
  CGAL::box_intersection_d(a.begin(), a.end(), b.begin(), b.end(), [&](const Box& x, const Box& y) {
    if (crosses || x.info() == y.info())
    {
      return;
    }
    const std::int64_t* p = ids(x.info());
    const std::int64_t* q = ids(y.info());
    int inP[3] = { -1, -1, -1 }; // per point of p: its place in q, or -1
    int shared = 0;
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        if (p[i] == q[j])
        {
          inP[i] = j;
          ++shared;
        }
      }
    }
    const Tri s(g.At(p[0]), g.At(p[1]), g.At(p[2])), o(g.At(q[0]), g.At(q[1]), g.At(q[2]));
    if (shared == 0)
    {
      crosses = CGAL::do_intersect(s, o);
    }
    else if (shared == 1)
    {
      // Each one's edge away from the shared point must miss the other.
      const int i = inP[0] >= 0 ? 0 : inP[1] >= 0 ? 1 : 2, j = inP[i];
      const K::Segment_3 ep(g.At(p[(i + 1) % 3]), g.At(p[(i + 2) % 3])), eq(g.At(q[(j + 1) % 3]), g.At(q[(j + 2) % 3]));
      crosses = CGAL::do_intersect(ep, o) || CGAL::do_intersect(eq, s);
    }
    else if (shared == 2)
    {
      // Folded onto each other: coplanar, the far points on one side of the edge.
      const int i = inP[0] < 0 ? 0 : inP[1] < 0 ? 1 : 2;
      int j = 0;
      while (q[j] == p[(i + 1) % 3] || q[j] == p[(i + 2) % 3])
      {
        ++j;
      }
      const Pt a = g.At(p[(i + 1) % 3]), b = g.At(p[(i + 2) % 3]), c = g.At(p[i]), d = g.At(q[j]);
      crosses = CGAL::orientation(a, b, c, d) == CGAL::COPLANAR && CGAL::coplanar_orientation(a, b, c, d) == CGAL::POSITIVE;
    }
  });
  return crosses;
}
}

bool CavitySeparatingStrip(const std::vector<double>& points, const std::vector<std::int64_t>& boundary,
  const std::vector<std::int64_t>& surface, double minAngle, std::vector<std::int64_t>& strip,
  std::vector<double>& newPoints, std::string& why)
{
  strip.clear();
  newPoints.clear();
  const Geometry g{ points };
  // ---- S's border loops.
  std::vector<Edge> border;
  std::vector<Loop> sLoops;
  if (surface.empty() || !BorderEdges(surface, border) || border.empty() || !ChainLoops(border, sLoops))
  {
    why = "S has no closed, manifold border";
    return false;
  }
  if (sLoops.size() > 8)
  {
    why = "S has " + std::to_string(sLoops.size()) + " border loops";
    return false;
  }
  // ---- The boundary's triangles by the side of S their centroid is on.
  std::vector<Tri> sTris;
  for (std::size_t t = 0; 3 * t < surface.size(); ++t)
  {
    sTris.emplace_back(g.At(surface[3 * t]), g.At(surface[3 * t + 1]), g.At(surface[3 * t + 2]));
  }
  Tree tree(sTris.begin(), sTris.end());
  tree.accelerate_distance_queries();
  const std::size_t nBoundary = boundary.size() / 3;
  std::vector<char> plus(nBoundary, 0);
  ParallelFor(
    nBoundary,
    [&](std::size_t first, std::size_t last) {
      // The boundary's triangles come in the cavity's order, mostly each
      // next to the one before: that one's closest point is a hint from
      // which AABB_tree's traversal is quicker than from its own (the
      // nearest point of its kd-tree, slow to find this far from S): 0.68
      // -> 0.48 s for the 5e6 cube's 45k faces. The closest point is the
      // same either way; only where two triangles of S are exactly as near
      // may the other be named, and its side is the same unless S folds there.
      Tree::Point_and_primitive_id previous;
      Pt previousC;
      bool have = false;
      for (std::size_t t = first; t < last; ++t)
      {
        const Pt c = CGAL::centroid(g.At(boundary[3 * t]), g.At(boundary[3 * t + 1]), g.At(boundary[3 * t + 2]));
        const bool near =
          have && CGAL::squared_distance(c, previousC) < 0.25 * CGAL::squared_distance(previousC, previous.first);
        const auto hit = near ? tree.closest_point_and_primitive(c, previous) : tree.closest_point_and_primitive(c);
        const Tri& s = *hit.second;
        const K::Vector_3 n = CGAL::cross_product(s[1] - s[0], s[2] - s[0]);
        plus[t] = (c - hit.first) * n >= 0.0 ? 1 : 0;
        previous = hit;
        previousC = c;
        have = true;
      }
    },
    0, 256);
  std::vector<Edge> change;
  std::vector<Loop> bLoops;
  if (!SideChangeEdges(boundary, plus, change) || change.empty() || !ChainLoops(change, bLoops))
  {
    why = "the boundary's sides of S do not meet in closed loops";
    return false;
  }
  if (bLoops.size() != sLoops.size())
  {
    why = std::to_string(bLoops.size()) + " loops on the boundary for " + std::to_string(sLoops.size()) +
      " border loops of S";
    return false;
  }
  // ---- Match each border loop with the nearest boundary loop, one to one.
  std::vector<int> match(sLoops.size(), -1);
  std::vector<std::vector<std::size_t>> nearOf(sLoops.size()); // per border point: the nearest of its match
  std::vector<char> taken(bLoops.size(), 0);
  for (std::size_t s = 0; s < sLoops.size(); ++s)
  {
    double best = std::numeric_limits<double>::max();
    for (std::size_t b = 0; b < bLoops.size(); ++b)
    {
      std::vector<std::size_t> near = Nearest(g, sLoops[s], bLoops[b]);
      double sum = 0.0;
      for (std::size_t i = 0; i < near.size(); ++i)
      {
        sum += std::sqrt(g.Distance2(sLoops[s][i], bLoops[b][near[i]]));
      }
      if (sum < best)
      {
        best = sum;
        match[s] = static_cast<int>(b);
        nearOf[s] = std::move(near);
      }
    }
    if (taken[match[s]])
    {
      why = "two border loops of S nearest to one loop on the boundary";
      return false;
    }
    taken[match[s]] = 1;
  }
  // ---- Each pair joined through loops of new points between them: the
  // band is several of S's edges wide and its two loops differ in spacing
  // (S's edge, the input's size), so one band of triangles would be thin.
  // The loops between follow the rungs (b_i, l_j) of the two loops' own
  // stitching at fractions t = 1/N .. (N-1)/N of the way, resampled at a
  // spacing growing geometrically from S's edge to the boundary's; N bands
  // about as wide as their spacing.
  // The boundary's inward normal at the loops' points (its triangles face
  // away from the cavity), where the strip leaves it square.
  std::unordered_map<std::int64_t, K::Vector_3> inward;
  for (const Loop& l : bLoops)
  {
    for (const std::int64_t v : l)
    {
      inward[v] = K::Vector_3(0.0, 0.0, 0.0);
    }
  }
  for (std::size_t t = 0; t < nBoundary; ++t)
  {
    const std::int64_t* v = &boundary[3 * t];
    const K::Vector_3 n = CGAL::cross_product(g.At(v[1]) - g.At(v[0]), g.At(v[2]) - g.At(v[0]));
    for (int k = 0; k < 3; ++k)
    {
      const auto it = inward.find(v[k]);
      if (it != inward.end())
      {
        it->second = it->second - n;
      }
    }
  }
  std::vector<double> all = points;
  const Geometry h{ all };
  const std::int64_t firstNew = static_cast<std::int64_t>(points.size() / 3);
  for (std::size_t s = 0; s < sLoops.size(); ++s)
  {
    const Loop& b = sLoops[s];
    Loop l = bLoops[match[s]];
    std::vector<std::size_t>& near = nearOf[s];
    double along = 0.0;
    const std::size_t k = l.size();
    for (std::size_t i = 0; i < b.size(); ++i)
    {
      const Pt p = g.At(b[i]), q = g.At(b[(i + 1) % b.size()]);
      const Pt u = g.At(l[(near[i] + 1) % k]), w = g.At(l[(near[i] + k - 1) % k]);
      along += (q - p) * (u - w);
    }
    if (along < 0.0)
    {
      std::reverse(l.begin(), l.end());
      for (std::size_t& j : near)
      {
        j = k - 1 - j;
      }
    }
    std::vector<std::int64_t> direct;
    std::vector<Edge> rungs;
    Stitch(g, b, l, near[0], direct, &rungs);
    auto meanEdge = [&](const Loop& loop) {
      double sum = 0.0;
      for (std::size_t i = 0; i < loop.size(); ++i)
      {
        sum += std::sqrt(g.Distance2(loop[i], loop[(i + 1) % loop.size()]));
      }
      return sum / static_cast<double>(loop.size());
    };
    const double eB = meanEdge(b), eL = meanEdge(l);
    double gap = 0.0;
    for (const Edge& r : rungs)
    {
      gap += std::sqrt(g.Distance2(r.first, r.second)) / static_cast<double>(rungs.size());
    }
    // Bands as wide as their triangles are high (0.87 of their spacing):
    // widths and spacings both growing by q from S's edge to the
    // boundary's, q^N = eL / eB.
    const double r = std::max(1.0, eL / eB);
    const double q0 = 1.0 + 0.87 * std::max(0.0, eL - eB) / std::max(gap, 1e-300);
    const int bands = r > 1.0 && q0 > 1.0
      ? std::max(1, std::min(20, static_cast<int>(std::lround(std::log(r) / std::log(q0)))))
      : std::max(1, std::min(20, static_cast<int>(std::lround(gap / (0.87 * eB)))));
    const double q = std::pow(r, 1.0 / bands);
    auto fraction = [&](int n) {
      return q > 1.0 + 1e-9 ? (std::pow(q, n) - 1.0) / (std::pow(q, bands) - 1.0) : static_cast<double>(n) / bands;
    };
    Loop inner = b;
    for (int n = 1; n <= bands; ++n)
    {
      Loop outer;
      if (n == bands)
      {
        outer = l;
      }
      else
      {
        const double t = fraction(n);
        std::vector<double> line;
        for (const Edge& r : rungs)
        {
          // A quadratic Bezier curve from S's border to the boundary,
          // arriving along the boundary's inward normal (so the strip
          // meets the boundary square, not in a thin wedge).
          const Pt p = g.At(r.first), q = g.At(r.second);
          K::Vector_3 n = inward[r.second];
          const double nn = std::sqrt(n.squared_length());
          const double d = 0.5 * std::sqrt(CGAL::squared_distance(p, q));
          const Pt c = nn > 0.0 ? q + (d / nn) * n : CGAL::midpoint(p, q);
          const double a = (1 - t) * (1 - t), bb = 2 * t * (1 - t), cc = t * t;
          line.insert(line.end(), { a * p.x() + bb * c.x() + cc * q.x(), a * p.y() + bb * c.y() + cc * q.y(),
                                    a * p.z() + bb * c.z() + cc * q.z() });
        }
        double length = 0.0;
        for (std::size_t i = 0; 3 * i < line.size(); ++i)
        {
          const std::size_t j = (i + 1) % (line.size() / 3);
          length += std::sqrt((line[3 * j] - line[3 * i]) * (line[3 * j] - line[3 * i]) +
            (line[3 * j + 1] - line[3 * i + 1]) * (line[3 * j + 1] - line[3 * i + 1]) +
            (line[3 * j + 2] - line[3 * i + 2]) * (line[3 * j + 2] - line[3 * i + 2]));
        }
        const double spacing = eB * std::pow(q, n);
        const auto count = static_cast<std::size_t>(std::max(3L, std::lround(length / spacing)));
        const std::vector<double> ring = Resample(line, count);
        for (std::size_t i = 0; 3 * i < ring.size(); ++i)
        {
          outer.push_back(static_cast<std::int64_t>(all.size() / 3));
          all.insert(all.end(), &ring[3 * i], &ring[3 * i] + 3);
        }
      }
      std::size_t j0 = 0;
      double best = std::numeric_limits<double>::max();
      for (std::size_t j = 0; j < outer.size(); ++j)
      {
        const double d = h.Distance2(inner[0], outer[j]);
        if (d < best)
        {
          best = d;
          j0 = j;
        }
      }
      Stitch(h, inner, outer, j0, strip);
      inner = std::move(outer);
    }
  }
  // ---- The new points smoothed within the strip (a few damped Laplacian
  // passes, a point's move kept only where its triangles' smallest angle
  // does not fall): the rings' corners, at the domain's edges and S's
  // jagged border, leave some thin triangles.
  {
    const std::size_t nAll = all.size() / 3;
    std::vector<std::vector<std::size_t>> star(nAll - firstNew), ring(nAll - firstNew);
    for (std::size_t t = 0; 3 * t < strip.size(); ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        const std::int64_t v = strip[3 * t + k];
        if (v >= firstNew)
        {
          star[v - firstNew].push_back(t);
          for (int o = 1; o < 3; ++o)
          {
            ring[v - firstNew].push_back(static_cast<std::size_t>(strip[3 * t + (k + o) % 3]));
          }
        }
      }
    }
    auto starAngle = [&](std::size_t i) {
      double a = 180.0;
      for (const std::size_t t : star[i])
      {
        a = std::min(a, MinAngle(h, strip[3 * t], strip[3 * t + 1], strip[3 * t + 2]));
      }
      return a;
    };
    for (int pass = 0; pass < 5; ++pass)
    {
      for (std::size_t i = 0; i < star.size(); ++i)
      {
        double c[3] = { 0.0, 0.0, 0.0 };
        for (const std::size_t v : ring[i])
        {
          for (int d = 0; d < 3; ++d)
          {
            c[d] += all[3 * v + d] / static_cast<double>(ring[i].size());
          }
        }
        double* x = &all[3 * (firstNew + i)];
        const double before = starAngle(i), old[3] = { x[0], x[1], x[2] };
        for (int d = 0; d < 3; ++d)
        {
          x[d] += 0.5 * (c[d] - x[d]);
        }
        if (starAngle(i) < before)
        {
          std::copy(old, old + 3, x);
        }
      }
    }
  }
  CollapseThinTriangles(h, firstNew, minAngle, strip);
  // ---- Its quality, and nothing crossed.
  double worst = 180.0;
  for (std::size_t t = 0; 3 * t < strip.size(); ++t)
  {
    worst = std::min(worst, MinAngle(h, strip[3 * t], strip[3 * t + 1], strip[3 * t + 2]));
  }
  if (worst < minAngle)
  {
    why = "the strip has a " + std::to_string(worst) + " degree angle";
    strip.clear();
    return false;
  }
  std::vector<std::int64_t> others = boundary;
  others.insert(others.end(), surface.begin(), surface.end());
  if (StripCrosses(h, strip, others))
  {
    why = "the strip would cross the boundary or S";
    strip.clear();
    return false;
  }
  // The strip's own points that its triangles still use (the collapses
  // leave some unused), renumbered.
  std::vector<std::int64_t> renumber(all.size() / 3 - static_cast<std::size_t>(firstNew), -1);
  std::vector<double> added;
  for (std::int64_t& v : strip)
  {
    if (v >= firstNew)
    {
      std::int64_t& r = renumber[static_cast<std::size_t>(v - firstNew)];
      if (r < 0)
      {
        r = firstNew + static_cast<std::int64_t>(added.size() / 3);
        added.insert(added.end(), &all[3 * v], &all[3 * v] + 3);
      }
      v = r;
    }
  }
  newPoints = std::move(added);
  return true;
}

void CollapseThinStripTriangles(
  const std::vector<double>& points, std::int64_t firstNew, double minAngle, std::vector<std::int64_t>& strip)
{
  CollapseThinTriangles(Geometry{ points }, firstNew, minAngle, strip);
}
}
