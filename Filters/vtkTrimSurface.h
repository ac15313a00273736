// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkTrimSurface
 * @brief Cuts a surface exactly with a plane or a box (vtkClipPolyData).
 *
 * The ParaView filter TrimSurface: ClipFunction is the Plane or Box of
 * ParaView's interactive widgets (vtkPVPlane, vtkPVBox) or any
 * vtkImplicitFunction. A vtkPlane is passed to vtkClipPolyData as it is; a
 * vtkBox (with its transform) is cut as six planes carrying the same
 * transform, whose values are affine in x, so that every cut lies exactly on
 * the box's faces (the box function itself is not linear along an edge
 * and would cut its corners). Inside the box: the six cuts in turn. Outside
 * (InsideOut off): the surface is split by each face plane in turn (both
 * sides kept and merged, so the cut lines conform), then the triangles
 * inside the box are dropped. Other implicit functions are passed to vtkClipPolyData
 * as they are (the cut then interpolates the function linearly).
 *
 * InsideOut on (the default, as in ParaView's Clip): keep where the function
 * is negative (behind the plane, inside the box); off: where it is positive.
 * Output triangles with point arrays interpolated onto the cut and
 * cell arrays copied. No ClipFunction: pass-through with a warning.
 */
#ifndef vtkTrimSurface_h
#define vtkTrimSurface_h

#include "AdaptiveRedistributionFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

class vtkImplicitFunction;

class ADAPTIVEREDISTRIBUTIONFILTERS_EXPORT vtkTrimSurface : public vtkPolyDataAlgorithm
{
public:
  static vtkTrimSurface* New();
  vtkTypeMacro(vtkTrimSurface, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The plane, box or other implicit function to cut with.
  virtual void SetClipFunction(vtkImplicitFunction*);
  vtkGetObjectMacro(ClipFunction, vtkImplicitFunction);
  ///@}

  ///@{
  /// Keep where the function is negative (default on) or positive.
  vtkSetMacro(InsideOut, bool);
  vtkGetMacro(InsideOut, bool);
  vtkBooleanMacro(InsideOut, bool);
  ///@}

  vtkMTimeType GetMTime() override;

protected:
  vtkTrimSurface() = default;
  ~vtkTrimSurface() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkTrimSurface(const vtkTrimSurface&) = delete;
  void operator=(const vtkTrimSurface&) = delete;

  vtkImplicitFunction* ClipFunction = nullptr;
  bool InsideOut = true;
};

#endif
