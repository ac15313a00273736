/**
 * Private to the core's .cxx files (no public header includes it): the
 * CGAL types they share, and the one conversion of a triangle soup to a
 * Surface_mesh that each of them used to write out.
 */
#ifndef ARCGALTypes_h
#define ARCGALTypes_h

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include "ARParallelFor.h"
#include "ARUnionFind.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace ar
{
namespace cgal
{
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Triangle = Kernel::Triangle_3;
/// An AABB tree over a std::vector<Triangle> (which must outlive it).
using TriangleTree = CGAL::AABB_tree<
  CGAL::AABB_traits<Kernel, CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>>>;
namespace PMP = CGAL::Polygon_mesh_processing;
/// Triangles as indices into a point list.
using Soup = std::vector<std::array<std::size_t, 3>>;

/// Whether `faces` is a polygon mesh, as PMP::is_polygon_soup_a_polygon_mesh
/// decides it for triangles: no triangle with a repeated corner, no directed
/// edge in two triangles (so an edge has at most two, in opposite
/// directions), and the triangles at each vertex one fan (edge-connected
/// around it). With sorted arrays and a union-find over the corners instead
/// of CGAL's std::set and maps: about 0.2 s instead of 1.2 s for the 206,109
/// triangles of the 5e6 cube's S.
inline bool IsTriangleSoupAMesh(const Soup& faces)
{
  const std::size_t n = faces.size();
  // Directed edges (a, b) as (min, max, face, corner of a), the direction in
  // whether a is the min.
  struct Edge
  {
    std::size_t Lo, Hi, Face;
    int Corner; // the corner of the edge's start in Face
    bool Up;    // start == Lo
  };
  std::vector<Edge> edges;
  edges.reserve(3 * n);
  for (std::size_t f = 0; f < n; ++f)
  {
    const auto& t = faces[f];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
    {
      return false;
    }
    for (int k = 0; k < 3; ++k)
    {
      const std::size_t a = t[k], b = t[(k + 1) % 3];
      edges.push_back({ std::min(a, b), std::max(a, b), f, k, a < b });
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
    return x.Lo != y.Lo ? x.Lo < y.Lo : (x.Hi != y.Hi ? x.Hi < y.Hi : x.Up < y.Up);
  });
  // Corners (3 per face), joined across each edge two faces share: around
  // both its ends.
  UnionFind corners(3 * n);
  for (std::size_t i = 0; i < edges.size();)
  {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].Lo == edges[i].Lo && edges[j].Hi == edges[i].Hi)
    {
      ++j;
    }
    if (j - i > 2 || (j - i == 2 && edges[i].Up == edges[i + 1].Up))
    {
      return false; // a directed edge twice
    }
    if (j - i == 2)
    {
      // edges[i] runs Hi -> Lo in its face, edges[i + 1] Lo -> Hi.
      const Edge& down = edges[i];
      const Edge& up = edges[i + 1];
      const std::size_t downHi = 3 * down.Face + down.Corner, downLo = 3 * down.Face + (down.Corner + 1) % 3;
      const std::size_t upLo = 3 * up.Face + up.Corner, upHi = 3 * up.Face + (up.Corner + 1) % 3;
      corners.Union(static_cast<std::int64_t>(downHi), static_cast<std::int64_t>(upHi));
      corners.Union(static_cast<std::int64_t>(downLo), static_cast<std::int64_t>(upLo));
    }
    i = j;
  }
  // One fan per vertex: all its corners in one set.
  std::vector<std::pair<std::size_t, std::int64_t>> vertexRoot(3 * n);
  for (std::size_t f = 0; f < n; ++f)
  {
    for (int k = 0; k < 3; ++k)
    {
      vertexRoot[3 * f + k] = { faces[f][k], corners.Find(static_cast<std::int64_t>(3 * f + k)) };
    }
  }
  std::sort(vertexRoot.begin(), vertexRoot.end());
  for (std::size_t i = 1; i < vertexRoot.size(); ++i)
  {
    if (vertexRoot[i].first == vertexRoot[i - 1].first && vertexRoot[i].second != vertexRoot[i - 1].second)
    {
      return false; // two fans at a vertex
    }
  }
  return true;
}

/// `faces` over `points` as the Surface_mesh `mesh` when they are a
/// polygon mesh (manifold and consistently oriented: IsTriangleSoupAMesh);
/// false, `mesh` untouched, when not.
inline bool SoupToMesh(const std::vector<Point>& points, const Soup& faces, Mesh& mesh)
{
  if (!IsTriangleSoupAMesh(faces))
  {
    return false;
  }
  PMP::polygon_soup_to_polygon_mesh(points, faces, mesh);
  return true;
}

/// Whether `mesh` intersects itself (PMP::does_self_intersect), in two
/// halves side by side on up to `threads` threads (0: the hardware's;
/// CGAL's own parallel test needs TBB): cut at the median of the triangles'
/// centres along the longest axis of the bounding box, L the triangles
/// whose extent along it starts below the cut, R those whose extent reaches
/// the cut or beyond (a straddler is in both). Two triangles that meet have
/// extents that overlap, and the overlap starts below the cut (both in L)
/// or at or above it (both in R), so the halves find every intersection the
/// whole test does; the answer is the same on any number of threads.
inline bool DoesSelfIntersect(const Mesh& mesh, std::size_t threads)
{
  std::vector<Mesh::Face_index> all(mesh.faces().begin(), mesh.faces().end());
  if (all.empty())
  {
    return false;
  }
  const CGAL::Bbox_3 box = PMP::bbox(mesh);
  int axis = 0;
  for (int a = 1; a < 3; ++a)
  {
    if (box.max(a) - box.min(a) > box.max(axis) - box.min(axis))
    {
      axis = a;
    }
  }
  std::vector<std::array<double, 2>> span(all.size()); // per face: its extent along the axis
  for (std::size_t f = 0; f < all.size(); ++f)
  {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(all[f]), mesh))
    {
      const double c = mesh.point(v)[axis];
      lo = std::min(lo, c);
      hi = std::max(hi, c);
    }
    span[f] = { lo, hi };
  }
  // The median of the finite centres (a face with a non-finite coordinate
  // goes to both halves).
  std::vector<double> centre;
  centre.reserve(all.size());
  for (const auto& e : span)
  {
    if (std::isfinite(e[0]) && std::isfinite(e[1]))
    {
      centre.push_back(0.5 * (e[0] + e[1]));
    }
  }
  if (!centre.empty())
  {
    std::nth_element(centre.begin(), centre.begin() + centre.size() / 2, centre.end());
  }
  const double cut = centre.empty() ? 0.0 : centre[centre.size() / 2];
  std::vector<std::vector<Mesh::Face_index>> halves(2);
  for (std::size_t f = 0; f < all.size(); ++f)
  {
    const bool finite = std::isfinite(span[f][0]) && std::isfinite(span[f][1]);
    if (!finite || span[f][0] < cut)
    {
      halves[0].push_back(all[f]);
    }
    if (!finite || span[f][1] >= cut)
    {
      halves[1].push_back(all[f]);
    }
  }
  char crossing[2] = { 0, 0 };
  ParallelFor(
    2,
    [&](std::size_t first, std::size_t last) {
      for (std::size_t k = first; k < last; ++k)
      {
        crossing[k] = PMP::does_self_intersect(halves[k], mesh) ? 1 : 0;
      }
    },
    threads, 1);
  return crossing[0] || crossing[1];
}
}
}

#endif
