// SPDX-License-Identifier: BSD-3-Clause
#include "ARMedialAxis.h"
#include "ARCGALTypes.h"
#include "ARParallelFor.h"
#include "ARUnionFind.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <numeric>
#include <sstream>
#include <utility>

namespace ar
{
namespace
{
using cgal::Kernel;
using cgal::Point;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_3<std::int64_t, Kernel>;
using CellBase = CGAL::Delaunay_triangulation_cell_base_3<Kernel>;
using CellBaseInfo = CGAL::Triangulation_cell_base_with_info_3<std::int64_t, Kernel, CellBase>;
using Tds = CGAL::Triangulation_data_structure_3<VertexBase, CellBaseInfo>;
using Delaunay = CGAL::Delaunay_triangulation_3<Kernel, Tds>;
using cgal::Mesh;

constexpr double Pi = 3.14159265358979323846;

bool Finite3(const double* v)
{
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

double Distance(const double* a, const double* b)
{
  const double d[3] = { a[0] - b[0], a[1] - b[1], a[2] - b[2] };
  return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

double TriangleArea(const double* a, const double* b, const double* c)
{
  const double u[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
  const double v[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
  const double w[3] = { u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
    u[0] * v[1] - u[1] * v[0] };
  return 0.5 * std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
}

/// y = A x + b.
struct Affine
{
  double A[3][3];
  double b[3];

  void Apply(const double* x, double* y) const
  {
    for (int i = 0; i < 3; ++i)
    {
      y[i] = this->A[i][0] * x[0] + this->A[i][1] * x[1] + this->A[i][2] * x[2] + this->b[i];
    }
  }
  void ApplyLinear(const double* x, double* y) const
  {
    for (int i = 0; i < 3; ++i)
    {
      y[i] = this->A[i][0] * x[0] + this->A[i][1] * x[1] + this->A[i][2] * x[2];
    }
  }
  /// this o other
  Affine After(const Affine& other) const
  {
    Affine r;
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        r.A[i][j] = 0.0;
        for (int k = 0; k < 3; ++k)
        {
          r.A[i][j] += this->A[i][k] * other.A[k][j];
        }
      }
    }
    this->ApplyLinear(other.b, r.b);
    for (int i = 0; i < 3; ++i)
    {
      r.b[i] += this->b[i];
    }
    return r;
  }
  bool Near(const Affine& o, double lengthTol) const
  {
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        if (std::abs(this->A[i][j] - o.A[i][j]) > 1e-9)
        {
          return false;
        }
      }
      if (std::abs(this->b[i] - o.b[i]) > lengthTol)
      {
        return false;
      }
    }
    return true;
  }
  static Affine Identity()
  {
    return Affine{ { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } }, { 0, 0, 0 } };
  }
};

struct MirrorPlane
{
  double Origin[3];
  double Normal[3]; ///< unit, pointing to the side that holds the surface
  Affine Reflection;
  double Distance(const double* x) const
  {
    return (x[0] - this->Origin[0]) * this->Normal[0] + (x[1] - this->Origin[1]) * this->Normal[1] +
      (x[2] - this->Origin[2]) * this->Normal[2];
  }
};

/// Point-in-domain test on a closed triangulated surface (CGAL AABB tree).
class DomainTest
{
public:
  bool Build(const ClosedSurface& domain, std::string& error)
  {
    namespace PMP = CGAL::Polygon_mesh_processing;
    const std::size_t np = domain.Points.size() / 3;
    std::vector<Point> points;
    points.reserve(np);
    for (std::size_t i = 0; i < np; ++i)
    {
      const double* p = domain.Points.data() + 3 * i;
      if (!Finite3(p))
      {
        error = "the domain boundary has a non-finite coordinate at point " + std::to_string(i) + ".";
        return false;
      }
      points.emplace_back(p[0], p[1], p[2]);
    }
    cgal::Soup faces(domain.Triangles.size() / 3);
    for (std::size_t t = 0; t < faces.size(); ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        const std::int64_t id = domain.Triangles[3 * t + k];
        if (id < 0 || static_cast<std::size_t>(id) >= np)
        {
          error = "the domain boundary has a triangle index out of range.";
          return false;
        }
        faces[t][k] = static_cast<std::size_t>(id);
      }
    }
    if (faces.empty())
    {
      error = "the domain boundary has no triangles.";
      return false;
    }
    if (!cgal::SoupToMesh(points, faces, this->Surface))
    {
      error = "the domain boundary is not a manifold, consistently oriented triangle mesh.";
      return false;
    }
    if (!CGAL::is_closed(this->Surface))
    {
      error = "the domain boundary is not closed (it has border edges).";
      return false;
    }
    this->Inside = std::make_unique<CGAL::Side_of_triangle_mesh<Mesh, Kernel>>(this->Surface);
    return true;
  }

  bool Contains(const Point& p) const
  {
    return (*this->Inside)(p) != CGAL::ON_UNBOUNDED_SIDE;
  }

private:
  Mesh Surface;
  std::unique_ptr<CGAL::Side_of_triangle_mesh<Mesh, Kernel>> Inside;
};

/**
 * One ComputeMedialSheet run: the inputs, the state its stages share, and the
 * stages in the order they run (Execute), each a step of the header's
 * algorithm; as CavityRun (ARCavity.cxx) keeps its passes over one state.
 */
class MedialRun
{
public:
  MedialRun(const double* points_, std::size_t nPoints_, const double* normals_,
    const std::int64_t* triangles_, std::size_t nTriangles_, const MedialAxisOptions& options_,
    const ClosedSurface* domain_, MedialSheet& out_, std::string& error_,
    const ProgressCallback& progress_)
    : points(points_)
    , nPoints(nPoints_)
    , normals(normals_)
    , triangles(triangles_)
    , nTriangles(nTriangles_)
    , options(options_)
    , domain(domain_)
    , out(out_)
    , error(error_)
    , progress(progress_)
  {
  }

  bool Execute();

private:
  bool Validate();                ///< sizes, options, finite input, triangle indices
  void ComputeEdgeLengths();      ///< each point's longest surface edge
  bool BuildDomain();             ///< the point-in-domain test, if a domain is given
  bool BuildMirrorPlanes();       ///< the symmetry planes, oriented to the surface's side
  void BuildMirrorCopies();       ///< the products of their reflections
  void AddMirrorImages();         ///< the surface and its mirror images: all*
  bool Triangulate();             ///< the Delaunay tetrahedra of all the points
  void ComputeVoronoiVertices();  ///< circumcentres, radii and the interior test
  void MergeCoincidentVertices(); ///< cospherical points' circumcentres as one
  bool CollectFacets();           ///< Voronoi facets with an interior ring
  void JoinSheets();              ///< facets joined along Voronoi edges
  void TriangulateFacets();       ///< fans, and each facet's area
  void SelectSheets();            ///< sheet areas, the kept sheets' ids
  void Output();                  ///< compact points, triangles, sheet ids

  /// Folds a point into the original side of every symmetry plane.
  void Fold(double* x) const;
  /// Reports `f` to the progress callback; true (with the error set) to abort.
  bool Aborted(double f)
  {
    if (this->progress && this->progress(f))
    {
      this->error = "aborted.";
      return true;
    }
    return false;
  }

  // Inputs.
  const double* points;
  const std::size_t nPoints;
  const double* normals;
  const std::int64_t* triangles;
  const std::size_t nTriangles;
  const MedialAxisOptions& options;
  const ClosedSurface* domain;
  MedialSheet& out;
  std::string& error;
  const ProgressCallback& progress;

  // The surface: each point's longest edge, the domain test.
  std::vector<double> edgeLength;
  std::unique_ptr<DomainTest> inDomain;
  // Symmetry planes and the copies of the surface.
  double samePoint = 0.0;
  std::vector<MirrorPlane> planes;
  std::vector<Affine> copies;
  std::vector<double> allPoints, allNormals, allEdgeLength;
  std::size_t nAll = 0;
  // The Delaunay tetrahedra (cells' info: their index in `cells`, -1 if
  // infinite), their Voronoi vertices and which are interior.
  Delaunay dt;
  std::vector<Delaunay::Cell_handle> cells;
  std::size_t nCells = 0;
  std::vector<double> centre, radius;
  std::vector<char> keep;
  UnionFind same{ 0 };
  // The Voronoi facets: polygons of (merged) cell ids; the facet of each cell
  // and local edge.
  std::vector<std::int64_t> facetOffsets{ 0 };
  std::vector<std::int64_t> facetCells;
  std::vector<std::int32_t> facetOf;
  std::size_t nFacets = 0;
  // Sheets, the facets' fan triangles (cell ids) and the kept sheets.
  UnionFind sheets{ 0 };
  std::vector<std::int64_t> tris;
  std::vector<std::int64_t> triFacet;
  std::vector<double> facetArea;
  std::vector<std::int64_t> sheetOfRoot;
  std::vector<int> newSheetId;
};

/// The local edges of a tetrahedron, numbered 0..5.
const int EdgeIndex[4][4] = { { -1, 0, 1, 2 }, { 0, -1, 3, 4 }, { 1, 3, -1, 5 }, { 2, 4, 5, -1 } };

bool MedialRun::Execute()
{
  out = MedialSheet();
  if (!Validate())
  {
    return false;
  }
  ComputeEdgeLengths();
  if (!BuildDomain() || !BuildMirrorPlanes())
  {
    return false;
  }
  BuildMirrorCopies();
  AddMirrorImages();
  if (!Triangulate() || Aborted(0.4))
  {
    return false;
  }
  ComputeVoronoiVertices();
  if (Aborted(0.6))
  {
    return false;
  }
  MergeCoincidentVertices();
  if (!CollectFacets())
  {
    return false;
  }
  JoinSheets();
  TriangulateFacets();
  SelectSheets();
  Output();
  progress && progress(1.0);
  return true;
}

// ---- Validation.
bool MedialRun::Validate()
{
  if (nPoints < 4)
  {
    error = "the surface has " + std::to_string(nPoints) +
      " points; a medial axis needs at least 4 that are not coplanar.";
    return false;
  }
  if (nTriangles == 0)
  {
    error = "the surface has no triangles.";
    return false;
  }
  // Options out of range are refused, not clamped (the filter's own check
  // names them first; a direct caller of the core gets the same answer).
  if (!(options.MinimumObjectAngle >= 0.0 && options.MinimumObjectAngle <= 180.0))
  {
    std::ostringstream msg;
    msg << "MinimumObjectAngle is " << options.MinimumObjectAngle << "; it must lie in [0, 180] degrees.";
    error = msg.str();
    return false;
  }
  if (!(options.MinimumRadiusFactor >= 0.0) || !std::isfinite(options.MinimumRadiusFactor))
  {
    std::ostringstream msg;
    msg << "MinimumRadiusFactor is " << options.MinimumRadiusFactor << "; it must be at least 0 (and finite).";
    error = msg.str();
    return false;
  }
  for (std::size_t i = 0; i < nPoints; ++i)
  {
    if (!Finite3(points + 3 * i))
    {
      error = "surface point " + std::to_string(i) + " has a non-finite coordinate (NaN or Inf).";
      return false;
    }
    if (!Finite3(normals + 3 * i))
    {
      error = "the normal at surface point " + std::to_string(i) + " is not finite.";
      return false;
    }
  }
  for (std::size_t k = 0; k < 3 * nTriangles; ++k)
  {
    if (triangles[k] < 0 || static_cast<std::size_t>(triangles[k]) >= nPoints)
    {
      error = "triangle " + std::to_string(k / 3) + " refers to point " +
        std::to_string(triangles[k]) + ", which does not exist.";
      return false;
    }
  }
  return true;
}

// ---- Local surface edge length: each point's longest surface edge.
void MedialRun::ComputeEdgeLengths()
{
  edgeLength.assign(nPoints, 0.0);
  for (std::size_t t = 0; t < nTriangles; ++t)
  {
    const std::int64_t* tri = triangles + 3 * t;
    for (int k = 0; k < 3; ++k)
    {
      const std::int64_t a = tri[k], b = tri[(k + 1) % 3];
      const double l = Distance(points + 3 * a, points + 3 * b);
      edgeLength[a] = std::max(edgeLength[a], l);
      edgeLength[b] = std::max(edgeLength[b], l);
    }
  }
}

bool MedialRun::BuildDomain()
{
  if (domain)
  {
    inDomain = std::make_unique<DomainTest>();
    if (!inDomain->Build(*domain, error))
    {
      return false;
    }
  }
  return true;
}

// ---- Symmetry planes: the surface and its mirror images.
bool MedialRun::BuildMirrorPlanes()
{
  double lo[3] = { points[0], points[1], points[2] }, hi[3] = { lo[0], lo[1], lo[2] };
  for (std::size_t i = 0; i < nPoints; ++i)
  {
    for (int d = 0; d < 3; ++d)
    {
      lo[d] = std::min(lo[d], points[3 * i + d]);
      hi[d] = std::max(hi[d], points[3 * i + d]);
    }
  }
  const double diagonal = Distance(lo, hi);
  samePoint = 1e-9 * diagonal;
  for (std::size_t k = 0; k + 5 < options.SymmetryPlanes.size(); k += 6)
  {
    MirrorPlane m;
    const double* v = options.SymmetryPlanes.data() + k;
    const double len = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5]);
    if (!Finite3(v) || !Finite3(v + 3) || !(len > 0.0))
    {
      error = "symmetry plane " + std::to_string(k / 6) + " has a zero or non-finite normal or origin.";
      return false;
    }
    for (int d = 0; d < 3; ++d)
    {
      m.Origin[d] = v[d];
      m.Normal[d] = v[3 + d] / len;
    }
    // The normal points to the side that holds most of the surface.
    double side = 0.0;
    for (std::size_t i = 0; i < nPoints; ++i)
    {
      const double dist = m.Distance(points + 3 * i);
      side += dist > samePoint ? 1.0 : (dist < -samePoint ? -1.0 : 0.0);
    }
    if (side < 0.0)
    {
      for (double& c : m.Normal)
      {
        c = -c;
      }
    }
    const double on = m.Origin[0] * m.Normal[0] + m.Origin[1] * m.Normal[1] + m.Origin[2] * m.Normal[2];
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        m.Reflection.A[i][j] = (i == j ? 1.0 : 0.0) - 2.0 * m.Normal[i] * m.Normal[j];
      }
      m.Reflection.b[i] = 2.0 * on * m.Normal[i];
    }
    planes.push_back(m);
  }
  return true;
}

// The copies: products of reflections, breadth first, up to 8 of them (two
// parallel planes generate an endless stack; 8 copies give the original
// four neighbours on each side).
void MedialRun::BuildMirrorCopies()
{
  copies.assign(1, Affine::Identity());
  std::vector<Affine> frontier = copies;
  const std::size_t maxCopies = 9;
  while (!frontier.empty() && copies.size() < maxCopies && !planes.empty())
  {
    std::vector<Affine> next;
    for (const Affine& t : frontier)
    {
      for (const MirrorPlane& m : planes)
      {
        const Affine r = m.Reflection.After(t);
        bool known = false;
        for (const Affine& c : copies)
        {
          known = known || c.Near(r, samePoint);
        }
        if (!known && copies.size() < maxCopies)
        {
          copies.push_back(r);
          next.push_back(r);
        }
      }
    }
    frontier = std::move(next);
  }
  out.NumberOfMirrorCopies = copies.size() - 1;
}

void MedialRun::AddMirrorImages()
{
  allPoints.assign(points, points + 3 * nPoints);
  allNormals.assign(normals, normals + 3 * nPoints);
  allEdgeLength = edgeLength;
  if (copies.size() > 1)
  {
    // Mirror images that fall on an existing point (points on a plane) are not added.
    const double cell = 1e3 * samePoint;
    auto key = [cell](const double* x, int dx, int dy, int dz) {
      return std::array<long long, 3>{ static_cast<long long>(std::floor(x[0] / cell)) + dx,
        static_cast<long long>(std::floor(x[1] / cell)) + dy,
        static_cast<long long>(std::floor(x[2] / cell)) + dz };
    };
    std::map<std::array<long long, 3>, std::vector<std::int64_t>> grid;
    auto find = [&](const double* y) {
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz)
          {
            auto it = grid.find(key(y, dx, dy, dz));
            if (it == grid.end())
              continue;
            for (std::int64_t j : it->second)
            {
              if (Distance(y, allPoints.data() + 3 * j) <= samePoint)
                return true;
            }
          }
      return false;
    };
    for (std::size_t i = 0; i < nPoints; ++i)
    {
      grid[key(points + 3 * i, 0, 0, 0)].push_back(static_cast<std::int64_t>(i));
    }
    for (std::size_t c = 1; c < copies.size(); ++c)
    {
      for (std::size_t i = 0; i < nPoints; ++i)
      {
        double y[3], n[3];
        copies[c].Apply(points + 3 * i, y);
        if (find(y))
        {
          continue;
        }
        copies[c].ApplyLinear(normals + 3 * i, n);
        const auto id = static_cast<std::int64_t>(allEdgeLength.size());
        allPoints.insert(allPoints.end(), y, y + 3);
        allNormals.insert(allNormals.end(), n, n + 3);
        allEdgeLength.push_back(edgeLength[i]);
        grid[key(y, 0, 0, 0)].push_back(id);
      }
    }
  }
  nAll = allEdgeLength.size();
}

void MedialRun::Fold(double* x) const
{
  for (std::size_t pass = 0; pass < 2 * copies.size(); ++pass)
  {
    bool moved = false;
    for (const MirrorPlane& m : planes)
    {
      if (m.Distance(x) < -samePoint)
      {
        double y[3];
        m.Reflection.Apply(x, y);
        std::copy(y, y + 3, x);
        moved = true;
      }
    }
    if (!moved)
    {
      return;
    }
  }
}

// ---- Delaunay tetrahedralization (spatially sorted insertion).
bool MedialRun::Triangulate()
{
  {
    std::vector<std::pair<Point, std::int64_t>> input;
    input.reserve(nAll);
    for (std::size_t i = 0; i < nAll; ++i)
    {
      const double* p = allPoints.data() + 3 * i;
      input.emplace_back(Point(p[0], p[1], p[2]), static_cast<std::int64_t>(i));
    }
    dt.insert(input.begin(), input.end());
  }
  if (dt.dimension() < 3)
  {
    error = "the " + std::to_string(nPoints) +
      " surface points are all coplanar (or collinear): their Delaunay triangulation has "
      "dimension " +
      std::to_string(dt.dimension()) + " and no tetrahedra, so there is no region to take the medial axis of.";
    return false;
  }
  if (dt.number_of_vertices() != nAll)
  {
    std::vector<char> used(nAll, 0);
    for (auto v = dt.finite_vertices_begin(); v != dt.finite_vertices_end(); ++v)
    {
      used[v->info()] = 1;
    }
    const auto first = std::find(used.begin(), used.begin() + nPoints, 0) - used.begin();
    if (static_cast<std::size_t>(first) == nPoints)
    {
      error = "mirror images of the surface coincide with it away from the symmetry planes "
              "(are two symmetry planes the same plane?).";
      return false;
    }
    std::ostringstream msg;
    msg << (nAll - dt.number_of_vertices()) << " surface points coincide with other points (the "
        << "first is point " << first << " at (" << points[3 * first] << ", "
        << points[3 * first + 1] << ", " << points[3 * first + 2]
        << ")). Merge them first (ParaView's Clean filter).";
    error = msg.str();
    return false;
  }
  return true;
}

// ---- Voronoi vertices of the finite tetrahedra and which of them are interior.
void MedialRun::ComputeVoronoiVertices()
{
  cells.reserve(dt.number_of_finite_cells());
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c)
  {
    c->info() = static_cast<std::int64_t>(cells.size());
    cells.push_back(c);
  }
  for (auto c = dt.all_cells_begin(); c != dt.all_cells_end(); ++c)
  {
    if (dt.is_infinite(c))
    {
      c->info() = -1;
    }
  }
  nCells = cells.size();
  out.NumberOfTetrahedra = nCells;
  centre.resize(3 * nCells);
  radius.resize(nCells);
  keep.assign(nCells, 0);
  const double minRadiusFactor = options.MinimumRadiusFactor;
  const double side = options.RegionAgainstNormals ? -1.0 : 1.0;
  ParallelFor(nCells, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      const auto& c = cells[i];
      const Point cc = CGAL::circumcenter(c->vertex(0)->point(), c->vertex(1)->point(),
        c->vertex(2)->point(), c->vertex(3)->point());
      double* x = centre.data() + 3 * i;
      x[0] = cc.x();
      x[1] = cc.y();
      x[2] = cc.z();
      double vote = 0.0, local = 0.0, r = 0.0;
      for (int k = 0; k < 4; ++k)
      {
        const std::int64_t id = c->vertex(k)->info();
        const double* p = allPoints.data() + 3 * id;
        const double* n = allNormals.data() + 3 * id;
        const double d[3] = { x[0] - p[0], x[1] - p[1], x[2] - p[2] };
        const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        r += len;
        if (len > 0.0)
        {
          vote += (d[0] * n[0] + d[1] * n[1] + d[2] * n[2]) / len;
        }
        local += allEdgeLength[id];
      }
      r *= 0.25;
      local *= 0.25;
      radius[i] = r;
      keep[i] = Finite3(x) && side * vote > 0.0 && r >= minRadiusFactor * local;
    }
  });
  if (inDomain)
  {
    for (std::size_t i = 0; i < nCells; ++i)
    {
      if (keep[i])
      {
        double x[3] = { centre[3 * i], centre[3 * i + 1], centre[3 * i + 2] };
        Fold(x);
        keep[i] = inDomain->Contains(Point(x[0], x[1], x[2]));
      }
    }
  }
  out.NumberOfInteriorTetrahedra =
    static_cast<std::size_t>(std::count(keep.begin(), keep.end(), char(1)));
}

// ---- Coincident Voronoi vertices (cospherical surface points) become one point:
// neighbouring tetrahedra whose circumcentres agree to round-off.
void MedialRun::MergeCoincidentVertices()
{
  same = UnionFind(nCells);
  for (std::size_t i = 0; i < nCells; ++i)
  {
    if (!keep[i])
    {
      continue;
    }
    const double tol = 1e-9 * radius[i];
    for (int k = 0; k < 4; ++k)
    {
      const std::int64_t j = cells[i]->neighbor(k)->info();
      if (j > static_cast<std::int64_t>(i) && keep[j] &&
        Distance(centre.data() + 3 * i, centre.data() + 3 * j) <= tol)
      {
        same.Union(static_cast<std::int64_t>(i), j);
      }
    }
  }
}

// ---- Voronoi facets dual to Delaunay edges with an interior ring of tetrahedra.
// A ring is walked from a kept cell and abandoned at its first cell that
// fails (infinite, not interior, or too small an angle), so that the walks
// cost little outside the region; a ring that passes is marked done in all
// its cells (a bit per cell and local edge). CGAL's finite_edges iterator
// would walk every ring in full, several times over.
bool MedialRun::CollectFacets()
{
  const double minAngle = options.MinimumObjectAngle * Pi / 180.0;
  const double sinHalf = std::sin(0.5 * minAngle);
  facetOf.assign(6 * nCells, -1);
  std::vector<std::uint8_t> walked(nCells, 0);
  std::vector<std::int64_t> ring;
  std::vector<int> ringEdge;
  for (std::size_t ci = 0; ci < nCells; ++ci)
  {
    if ((ci & 0xFFFF) == 0 && Aborted(0.6 + 0.3 * static_cast<double>(ci) / static_cast<double>(nCells)))
    {
      return false;
    }
    if (!keep[ci])
    {
      continue;
    }
    const Delaunay::Cell_handle c = cells[ci];
    for (int i = 0; i < 3; ++i)
    {
      for (int j = i + 1; j < 4; ++j)
      {
        if (walked[ci] & (1u << EdgeIndex[i][j]))
        {
          continue;
        }
        const auto va = c->vertex(i), vb = c->vertex(j);
        const std::int64_t ip = va->info(), iq = vb->info();
        const double pq = Distance(allPoints.data() + 3 * ip, allPoints.data() + 3 * iq);
        ring.clear();
        ringEdge.clear();
        bool ok = true;
        Delaunay::Cell_handle cur = c;
        int a = i, b = j;
        do
        {
          const std::int64_t id = cur->info();
          // Angle pvq = 2 asin(|pq| / 2r) >= minAngle  <=>  |pq| >= 2 r sin(minAngle/2).
          if (id < 0 || !keep[id] || pq < 2.0 * radius[id] * sinHalf)
          {
            ok = false;
            break;
          }
          ring.push_back(id);
          ringEdge.push_back(EdgeIndex[a][b]);
          const Delaunay::Cell_handle next = cur->neighbor(CGAL::Triangulation_utils_3::next_around_edge(a, b));
          a = next->index(va);
          b = next->index(vb);
          cur = next;
        } while (cur != c);
        if (!ok || ring.size() < 3)
        {
          continue;
        }
        const auto facet = static_cast<std::int32_t>(facetOffsets.size() - 1);
        for (std::size_t k = 0; k < ring.size(); ++k)
        {
          walked[ring[k]] |= static_cast<std::uint8_t>(1u << ringEdge[k]);
          facetOf[6 * ring[k] + ringEdge[k]] = facet;
          facetCells.push_back(same.Find(ring[k]));
        }
        facetOffsets.push_back(static_cast<std::int64_t>(facetCells.size()));
      }
    }
  }
  nFacets = facetOffsets.size() - 1;
  out.NumberOfFacets = nFacets;
  return true;
}

// ---- Sheets: facets joined along Voronoi edges. A Voronoi edge is dual to
// a Delaunay triangle (the face between two cells); the facets dual to the
// triangle's three edges that were kept share it.
void MedialRun::JoinSheets()
{
  sheets = UnionFind(nFacets);
  for (std::size_t ci = 0; ci < nCells; ++ci)
  {
    const std::int32_t* f6 = facetOf.data() + 6 * ci;
    if (std::max({ f6[0], f6[1], f6[2], f6[3], f6[4], f6[5] }) < 0)
    {
      continue; // no kept facet around this cell's edges
    }
    for (int k = 0; k < 4; ++k)
    {
      const std::int64_t n = cells[ci]->neighbor(k)->info();
      if (n >= 0 && n < static_cast<std::int64_t>(ci))
      {
        continue; // the face was seen from the other cell
      }
      std::int32_t first = -1;
      for (int i = 0; i < 3; ++i)
      {
        for (int j = i + 1; j < 4; ++j)
        {
          if (i == k || j == k)
          {
            continue;
          }
          const std::int32_t f = facetOf[6 * ci + EdgeIndex[i][j]];
          if (f < 0)
          {
            continue;
          }
          if (first < 0)
          {
            first = f;
          }
          else
          {
            sheets.Union(first, f);
          }
        }
      }
    }
  }
  facetOf.clear();
  facetOf.shrink_to_fit();
}

// Triangulate each facet as a fan (it is planar and convex: a Voronoi face),
// skipping the repeated vertices of merged circumcentres.
void MedialRun::TriangulateFacets()
{
  facetArea.assign(nFacets, 0.0);
  std::vector<std::int64_t> poly;
  for (std::size_t f = 0; f < nFacets; ++f)
  {
    poly.clear();
    for (std::int64_t k = facetOffsets[f]; k < facetOffsets[f + 1]; ++k)
    {
      if (poly.empty() || poly.back() != facetCells[k])
      {
        poly.push_back(facetCells[k]);
      }
    }
    while (poly.size() > 1 && poly.back() == poly.front())
    {
      poly.pop_back();
    }
    for (std::size_t k = 1; k + 1 < poly.size(); ++k)
    {
      const double area = TriangleArea(centre.data() + 3 * poly[0],
        centre.data() + 3 * poly[k], centre.data() + 3 * poly[k + 1]);
      if (area <= 0.0)
      {
        continue;
      }
      tris.insert(tris.end(), { poly[0], poly[k], poly[k + 1] });
      triFacet.push_back(static_cast<std::int64_t>(f));
      facetArea[f] += area;
    }
  }
}

// Sheet areas, largest first; ties by the smallest facet root (deterministic).
void MedialRun::SelectSheets()
{
  std::vector<std::int64_t> rootOfSheet;
  sheetOfRoot.assign(nFacets, -1);
  std::vector<double> area;
  for (std::size_t f = 0; f < nFacets; ++f)
  {
    const std::int64_t r = sheets.Find(static_cast<std::int64_t>(f));
    if (sheetOfRoot[r] < 0)
    {
      sheetOfRoot[r] = static_cast<std::int64_t>(rootOfSheet.size());
      rootOfSheet.push_back(r);
      area.push_back(0.0);
    }
    area[sheetOfRoot[r]] += facetArea[f];
  }
  out.NumberOfSheetsFound = rootOfSheet.size();
  std::vector<std::int64_t> order(rootOfSheet.size());
  std::iota(order.begin(), order.end(), std::int64_t(0));
  std::stable_sort(order.begin(), order.end(),
    [&](std::int64_t a, std::int64_t b) { return area[a] > area[b]; });
  newSheetId.assign(rootOfSheet.size(), -1);
  const double largest = order.empty() ? 0.0 : area[order[0]];
  for (std::size_t k = 0; k < order.size(); ++k)
  {
    const double a = area[order[k]];
    if (a <= 0.0 || a < options.MinimumAreaFraction * largest ||
      (options.MaximumNumberOfSheets > 0 &&
        static_cast<int>(k) >= options.MaximumNumberOfSheets))
    {
      break;
    }
    newSheetId[order[k]] = static_cast<int>(k);
    out.SheetAreas.push_back(a);
  }
}

// ---- Output: compact points.
void MedialRun::Output()
{
  std::vector<std::int64_t> pointOf(nCells, -1);
  for (std::size_t t = 0; t < triFacet.size(); ++t)
  {
    const int sheet = newSheetId[sheetOfRoot[sheets.Find(triFacet[t])]];
    if (sheet < 0)
    {
      continue;
    }
    for (int k = 0; k < 3; ++k)
    {
      const std::int64_t c = tris[3 * t + k];
      if (pointOf[c] < 0)
      {
        pointOf[c] = static_cast<std::int64_t>(out.Radius.size());
        out.Points.insert(out.Points.end(), centre.begin() + 3 * c, centre.begin() + 3 * c + 3);
        out.Radius.push_back(radius[c]);
      }
      out.Triangles.push_back(pointOf[c]);
    }
    out.SheetId.push_back(sheet);
  }
}
}

bool ComputeMedialSheet(const double* points, std::size_t nPoints, const double* normals,
  const std::int64_t* triangles, std::size_t nTriangles, const MedialAxisOptions& options,
  const ClosedSurface* domain, MedialSheet& out, std::string& error,
  const ProgressCallback& progress)
{
  MedialRun run(points, nPoints, normals, triangles, nTriangles, options, domain, out, error, progress);
  return run.Execute();
}
}
