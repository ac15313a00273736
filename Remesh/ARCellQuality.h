// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file ARCellQuality.h
 * @brief Shape quality of linear 3-D cells of every type (no VTK): dihedral
 *        angles, corner Jacobians and edge aspect ratio of tetrahedra,
 *        pyramids, prisms (wedges) and hexahedra, for the paper's quality
 *        histogram (Fig. 11b) and the validity of hybrid meshes.
 *
 * Node order and orientation are VTK's, the orientation VTK's cell validator
 * calls correct (the one that gives vtkCellSizeFilter a positive volume):
 * - tetrahedron 0-3: (p1-p0).((p2-p0)x(p3-p0)) > 0;
 * - pyramid 0-3 base, 4 apex: the base runs counterclockwise seen from the apex;
 * - wedge (prism) 0-2 one triangle, 3-5 the other (3 above 0, ...): the
 *   triangle 0 1 2 runs clockwise seen from the triangle 3 4 5 (its right-hand
 *   normal points away from it; note: the opposite of Gmsh's prism, and of
 *   what Verdict's wedge volume counts as positive);
 * - hexahedron 0-3 bottom, 4-7 top (4 above 0, ...): the bottom runs
 *   counterclockwise seen from the top.
 *
 * Dihedral angles: at every edge of the cell, the interior angle between the
 * two faces that meet there, from the faces' planes (180 degrees minus the
 * angle between their outward normals). A quadrilateral face that is not
 * planar has no plane: its average normal is used (the Newell normal, the
 * cross product of its diagonals). A reflex (concave) edge is not seen as
 * more than 180 degrees: the angle is in [0, 180]. A face of zero area gives
 * the angle 0 at its edges.
 *
 * Corner Jacobians: at every corner the determinant of the three edge vectors
 * that leave it, ordered so that it is positive for a valid cell (six times
 * the volume of the corner tetrahedron; for a hexahedron the Jacobian of the
 * trilinear map at that corner). The pyramid's apex has four edges, not
 * three: its value is the smallest of the four determinants (b_i - a,
 * b_i+1 - a, c - a) with c the centroid of the base, i.e. the apex seen over
 * each triangle of the base split at its centroid; for a planar base it is
 * positive exactly when the apex lies on the inner side of the base plane.
 * The scaled Jacobian divides each determinant by the lengths of its three
 * edge vectors (1 for a right corner, <= 0 for an invalid one).
 *
 * Aspect ratio: longest edge / shortest edge of the cell (Verdict's "edge
 * ratio"): 1 for a regular tetrahedron and a cube; thin layer cells have
 * large ones by design.
 */
#ifndef ARCellQuality_h
#define ARCellQuality_h

#include <cstddef>

namespace ar
{
/// Linear 3-D cell types; the value is the number of nodes.
enum class CellShape : int
{
  Tetrahedron = 4,
  Pyramid = 5,
  Wedge = 6,
  Hexahedron = 8
};

/// Number of nodes, edges, faces of a shape (4/6/4, 5/8/5, 6/9/5, 8/12/6).
int NumberOfNodes(CellShape shape);
int NumberOfEdges(CellShape shape);
int NumberOfFaces(CellShape shape);

/// Face f of a shape: four local node ids, outward (right-hand normal out of
/// a valid cell); a triangle ends with -1.
const int* CellFace(CellShape shape, int f);

/// Edge e of a shape: its two local node ids (the lower first).
void CellEdge(CellShape shape, int e, int& a, int& b);

struct CellQuality
{
  double MinDihedralAngle = 0.0;  ///< degrees
  double MaxDihedralAngle = 0.0;  ///< degrees
  double MinCornerJacobian = 0.0; ///< smallest corner determinant (length^3); <= 0: invalid
  double MinScaledJacobian = 0.0; ///< smallest corner determinant / its three edge lengths
  double AspectRatio = 0.0;       ///< longest edge / shortest edge (infinite for a zero edge)
};

/// The dihedral angle at every edge (degrees), NumberOfEdges(shape) values.
/// `points`: the nodes' coordinates, x y z per node, in VTK order.
void CellDihedralAngles(CellShape shape, const double* points, double* angles);

/// The corner Jacobian at every node, NumberOfNodes(shape) values; with
/// `scaled`, the scaled ones.
void CellCornerJacobians(CellShape shape, const double* points, double* jacobians, bool scaled = false);

/// Longest edge / shortest edge.
double CellAspectRatio(CellShape shape, const double* points);

/// The volume enclosed by the cell's faces (divergence theorem), a
/// quadrilateral face taken as the four triangles of its centroid. A face
/// shared by two cells is split the same way from both sides, so the
/// volumes of a conforming mesh sum to the volume of its boundary, even where
/// quads are not planar.
double CellVolume(CellShape shape, const double* points);

/// The length an explicit finite-volume scheme's stable time step follows:
/// 2 V / (sum of the face areas), V as CellVolume measures it and a quad's
/// area half its diagonals' cross product. OpenFOAM's Courant number is
/// 0.5 dt sum_f |phi_f| / V with |phi_f| about (|u.n| + a) A_f, so a cell
/// allows dt up to about Co_max 2V / (sum A_f (|u| + a)): the mesh's smallest
/// step length sets the global time step. A regular tetrahedron of edge l
/// has l / (3 sqrt 6) = 0.136 l, a cube of edge h h / 3. `skipAxis` (0, 1,
/// 2; -1 none): faces whose normal lies along that axis carry no flux and are
/// left out of the sum (a one-cell-deep mesh's front and back, OpenFOAM's
/// empty patches): then a square of side h gives h / 2 and an equilateral
/// triangle of side l l / (2 sqrt 3), its inradius. 0 for a cell without area.
double CellStepLength(CellShape shape, const double* points, int skipAxis = -1);
/// All of the above, summarised; without `scaledJacobian` MinScaledJacobian
/// is not computed (it stays 0), for callers that do not report it.
CellQuality ComputeCellQuality(CellShape shape, const double* points, bool scaledJacobian = true);
}

#endif
