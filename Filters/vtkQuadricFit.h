// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkQuadricFit
 * @brief A feature surface fitted to one cluster's medial points and meshed (Ito et al., Eq. 4).
 *
 * The paper's mathematical-representation approach (section 2.3): the medial
 * points of one feature cluster (vtkFeatureCluster's output port 1) are
 * fitted to a template surface by weighted least squares, each point weighted
 * by 1 / l_j, its local mesh size (Eq. 4), and the fitted surface is meshed
 * with nearly equilateral triangles and trimmed to the cluster and to the
 * computational domain.
 *
 * Input port 0: points (any vtkPointSet, usually vtkPolyData vertices) with
 * the point arrays
 * - `ClusterId` (any numeric type, 1 component): the points whose id equals
 *   ClusterId are fitted (ClusterId -1: all points; the array may then be
 *   missing);
 * - `Weight` (1 / l_j) or, when it is missing, `LocalSize` (l_j, weight
 *   1 / l_j); with neither, all weights are 1 (a warning says so).
 * Input port 1, "Domain" (optional): any vtkDataSet, usually the volume mesh.
 * Its boundary surface (vtkGeometryFilter) trims the output: nothing of the
 * surface lies outside the domain.
 *
 * Templates (Template): PLANE, QUADRIC (z = f(x, y), degree 2), CONE (apex,
 * axis, half-angle) and QUARTIC (z = f(x, y), degree 4). z runs along the
 * axis: AxisOrigin + AxisDirection when UseAutomaticAxis is off, otherwise
 * the points' smallest weighted principal direction (plane, quadric,
 * quartic) or, for the cone, the axis of the best cone fitted by orthogonal
 * distances from starts given by the axes of a general quadric through the
 * points (see ARSurfaceFit.h for the details). Eq. 4 (vertical offsets
 * z - f) gives the first answer; GeometricRefinement (default on) then
 * minimizes the weighted true point-to-surface distances (Levenberg-Marquardt;
 * for the plane the exact weighted principal-direction solution), which is
 * what a thick or steep point band needs.
 *
 * The surface mesh: triangles of edge SurfaceEdgeLength (0, the default:
 * the median LocalSize of the cluster's points; without LocalSize the median
 * of 1 / Weight) on an equilateral grid in the axis frame mapped onto the
 * surface (plane, quadric, quartic), or on rings along the cone's
 * generators. A surface point is kept if it lies within Margin edge lengths
 * (at least one) of the foot of a cluster point on the surface (its
 * orthogonal projection): the cut follows the cluster's outline at that
 * distance (vtkClipPolyData of the distance field). With a Domain, the
 * surface is then clipped by vtkImplicitPolyDataDistance of the domain's
 * boundary, which cuts exactly where the boundary is flat and never outside
 * a convex domain.
 *
 * Output: the triangulated surface, with field data
 * - `Template` (string), `Coefficients` (plane: a b c d of a x + b y + c z + d = 0;
 *   quadric 6 and quartic 15: z = f(x, y) in the frame, monomials
 *   1, x, y, x^2, xy, y^2, x^3, x^2 y, x y^2, y^3, x^4, x^3 y, x^2 y^2, x y^3, y^4;
 *   cone: apex (3), axis (3), half-angle in degrees), `FrameOrigin` (3) and
 *   `FrameAxes` (3 x 3, the frame's x, y, z as rows) in which the
 *   coefficients hold, `RMSResidual` (root mean square orthogonal distance
 *   of the fitted points from the surface), `WeightedRMSResidual`,
 *   `NumberOfFitPoints`, `SurfaceEdgeLength` (the length used);
 * - plane: `Normal`, `Origin`; cone: `Apex`, `AxisDirection`, `HalfAngle`
 *   (degrees).
 *
 * Several clusters: one filter per cluster id. In pvpython:
 * @code
 * cluster = FeatureCluster(Input=sensor, ...)
 * sizes = servermanager.Fetch(cluster, idx=1).GetFieldData().GetArray("ClusterSizes")
 * surfaces = [QuadricFit(Input=OutputPort(cluster, 1), Domain=sensor, ClusterId=i,
 *                        Template='Cone') for i in range(sizes.GetNumberOfTuples())]
 * @endcode
 *
 * Errors (output empty, vtkErrorMacro naming the problem): no points, no
 * `ClusterId` array, no point with that id, NaN/Inf coordinates, a weight or
 * local size that is not positive and finite, fewer points than the template
 * needs (3, 6, 6 (cone; 10 with the automatic axis), 15), a zero
 * AxisDirection, collinear points, coplanar points for a cone, a singular
 * system, no cone found, an empty Domain, a surface that lies entirely
 * outside the domain, a mesh that would be too large (over 4 million
 * triangles).
 *
 * Under MPI the cluster's points are gathered on rank 0, which fits and
 * meshes the surface (the other ranks' outputs are empty); each rank's part
 * of the domain boundary is gathered too (faces between pieces, which appear
 * twice, are dropped).
 *
 * @sa vtkFeatureCluster
 */
#ifndef vtkQuadricFit_h
#define vtkQuadricFit_h

#include "AdaptiveRedistributionFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"
#include "vtkSmartPointer.h" // for DomainBoundary

#include <vector> // for ExtraClusterIds

class ADAPTIVEREDISTRIBUTIONFILTERS_EXPORT vtkQuadricFit : public vtkPolyDataAlgorithm
{
public:
  static vtkQuadricFit* New();
  vtkTypeMacro(vtkQuadricFit, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Templates
  {
    PLANE = 0,
    QUADRIC = 1,
    CONE = 2,
    QUARTIC = 3,
    AUTOMATIC = 4 ///< plane, cone, quadric (quartic on one-cell-deep points), by the fits' residuals (ar::FitSurfaceAutomatic)
  };

  /// The domain to trim the surface to (input port 1, optional).
  void SetDomainConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetDomainData(vtkDataObject* data) { this->SetInputData(1, data); }

  ///@{
  /// The template surface. Default AUTOMATIC: the plane, the cone and the
  /// quadric are fitted and the simplest whose RMS residual is within 1.25 x
  /// the best + 0.1 x the points' median local size is kept (field data
  /// Template names it, TemplateResiduals gives the residuals: plane, cone,
  /// quadric, quartic). On one-cell-deep points (a 2-D mesh) the candidates
  /// are the plane, the quadric and the quartic extruded along the depth
  /// (z = f(x) across it: a curved 2-D shock), not the cone. Not
  /// clamped: a value outside 0..4 is refused with an error naming it.
  vtkSetMacro(Template, int);
  vtkGetMacro(Template, int);
  ///@}

  ///@{
  /// The cluster to fit (points whose ClusterId equals it); -1 fits all
  /// points. Default 0. At least -1: refused otherwise, not clamped.
  vtkSetMacro(ClusterId, int);
  vtkGetMacro(ClusterId, int);
  ///@}

  ///@{
  /// More clusters fitted together with ClusterId as one surface (C++ only;
  /// AdaptToShocks joins the pieces of one shock this way). Empty by default.
  void SetExtraClusterIds(const std::vector<int>& ids)
  {
    this->ExtraClusterIds = ids;
    this->Modified();
  }
  const std::vector<int>& GetExtraClusterIds() const { return this->ExtraClusterIds; }
  ///@}

  ///@{
  /// The axis (z of the fit's frame) when UseAutomaticAxis is off: a point on
  /// it and its direction (need not be unit, must not be zero). For the cone,
  /// an approximate cone axis. Defaults (0, 0, 0) and (0, 0, 1).
  vtkSetVector3Macro(AxisOrigin, double);
  vtkGetVector3Macro(AxisOrigin, double);
  vtkSetVector3Macro(AxisDirection, double);
  vtkGetVector3Macro(AxisDirection, double);
  ///@}

  ///@{
  /// Derive the axis from the points instead of AxisOrigin/AxisDirection.
  /// Default on.
  vtkSetMacro(UseAutomaticAxis, bool);
  vtkGetMacro(UseAutomaticAxis, bool);
  vtkBooleanMacro(UseAutomaticAxis, bool);
  ///@}

  ///@{
  /// Refine the Eq. 4 fit by minimizing the true (orthogonal) distances.
  /// Default on.
  vtkSetMacro(GeometricRefinement, bool);
  vtkGetMacro(GeometricRefinement, bool);
  vtkBooleanMacro(GeometricRefinement, bool);
  ///@}

  ///@{
  /**
   * Robust fit (default on): iteratively reweighted least squares with
   * Tukey's biweight on the orthogonal distances (scale from their median),
   * so that medial points off the feature surface stop pulling it: where a
   * feature band is cut by a wall, FeatureCluster's edge distance peaks on the
   * wall and puts medial points there. On clean data the answer is that of
   * the plain fit.
   */
  vtkSetMacro(RobustFit, bool);
  vtkGetMacro(RobustFit, bool);
  vtkBooleanMacro(RobustFit, bool);
  ///@}

  ///@{
  /**
   * Shock centring (default on; needs the Domain input): after the first
   * fit, every point is moved along the fitted surface's normal to where
   * CentringArray (a point array of the Domain) is halfway through its jump,
   * and the surface is fitted again to the moved points. The jump is read on
   * a line of +-3 LocalSize through the point: from the array's smallest
   * value on it to, where the array is the pressure or the density and the
   * Domain has p, rho and U, the Rankine-Hugoniot value behind a shock with
   * a sample's state upstream (the largest over the samples in the lower
   * half of the rise; normal Mach number from U along the fitted surface's
   * normal, Gamma), else the largest value on the line. Behind a conical
   * shock p keeps rising towards the wall (by 0.58 of the shock's own jump
   * on a Mach 4, 10 degree cone): the largest value put the centred surface
   * 0.9-1.7 degrees inside the solution's shock. The points are centred
   * again while the fit's normals move by more than 0.25 degree (the jump
   * follows the normal). A point whose line finds no jump of at least 5 %,
   * or leaves the domain within one LocalSize of it, does not take part in
   * the second fit. Medial points are mesh nodes anywhere in a captured
   * shock's band, 2-4 cells thick; the band's node-distance medial layer is
   * skewed where the band is (towards the wall at the tip of a wedge or
   * cone, and on weak shocks across a band ~10 degrees wide), so the plain
   * and robust fits of the medial points disagree by up to 0.45 degrees and
   * lie up to 1.3 degrees off theory; the half-jump points lie on the
   * solution's own shock (see the README's validation table). Field data
   * CentredPoints (the number moved and fitted), CentringArrayUsed and
   * CentringShift (the median move in LocalSize), ShockThickness (the
   * median 10-90 % width of the rise along the centred lines, length units:
   * the captured shock's thickness; 0 without centring). Fewer than half the points
   * centred: the first fit is kept, with a warning. With the Automatic
   * template, where the refit chooses another template than the one whose
   * normals the lines followed, the original points are centred again along
   * the new fit's normals (at most three passes): on a weak conical shock the
   * first fit can be a plane, whose normals run up to 45 degrees off the
   * cone's, and its lines then cross the whole layer behind the shock.
   */
  vtkSetMacro(ShockCentring, bool);
  vtkGetMacro(ShockCentring, bool);
  vtkBooleanMacro(ShockCentring, bool);
  ///@}

  ///@{
  /// The Domain's point array whose jump centres the points (ShockCentring).
  /// Default "(automatic)": the pressure by the names solvers write (p,
  /// Pressure, ... as ShockSensor finds it), else the density (rho, Density).
  vtkSetStringMacro(CentringArray);
  vtkGetStringMacro(CentringArray);
  ///@}

  ///@{
  /// Ratio of specific heats, for ShockCentring's Rankine-Hugoniot jump
  /// (default 1.4). Greater than 1: refused otherwise, not clamped.
  vtkSetMacro(Gamma, double);
  vtkGetMacro(Gamma, double);
  ///@}

  ///@{
  /// Edge length of the output triangles; 0 (default) = the median LocalSize
  /// of the cluster's points. At least 0: refused otherwise, not clamped.
  vtkSetMacro(SurfaceEdgeLength, double);
  vtkGetMacro(SurfaceEdgeLength, double);
  ///@}

  ///@{
  /// How far the surface extends beyond the cluster's points, in edge
  /// lengths (at least 1, so that the gaps between neighbouring medial points
  /// stay covered), at most 1e6: refused otherwise, not clamped. Default 3.
  vtkSetMacro(Margin, double);
  vtkGetMacro(Margin, double);
  ///@}

  ///@{
  /**
   * The Domain's boundary as vtkARParallel::GatherDomainBoundary gives it
   * for that Domain (C++ only): AdaptToShocks extracts it once for all its
   * fits. When set, every rank sets it (rank 0's whole, the other ranks'
   * empty) and the fit does not extract it again; null (the default)
   * extracts it from the Domain, as a standalone QuadricFit does.
   */
  void SetDomainBoundary(vtkPolyData* boundary);
  vtkPolyData* GetDomainBoundary() const { return this->DomainBoundary; }
  ///@}

protected:
  vtkQuadricFit();
  ~vtkQuadricFit() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  /// RequestData's work, with vtkSMPTools on threads (vtkARMeshKernels::Threaded).
  int ExecuteData(vtkInformation*, vtkInformationVector**, vtkInformationVector*);

private:
  vtkQuadricFit(const vtkQuadricFit&) = delete;
  void operator=(const vtkQuadricFit&) = delete;

  int Template = AUTOMATIC;
  int ClusterId = 0;
  std::vector<int> ExtraClusterIds;
  double AxisOrigin[3] = { 0.0, 0.0, 0.0 };
  double AxisDirection[3] = { 0.0, 0.0, 1.0 };
  bool UseAutomaticAxis = true;
  bool GeometricRefinement = true;
  bool RobustFit = true;
  double SurfaceEdgeLength = 0.0;
  bool ShockCentring = true;
  char* CentringArray = nullptr;
  double Gamma = 1.4;
  double Margin = 3.0;
  vtkSmartPointer<vtkPolyData> DomainBoundary;
};

#endif
