// SPDX-License-Identifier: BSD-3-Clause
#include "ARSurfaceRemesh.h"
#include "ARCGALTypes.h"

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>

#include <array>
#include <cmath>

namespace ar
{
namespace
{
using cgal::Kernel;
using cgal::Mesh;
using cgal::Point;
}

bool RemeshSurfaceIsotropic(const std::vector<double>& points, const std::vector<std::int64_t>& triangles,
  double edgeLength, std::vector<double>& outPoints, std::vector<std::int64_t>& outTriangles,
  std::string& error)
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
  PMP::isotropic_remeshing(CGAL::faces(mesh), edgeLength, mesh,
    CGAL::parameters::number_of_iterations(8).protect_constraints(true));
  mesh.collect_garbage();
  // (after the garbage is collected the vertex indices run 0 .. n-1)
  std::vector<std::int64_t> index(mesh.number_of_vertices(), -1);
  for (Mesh::Vertex_index v : mesh.vertices())
  {
    index[static_cast<std::size_t>(v)] = static_cast<std::int64_t>(outPoints.size() / 3);
    const Point& p = mesh.point(v);
    outPoints.insert(outPoints.end(), { p.x(), p.y(), p.z() });
  }
  for (Mesh::Face_index f : mesh.faces())
  {
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
    {
      outTriangles.push_back(index[static_cast<std::size_t>(v)]);
    }
  }
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
