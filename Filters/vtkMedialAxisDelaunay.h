// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkMedialAxisDelaunay
 * @brief Medial sheet of a feature region bounded by a triangulated
 *        isosurface, from the circumcentres of its Delaunay tetrahedra.
 *
 * The discrete surface-based approach of the paper (section 2.3): the input
 * is a triangulated surface around a feature region, typically ParaView's
 * Contour of `WeightFunction` on the solution. It may be in several pieces,
 * open where it meets the domain boundary, noisy, with holes.
 *
 * 1. Optional smoothing of the surface (windowed sinc or Laplacian; VTK).
 * 2. Delaunay tetrahedralization of the surface points (CGAL, exact
 *    predicates). A tetrahedron is interior when its circumcentre lies on the
 *    region's side of the oriented point normals at its four points (needs no
 *    closed surface), and, with a Domain connected, inside the domain.
 * 3. The medial sheet: the Voronoi facets dual to Delaunay edges whose ring of
 *    tetrahedra is interior, pruned by the object angle (Dey and Zhao 2004),
 *    by the pole radius relative to the local surface edge length, and by
 *    sheet area. See ARMedialAxis.h for the details.
 * 4. Optional symmetry planes: the surface is mirrored across them before
 *    the Delaunay step, so that the region is not closed at the plane and its
 *    sheet crosses the plane orthogonally; the sheet is then cut at the plane
 *    (SymmetryTrimDistance short of it) and its open edges near the plane are
 *    extended orthogonally onto it (vtkExtendToPlane), so that one sheet
 *    spans between symmetry planes (the repair the paper made by hand, its
 *    Figure 2c). Two parallel planes (a one-cell-thick 2-D mesh) are handled:
 *    the mirrored copies stack up.
 *
 * Orientation: ParaView's Contour gives point normals that point out of the
 * region above the iso-value (towards lower values). FeatureRegion
 * ABOVE_ISOVALUE (default) takes the region the normals point away from;
 * BELOW_ISOVALUE the other side. Without a `Normals` point array the normals
 * are computed and oriented outwards (right for a closed surface; an open
 * surface without normals gets a warning).
 *
 * 5. Optional filling of the small holes pruned facets leave (vtkFillHolesFilter).
 *
 * Output: vtkPolyData of triangles with point array `Radius` (the inscribed
 * ball radius), cell arrays `SheetId` (0 = largest) and `Extended` (1 on the
 * strips added at symmetry planes); field data `SheetAreas`,
 * `DelaunayTetrahedra`, `InteriorTetrahedra`, `VoronoiFacets`.
 *
 * Under MPI the surface pieces (and the domain boundary) are gathered to
 * rank 0, which computes the sheet; the other ranks output nothing.
 */
#ifndef vtkMedialAxisDelaunay_h
#define vtkMedialAxisDelaunay_h

#include "AdaptiveRedistributionFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for Fail
#include <vector> // for the symmetry planes

class ADAPTIVEREDISTRIBUTIONFILTERS_EXPORT vtkMedialAxisDelaunay : public vtkPolyDataAlgorithm
{
public:
  static vtkMedialAxisDelaunay* New();
  vtkTypeMacro(vtkMedialAxisDelaunay, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum SmoothingModes
  {
    NO_SMOOTHING = 0,
    WINDOWED_SINC = 1,
    LAPLACIAN = 2
  };
  enum FeatureRegions
  {
    ABOVE_ISOVALUE = 0, ///< the side the normals point away from
    BELOW_ISOVALUE = 1  ///< the side the normals point to
  };

  /// The flow domain (input port 1, optional): a volume mesh. Voronoi
  /// vertices outside it are not part of the sheet.
  void SetDomainConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetDomainData(vtkDataObject* data) { this->SetInputData(1, data); }

  /// The properties below are not clamped: RequestData refuses a value out
  /// of its range (Smoothing 0-2, SmoothingIterations 0-10000, PassBand
  /// (0, 2], RelaxationFactor [0, 1], FeatureRegion 0-1, MinimumObjectAngle
  /// [0, 180], MinimumRadiusFactor [0, 1e6], MinimumAreaFraction [0, 1],
  /// MaximumNumberOfSheets >= 0, SymmetryTrimDistance >= 0, MaximumHoleSize
  /// [0, 1e6]) with an error naming it, and the output is empty.

  ///@{
  /// Smoothing of the input surface before the Delaunay step. Default NO_SMOOTHING
  /// (windowed sinc costs more than the whole medial axis at 1e6 points).
  vtkSetMacro(Smoothing, int);
  vtkGetMacro(Smoothing, int);
  vtkSetMacro(SmoothingIterations, int);
  vtkGetMacro(SmoothingIterations, int);
  /// Pass band of the windowed sinc filter (0, 2); smaller smooths more. Default 0.1.
  vtkSetMacro(PassBand, double);
  vtkGetMacro(PassBand, double);
  /// Relaxation factor of Laplacian smoothing. Default 0.1.
  vtkSetMacro(RelaxationFactor, double);
  vtkGetMacro(RelaxationFactor, double);
  ///@}

  ///@{
  /// Which side of the surface is the feature region. Default ABOVE_ISOVALUE.
  vtkSetMacro(FeatureRegion, int);
  vtkGetMacro(FeatureRegion, int);
  ///@}

  ///@{
  /// Pruning (see ARMedialAxis.h). Defaults 110 degrees, 0.5, 0.05, 0 (no limit).
  vtkSetMacro(MinimumObjectAngle, double);
  vtkGetMacro(MinimumObjectAngle, double);
  vtkSetMacro(MinimumRadiusFactor, double);
  vtkGetMacro(MinimumRadiusFactor, double);
  vtkSetMacro(MinimumAreaFraction, double);
  vtkGetMacro(MinimumAreaFraction, double);
  vtkSetMacro(MaximumNumberOfSheets, int);
  vtkGetMacro(MaximumNumberOfSheets, int);
  ///@}

  ///@{
  /// Symmetry planes, 6 values each (origin x y z, normal x y z; the normal
  /// need not be unit). Default none.
  void SetNumberOfSymmetryPlaneValues(int n);
  void SetSymmetryPlaneValue(int i, double value);
  void AddSymmetryPlane(const double origin[3], const double normal[3]);
  void RemoveAllSymmetryPlanes();
  int GetNumberOfSymmetryPlanes() const { return static_cast<int>(this->SymmetryPlanes.size() / 6); }
  ///@}

  ///@{
  /// One more symmetry plane from ParaView's plane widget, used when
  /// UseSymmetryPlaneWidget is on. Defaults off, (0,0,0), (0,0,1).
  vtkSetMacro(UseSymmetryPlaneWidget, bool);
  vtkGetMacro(UseSymmetryPlaneWidget, bool);
  vtkBooleanMacro(UseSymmetryPlaneWidget, bool);
  vtkSetVector3Macro(SymmetryPlaneOrigin, double);
  vtkGetVector3Macro(SymmetryPlaneOrigin, double);
  vtkSetVector3Macro(SymmetryPlaneNormal, double);
  vtkGetVector3Macro(SymmetryPlaneNormal, double);
  ///@}

  ///@{
  /// Also take as symmetry planes the Domain's planar boundary patches that
  /// hold at least 10 % of the feature surface's open-edge points and on
  /// which the surface ends at a right angle (an isosurface stands
  /// orthogonally on a plane of symmetry; a shock leaving through an outlet
  /// or meeting a wall does not). The planes used are the field array
  /// `SymmetryPlanesUsed`. Default off.
  vtkSetMacro(SymmetryPlanesFromDomain, bool);
  vtkGetMacro(SymmetryPlanesFromDomain, bool);
  vtkBooleanMacro(SymmetryPlanesFromDomain, bool);
  ///@}

  ///@{
  /// How far short of a symmetry plane the sheet is cut before its open edges
  /// near the plane are extended orthogonally onto it (vtkExtendToPlane, for
  /// edges within SymmetryTrimDistance + 2 median surface edge lengths).
  /// Default 0: the sheet of the mirrored surface already meets the plane at
  /// a right angle, and the extension only closes gaps that the pruning left
  /// next to the plane; a positive distance replaces a ragged end of the sheet
  /// by an exactly orthogonal strip.
  vtkSetMacro(SymmetryTrimDistance, double);
  vtkGetMacro(SymmetryTrimDistance, double);
  ///@}

  ///@{
  /// Fill the small holes that pruned facets leave in a sheet
  /// (vtkFillHolesFilter): holes whose boundary loop fits in a sphere of
  /// radius MaximumHoleSize times the median surface edge length. Holes
  /// bounded by a non-manifold edge stay. Defaults on, 2.
  vtkSetMacro(FillHoles, bool);
  vtkGetMacro(FillHoles, bool);
  vtkBooleanMacro(FillHoles, bool);
  vtkSetMacro(MaximumHoleSize, double);
  vtkGetMacro(MaximumHoleSize, double);
  ///@}

protected:
  vtkMedialAxisDelaunay();
  ~vtkMedialAxisDelaunay() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkMedialAxisDelaunay(const vtkMedialAxisDelaunay&) = delete;
  void operator=(const vtkMedialAxisDelaunay&) = delete;

  ///@{
  /// The passes of RequestData, in order, over the state of one execution
  /// (SheetState, in the .cxx). A pass that returns false has reported the
  /// error (Fail: an error, and an empty output).
  struct SheetState;
  bool Fail(SheetState& st, const std::string& message);
  bool CheckSurface(SheetState& st);
  bool SmoothSurface(SheetState& st);
  bool OrientNormals(SheetState& st);
  bool ReadDomain(SheetState& st);
  bool ComputeSheet(SheetState& st);
  void BuildSheet(SheetState& st);
  void FillSheetHoles(SheetState& st);
  void TrimAtSymmetryPlanes(SheetState& st);
  void WriteOutput(SheetState& st);
  ///@}

  int Smoothing = NO_SMOOTHING;
  int SmoothingIterations = 20;
  double PassBand = 0.1;
  double RelaxationFactor = 0.1;
  int FeatureRegion = ABOVE_ISOVALUE;
  double MinimumObjectAngle = 110.0;
  double MinimumRadiusFactor = 0.5;
  double MinimumAreaFraction = 0.05;
  int MaximumNumberOfSheets = 0;
  std::vector<double> SymmetryPlanes;
  bool UseSymmetryPlaneWidget = false;
  double SymmetryPlaneOrigin[3] = { 0.0, 0.0, 0.0 };
  double SymmetryPlaneNormal[3] = { 0.0, 0.0, 1.0 };
  double SymmetryTrimDistance = 0.0;
  bool SymmetryPlanesFromDomain = false;
  bool FillHoles = true;
  double MaximumHoleSize = 2.0;
};

#endif
