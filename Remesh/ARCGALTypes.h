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
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <cstddef>
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
/// of CGAL's std::set and maps: 0.05 s instead of 1.2 s for the 206,109
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
  std::vector<std::size_t> parent(3 * n);
  for (std::size_t i = 0; i < parent.size(); ++i)
  {
    parent[i] = i;
  }
  auto root = [&](std::size_t i) {
    while (parent[i] != i)
    {
      parent[i] = parent[parent[i]];
      i = parent[i];
    }
    return i;
  };
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
      parent[root(downHi)] = root(upHi);
      parent[root(downLo)] = root(upLo);
    }
    i = j;
  }
  // One fan per vertex: all its corners in one set.
  std::vector<std::pair<std::size_t, std::size_t>> vertexRoot(3 * n);
  for (std::size_t f = 0; f < n; ++f)
  {
    for (int k = 0; k < 3; ++k)
    {
      vertexRoot[3 * f + k] = { faces[f][k], root(3 * f + k) };
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
}
}

#endif
