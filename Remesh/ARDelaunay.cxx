// SPDX-License-Identifier: BSD-3-Clause
#include "ARDelaunay.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <cmath>
#include <utility>
#include <vector>

namespace ar
{
namespace
{
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_3<std::int64_t, Kernel>;
using Tds = CGAL::Triangulation_data_structure_3<VertexBase>;
using Delaunay = CGAL::Delaunay_triangulation_3<Kernel, Tds>;
}

bool DelaunayTetrahedralize(const double* xyz, std::size_t n, TetMesh& out, std::string& error)
{
  out = TetMesh();
  if (n < 4)
  {
    error = "Delaunay tetrahedralization needs at least 4 points, got " + std::to_string(n) + ".";
    return false;
  }
  std::vector<std::pair<Kernel::Point_3, std::int64_t>> input;
  input.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const double* p = xyz + 3 * i;
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
    {
      error = "point " + std::to_string(i) + " has a non-finite coordinate.";
      return false;
    }
    input.emplace_back(Kernel::Point_3(p[0], p[1], p[2]), static_cast<std::int64_t>(i));
  }

  // Spatially sorted insertion (CGAL does the sorting for a range of pairs).
  Delaunay dt(input.begin(), input.end());
  if (dt.dimension() < 3)
  {
    error = "the " + std::to_string(n) +
      " points are all coplanar (or collinear): their Delaunay triangulation has dimension " +
      std::to_string(dt.dimension()) + " and no tetrahedra.";
    return false;
  }

  out.Points.assign(xyz, xyz + 3 * n);
  out.Tetrahedra.reserve(4 * dt.number_of_finite_cells());
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c)
  {
    for (int k = 0; k < 4; ++k)
    {
      out.Tetrahedra.push_back(c->vertex(k)->info());
    }
  }
  return true;
}
}
