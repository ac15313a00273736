// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkShockSensor
 * @brief Lovely-Haimes shock sensor: normal Mach number and shock cells (Ito et al., Eq. 3).
 *
 * At every point the filter computes the normal Mach number
 *
 *   Mn = V . grad(p) / ( a |grad(p)| ),   a = sqrt(Gamma p / rho),
 *
 * the Mach number of the flow in the direction of the pressure gradient. A
 * shock is where Mn passes through 1. grad(p) at a point is the volume-weighted
 * average of the cell gradients around it (exact P1 gradients in tetrahedra,
 * least-squares linear fits in other linear 3-D cells).
 *
 * The flow state comes from one of three sets of arrays (VariableSet), point
 * or cell data (cell data are first averaged to the points):
 * - VELOCITY_PRESSURE_DENSITY: Velocity (3), Pressure, Density;
 * - VELOCITY_PRESSURE_TEMPERATURE: Velocity, Pressure, Temperature, with
 *   rho = p / (GasConstant T);
 * - CONSERVED: Density, Momentum (rho V, 3), TotalEnergy (rho E, per unit
 *   volume), with p = (Gamma - 1) (rhoE - |rhoV|^2 / (2 rho)).
 * The arrays are chosen with SetInputArrayToProcess: index 0 Velocity,
 * 1 Pressure, 2 Density, 3 Temperature, 4 Momentum, 5 TotalEnergy. An
 * array named "(automatic)" (the default, and an empty name) is found by the
 * names solvers and their exporters use (OpenFOAM, SU2, Fluent, CGNS as
 * ParaView's readers present them; KnownArrayNames), compared without case,
 * point data first, and only with the right number of components: an array
 * of another quantity is never taken. VariableSet AUTOMATIC (the default)
 * takes the first complete set among velocity/pressure/density,
 * velocity/pressure/temperature and the conserved variables; where none is
 * complete the error names what is missing.
 *
 * GasConstant 0 (the default) takes R from the data: p / (rho T) where a
 * density is present too (the median), else the field data "GasConstant";
 * a GasConstant that differs from the data's p / (rho T) by more than 2 % is
 * refused as a mismatch (on non-dimensional data R = 287.05 would find no
 * shock at all). The output's field data "FlowStateArrays" (the names used,
 * in the order of the set) and "VariableSetUsed" say what was read, and
 * "GasConstantUsed" the R used with temperature.
 *
 * Output: the input, shallow-copied, plus the point array "NormalMach" and
 * the cell array "ShockCells" (unsigned char, 1 or 0). NormalMach is set to 0
 * where |grad p| is below PressureGradientThreshold times its global maximum:
 * there the direction of grad p, and so Mn, is noise (round-off in a uniform
 * stream) that would clutter contours and clusters of Mn. A cell is a shock cell
 * when the iso-surface Mn = 1 crosses it (one of its edges has ends on either
 * side of 1; as a cell's edges connect all its points this is min Mn < 1 <=
 * max Mn over the points), Mn falls where p rises across it (grad Mn . grad p
 * < 0 in the cell: the order of a shock, which a crossing made by noise in
 * the direction of a weak grad p lacks), and it passes the noise filters:
 * - PressureGradientThreshold (default 0.05): the mean |grad p| over the
 *   cell's points is at least this fraction of the global maximum of
 *   |grad p|. Where p is nearly uniform the direction of grad p is noise and
 *   so is Mn; 0 disables the filter (and the masking of NormalMach).
 * - LocalPeakFraction (default 0.5): the mean |grad p| over the cell's
 *   points is at least this fraction of the largest |grad p| within two rings
 *   of points around it. A captured shock is 2-3 cells thick; in its tails
 *   the direction of grad p is poorly resolved, and behind an oblique shock
 *   (supersonic tangential flow) a few degrees of error make Mn cross 1. This
 *   local test keeps the core of weak and strong shocks alike.
 * - CompressionOnly (default on): V . grad(p) > 0 (averaged over the cell's
 *   points): the flow runs into rising pressure. Expansion fans also have
 *   Mn = 1 surfaces, with V . grad(p) < 0.
 * - UpstreamMachRange (default [1, 1e6]): the largest local Mach number
 *   |V|/a over the cell's points, i.e. on its upstream side, lies in the
 *   range. A shock needs a supersonic upstream state; raise the lower bound
 *   to keep only strong shocks.
 *
 * Errors (output = input, unchanged): a missing array, a wrong number of
 * components, NaN or Inf, p <= 0, rho <= 0 or T <= 0 (or p <= 0 derived from
 * conserved variables), Gamma <= 1, an empty mesh, no 3-D cells.
 *
 * Under MPI the maximum of |grad p| is reduced over ranks and one level of
 * ghost cells is requested, so that -np N equals the serial run.
 *
 * @sa vtkWeightFunction
 */
#ifndef vtkShockSensor_h
#define vtkShockSensor_h

#include "AdaptiveRedistributionFiltersModule.h" // for export macro
#include "vtkARVolumeFilter.h"

class ADAPTIVEREDISTRIBUTIONFILTERS_EXPORT vtkShockSensor : public vtkARVolumeFilter
{
public:
  static vtkShockSensor* New();
  vtkTypeMacro(vtkShockSensor, vtkARVolumeFilter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum VariableSets
  {
    VELOCITY_PRESSURE_DENSITY = 0,
    VELOCITY_PRESSURE_TEMPERATURE = 1,
    CONSERVED = 2,
    AUTOMATIC = 3 ///< the first complete set found by the arrays' names
  };

  /// Indices for SetInputArrayToProcess.
  enum ArrayIndices
  {
    VELOCITY = 0,
    PRESSURE = 1,
    DENSITY = 2,
    TEMPERATURE = 3,
    MOMENTUM = 4,
    TOTAL_ENERGY = 5
  };

  ///@{
  /// Which arrays describe the flow. Default AUTOMATIC. Not clamped: a value
  /// outside 0..3 is refused with an error naming it.
  vtkSetMacro(VariableSet, int);
  vtkGetMacro(VariableSet, int);
  ///@}

  ///@{
  /// Ratio of specific heats. Default 1.4.
  vtkSetMacro(Gamma, double);
  vtkGetMacro(Gamma, double);
  ///@}

  ///@{
  /// Specific gas constant R (J/(kg K); 287.05 for air), used with
  /// temperature. Default 0: from the data (see above).
  vtkSetMacro(GasConstant, double);
  vtkGetMacro(GasConstant, double);
  ///@}

  ///@{
  /// Fraction of the global maximum of |grad p| below which a cell is not a
  /// shock cell, in [0, 1] (refused otherwise, not clamped). Default 0.05.
  vtkSetMacro(PressureGradientThreshold, double);
  vtkGetMacro(PressureGradientThreshold, double);
  ///@}

  ///@{
  /// Fraction of the local peak of |grad p| (the largest |grad p| within two
  /// rings of points) that a shock cell's mean |grad p| must reach. Keeps the
  /// shock cells at the core of a captured shock, for weak and strong shocks
  /// alike, and drops crossings in its tails, in [0, 1] (refused otherwise,
  /// not clamped). Default 0.5; 0 disables.
  vtkSetMacro(LocalPeakFraction, double);
  vtkGetMacro(LocalPeakFraction, double);
  ///@}

  ///@{
  /// Keep only compressions (V . grad p > 0). Default on.
  vtkSetMacro(CompressionOnly, bool);
  vtkGetMacro(CompressionOnly, bool);
  vtkBooleanMacro(CompressionOnly, bool);
  ///@}

  ///@{
  /// Range of the upstream local Mach number. Default [1, 1e6].
  vtkSetVector2Macro(UpstreamMachRange, double);
  vtkGetVector2Macro(UpstreamMachRange, double);
  ///@}

protected:
  vtkShockSensor();
  ~vtkShockSensor() override = default;

  int Execute(Execution& run) override;

public:
  /// The names an automatic array of index `idx` (ArrayIndices) is looked
  /// for by, in order of preference (nullptr-terminated).
  static const char* const* KnownArrayNames(int idx);
  /// The name of an array left to the filter to find.
  static constexpr const char* AutomaticArrayName = "(automatic)";
  /// The first array of `input` whose name is one of KnownArrayNames(idx)
  /// (compared without case; for each name point data first, then cell
  /// data) with `components` components; nullptr when there is none.
  /// `association`: FIELD_ASSOCIATION_POINTS or _CELLS of the one found.
  static vtkDataArray* FindKnownArray(int idx, int components, vtkDataSet* input, int& association);

protected:
  /// The array of index `idx` on `input` (the named one, or the first known
  /// name with `components` components); nullptr when there is none.
  /// `association`: point or cell; `automatic`: it was looked up by name.
  vtkDataArray* ResolveArray(int idx, int components, vtkDataSet* input, int& association, bool& automatic);

private:
  vtkShockSensor(const vtkShockSensor&) = delete;
  void operator=(const vtkShockSensor&) = delete;

  ///@{
  /// The passes of Execute, in order, over the state of one execution
  /// (FlowState, in the .cxx).
  struct FlowState;
  void ResolveFlowState(Execution& run, FlowState& st);
  void ReadFlowState(Execution& run, FlowState& st);
  void ResolveGasConstant(Execution& run, FlowState& st);
  bool ToPrimitiveState(Execution& run, FlowState& st);
  bool PressureGradient(Execution& run, FlowState& st);
  void PointQuantities(Execution& run, FlowState& st);
  void LocalPeaks(Execution& run, FlowState& st);
  void MarkShockCells(Execution& run, FlowState& st);
  ///@}

  int VariableSet = AUTOMATIC;
  double Gamma = 1.4;
  double GasConstant = 0.0;
  double PressureGradientThreshold = 0.05;
  double LocalPeakFraction = 0.5;
  bool CompressionOnly = true;
  double UpstreamMachRange[2] = { 1.0, 1.0e6 };
};

#endif
