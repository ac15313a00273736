// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file ARTetGen.h
 * @brief Constrained quality tetrahedralization of a closed triangulated surface with TetGen.
 */
#ifndef ARTetGen_h
#define ARTetGen_h

#include "ARTetMesh.h"

#include <string>

namespace ar
{
struct TetGenOptions
{
  /// Radius-edge ratio bound of TetGen's -q switch (> 1; about 1.414 is TetGen's default).
  double MaxRadiusEdgeRatio = 1.414;
  /// Minimum dihedral angle TetGen tries to reach, degrees (second value of -q).
  double MinDihedralAngle = 12.0;
  /// Maximum tetrahedron volume (-a); 0 means no bound.
  double MaxVolume = 0.0;
  /// Keep the boundary triangles exactly as given (-Y): no Steiner points on the surface.
  bool PreserveSurface = true;
  /// Mesh optimization level of TetGen's -O switch (flips and smoothing that
  /// remove slivers; 0 = TetGen's default, 2).
  int OptimizationLevel = 0;
  /// Largest dihedral angle (degrees) TetGen's optimization tries to remove
  /// (-o/; slivers have one near 180); 0 = TetGen's default, 165.
  double OptimizeMaxDihedral = 0.0;
};

/**
 * Tetrahedralizes the region bounded by a closed, consistently triangulated
 * surface (points as x y z triples, triangles as 3 point indices each).
 *
 * The input is validated first (TetGen may corrupt its heap on malformed
 * input): finite coordinates, indices in range, no triangle with a repeated
 * vertex or zero area, every edge shared by exactly two triangles. A TetGen
 * failure (it throws from terminatetetgen()) is caught. On failure the
 * function returns false and `error` says why.
 *
 * The output's first points are the input points, in order.
 */
bool TetGenTetrahedralizeSurface(const double* xyz, std::size_t nPoints,
  const std::int64_t* triangles, std::size_t nTriangles, const TetGenOptions& options,
  TetMesh& out, std::string& error);

/// The command-line switches that `options` stand for (e.g. "pq1.414/12YQ").
std::string TetGenSwitches(const TetGenOptions& options);

/// A piecewise linear complex for TetGen: closed shells of triangles
/// bounding the region(s) to mesh, internal triangles to embed, hole points
/// (TetGen removes the tetrahedra of the region around each), and optionally
/// a desired edge length per point (TetGen's -m size field).
struct PiecewiseLinearComplex
{
  /// x y z triples. A point on no triangle is a free point: TetGen inserts
  /// it where it lies inside the region, and it keeps its index either way
  /// (-J; one outside is in no tetrahedron of the result).
  std::vector<double> Points;
  std::vector<std::int64_t> Triangles; ///< 3 point indices each
  std::vector<int> TriangleMarkers;    ///< one per triangle (empty: all 1)
  std::vector<double> Holes;           ///< x y z per hole point
  std::vector<double> PointSizes;      ///< one per point, > 0 (empty: no size field)
};

struct TetGenResult
{
  TetMesh Mesh;                        ///< the input points first, in order; positively oriented
  std::vector<std::int64_t> Faces;     ///< triangles lying on input facets, 3 ids each
  std::vector<int> FaceMarkers;        ///< the marker of the facet each lies on
  std::size_t Pieces = 1;              ///< complexes meshed side by side (ARTetGenPieces.h)
};

/**
 * Constrained (quality) tetrahedralization of a piecewise linear complex.
 * Checks coordinates, indices and sizes only (the caller vouches for the
 * complex: no crossing facets); TetGen failures (its int throws) are caught.
 */
bool TetGenMeshComplex(const PiecewiseLinearComplex& plc, const TetGenOptions& options,
  TetGenResult& out, std::string& error);

/**
 * Writes `plc` as TetGen's own input files, `prefix`.node, `prefix`.smesh
 * (facets with their markers, hole points) and, with a size field,
 * `prefix`.mtr, so the same complex can be meshed by the `tetgen` program
 * (`tetgen -p<switches>m prefix.smesh`): to compare against TetGen alone,
 * or to attach a failing refill to a report. Returns false when a file
 * cannot be written.
 */
bool WriteTetGenFiles(const PiecewiseLinearComplex& plc, const std::string& prefix, std::string& error);
}

#endif
