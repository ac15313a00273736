// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkWeightFunction
 * @brief Soni et al.'s weight function W in [1, 2] (Ito et al., Eq. 1-2).
 *
 * For every linear 3-D cell (tetrahedron, pyramid, wedge, hexahedron, voxel,
 * pentagonal/hexagonal prism, polyhedron) of an unstructured grid, W marks
 * how strongly the selected solution variables vary across the cell:
 *
 *   r_ik(e) = | dq^i/dx_k (e) | / ( |qbar^i(e)| + Epsilon )       (normalized gradient)
 *   n_ik(e) = r_ik(e) / max_{e', k'} r_ik'(e')                     ("[.]_max" in Eq. 1)
 *   W^k(e)  = n_1k (+) n_2k (+) ... (+) n_nq,k                     (Boolean sum over variables)
 *   W(e)    = 1 + (+)_k  W^k(e) / max_{e',k'} W^k'(e')             (Boolean sum over x, y, z)
 *
 * with a (+) b = a + b - ab (Eq. 2). How each max is read, and why:
 * - "[.]_max" for variable i is the maximum of r_ik over every cell of the
 *   whole dataset (all MPI ranks) AND over the three directions k. Over all
 *   cells, so that n_ik lies in [0, 1] and a variable with tiny absolute
 *   gradients weighs as much as one with large ones (the purpose of the
 *   normalization). Over the directions too (the paper's subscript names no
 *   index), because a per-direction maximum would blow up a direction in
 *   which a variable hardly varies to full weight: the spanwise direction
 *   of a 2-D solution on a one-cell-thick 3-D mesh, or the tangential
 *   directions of an axis-aligned shock, would then mark every cell.
 *   A variable whose relative change across the domain is below round-off
 *   (max r times the domain diagonal < 1e-8) is constant and counts as 0.
 * - "max(W^1, W^2, W^3)" is the maximum over all three directions AND all
 *   cells. Read per cell it would scale the largest direction of every cell
 *   to 1 and give W = 2 wherever any gradient exists, which erases the
 *   feature; read globally it keeps W^k/max in [0, 1] and W in [1, 2], with
 *   W = 1 where nothing varies and W near 2 only at the strongest features.
 * - dq/dx_k is the gradient in physical space (the paper's xi_k are x, y, z),
 *   the exact P1 gradient in a tetrahedron and the least-squares linear fit
 *   over the points of other cells; qbar is the value at the centroid: the
 *   mean of the cell's point values for point arrays, the cell value for
 *   cell arrays.
 *
 * Every component of a multi-component array is one variable q^i (the paper
 * uses the conserved variables rho, rhoU, rhoV, rhoW, rhoE). Cell arrays are
 * first averaged to the points (weighted by cell volume) to take gradients.
 * A name present both as a point and as a cell array is taken from the point
 * data.
 *
 * Output: the input, shallow-copied, with the cell array ResultArrayName
 * (default "WeightFunction") and, if ComputePointWeight is on, a point array
 * of the same name averaged from the cells. Cells that are not linear 3-D
 * cells, and degenerate cells, get W = 1.
 *
 * Errors (output passes the input through unchanged): no variable selected,
 * a variable that is not an array of the input, NaN or Inf in a variable, an
 * empty mesh, a mesh with no 3-D cells.
 *
 * Under MPI the maxima are reduced over all ranks, and ghost cells (one level
 * is requested upstream) complete the stencils at partition boundaries, so the
 * result equals the serial one.
 *
 * @sa vtkShockSensor
 */
#ifndef vtkWeightFunction_h
#define vtkWeightFunction_h

#include "AdaptiveRedistributionFiltersModule.h" // for export macro
#include "vtkARVolumeFilter.h"

#include <string>

class vtkDataArraySelection;

class ADAPTIVEREDISTRIBUTIONFILTERS_EXPORT vtkWeightFunction : public vtkARVolumeFilter
{
public:
  static vtkWeightFunction* New();
  vtkTypeMacro(vtkWeightFunction, vtkARVolumeFilter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * The variables q^i: names of point or cell arrays; enabled entries are
   * used. Every component of a vector array is a variable. With none
   * enabled: the conserved variables by their usual names
   * (vtkShockSensor::KnownArrayNames for density, momentum, total energy),
   * else density, velocity, pressure; field data VariablesUsed.
   */
  vtkDataArraySelection* GetVariableSelection() { return this->VariableSelection; }
  void AddVariable(const char* name);
  void RemoveAllVariables();

  ///@{
  /// epsilon of Eq. 1, added to |qbar| to keep the normalization finite where
  /// a variable passes through zero. Default 1e-3 (in the units of the
  /// variables: scale it with them). At least 0 and finite: refused
  /// otherwise, not clamped.
  vtkSetMacro(Epsilon, double);
  vtkGetMacro(Epsilon, double);
  ///@}

  ///@{
  /// Name of the output array. Default "WeightFunction".
  vtkSetStdStringFromCharMacro(ResultArrayName);
  vtkGetCharFromStdStringMacro(ResultArrayName);
  ///@}

  ///@{
  /// Also output a point array (same name) averaged from the cells. Default off.
  vtkSetMacro(ComputePointWeight, bool);
  vtkGetMacro(ComputePointWeight, bool);
  vtkBooleanMacro(ComputePointWeight, bool);
  ///@}

protected:
  vtkWeightFunction();
  ~vtkWeightFunction() override;

  int Execute(Execution& run) override;

private:
  vtkWeightFunction(const vtkWeightFunction&) = delete;
  void operator=(const vtkWeightFunction&) = delete;

  ///@{
  /// The passes of Execute, in order, over the state of one execution
  /// (WeightState, in the .cxx).
  struct WeightState;
  void SelectVariables(Execution& run, WeightState& st);
  void PackValues(Execution& run, WeightState& st);
  bool CellValuesToPoints(Execution& run, WeightState& st);
  bool ComputeWeights(Execution& run, WeightState& st);
  void WriteWeights(Execution& run, WeightState& st);
  ///@}

  vtkDataArraySelection* VariableSelection;
  double Epsilon = 1e-3;
  std::string ResultArrayName = "WeightFunction";
  bool ComputePointWeight = false;
};

#endif
