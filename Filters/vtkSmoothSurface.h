// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkSmoothSurface
 * @brief Windowed-sinc smoothing of a surface whose fixed points really stay put.
 *
 * vtkWindowedSincPolyDataFilter with its usual properties. The VTK of
 * ParaView 5.11 (Hamming window) scales the whole surface by the sum of the
 * window's coefficients, slightly different from 1 (a known VTK issue, fixed
 * later by the Nuttall window): its "fixed" boundary points move (by about
 * 1e-3 of the size of a noisy unit plane). This filter corrects that: the
 * scale s and offset a of y = a + s x are fitted by least squares to the
 * fixed points (open-edge points when BoundarySmoothing is off, points on
 * edges of three or more polygons when NonManifoldSmoothing is off), every
 * point is mapped back by x = (y - a) / s, and the fixed points are set to
 * their input positions. Without fixed points nothing is corrected.
 */
#ifndef vtkSmoothSurface_h
#define vtkSmoothSurface_h

#include "AdaptiveRedistributionFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

class ADAPTIVEREDISTRIBUTIONFILTERS_EXPORT vtkSmoothSurface : public vtkPolyDataAlgorithm
{
public:
  static vtkSmoothSurface* New();
  vtkTypeMacro(vtkSmoothSurface, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Not clamped: values out of range (NumberOfIterations >= 0, PassBand in
  /// [0, 2], FeatureAngle and EdgeAngle in [0, 180] degrees) are refused
  /// with an error naming them, as a NaN or Inf point is; the input passes
  /// through.
  vtkSetMacro(NumberOfIterations, int);
  vtkGetMacro(NumberOfIterations, int);
  vtkSetMacro(PassBand, double);
  vtkGetMacro(PassBand, double);
  vtkSetMacro(BoundarySmoothing, bool);
  vtkGetMacro(BoundarySmoothing, bool);
  vtkSetMacro(FeatureEdgeSmoothing, bool);
  vtkGetMacro(FeatureEdgeSmoothing, bool);
  vtkSetMacro(FeatureAngle, double);
  vtkGetMacro(FeatureAngle, double);
  vtkSetMacro(EdgeAngle, double);
  vtkGetMacro(EdgeAngle, double);
  vtkSetMacro(NonManifoldSmoothing, bool);
  vtkGetMacro(NonManifoldSmoothing, bool);
  vtkSetMacro(NormalizeCoordinates, bool);
  vtkGetMacro(NormalizeCoordinates, bool);

protected:
  vtkSmoothSurface() = default;
  ~vtkSmoothSurface() override = default;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkSmoothSurface(const vtkSmoothSurface&) = delete;
  void operator=(const vtkSmoothSurface&) = delete;

  int NumberOfIterations = 20;
  double PassBand = 0.1;
  bool BoundarySmoothing = false;
  bool FeatureEdgeSmoothing = false;
  double FeatureAngle = 45.0;
  double EdgeAngle = 15.0;
  bool NonManifoldSmoothing = false;
  bool NormalizeCoordinates = true;
};

#endif
