// SPDX-License-Identifier: BSD-3-Clause
#include "vtkWeightFunction.h"

#include "vtkShockSensor.h"

#include "vtkARInputChecks.h"
#include "vtkARVolumeFilterExecution.h"
#include "vtkARMeshKernels.h"
#include "vtkARParallel.h"
#include "vtkCellData.h"
#include "vtkNew.h"
#include "vtkStringArray.h"
#include "vtkCommand.h"
#include "vtkDataArraySelection.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkWeightFunction);

namespace
{
/// One selected array; each of its components is a variable q^i.
struct Variable
{
  vtkDataArray* Array = nullptr;
  bool OnPoints = true;
  int FirstColumn = 0; ///< column of its first component in the point-value table
};

inline double BooleanSum(double a, double b)
{
  return a + b - a * b;
}
}

//------------------------------------------------------------------------------
vtkWeightFunction::vtkWeightFunction()
  : vtkARVolumeFilter("the weight function")
  , VariableSelection(vtkDataArraySelection::New())
{
  // A change of the selection re-executes the filter.
  this->VariableSelection->AddObserver(
    vtkCommand::ModifiedEvent, this, &vtkWeightFunction::Modified);
}

vtkWeightFunction::~vtkWeightFunction()
{
  this->VariableSelection->Delete();
}

void vtkWeightFunction::AddVariable(const char* name)
{
  if (name)
  {
    this->VariableSelection->EnableArray(name);
  }
}

void vtkWeightFunction::RemoveAllVariables()
{
  this->VariableSelection->RemoveAllArrays();
}

//------------------------------------------------------------------------------
//------------------------------------------------------------------------------
/// The state of one execution, shared by the passes of Execute.
struct vtkWeightFunction::WeightState
{
  std::vector<Variable> Variables;
  int NumberOfColumns = 0;       ///< nq: the variables' components
  std::vector<double> Q;         ///< the variables at the points, nq columns
  std::vector<double> CellValues; ///< cell variables, cell-major, nqc columns
  std::vector<int> CellColumns;   ///< their columns in Q
  int NumberOfCellColumns = 0;   ///< nqc
  std::vector<int> CellIndexOfColumn; ///< column -> index into CellValues, or -1
  std::vector<float> Wk;         ///< W^k per cell, 3 columns
  double WMax = 0.0;             ///< the maximum of W^k over cells and directions
};

int vtkWeightFunction::Execute(Execution& run)
{
  // The passes below share the state of this execution (WeightState).
  WeightState st;
  std::ostringstream& problem = run.Problem;

  // ---- Validation. Every rank reaches the same collective calls, in order.
  problem << vtkARInputChecks::Properties()
               .InRange("Epsilon", this->Epsilon, 0.0, VTK_DOUBLE_MAX, "added to |qbar| in Eq. 1")
               .Message();

  this->SelectVariables(run, st);
  this->PackValues(run, st);

  if (!this->Proceed(run))
  {
    return 1;
  }

  if (!this->CellValuesToPoints(run, st))
  {
    return 1;
  }
  if (!this->ComputeWeights(run, st))
  {
    return 1;
  }
  this->WriteWeights(run, st);
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkWeightFunction::SelectVariables(Execution& run, WeightState& st)
{
  vtkUnstructuredGrid* input = run.Input;
  std::ostringstream& problem = run.Problem;
  vtkARMeshKernels::MeshView& mesh = run.Mesh;

  vtkPointData* pd = input->GetPointData();
  vtkCellData* cd = input->GetCellData();
  // The variables: those selected, or with none selected (pvpython on a
  // reader that has not run yet gets an empty selection) the paper's
  // conserved variables found by their usual names (rho, rhoU, rhoE and the
  // SU2/CGNS spellings, vtkShockSensor::KnownArrayNames), else the
  // primitive ones (rho, U, p).
  std::vector<std::string> names;
  for (int i = 0; i < this->VariableSelection->GetNumberOfArrays(); ++i)
  {
    if (this->VariableSelection->GetArraySetting(i))
    {
      names.emplace_back(this->VariableSelection->GetArrayName(i));
    }
  }
  const bool automatic = names.empty();
  if (automatic)
  {
    const int sets[2][3] = { { vtkShockSensor::DENSITY, vtkShockSensor::MOMENTUM, vtkShockSensor::TOTAL_ENERGY },
      { vtkShockSensor::DENSITY, vtkShockSensor::VELOCITY, vtkShockSensor::PRESSURE } };
    const int components[3] = { 1, 3, 1 }; // (both sets: a scalar, a vector, a scalar)
    for (int k = 0; k < 2 && names.empty(); ++k)
    {
      std::vector<std::string> found;
      for (int r = 0; r < 3; ++r)
      {
        int association = -1;
        vtkDataArray* a = vtkShockSensor::FindKnownArray(sets[k][r], components[r], input, association);
        if (a && a->GetName())
        {
          found.emplace_back(a->GetName());
        }
      }
      if (found.size() == 3)
      {
        names = found;
      }
    }
  }
  for (const std::string& chosen : names)
  {
    const char* name = chosen.c_str();
    Variable v;
    v.Array = pd->GetArray(name);
    v.OnPoints = v.Array != nullptr;
    if (!v.Array)
    {
      v.Array = cd->GetArray(name);
    }
    if (!v.Array)
    {
      if (mesh.NumberOfCells > 0)
      {
        problem << "Variable '" << name << "' is not a numeric point or cell array of the input. ";
      }
      continue;
    }
    v.FirstColumn = st.NumberOfColumns;
    st.NumberOfColumns += v.Array->GetNumberOfComponents();
    st.Variables.push_back(v);
  }
  if (names.empty())
  {
    problem << "No variable is selected, and the input has neither the conserved variables (density "
               "rho, momentum rhoU, total energy rhoE, or their SU2/CGNS names) nor the primitive ones "
               "(rho, U, p) by name: choose one or more point or cell arrays (the paper uses the "
               "conserved variables). ";
  }
}

//------------------------------------------------------------------------------
void vtkWeightFunction::PackValues(Execution& run, WeightState& st)
{
  std::ostringstream& problem = run.Problem;
  const vtkIdType npts = run.Mesh.NumberOfPoints;
  const vtkIdType ncells = run.Mesh.NumberOfCells;

  // Values of all variables at the points: nq columns.
  st.Q.assign(static_cast<size_t>(npts) * std::max(st.NumberOfColumns, 1), 0.0);
  if (problem.str().empty() && ncells > 0)
  {
    for (const Variable& v : st.Variables)
    {
      if (v.OnPoints)
      {
        const vtkIdType bad =
          vtkARMeshKernels::PackComponents(v.Array, st.Q.data(), st.NumberOfColumns, v.FirstColumn);
        if (bad >= 0)
        {
          problem << "Point array '" << v.Array->GetName() << "' holds NaN or Inf (point " << bad
                  << "). ";
        }
      }
      else
      {
        for (int k = 0; k < v.Array->GetNumberOfComponents(); ++k)
        {
          st.CellColumns.push_back(v.FirstColumn + k);
        }
      }
    }
    const int nqc = static_cast<int>(st.CellColumns.size());
    if (nqc > 0)
    {
      st.CellValues.resize(static_cast<size_t>(ncells) * nqc);
      int offset = 0;
      for (const Variable& v : st.Variables)
      {
        if (!v.OnPoints)
        {
          const vtkIdType bad =
            vtkARMeshKernels::PackComponents(v.Array, st.CellValues.data(), nqc, offset);
          if (bad >= 0)
          {
            problem << "Cell array '" << v.Array->GetName() << "' holds NaN or Inf (cell " << bad
                    << "). ";
          }
          offset += v.Array->GetNumberOfComponents();
        }
      }
    }
  }
}

//------------------------------------------------------------------------------
bool vtkWeightFunction::CellValuesToPoints(Execution& run, WeightState& st)
{
  vtkARMeshKernels::MeshView& mesh = run.Mesh;

  // ---- Cell variables are averaged to the points to take their gradients.
  st.NumberOfCellColumns = static_cast<int>(st.CellColumns.size());
  if (st.NumberOfCellColumns > 0)
  {
    std::vector<int> tableColumns(st.NumberOfCellColumns);
    for (int k = 0; k < st.NumberOfCellColumns; ++k)
    {
      tableColumns[k] = k;
    }
    if (!vtkARMeshKernels::CellColumnsToPoints(
          mesh, st.CellValues.data(), st.NumberOfCellColumns, tableColumns, st.Q.data(), st.NumberOfColumns, st.CellColumns, this))
    {
      return false;
    }
  }
  // Column -> index into cellValues, or -1 for a point variable.
  st.CellIndexOfColumn.assign(st.NumberOfColumns, -1);
  for (int k = 0; k < st.NumberOfCellColumns; ++k)
  {
    st.CellIndexOfColumn[st.CellColumns[k]] = k;
  }
  this->UpdateProgress(0.2);
  return true;
}

//------------------------------------------------------------------------------
bool vtkWeightFunction::ComputeWeights(Execution& run, WeightState& st)
{
  // Passes 1 and 2 of Eq. 1-2 together (about 190 lines): both evaluate the
  // normalized gradients of every cell with the one lambda below.
  vtkUnstructuredGrid* input = run.Input;
  vtkUnstructuredGrid* output = run.Output;
  vtkARMeshKernels::MeshView& mesh = run.Mesh;
  const vtkIdType ncells = run.Mesh.NumberOfCells;

  // Normalized gradient magnitudes r_ik of cell c; returns false for cells
  // that do not take part (not a linear 3-D cell, degenerate).
  const double eps = this->Epsilon;
  auto normalizedGradients = [&](vtkIdType c, double* r) -> bool {
    if (mesh.CellSize(c) == 4 && mesh.IsVolumeCell(c))
    {
      // Tetrahedra, the common case, inline: gradients from point differences.
      const vtkIdType* ids = mesh.CellPoints(c);
      double Jinv[3][3], volume;
      if (!vtkARMeshKernels::TetInverseJacobian(mesh.X, ids, Jinv, volume))
      {
        return false;
      }
      const double* q0 = &st.Q[static_cast<size_t>(ids[0]) * st.NumberOfColumns];
      const double* q1 = &st.Q[static_cast<size_t>(ids[1]) * st.NumberOfColumns];
      const double* q2 = &st.Q[static_cast<size_t>(ids[2]) * st.NumberOfColumns];
      const double* q3 = &st.Q[static_cast<size_t>(ids[3]) * st.NumberOfColumns];
      for (int i = 0; i < st.NumberOfColumns; ++i)
      {
        const double d1 = q1[i] - q0[i], d2 = q2[i] - q0[i], d3 = q3[i] - q0[i];
        double mean = 0.25 * (q0[i] + q1[i] + q2[i] + q3[i]);
        if (st.CellIndexOfColumn[i] >= 0)
        {
          mean = st.CellValues[static_cast<size_t>(c) * st.NumberOfCellColumns + st.CellIndexOfColumn[i]];
        }
        const double inv = 1.0 / (std::abs(mean) + eps);
        for (int k = 0; k < 3; ++k)
        {
          r[3 * i + k] = std::abs(Jinv[k][0] * d1 + Jinv[k][1] * d2 + Jinv[k][2] * d3) * inv;
        }
      }
      return true;
    }
    double W[vtkARMeshKernels::MaxCellPoints][3];
    int n;
    double measure;
    if (!mesh.IsVolumeCell(c) || !vtkARMeshKernels::GradientOperator(mesh, c, W, n, measure))
    {
      return false;
    }
    const vtkIdType* ids = mesh.CellPoints(c);
    for (int i = 0; i < st.NumberOfColumns; ++i)
    {
      double g0 = 0.0, g1 = 0.0, g2 = 0.0, mean = 0.0;
      for (int a = 0; a < n; ++a)
      {
        const double q = st.Q[static_cast<size_t>(ids[a]) * st.NumberOfColumns + i];
        g0 += W[a][0] * q;
        g1 += W[a][1] * q;
        g2 += W[a][2] * q;
        mean += q;
      }
      mean /= n;
      if (st.CellIndexOfColumn[i] >= 0)
      {
        mean = st.CellValues[static_cast<size_t>(c) * st.NumberOfCellColumns + st.CellIndexOfColumn[i]];
      }
      const double inv = 1.0 / (std::abs(mean) + eps);
      r[3 * i + 0] = std::abs(g0) * inv;
      r[3 * i + 1] = std::abs(g1) * inv;
      r[3 * i + 2] = std::abs(g2) * inv;
    }
    return true;
  };

  // ---- Pass 1: maxima of r_ik over owned cells, then over ranks.
  std::atomic<bool> aborted(false);
  vtkSMPThreadLocal<std::vector<double>> localMax;
  vtkSMPTools::For(0, ncells, [&](vtkIdType b, vtkIdType e) {
    if (aborted || vtkARMeshKernels::Aborted(this))
    {
      aborted = true;
      return;
    }
    std::vector<double>& mx = localMax.Local();
    mx.resize(3 * st.NumberOfColumns, 0.0);
    std::vector<double> r(3 * st.NumberOfColumns);
    for (vtkIdType c = b; c < e; ++c)
    {
      if (mesh.IsOwnedCell(c) && normalizedGradients(c, r.data()))
      {
        for (int j = 0; j < 3 * st.NumberOfColumns; ++j)
        {
          mx[j] = std::max(mx[j], r[j]);
        }
      }
    }
  });
  std::vector<double> rMax(3 * st.NumberOfColumns, 0.0);
  for (auto& mx : localMax)
  {
    for (size_t j = 0; j < mx.size(); ++j)
    {
      rMax[j] = std::max(rMax[j], mx[j]);
    }
  }
  // The bounding box diagonal L, for the round-off floor below.
  double bounds[6];
  input->GetBounds(bounds);
  double extent[6] = { -bounds[0], bounds[1], -bounds[2], bounds[3], -bounds[4], bounds[5] };
  vtkARParallel::AllReduceMax(rMax.data(), 3 * st.NumberOfColumns);
  vtkARParallel::AllReduceMax(extent, 6);
  const double L = std::sqrt((extent[1] + extent[0]) * (extent[1] + extent[0]) +
    (extent[3] + extent[2]) * (extent[3] + extent[2]) + (extent[5] + extent[4]) * (extent[5] + extent[4]));
  double abortFlag = aborted ? 1.0 : 0.0;
  vtkARParallel::AllReduceMax(&abortFlag, 1);
  if (abortFlag > 0.0)
  {
    output->ShallowCopy(input);
    return false;
  }
  // [.]_max of Eq. 1: per variable, over all cells and all three directions.
  // A variable whose relative change across the whole domain stays below
  // 1e-8 (r * L) is constant up to round-off and contributes nothing.
  std::vector<double> rInv(3 * st.NumberOfColumns, 0.0);
  for (int i = 0; i < st.NumberOfColumns; ++i)
  {
    const double m = std::max({ rMax[3 * i], rMax[3 * i + 1], rMax[3 * i + 2] });
    for (int k = 0; k < 3; ++k)
    {
      rInv[3 * i + k] = (m * L > 1e-8) ? 1.0 / m : 0.0;
    }
  }
  this->UpdateProgress(0.5);

  // ---- Pass 2: W^k per cell (Boolean sum over variables), and its maximum.
  st.Wk.assign(3 * static_cast<size_t>(ncells), 0.0f);
  vtkSMPThreadLocal<double> localWMax(0.0);
  vtkSMPTools::For(0, ncells, [&](vtkIdType b, vtkIdType e) {
    if (aborted || vtkARMeshKernels::Aborted(this))
    {
      aborted = true;
      return;
    }
    double& wmax = localWMax.Local();
    std::vector<double> r(3 * st.NumberOfColumns);
    for (vtkIdType c = b; c < e; ++c)
    {
      if (!normalizedGradients(c, r.data()))
      {
        continue;
      }
      double w[3] = { 0.0, 0.0, 0.0 };
      for (int i = 0; i < st.NumberOfColumns; ++i)
      {
        for (int k = 0; k < 3; ++k)
        {
          w[k] = BooleanSum(w[k], std::min(1.0, r[3 * i + k] * rInv[3 * i + k]));
        }
      }
      for (int k = 0; k < 3; ++k)
      {
        st.Wk[3 * static_cast<size_t>(c) + k] = static_cast<float>(w[k]);
        if (mesh.IsOwnedCell(c))
        {
          wmax = std::max(wmax, w[k]);
        }
      }
    }
  });
  st.WMax = 0.0;
  for (double m : localWMax)
  {
    st.WMax = std::max(st.WMax, m);
  }
  vtkARParallel::AllReduceMax(&st.WMax, 1);
  abortFlag = aborted ? 1.0 : 0.0;
  vtkARParallel::AllReduceMax(&abortFlag, 1);
  if (abortFlag > 0.0)
  {
    output->ShallowCopy(input);
    return false;
  }
  this->UpdateProgress(0.8);
  return true;
}

//------------------------------------------------------------------------------
void vtkWeightFunction::WriteWeights(Execution& run, WeightState& st)
{
  vtkUnstructuredGrid* output = run.Output;
  vtkARMeshKernels::MeshView& mesh = run.Mesh;
  const vtkIdType npts = run.Mesh.NumberOfPoints;
  const vtkIdType ncells = run.Mesh.NumberOfCells;

  // ---- Pass 3: W = 1 + Boolean sum over directions of W^k / max.
  vtkNew<vtkDoubleArray> result;
  result->SetName(this->ResultArrayName.c_str());
  result->SetNumberOfTuples(ncells);
  double* out = result->GetPointer(0);
  const double wInv = st.WMax > 0.0 ? 1.0 / st.WMax : 0.0;
  vtkSMPTools::For(0, ncells, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType c = b; c < e; ++c)
    {
      double s = 0.0;
      for (int k = 0; k < 3; ++k)
      {
        s = BooleanSum(s, std::min(1.0, st.Wk[3 * static_cast<size_t>(c) + k] * wInv));
      }
      out[c] = 1.0 + s;
    }
  });
  output->GetCellData()->AddArray(result);
  vtkNew<vtkStringArray> used; // the variables W was computed from (chosen or automatic)
  used->SetName("VariablesUsed");
  for (const Variable& v : st.Variables)
  {
    used->InsertNextValue(v.Array->GetName());
  }
  output->GetFieldData()->AddArray(used);

  if (this->ComputePointWeight)
  {
    std::vector<double> pointW;
    const bool ok = vtkARMeshKernels::CellsToPoints(
      mesh, 1,
      [&](vtkIdType c, double* values, double& weight) {
        double W[vtkARMeshKernels::MaxCellPoints][3];
        int n;
        if (!mesh.IsVolumeCell(c) || !vtkARMeshKernels::GradientOperator(mesh, c, W, n, weight))
        {
          return false;
        }
        values[0] = out[c];
        return true;
      },
      pointW, this);
    if (ok)
    {
      vtkNew<vtkDoubleArray> pointResult;
      pointResult->SetName(this->ResultArrayName.c_str());
      pointResult->SetNumberOfTuples(npts);
      double* pw = pointResult->GetPointer(0);
      vtkSMPTools::For(0, npts, [&](vtkIdType b, vtkIdType e) {
        for (vtkIdType p = b; p < e; ++p)
        {
          // Points reached by no 3-D cell keep the neutral value 1.
          pw[p] = pointW[p] > 0.0 ? pointW[p] : 1.0;
        }
      });
      output->GetPointData()->AddArray(pointResult);
    }
  }
}

//------------------------------------------------------------------------------
void vtkWeightFunction::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Variables:";
  for (int i = 0; i < this->VariableSelection->GetNumberOfArrays(); ++i)
  {
    if (this->VariableSelection->GetArraySetting(i))
    {
      os << " " << this->VariableSelection->GetArrayName(i);
    }
  }
  os << "\n";
  os << indent << "Epsilon: " << this->Epsilon << "\n";
  os << indent << "ResultArrayName: " << this->ResultArrayName << "\n";
  os << indent << "ComputePointWeight: " << this->ComputePointWeight << "\n";
}
