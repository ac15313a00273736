// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file ARMedialAxis.h
 * @brief Medial sheet of a region bounded by a triangulated surface, from the
 *        Voronoi diagram of the surface points (paper section 2.3, the
 *        discrete surface-based approach).
 *
 * The Delaunay tetrahedra of the surface points are computed with CGAL (exact
 * predicates). A tetrahedron is *interior* when its circumcentre (a Voronoi
 * vertex, the centre of an empty ball touching the surface at the tetrahedron's
 * four points) lies on the region's side of the surface: the side opposite to
 * the oriented point normals at those four points. This local test needs no
 * closed surface, so isosurfaces that are open where they meet the domain
 * boundary, or that have holes, work.
 *
 * The medial sheet is the union of the Voronoi facets dual to Delaunay edges
 * pq whose surrounding tetrahedra are all interior and which pass the pruning
 * below. The facets share their Voronoi vertices, so the output is one
 * connected polygonal surface per sheet (triangulated as fans; a facet is
 * planar, being part of the bisector plane of p and q).
 *
 * Pruning:
 *  - object angle (Dey and Zhao, "Approximate medial axis as a Voronoi
 *    subcomplex", Computer-Aided Design 36(2), 2004; the same "object angle"
 *    as Foskey, Lin and Manocha, "Efficient computation of a simplified medial
 *    axis", 2003): a facet dual to pq is kept only if at each of its Voronoi
 *    vertices v the angle pvq is at least MinimumObjectAngle. Facets dual to
 *    short edges between neighbouring surface points (the spikes that every
 *    bump of a sampled surface adds) subtend small angles and go;
 *  - small poles: Voronoi vertices whose radius is below MinimumRadiusFactor
 *    times the local surface edge length (noise and bumps);
 *  - small sheets: connected sheets (facets joined along Voronoi edges) whose
 *    area is below MinimumAreaFraction of the largest, and beyond
 *    MaximumNumberOfSheets.
 */
#ifndef ARMedialAxis_h
#define ARMedialAxis_h

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ar
{
struct MedialAxisOptions
{
  /// Minimum angle pvq (degrees) at every Voronoi vertex v of a facet dual to pq.
  double MinimumObjectAngle = 110.0;
  /// A Voronoi vertex whose ball radius is below this times the local surface
  /// edge length (the mean, over the tetrahedron's points, of each point's
  /// longest surface edge) is dropped.
  double MinimumRadiusFactor = 0.5;
  /// Sheets with less area than this fraction of the largest sheet are dropped.
  double MinimumAreaFraction = 0.05;
  /// Keep at most this many sheets, the largest first (0: no limit).
  int MaximumNumberOfSheets = 0;
  /// true: the region lies on the side opposite to the normals (outward normals,
  /// or ParaView's Contour normals for the region above the iso-value).
  bool RegionAgainstNormals = true;
  /// Symmetry planes, 6 values each: a point and a normal (any length, any
  /// sense). The surface is reflected across them (repeatedly: for two
  /// parallel planes, as for a one-cell-thick 2-D mesh, the copies stack up)
  /// and the medial sheet of the symmetric union is computed, so that the
  /// sheet crosses each plane orthogonally instead of bending to close the
  /// region there. The output then contains the mirrored copies of the sheet
  /// too; cut it at the planes (the filter does). Points lying on a plane are
  /// not duplicated. The domain test folds each Voronoi vertex back into the
  /// original side of the planes first.
  std::vector<double> SymmetryPlanes;
};

/// An optional closed triangulated surface (the boundary of the flow domain):
/// Voronoi vertices outside it are not part of the medial sheet.
struct ClosedSurface
{
  std::vector<double> Points;           ///< x y z triples
  std::vector<std::int64_t> Triangles;  ///< 3 point indices each
};

struct MedialSheet
{
  std::vector<double> Points;            ///< Voronoi vertices used by the sheet, x y z
  std::vector<double> Radius;            ///< inscribed-ball radius at each point
  std::vector<std::int64_t> Triangles;   ///< 3 point indices each
  std::vector<int> SheetId;              ///< per triangle, 0 = largest sheet
  std::vector<double> SheetAreas;        ///< per kept sheet, largest first

  // Counts, for the user and the tests.
  std::size_t NumberOfTetrahedra = 0;          ///< finite Delaunay tetrahedra
  std::size_t NumberOfInteriorTetrahedra = 0;  ///< interior, after radius and domain tests
  std::size_t NumberOfFacets = 0;              ///< Voronoi facets kept (before the sheet filter)
  std::size_t NumberOfSheetsFound = 0;         ///< connected sheets before the sheet filter
  std::size_t NumberOfMirrorCopies = 0;        ///< reflected copies of the surface added
};

/// Progress in [0,1]; return true to abort.
using ProgressCallback = std::function<bool(double)>;

/**
 * Computes the medial sheet of the region bounded by a triangulated surface
 * (`nPoints` points, x y z; `normals` one oriented unit normal per point;
 * `nTriangles` triangles). `domain`, if not null, must be a closed surface.
 *
 * Returns false with `error` naming the problem for: fewer than 4 points, no
 * triangles, a triangle index out of range, a non-finite coordinate or normal,
 * coincident points (CGAL would merge them silently), points that are all
 * coplanar, an open or non-manifold domain surface, a symmetry plane with a
 * zero or non-finite normal, or an abort.
 */
bool ComputeMedialSheet(const double* points, std::size_t nPoints, const double* normals,
  const std::int64_t* triangles, std::size_t nTriangles, const MedialAxisOptions& options,
  const ClosedSurface* domain, MedialSheet& out, std::string& error,
  const ProgressCallback& progress = ProgressCallback());
}

#endif
