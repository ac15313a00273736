// SPDX-License-Identifier: BSD-3-Clause
#include "ARSurfaceRemesh.h"
#include "ARCGALTypes.h"
#include "ARParallelFor.h"

#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/measure.h>

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>

namespace ar
{
namespace
{
using cgal::Kernel;
using cgal::Mesh;
using cgal::Point;
using cgal::Triangle;
using cgal::TriangleTree;
}

namespace
{
/// A surface remeshed in pieces when it would have at least this many
/// triangles at the target length (its area over an equilateral triangle's).
constexpr double PieceTriangles = 60000.0;

/**
 * What the remeshed points are projected on: the input's triangles, one
 * AABB tree per connected piece of the surface, as CGAL's own projection
 * (a point goes to its own piece, not to another lying closer, such as a
 * second sheet a hair's breadth away).
 */
struct Projection
{
  std::vector<std::vector<Triangle>> Triangles;
  std::vector<std::unique_ptr<TriangleTree>> Trees;

  /// The pieces of `mesh` and their trees (built, so that threads only query
  /// them); "v:ar_component" gets each vertex's piece.
  explicit Projection(Mesh& mesh)
  {
    namespace PMP = CGAL::Polygon_mesh_processing;
    auto faceComponent = mesh.add_property_map<Mesh::Face_index, std::size_t>("f:ar_component", 0).first;
    const std::size_t n = PMP::connected_components(mesh, faceComponent);
    Triangles.resize(n);
    auto component = mesh.add_property_map<Mesh::Vertex_index, int>("v:ar_component", -1).first;
    for (const Mesh::Face_index f : mesh.faces())
    {
      const Mesh::Halfedge_index h = mesh.halfedge(f);
      Triangles[faceComponent[f]].emplace_back(
        mesh.point(mesh.source(h)), mesh.point(mesh.target(h)), mesh.point(mesh.target(mesh.next(h))));
      for (const Mesh::Vertex_index v : CGAL::vertices_around_face(h, mesh))
      {
        component[v] = static_cast<int>(faceComponent[f]);
      }
    }
    mesh.remove_property_map(faceComponent);
    for (const std::vector<Triangle>& t : Triangles)
    {
      Trees.push_back(std::make_unique<TriangleTree>(t.begin(), t.end()));
      Trees.back()->build();
      Trees.back()->accelerate_distance_queries();
    }
  }
};

/**
 * CGAL's isotropic remeshing of `mesh` (8 iterations, border edges kept),
 * each point projected as CGAL's own projection does (the closest point of
 * its piece of the input), but each query started from a point known to lie
 * on it: where the point was projected last, or a neighbour's. CGAL's
 * default starts every query with a kd-tree search for the nearest of the
 * tree's reference points. The vertices' pieces are "v:ar_component".
 */
void RemeshMesh(Mesh& mesh, double edgeLength, const Projection& on)
{
  namespace PMP = CGAL::Polygon_mesh_processing;
  auto onSurface = mesh.add_property_map<Mesh::Vertex_index, Point>("v:ar_on_surface", Point(0, 0, 0)).first;
  auto known = mesh.add_property_map<Mesh::Vertex_index, bool>("v:ar_known", false).first;
  auto component = mesh.property_map<Mesh::Vertex_index, int>("v:ar_component").first;
  for (const Mesh::Vertex_index v : mesh.vertices())
  {
    onSurface[v] = mesh.point(v); // (the input's own points lie on it)
    known[v] = component[v] >= 0;
  }
  std::vector<Mesh::Vertex_index> front;
  auto project = [&](Mesh::Vertex_index v) {
    const Point& q = mesh.point(v);
    Mesh::Vertex_index from = v;
    if (!known[v])
    {
      // The nearest known point (a new point's neighbours mostly are).
      front.assign(1, v);
      for (std::size_t i = 0; i < front.size() && i < 256 && !known[from]; ++i)
      {
        for (const Mesh::Halfedge_index h : CGAL::halfedges_around_target(mesh.halfedge(front[i]), mesh))
        {
          const Mesh::Vertex_index u = mesh.source(h);
          if (known[u])
          {
            from = u;
            break;
          }
          front.push_back(u);
        }
      }
    }
    Point p = q;
    if (known[from])
    {
      component[v] = component[from];
      p = on.Trees[static_cast<std::size_t>(component[v])]->closest_point(q, onSurface[from]);
    }
    else
    {
      // (none near: the nearest piece)
      double best = std::numeric_limits<double>::max();
      for (std::size_t c = 0; c < on.Trees.size(); ++c)
      {
        const Point x = on.Trees[c]->closest_point(q);
        const double d = CGAL::to_double(CGAL::squared_distance(q, x));
        if (d < best)
        {
          best = d;
          p = x;
          component[v] = static_cast<int>(c);
        }
      }
    }
    onSurface[v] = p;
    known[v] = true;
    return p;
  };
  PMP::isotropic_remeshing(CGAL::faces(mesh), edgeLength, mesh,
    CGAL::parameters::number_of_iterations(8).protect_constraints(true).projection_functor(project));
  mesh.remove_property_map(onSurface);
  mesh.remove_property_map(known);
}

/// `mesh`'s points and triangles appended to `points`, `triangles`; a vertex
/// with a `shared` id (>= 0) that has come before is not repeated.
void Append(const Mesh& mesh, const Mesh::Property_map<Mesh::Vertex_index, std::int64_t>* shared,
  std::vector<std::int64_t>& firstOfShared, std::vector<double>& points, std::vector<std::int64_t>& triangles)
{
  std::vector<std::int64_t> index(mesh.number_of_vertices() + mesh.number_of_removed_vertices(), -1);
  for (const Mesh::Vertex_index v : mesh.vertices())
  {
    const std::int64_t g = shared ? (*shared)[v] : -1;
    if (g >= 0 && firstOfShared[static_cast<std::size_t>(g)] >= 0)
    {
      index[static_cast<std::size_t>(v)] = firstOfShared[static_cast<std::size_t>(g)];
      continue;
    }
    index[static_cast<std::size_t>(v)] = static_cast<std::int64_t>(points.size() / 3);
    if (g >= 0)
    {
      firstOfShared[static_cast<std::size_t>(g)] = index[static_cast<std::size_t>(v)];
    }
    const Point& p = mesh.point(v);
    points.insert(points.end(), { p.x(), p.y(), p.z() });
  }
  for (const Mesh::Face_index f : mesh.faces())
  {
    for (const Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
    {
      triangles.push_back(index[static_cast<std::size_t>(v)]);
    }
  }
}

/**
 * `mesh` cut in two pieces of about equal area, across the axis of its
 * largest extent (by the faces' centroids), the cut's edges split to the
 * target length as the border's are; each piece a mesh of its own whose
 * vertices carry their id in `mesh` ("v:ar_shared"). False where a piece
 * would not be a manifold (it touches the other at a single vertex, say):
 * the surface is then remeshed whole (with the cut's edges split).
 */
bool CutInTwo(Mesh& mesh, double edgeLength, std::array<Mesh, 2>& pieces)
{
  namespace PMP = CGAL::Polygon_mesh_processing;
  // (the cut's new points inherit the piece of the input they lie on)
  auto wholeComponent = mesh.property_map<Mesh::Vertex_index, int>("v:ar_component").first;
  const CGAL::Bbox_3 box = PMP::bbox(mesh);
  int axis = 0;
  for (int d = 1; d < 3; ++d)
  {
    if (box.max(d) - box.min(d) > box.max(axis) - box.min(axis))
    {
      axis = d;
    }
  }
  std::vector<std::pair<double, Mesh::Face_index>> order;
  std::vector<double> area(mesh.number_of_faces() + mesh.number_of_removed_faces(), 0.0);
  for (const Mesh::Face_index f : mesh.faces())
  {
    const Mesh::Halfedge_index h = mesh.halfedge(f);
    const Point &a = mesh.point(mesh.source(h)), &b = mesh.point(mesh.target(h)),
                &c = mesh.point(mesh.target(mesh.next(h)));
    order.emplace_back((a[axis] + b[axis] + c[axis]) / 3.0, f);
    area[static_cast<std::size_t>(f)] = std::sqrt(CGAL::to_double(CGAL::squared_area(a, b, c)));
  }
  std::sort(order.begin(), order.end());
  double total = 0.0;
  for (const auto& o : order)
  {
    total += area[static_cast<std::size_t>(o.second)];
  }
  auto piece = mesh.add_property_map<Mesh::Face_index, int>("f:ar_piece", -1).first;
  double sum = 0.0;
  for (const auto& o : order)
  {
    piece[o.second] = sum < 0.5 * total ? 0 : 1;
    sum += area[static_cast<std::size_t>(o.second)];
  }
  // The cut: the edges between the pieces, split as the border (their parts
  // stay marked), then the faces the splits made given their side's piece.
  auto cut = mesh.add_property_map<Mesh::Edge_index, bool>("e:ar_cut", false).first;
  std::vector<Mesh::Edge_index> cutEdges;
  for (const Mesh::Edge_index e : mesh.edges())
  {
    const Mesh::Halfedge_index h = mesh.halfedge(e);
    if (!mesh.is_border(e) && piece[mesh.face(h)] != piece[mesh.face(mesh.opposite(h))])
    {
      cut[e] = true;
      cutEdges.push_back(e);
    }
  }
  bool ok = !cutEdges.empty();
  if (ok)
  {
    PMP::split_long_edges(cutEdges, edgeLength, mesh, CGAL::parameters::edge_is_constrained_map(cut));
    for (const Mesh::Vertex_index v : mesh.vertices())
    {
      // (a split's new point: its edge's ends are the input's)
      for (const Mesh::Halfedge_index h : CGAL::halfedges_around_target(mesh.halfedge(v), mesh))
      {
        if (wholeComponent[v] >= 0)
        {
          break;
        }
        wholeComponent[v] = wholeComponent[mesh.source(h)];
      }
    }
    std::vector<Mesh::Face_index> front;
    for (const Mesh::Face_index f : mesh.faces())
    {
      if (piece[f] >= 0)
      {
        front.push_back(f);
      }
    }
    while (!front.empty())
    {
      const Mesh::Face_index f = front.back();
      front.pop_back();
      for (const Mesh::Halfedge_index h : CGAL::halfedges_around_face(mesh.halfedge(f), mesh))
      {
        const Mesh::Face_index g = mesh.face(mesh.opposite(h));
        if (g != Mesh::null_face() && !cut[mesh.edge(h)] && piece[g] < 0)
        {
          piece[g] = piece[f];
          front.push_back(g);
        }
      }
    }
    std::vector<cgal::Point> pts;
    for (int k = 0; k < 2 && ok; ++k)
    {
      std::vector<std::int64_t> local(mesh.number_of_vertices() + mesh.number_of_removed_vertices(), -1);
      std::vector<std::int64_t> global;
      pts.clear();
      cgal::Soup faces;
      for (const Mesh::Face_index f : mesh.faces())
      {
        if (piece[f] != k)
        {
          continue;
        }
        std::array<std::size_t, 3> t{};
        int j = 0;
        for (const Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
        {
          std::int64_t& l = local[static_cast<std::size_t>(v)];
          if (l < 0)
          {
            l = static_cast<std::int64_t>(pts.size());
            pts.push_back(mesh.point(v));
            global.push_back(static_cast<std::int64_t>(v));
          }
          t[j++] = static_cast<std::size_t>(l);
        }
        faces.push_back(t);
      }
      ok = !faces.empty() && cgal::SoupToMesh(pts, faces, pieces[k]);
      if (ok)
      {
        // (polygon_soup_to_polygon_mesh adds the points in their order)
        auto shared = pieces[k].add_property_map<Mesh::Vertex_index, std::int64_t>("v:ar_shared", -1).first;
        auto component = pieces[k].add_property_map<Mesh::Vertex_index, int>("v:ar_component", -1).first;
        for (const Mesh::Vertex_index v : pieces[k].vertices())
        {
          shared[v] = global[static_cast<std::size_t>(v)];
          component[v] = wholeComponent[Mesh::Vertex_index(static_cast<Mesh::size_type>(shared[v]))];
        }
      }
    }
  }
  mesh.remove_property_map(piece);
  mesh.remove_property_map(cut);
  return ok;
}
}

bool RemeshSurfaceIsotropic(const std::vector<double>& points, const std::vector<std::int64_t>& triangles,
  double edgeLength, std::vector<double>& outPoints, std::vector<std::int64_t>& outTriangles,
  std::string& error, int threads, int* pieces)
{
  namespace PMP = CGAL::Polygon_mesh_processing;
  outPoints.clear();
  outTriangles.clear();
  if (!(edgeLength > 0.0) || !std::isfinite(edgeLength))
  {
    error = "the target edge length must be a positive number.";
    return false;
  }
  const std::size_t n = points.size() / 3;
  std::vector<Point> pts;
  pts.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const double* x = &points[3 * i];
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
    {
      error = "the surface has a non-finite coordinate.";
      return false;
    }
    pts.emplace_back(x[0], x[1], x[2]);
  }
  std::vector<std::array<std::size_t, 3>> faces(triangles.size() / 3);
  for (std::size_t t = 0; t < faces.size(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const std::int64_t id = triangles[3 * t + k];
      if (id < 0 || static_cast<std::size_t>(id) >= n)
      {
        error = "a triangle of the surface refers to a point that does not exist.";
        return false;
      }
      faces[t][k] = static_cast<std::size_t>(id);
    }
  }
  if (faces.empty())
  {
    error = "the surface has no triangles.";
    return false;
  }
  PMP::orient_polygon_soup(pts, faces); // may duplicate points at non-manifold vertices
  Mesh mesh;
  if (!cgal::SoupToMesh(pts, faces, mesh))
  {
    error = "the surface is not an orientable manifold (non-manifold edges); remesh it by hand or "
            "remove the offending triangles.";
    return false;
  }
  std::vector<Mesh::Edge_index> border;
  for (Mesh::Halfedge_index h : mesh.halfedges())
  {
    if (mesh.is_border(h))
    {
      border.push_back(mesh.edge(h));
    }
  }
  PMP::split_long_edges(border, edgeLength, mesh);
  const Projection projection(mesh); // the input's pieces ("v:ar_component")
  // A large surface is cut in two pieces, the cut kept as the border is, and
  // the pieces remeshed side by side (by geometry alone, so the same output
  // on any number of threads: with one, one after the other).
  const double area = PMP::area(mesh);
  std::array<Mesh, 2> halves;
  const bool cut = area / (0.25 * std::sqrt(3.0) * edgeLength * edgeLength) >= PieceTriangles &&
    CutInTwo(mesh, edgeLength, halves);
  if (pieces)
  {
    *pieces = cut ? 2 : 1;
  }
  if (cut)
  {
    ParallelFor(
      2, [&](std::size_t first, std::size_t last) {
        for (std::size_t k = first; k < last; ++k)
        {
          RemeshMesh(halves[k], edgeLength, projection);
        }
      },
      static_cast<std::size_t>(std::max(1, threads)), 1);
    std::vector<std::int64_t> firstOfShared(mesh.number_of_vertices() + mesh.number_of_removed_vertices(), -1);
    for (const Mesh& piece : halves)
    {
      const auto shared = piece.property_map<Mesh::Vertex_index, std::int64_t>("v:ar_shared").first;
      Append(piece, &shared, firstOfShared, outPoints, outTriangles);
    }
    return true;
  }
  RemeshMesh(mesh, edgeLength, projection);
  std::vector<std::int64_t> none;
  Append(mesh, nullptr, none, outPoints, outTriangles);
  return true;
}

bool SurfacesIntersect(const std::vector<double>& pointsA, const std::vector<std::int64_t>& trianglesA,
  const std::vector<double>& pointsB, const std::vector<std::int64_t>& trianglesB)
{
  using K = cgal::Kernel;
  using Triangle = cgal::Triangle;
  using Tree = cgal::TriangleTree;
  auto triangles = [](const std::vector<double>& p, const std::vector<std::int64_t>& t) {
    std::vector<Triangle> out;
    out.reserve(t.size() / 3);
    auto point = [&](std::int64_t i) { return K::Point_3(p[3 * i], p[3 * i + 1], p[3 * i + 2]); };
    for (std::size_t k = 0; k + 2 < t.size(); k += 3)
    {
      const Triangle tri(point(t[k]), point(t[k + 1]), point(t[k + 2]));
      if (!tri.is_degenerate())
      {
        out.push_back(tri);
      }
    }
    return out;
  };
  const std::vector<Triangle> a = triangles(pointsA, trianglesA), b = triangles(pointsB, trianglesB);
  if (a.empty() || b.empty())
  {
    return false;
  }
  Tree tree(a.begin(), a.end());
  for (const Triangle& t : b)
  {
    if (tree.do_intersect(t))
    {
      return true;
    }
  }
  return false;
}
}
