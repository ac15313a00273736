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

/// `faces` over `points` as the Surface_mesh `mesh` when they are a
/// polygon mesh (manifold and consistently oriented:
/// PMP::is_polygon_soup_a_polygon_mesh); false, `mesh` untouched, when not.
inline bool SoupToMesh(const std::vector<Point>& points, const Soup& faces, Mesh& mesh)
{
  if (!PMP::is_polygon_soup_a_polygon_mesh(faces))
  {
    return false;
  }
  PMP::polygon_soup_to_polygon_mesh(points, faces, mesh);
  return true;
}
}
}

#endif
