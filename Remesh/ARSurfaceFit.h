// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file ARSurfaceFit.h
 * @brief Template surfaces fitted to a feature's medial points (no VTK).
 *
 * The paper's mathematical-representation approach (Ito et al., section 2.3):
 * a cluster's medial points x_j, each with its local mesh size l_j, are fitted
 * to a template surface by weighted least squares, Eq. 4,
 *
 *   E = sum_j ( (z_j - f(x_j, y_j)) / l_j )^2   ->  min,
 *
 * in a local frame (x, y, z) whose z runs along an axis (origin + direction).
 * The weight of point j is w_j = 1 / l_j. Vertical offsets (z - f) make the
 * problem linear, but they misjudge a thick point band on a tilted or steep
 * surface; the optional geometric refinement then minimizes the weighted
 * orthogonal distances sum_j (w_j d_j)^2, with d_j the true point-to-surface
 * distance, by Levenberg-Marquardt (Eigen QR for every step).
 *
 * Templates:
 * - Plane:   z = c0 + c1 x + c2 y. Refinement = weighted PCA (exact).
 * - Quadric: z = f(x, y), a polynomial of degree 2 (6 coefficients).
 * - Quartic: z = f(x, y), a polynomial of degree 4 (15 coefficients).
 *   Monomials by total degree, then by falling power of x:
 *   1; x, y; x^2, xy, y^2; x^3, x^2 y, x y^2, y^3; x^4, x^3 y, x^2 y^2, x y^3, y^4.
 *   Refinement: d_j is the distance to the graph surface, found per point by
 *   Newton's method on the squared distance to (x, y, f(x, y)).
 * - Cone:    apex a, unit axis d, half-angle theta (one nappe, opening along
 *   +d). Eq. 4 in the cone's own frame: z = z_apex + cot(theta) rho(x, y),
 *   rho the distance from the axis line. Refinement moves apex, axis and
 *   angle together; d_j = rho_j cos(theta) - h_j sin(theta) (h_j = (x_j - a).d).
 *
 * The axis frame. With a user axis (AutomaticAxis off) z runs along
 * AxisDirection through AxisOrigin, and x runs along the coordinate axis
 * least aligned with the direction, made orthogonal to it (z = +Z gives
 * x = +X, y = +Y). With AutomaticAxis on the frame comes from the points'
 * weighted principal directions (weights w_j^2, origin at the weighted
 * centroid): z along the smallest spread, x along the largest.
 *
 * The automatic cone axis: the principal directions say nothing reliable
 * about a cone (a wide cone's axis can be any of them), so a general quadric
 * q(x) = x^T A x + 2 b^T x + c is fitted first (algebraic distance, smallest
 * singular vector of the weighted design matrix). A cone is a quadric whose
 * axis is an eigenvector of A: each of the three eigenvectors is tried as the
 * axis direction; with the direction fixed, the cone
 * (x - x0)^2 + (y - y0)^2 = k^2 (z - z0)^2 is linear in its unknowns and
 * gives apex and angle, and Eq. 4 about that axis line gives another start.
 * Every start is refined by orthogonal distances and the cone with the
 * smallest residual gives the axis (a partial cone, a quarter of one say,
 * tilts the quadric's eigenvectors by degrees: the refinement straightens
 * them). With GeometricRefinement that cone is the answer; without it, Eq. 4
 * about its axis line. With a user axis and GeometricRefinement, Eq. 4 about
 * the axis line as given and the linear fit with the direction fixed (axis
 * position free) start the refinement; without refinement the answer is
 * Eq. 4 about the user's axis line.
 */
#ifndef ARSurfaceFit_h
#define ARSurfaceFit_h

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ar
{
enum class SurfaceTemplate : int
{
  Plane = 0,
  Quadric = 1,
  Cone = 2,
  Quartic = 3
};

/// "Plane", "Quadric", "Cone" or "Quartic".
const char* SurfaceTemplateName(SurfaceTemplate t);

/// Fewest points the template needs: 3, 6, 6 (cone), 15.
std::size_t SurfaceTemplateMinimumPoints(SurfaceTemplate t);

struct SurfaceFitOptions
{
  SurfaceTemplate Template = SurfaceTemplate::Plane;
  bool AutomaticAxis = true;              ///< frame from the points (see the file comment)
  double AxisOrigin[3] = { 0.0, 0.0, 0.0 };
  double AxisDirection[3] = { 0.0, 0.0, 1.0 };
  bool GeometricRefinement = true;        ///< orthogonal-distance refinement
  int MaximumIterations = 100;            ///< Levenberg-Marquardt iterations
  /// -1, or the coordinate axis (0, 1, 2) along which the surface is
  /// extruded (one-cell-deep points, set by FitSurfaceAutomatic): with the
  /// automatic axis the frame's z and x then lie across it (z along the
  /// points' smaller spread across the axis), y along it, so a plane
  /// contains the axis however thin the mesh is, and a quadric or quartic
  /// has only the monomials in x (z = f(x): a cylinder over the axis).
  int ExtrusionAxis = -1;
  /// With AutomaticAxis, a graph's (quadric's, quartic's) frame has its z
  /// along this direction (not normalised; zero: none, the principal frame),
  /// through the points' weighted centroid. FitSurfaceAutomatic fits the
  /// quadric in both frames and keeps the better. The principal frame of a quarter of a bow shock (a bowl
  /// spanning 90 degrees about the flow) stands 40 degrees off the flow,
  /// and its paraboloid missed the vertex on the stagnation line by 1.4
  /// cells; about the flow (vtkQuadricFit: the Domain's mean velocity), as
  /// the paper fits its capsule's bow shock, by 0.3.
  double GraphAxis[3] = { 0.0, 0.0, 0.0 };
};

struct SurfaceFitResult
{
  SurfaceTemplate Template = SurfaceTemplate::Plane;

  /// The axis frame: origin and orthonormal, right-handed axes (Z = the axis).
  /// For the cone: origin = apex, Z = the cone's axis.
  double FrameOrigin[3] = { 0.0, 0.0, 0.0 };
  double FrameX[3] = { 1.0, 0.0, 0.0 };
  double FrameY[3] = { 0.0, 1.0, 0.0 };
  double FrameZ[3] = { 0.0, 0.0, 1.0 };

  /**
   * The surface:
   * - Plane: (a, b, c, d) of a x + b y + c z + d = 0 in world coordinates,
   *   (a, b, c) = Normal (unit, along +FrameZ).
   * - Quadric (6) and Quartic (15): coefficients of z = f(x, y) in the
   *   frame, monomials in the order of the file comment.
   * - Cone (7): apex (3), axis direction (3), half-angle in degrees.
   */
  std::vector<double> Coefficients;

  double Normal[3] = { 0.0, 0.0, 1.0 };   ///< plane: unit normal
  double Origin[3] = { 0.0, 0.0, 0.0 };   ///< plane: a point of it (the points' weighted centroid, projected)
  double Apex[3] = { 0.0, 0.0, 0.0 };     ///< cone
  double AxisDirection[3] = { 0.0, 0.0, 1.0 }; ///< cone: unit axis, the nappe opens along it
  double HalfAngleDegrees = 0.0;          ///< cone

  double RMSResidual = 0.0;               ///< sqrt(mean d_j^2), d_j orthogonal distances (length units)
  double WeightedRMSResidual = 0.0;       ///< sqrt(sum (w_j d_j)^2 / sum w_j^2)
  std::size_t NumberOfPoints = 0;
  int Iterations = 0;                     ///< Levenberg-Marquardt iterations done (0: none)
  bool Refined = false;                   ///< the geometric refinement ran
};

/**
 * Fits the template to n points (x y z interleaved) with weights w_j = 1/l_j
 * (nullptr: all 1). Returns false with a message in `error` when the input
 * cannot define the surface: fewer points than the template needs, NaN/Inf
 * coordinates or weights, weights <= 0, a zero axis direction, collinear
 * points (plane), coplanar or collinear points (cone), a singular system
 * (the points do not determine the coefficients), or no cone found.
 */
bool FitSurface(const double* points, const double* weights, std::size_t n,
  const SurfaceFitOptions& options, SurfaceFitResult& result, std::string& error);

/**
 * Robust variant of FitSurface: iteratively reweighted least squares with
 * Tukey's biweight on the orthogonal distances in units of each point's
 * local size l_j = 1 / w_j, r_j = d_j / l_j: w_j <- w_j (1 - (r_j / (c s))^2)^2
 * for |r_j| < c s and 0 beyond, c = 4.685, s = 1.4826 x the median |r_j| (the
 * normal-consistent scale), until the weights settle (at most `iterations`
 * refits). Medial points that do not belong to the feature surface, such as
 * those where a feature band is cut by a wall and the edge distance peaks on
 * the wall, stop pulling the fit; on clean data the weights stay near 1 and
 * the answer is that of FitSurface. The scale follows the local size because
 * medial points scatter by a fraction of their own cell: on a mesh that grows
 * along the feature a single scale rejects the coarse part's good points and
 * biases the fit (0.9 degree on a cone). The loop stops when no multiplier moves
 * by 0.02 or more. `robustWeights`, if given, gets the final
 * multipliers in [0, 1]. The result's residuals are over all points.
 */
bool FitSurfaceRobust(const double* points, const double* weights, std::size_t n,
  const SurfaceFitOptions& options, SurfaceFitResult& result, std::string& error,
  int iterations = 10, std::vector<double>* robustWeights = nullptr);

/// The automatic choice of a template (the paper leaves it to the user): the
/// plane, the cone and the quadric are fitted (robustly when `robust`), and
/// the simplest of them (in that order, the quartic last) whose RMS residual is within
/// AutomaticTemplateRatio x the best one's + AutomaticTemplateSlack x `size`
/// wins. `size` is the points' typical local mesh size (the median l_j): a
/// residual a tenth of a cell above the best is no better surface for the
/// mesher, so the simpler template is kept (a plane shock is not fitted by
/// a cone of half-angle 89 degrees). `residuals`, if given, gets the four
/// RMS residuals, plane, cone, quadric, quartic (NaN where that template was
/// not tried or could not be fitted). The quadric is also fitted about
/// options.GraphAxis where one is given (the lower residual kept). The
/// quartic is tried only on points
/// that lie on two planes normal to a coordinate axis (a one-cell-deep
/// mesh's front and back); those are fitted with ExtrusionAxis set to that
/// axis: the plane, the quadric and the quartic z = f(x) extruded along it
/// (a curved 2-D shock: a parabola through a whole bow shock misses its
/// vertex by a cell or two, the quartic does not); the cone, which would fit
/// the two levels rather than the shock, is not tried. False with
/// `error` (every fit's failure) when none could be fitted.
constexpr double AutomaticTemplateRatio = 1.25;
constexpr double AutomaticTemplateSlack = 0.1;
bool FitSurfaceAutomatic(const double* points, const double* weights, std::size_t n,
  const SurfaceFitOptions& options, bool robust, double size, SurfaceFitResult& result, std::string& error,
  double residuals[4] = nullptr);

/// Signed orthogonal distance of p from the fitted surface (positive on the
/// +FrameZ side of a graph surface or plane, outside a cone).
double SurfaceDistance(const SurfaceFitResult& fit, const double p[3]);

/// The closest point of the fitted surface to p (for graphs: the local
/// minimum of the distance found by Newton's method from (x_p, y_p)).
void ProjectOntoSurface(const SurfaceFitResult& fit, const double p[3], double foot[3]);

/// A triangulated surface: x y z per point, three point indices per triangle.
struct SurfaceMesh
{
  std::vector<double> Points;
  std::vector<std::int64_t> Triangles;
};

/**
 * Meshes the fitted surface with nearly equilateral triangles of edge
 * `edgeLength`, covering at least every point of the surface within `reach`
 * of the feet (projections onto the surface) of the n points:
 * - Plane: an equilateral grid in the plane (exact);
 * - Quadric, Quartic: an equilateral grid in the frame's (x, y) mapped onto
 *   z = f(x, y) (stretched where the surface is steep);
 * - Cone: rings along the generators, Delta s = edgeLength sqrt(3)/2, each
 *   ring with as many points as keep its spacing near edgeLength, zipped
 *   ring to ring; the whole circle when the feet go round it, otherwise the
 *   arc they span plus the reach.
 * Triangles are oriented with normals along +FrameZ (graphs, plane) or away
 * from the axis (cone). Returns false (message in `error`) if the mesh would
 * exceed maxTriangles or the arguments are not positive and finite.
 */
bool TessellateSurface(const SurfaceFitResult& fit, const double* points, std::size_t n,
  double edgeLength, double reach, SurfaceMesh& mesh, std::string& error,
  std::size_t maxTriangles = 4000000);

/// Two families of directions (sign-free axes): see SplitDirectionFamilies.
struct DirectionFamilies
{
  double Axes[2][3] = { { 0, 0, 0 }, { 0, 0, 0 } }; ///< unit axis of each family
  double AngleDegrees = 0.0;  ///< between the two axes, in [0, 90]
  double SpreadDegrees = 0.0; ///< weighted median angle of a direction from its family's axis
  double Fraction = 0.0;      ///< weight of the lighter family over the total, in [0, 0.5]
};

/**
 * Splits n weighted directions (x y z each, not necessarily unit; the sign
 * is ignored: d and -d are the same axis) into the two families that best
 * explain them, by 2-means on axes: each direction goes to the axis it is
 * closer to, each axis is the principal eigenvector of its family's
 * weighted scatter (sum of w d d^T / |d|^2, Eigen's self-adjoint solver),
 * starting from the two axes of two equal families with the scatter of all
 * the directions. Directions of zero length or weight are ignored.
 *
 * A single family (one plane shock) split in two gives two close axes; a
 * continuous one (a cone's normals round its axis, a curved shock's) gives
 * families about as wide as they are apart (a uniform arc splits into
 * halves whose axes are 4 times their median spread apart; a Gaussian
 * about 3 times); two surfaces that meet give two tight families far
 * apart. Returns false if fewer than two directions count.
 */
bool SplitDirectionFamilies(const double* directions, const double* weights, std::size_t n,
  DirectionFamilies& result);
}

#endif
