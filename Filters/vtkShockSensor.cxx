// SPDX-License-Identifier: BSD-3-Clause
#include "vtkShockSensor.h"

#include "vtkARInputChecks.h"
#include "vtkARVolumeFilterExecution.h"
#include "vtkARMeshKernels.h"
#include "vtkARParallel.h"
#include "vtkCellData.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkShockSensor);

namespace
{
// Column layout of the 5-column state table: a 3-vector then two scalars.
struct Slot
{
  int Index;          // SetInputArrayToProcess index
  const char* Role;   // for messages
  int Components;     // 3 or 1
  int Column;         // first column in the table
  bool MustBePositive;
};

const char* ArrayName(vtkAlgorithm* self, int idx)
{
  vtkInformation* info = self->GetInputArrayInformation(idx);
  return (info && info->Has(vtkDataObject::FIELD_NAME())) ? info->Get(vtkDataObject::FIELD_NAME())
                                                          : "(none)";
}

const char* const RoleNames[6] = { "Velocity", "Pressure", "Density", "Temperature", "Momentum",
  "TotalEnergy" };
const int RoleComponents[6] = { 3, 1, 1, 1, 3, 1 };

/// Columns of the point state table: a 3-vector then two scalars.
constexpr int NC = 5;

/// Relative range of p, (max - min) / mean over a cell's points, below
/// which p is uniform (a free stream): grad p there is round-off.
constexpr double FlatPressure = 1e-5;

std::string Lower(const char* s)
{
  std::string out(s ? s : "");
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return std::tolower(c); });
  return out;
}

/// "one of a, b, c" for messages.
std::string NameList(int idx)
{
  std::string out;
  for (const char* const* n = vtkShockSensor::KnownArrayNames(idx); *n; ++n)
  {
    out += (out.empty() ? "" : ", ") + std::string(*n);
  }
  return out;
}
}

//------------------------------------------------------------------------------
const char* const* vtkShockSensor::KnownArrayNames(int idx)
{
  // OpenFOAM first (U, p, rho, T, and the rhoU/rhoE our converters add), then
  // SU2 (Velocity, Pressure, Density, Temperature, Momentum, Energy = rho E),
  // CGNS as ParaView's CGNS reader groups it (Velocity, Pressure, Density,
  // Temperature, Momentum, EnergyStagnationDensity), Fluent's exports
  // (velocity, pressure / absolute-pressure, density, temperature).
  static const char* const velocity[] = { "U", "Velocity", "Vel", "V", "velocity_vector", nullptr };
  static const char* const pressure[] = { "p", "Pressure", "StaticPressure", "static_pressure",
    "absolute-pressure", "absolute_pressure", "AbsolutePressure", nullptr };
  static const char* const density[] = { "rho", "Density", "Rho", nullptr };
  static const char* const temperature[] = { "T", "Temperature", "StaticTemperature", "static_temperature",
    nullptr };
  static const char* const momentum[] = { "rhoU", "Momentum", "rhoV", "rho_u", nullptr };
  static const char* const energy[] = { "rhoE", "Energy", "EnergyStagnationDensity", "TotalEnergy",
    "total_energy", "rho_E", nullptr };
  static const char* const none[] = { nullptr };
  switch (idx)
  {
    case VELOCITY:
      return velocity;
    case PRESSURE:
      return pressure;
    case DENSITY:
      return density;
    case TEMPERATURE:
      return temperature;
    case MOMENTUM:
      return momentum;
    case TOTAL_ENERGY:
      return energy;
    default:
      return none;
  }
}

//------------------------------------------------------------------------------
vtkDataArray* vtkShockSensor::ResolveArray(
  int idx, int components, vtkDataSet* input, int& association, bool& automatic)
{
  association = -1;
  vtkInformation* info = this->GetInputArrayInformation(idx);
  const char* name =
    (info && info->Has(vtkDataObject::FIELD_NAME())) ? info->Get(vtkDataObject::FIELD_NAME()) : nullptr;
  automatic = !name || !*name || std::string(name) == AutomaticArrayName;
  if (!automatic)
  {
    return this->GetInputArrayToProcess(idx, input, association);
  }
  return FindKnownArray(idx, components, input, association);
}

//------------------------------------------------------------------------------
vtkDataArray* vtkShockSensor::FindKnownArray(int idx, int components, vtkDataSet* input, int& association)
{
  association = -1;
  const int where[2] = { vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataObject::FIELD_ASSOCIATION_CELLS };
  for (const char* const* n = KnownArrayNames(idx); input && *n; ++n)
  {
    const std::string want = Lower(*n);
    for (int w = 0; w < 2; ++w)
    {
      vtkDataSetAttributes* data = w == 0 ? static_cast<vtkDataSetAttributes*>(input->GetPointData())
                                          : static_cast<vtkDataSetAttributes*>(input->GetCellData());
      for (int a = 0; a < data->GetNumberOfArrays(); ++a)
      {
        vtkDataArray* array = data->GetArray(a);
        if (array && array->GetName() && Lower(array->GetName()) == want &&
          array->GetNumberOfComponents() == components)
        {
          association = where[w];
          return array;
        }
      }
    }
  }
  return nullptr;
}

//------------------------------------------------------------------------------
vtkShockSensor::vtkShockSensor()
  : vtkARVolumeFilter("the shock sensor")
{
  // Every array found by its usual names unless the user names it.
  for (int i = 0; i < 6; ++i)
  {
    this->SetInputArrayToProcess(i, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, AutomaticArrayName);
  }
}

//------------------------------------------------------------------------------
//------------------------------------------------------------------------------
/// The state of one execution, shared by the passes of Execute.
struct vtkShockSensor::FlowState
{
  vtkDataArray* Found[6] = { nullptr, nullptr, nullptr, nullptr, nullptr, nullptr };
  int FoundAssociation[6] = { -1, -1, -1, -1, -1, -1 };
  bool FoundAutomatically[6] = { false, false, false, false, false, false };
  int Set = AUTOMATIC;
  bool SetFound = true; ///< false: the set's problem is reported already, its arrays are not read
  Slot Slots[3];
  std::vector<double> State;     ///< NC columns at the points: V (or rho V), then two scalars
  std::vector<double> CellState; ///< the cell arrays' columns, before averaging to the points
  std::vector<int> CellColumns;
  double R = 0.0;
  std::vector<double> GradP;
  std::vector<double> RawMach;   ///< Mn before masking
  std::vector<double> PointInfo; ///< |grad p|, V.grad p, Mach
  double GradMax = 0.0;
  vtkNew<vtkDoubleArray> NormalMach;
  std::vector<double> LocalPeak;
  std::vector<double> CellRange;
  vtkNew<vtkUnsignedCharArray> ShockCells;
};

int vtkShockSensor::Execute(Execution& run)
{
  // The passes below share the state of this execution (FlowState); every
  // rank reaches the same collective calls, in order.
  FlowState st;
  vtkUnstructuredGrid* output = run.Output;
  std::ostringstream& problem = run.Problem;
  vtkARMeshKernels::MeshView& mesh = run.Mesh;

  problem << vtkARInputChecks::Properties()
               .InRange("PressureGradientThreshold", this->PressureGradientThreshold, 0.0, 1.0,
                 "a fraction of the largest |grad p|")
               .InRange("LocalPeakFraction", this->LocalPeakFraction, 0.0, 1.0, "a fraction of the local peak; 0 off")
               .Message();
  if (!(this->Gamma > 1.0))
  {
    problem << "Gamma must be greater than 1 (it is " << this->Gamma << "). ";
  }
  if (!(this->GasConstant >= 0.0) || !std::isfinite(this->GasConstant))
  {
    problem << "GasConstant is " << this->GasConstant
            << "; it must be positive (J/(kg K), 287.05 for air), or 0 to take it from the data. ";
  }

  this->ResolveFlowState(run, st);
  this->ReadFlowState(run, st);
  this->ResolveGasConstant(run, st);
  if (!this->Proceed(run))
  {
    return 1;
  }

  if (!st.CellColumns.empty() &&
    !vtkARMeshKernels::CellColumnsToPoints(
      mesh, st.CellState.data(), NC, st.CellColumns, st.State.data(), NC, st.CellColumns, this))
  {
    return 1;
  }

  if (!this->ToPrimitiveState(run, st))
  {
    return 1;
  }
  if (!this->PressureGradient(run, st))
  {
    return 1;
  }
  this->PointQuantities(run, st);
  this->LocalPeaks(run, st);
  this->MarkShockCells(run, st);

  output->GetPointData()->AddArray(st.NormalMach);
  output->GetCellData()->AddArray(st.ShockCells);
  // What was read: the arrays of the set, the set, and R with temperature.
  vtkNew<vtkStringArray> used;
  used->SetName("FlowStateArrays");
  for (const Slot& s : st.Slots)
  {
    used->InsertNextValue(st.Found[s.Index]->GetName());
  }
  output->GetFieldData()->AddArray(used);
  double setUsed = st.Set;
  output->GetFieldData()->AddArray(vtkARMeshKernels::FieldArray("VariableSetUsed", &setUsed, 1));
  if (st.Set == VELOCITY_PRESSURE_TEMPERATURE)
  {
    output->GetFieldData()->AddArray(vtkARMeshKernels::FieldArray("GasConstantUsed", &st.R, 1));
  }
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkShockSensor::ResolveFlowState(Execution& run, FlowState& st)
{
  vtkUnstructuredGrid* input = run.Input;
  std::ostringstream& problem = run.Problem;
  const vtkIdType ncells = run.Mesh.NumberOfCells;

  // ---- The arrays: named, or found by their usual names; the set.
  for (int i = 0; i < 6; ++i)
  {
    st.Found[i] = this->ResolveArray(i, RoleComponents[i], input, st.FoundAssociation[i], st.FoundAutomatically[i]);
  }
  st.Set = this->VariableSet;
  st.SetFound = true; // false: the set's problem is reported already, its arrays are not read
  if (st.Set < VELOCITY_PRESSURE_DENSITY || st.Set > AUTOMATIC)
  {
    problem << "VariableSet is " << st.Set
            << "; it must be 0 (velocity, pressure, density), 1 (velocity, pressure, temperature), 2 "
               "(conserved) or 3 (automatic). ";
    st.Set = VELOCITY_PRESSURE_DENSITY;
    st.SetFound = false;
  }
  else if (ncells == 0)
  {
    st.SetFound = false; // the mesh's problem is reported; no array is read
    st.Set = VELOCITY_PRESSURE_DENSITY;
  }
  else if (st.Set == AUTOMATIC)
  {
    // The first complete set that holds every array the user named (a
    // named array is never ignored in favour of another set).
    const int members[3][3] = { { VELOCITY, PRESSURE, DENSITY }, { VELOCITY, PRESSURE, TEMPERATURE },
      { DENSITY, MOMENTUM, TOTAL_ENERGY } };
    bool namedMissing = false;
    for (int i = 0; i < 6; ++i)
    {
      if (!st.FoundAutomatically[i] && !st.Found[i])
      {
        problem << "The " << RoleNames[i] << " array '" << ArrayName(this, i)
                << "' is not a point or cell array of the input. ";
        namedMissing = true;
      }
    }
    for (int candidate = 0; candidate < 3 && st.Set == AUTOMATIC; ++candidate)
    {
      bool eligible = true;
      for (int k = 0; k < 3; ++k)
      {
        eligible = eligible && st.Found[members[candidate][k]];
      }
      for (int i = 0; i < 6 && eligible; ++i)
      {
        const int* m = members[candidate];
        eligible = st.FoundAutomatically[i] || i == m[0] || i == m[1] || i == m[2];
      }
      if (eligible)
      {
        st.Set = candidate;
      }
    }
    if (st.Set == AUTOMATIC && namedMissing)
    {
      st.Set = VELOCITY_PRESSURE_DENSITY;
      st.SetFound = false;
    }
    else if (st.Set == AUTOMATIC)
    {
      problem << "No complete flow state among the input's arrays. The sensor needs a velocity ("
              << RoleNames[VELOCITY] << ": " << NameList(VELOCITY) << ") and a pressure (" << NameList(PRESSURE)
              << ") with a density (" << NameList(DENSITY) << ") or a temperature ("
              << NameList(TEMPERATURE) << "), or the conserved density, momentum (" << NameList(MOMENTUM)
              << ") and total energy (" << NameList(TOTAL_ENERGY) << "). Found:";
      for (int i = 0; i < 6; ++i)
      {
        problem << " " << RoleNames[i] << " " << (st.Found[i] ? st.Found[i]->GetName() : "-");
      }
      problem << ". Pick the arrays and the VariableSet. ";
      st.Set = VELOCITY_PRESSURE_DENSITY;
      st.SetFound = false;
    }
  }

  switch (st.Set)
  {
    case VELOCITY_PRESSURE_TEMPERATURE:
      st.Slots[0] = { VELOCITY, "Velocity", 3, 0, false };
      st.Slots[1] = { PRESSURE, "Pressure", 1, 3, true };
      st.Slots[2] = { TEMPERATURE, "Temperature", 1, 4, true };
      break;
    case CONSERVED:
      st.Slots[0] = { MOMENTUM, "Momentum", 3, 0, false };
      st.Slots[1] = { DENSITY, "Density", 1, 3, true };
      st.Slots[2] = { TOTAL_ENERGY, "TotalEnergy", 1, 4, false };
      break;
    default:
      st.Slots[0] = { VELOCITY, "Velocity", 3, 0, false };
      st.Slots[1] = { PRESSURE, "Pressure", 1, 3, true };
      st.Slots[2] = { DENSITY, "Density", 1, 4, true };
  }
}

//------------------------------------------------------------------------------
void vtkShockSensor::ReadFlowState(Execution& run, FlowState& st)
{
  std::ostringstream& problem = run.Problem;
  const vtkIdType npts = run.Mesh.NumberOfPoints;
  const vtkIdType ncells = run.Mesh.NumberOfCells;

  // The raw state, 5 columns at the points; cell arrays go through a cell
  // table and are averaged to the points.
  st.State.assign(static_cast<size_t>(npts) * NC, 0.0);
  if (ncells > 0 && st.SetFound)
  {
    for (const Slot& s : st.Slots)
    {
      const int association = st.FoundAssociation[s.Index];
      vtkDataArray* array = st.Found[s.Index];
      if (!array)
      {
        if (st.FoundAutomatically[s.Index])
        {
          problem << "No " << s.Role << " array: none of " << NameList(s.Index) << " is a "
                  << s.Components << "-component point or cell array of the input; pick it. ";
        }
        else
        {
          problem << "The " << s.Role << " array '" << ArrayName(this, s.Index)
                  << "' is not a point or cell array of the input. ";
        }
        continue;
      }
      if (array->GetNumberOfComponents() != s.Components)
      {
        problem << "The " << s.Role << " array '" << array->GetName() << "' has "
                << array->GetNumberOfComponents() << " components; it needs " << s.Components
                << ". ";
        continue;
      }
      const bool onPoints = association == vtkDataObject::FIELD_ASSOCIATION_POINTS;
      double* table = st.State.data();
      int column = s.Column;
      int stride = NC;
      if (!onPoints)
      {
        st.CellState.resize(static_cast<size_t>(ncells) * NC, 0.0);
        table = st.CellState.data();
        for (int k = 0; k < s.Components; ++k)
        {
          st.CellColumns.push_back(s.Column + k);
        }
      }
      const vtkIdType bad = vtkARMeshKernels::PackComponents(array, table, stride, column);
      if (bad >= 0)
      {
        problem << "The " << s.Role << " array '" << array->GetName() << "' holds NaN or Inf ("
                << (onPoints ? "point " : "cell ") << bad << "). ";
        continue;
      }
      if (s.MustBePositive)
      {
        const vtkIdType n = onPoints ? npts : ncells;
        for (vtkIdType i = 0; i < n; ++i)
        {
          const double v = table[static_cast<size_t>(i) * stride + column];
          if (!(v > 0.0))
          {
            problem << "The " << s.Role << " array '" << array->GetName() << "' is " << v
                    << " at " << (onPoints ? "point " : "cell ") << i
                    << ": it must be positive everywhere. ";
            break;
          }
        }
      }
    }
  }
}

//------------------------------------------------------------------------------
void vtkShockSensor::ResolveGasConstant(Execution& run, FlowState& st)
{
  vtkUnstructuredGrid* input = run.Input;
  std::ostringstream& problem = run.Problem;

  // ---- The gas constant with temperature: from the data's p / (rho T)
  // where a density is present too (the median: point data averaged across
  // a shock scatter by a few per cent), else the field data's GasConstant.
  st.R = this->GasConstant;
  if (st.Set == VELOCITY_PRESSURE_TEMPERATURE)
  {
    double fromData = 0.0;
    vtkDataArray* p = st.Found[PRESSURE];
    vtkDataArray* rho = st.Found[DENSITY];
    vtkDataArray* T = st.Found[TEMPERATURE];
    if (p && rho && T && st.FoundAssociation[PRESSURE] == st.FoundAssociation[DENSITY] &&
      st.FoundAssociation[PRESSURE] == st.FoundAssociation[TEMPERATURE] &&
      p->GetNumberOfTuples() == rho->GetNumberOfTuples() && p->GetNumberOfTuples() == T->GetNumberOfTuples())
    {
      std::vector<double> ratio;
      ratio.reserve(static_cast<std::size_t>(p->GetNumberOfTuples()));
      for (vtkIdType i = 0; i < p->GetNumberOfTuples(); ++i)
      {
        const double r = p->GetComponent(i, 0) / (rho->GetComponent(i, 0) * T->GetComponent(i, 0));
        if (r > 0.0 && std::isfinite(r))
        {
          ratio.push_back(r);
        }
      }
      if (!ratio.empty())
      {
        std::nth_element(ratio.begin(), ratio.begin() + ratio.size() / 2, ratio.end());
        fromData = ratio[ratio.size() / 2];
      }
    }
    // The same on every rank (each rank's median, the largest: documented
    // as the one reduction here that is not the serial run's bit for bit).
    vtkARParallel::AllReduceMax(&fromData, 1);
    vtkDataArray* field = input->GetFieldData() ? input->GetFieldData()->GetArray("GasConstant") : nullptr;
    const double fromField = field && field->GetNumberOfTuples() > 0 ? field->GetComponent(0, 0) : 0.0;
    if (fromData > 0.0)
    {
      if (st.R <= 0.0)
      {
        st.R = fromData;
      }
      else if (std::abs(st.R / fromData - 1.0) > 0.02)
      {
        problem << "GasConstant is " << st.R << ", but the data's p / (rho T) is " << fromData
                << " (the median over the " << (st.FoundAssociation[PRESSURE] == vtkDataObject::FIELD_ASSOCIATION_POINTS ? "points" : "cells")
                << "): the arrays are not in the units of that R (non-dimensional data?). Set GasConstant to 0 "
                   "to take it from the data. ";
      }
    }
    else if (st.R <= 0.0)
    {
      if (fromField > 0.0 && std::isfinite(fromField))
      {
        st.R = fromField;
      }
      else
      {
        problem << "GasConstant is 0 (take it from the data), but the input has no density array to "
                   "compute p / (rho T) from, nor a GasConstant in its field data: set GasConstant "
                   "(J/(kg K); 287.05 for air). ";
      }
    }
  }
}

//------------------------------------------------------------------------------
bool vtkShockSensor::ToPrimitiveState(Execution& run, FlowState& st)
{
  vtkARMeshKernels::MeshView& mesh = run.Mesh;
  const vtkIdType npts = run.Mesh.NumberOfPoints;
  const double gamma = this->Gamma;

  // ---- Primitive state at the points: V (3), p, rho.
  std::atomic<vtkIdType> badPressure(-1);
  vtkSMPTools::For(0, npts, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType p = b; p < e; ++p)
    {
      double* s = &st.State[static_cast<size_t>(p) * NC];
      if (st.Set == VELOCITY_PRESSURE_TEMPERATURE)
      {
        s[4] = s[3] / (st.R * s[4]); // rho = p / (R T)
      }
      else if (st.Set == CONSERVED)
      {
        const double rho = s[3], rhoE = s[4];
        const double m2 = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
        const double pressure = (gamma - 1.0) * (rhoE - 0.5 * m2 / rho);
        s[0] /= rho;
        s[1] /= rho;
        s[2] /= rho;
        s[3] = pressure;
        s[4] = rho;
        if (!(pressure > 0.0) && mesh.IsOwnedPoint(p))
        {
          vtkIdType expected = -1;
          badPressure.compare_exchange_strong(expected, p);
        }
      }
    }
  });
  double derivedBad = badPressure >= 0 ? 1.0 : 0.0;
  vtkARParallel::AllReduceMax(&derivedBad, 1);
  if (badPressure >= 0)
  {
    vtkErrorMacro(<< "The pressure derived from the conserved variables, (Gamma - 1)(rhoE - "
                     "|rhoU|^2 / (2 rho)), is not positive at point "
                  << badPressure.load()
                  << ": check the TotalEnergy array (energy per unit volume) and Gamma. The "
                     "output is the input, unchanged.");
  }
  if (derivedBad > 0.0)
  {
    return false;
  }
  this->UpdateProgress(0.3);
  if (this->Cancelled())
  {
    return 1; // cancelled (collective work under MPI runs to its end)
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkShockSensor::PressureGradient(Execution& run, FlowState& st)
{
  vtkARMeshKernels::MeshView& mesh = run.Mesh;

  // ---- grad p at the points: weighted average of the cell gradients.
  const bool ok = vtkARMeshKernels::CellsToPoints(
    mesh, 3,
    [&](vtkIdType c, double* g, double& weight) {
      double W[vtkARMeshKernels::MaxCellPoints][3];
      int n;
      if (!mesh.IsVolumeCell(c) || !vtkARMeshKernels::GradientOperator(mesh, c, W, n, weight))
      {
        return false;
      }
      const vtkIdType* ids = mesh.CellPoints(c);
      g[0] = g[1] = g[2] = 0.0;
      for (int a = 0; a < n; ++a)
      {
        const double pa = st.State[static_cast<size_t>(ids[a]) * NC + 3];
        g[0] += W[a][0] * pa;
        g[1] += W[a][1] * pa;
        g[2] += W[a][2] * pa;
      }
      return true;
    },
    st.GradP, this);
  double abortFlag = ok ? 0.0 : 1.0;
  vtkARParallel::AllReduceMax(&abortFlag, 1);
  if (abortFlag > 0.0)
  {
    return false;
  }
  this->UpdateProgress(0.7);
  if (this->Cancelled())
  {
    return 1; // cancelled (collective work under MPI runs to its end)
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkShockSensor::PointQuantities(Execution& run, FlowState& st)
{
  vtkARMeshKernels::MeshView& mesh = run.Mesh;
  const vtkIdType npts = run.Mesh.NumberOfPoints;
  const double gamma = this->Gamma;

  // ---- Point quantities: Mn, |grad p|, V.grad p, local Mach.
  st.RawMach.assign(npts, 0.0);
  double* mn = st.RawMach.data();
  st.PointInfo.assign(3 * static_cast<size_t>(npts), 0.0); // |grad p|, V.grad p, Mach
  vtkSMPThreadLocal<double> localMax(0.0);
  vtkSMPTools::For(0, npts, [&](vtkIdType b, vtkIdType e) {
    double& gmax = localMax.Local();
    for (vtkIdType p = b; p < e; ++p)
    {
      const double* s = &st.State[static_cast<size_t>(p) * NC];
      const double* g = &st.GradP[3 * static_cast<size_t>(p)];
      const double a = std::sqrt(gamma * s[3] / s[4]);
      const double gmag = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
      const double vg = s[0] * g[0] + s[1] * g[1] + s[2] * g[2];
      mn[p] = gmag > 0.0 ? vg / (a * gmag) : 0.0;
      double* info = &st.PointInfo[3 * static_cast<size_t>(p)];
      info[0] = gmag;
      info[1] = vg;
      info[2] = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]) / a;
      if (mesh.IsOwnedPoint(p))
      {
        gmax = std::max(gmax, gmag);
      }
    }
  });
  st.GradMax = 0.0;
  for (double m : localMax)
  {
    st.GradMax = std::max(st.GradMax, m);
  }
  vtkARParallel::AllReduceMax(&st.GradMax, 1);

  // The output Mn is 0 where |grad p| is below the threshold: there the
  // direction of grad p, and Mn with it, is noise (round-off in a uniform
  // stream), which would only clutter contours and clusters of NormalMach.
  st.NormalMach->SetName("NormalMach");
  st.NormalMach->SetNumberOfTuples(npts);
  vtkARParallel::AdviseHugePages(st.NormalMach);
  {
    double* outMn = st.NormalMach->GetPointer(0);
    const double limit = this->PressureGradientThreshold * st.GradMax;
    vtkSMPTools::For(0, npts, [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType p = b; p < e; ++p)
      {
        outMn[p] = st.PointInfo[3 * static_cast<size_t>(p)] >= limit ? mn[p] : 0.0;
      }
    });
  }
}

//------------------------------------------------------------------------------
void vtkShockSensor::LocalPeaks(Execution& run, FlowState& st)
{
  vtkARMeshKernels::MeshView& mesh = run.Mesh;
  const vtkIdType npts = run.Mesh.NumberOfPoints;
  const vtkIdType ncells = run.Mesh.NumberOfCells;

  // ---- Local peak of |grad p|: at each point, the largest |grad p| over
  // the points of the cells around it (its two-ring); and whether p varies
  // at all there: the largest relative range of p, (max - min) / mean over a
  // cell's points, of the cells around the point. Where p is uniform to
  // FlatPressure (a free stream) grad p is round-off, its direction and Mn
  // are noise at any threshold relative to the (round-off) maximum: those
  // points get Mn = 0 and their cells are never shock cells.
  st.LocalPeak.assign(npts, 0.0);
  std::vector<double> localRange(npts, 0.0);
  st.CellRange.assign(static_cast<size_t>(ncells), 0.0);
  {
    vtkSMPThreadLocal<std::vector<double>> partial, partialRange;
    vtkSMPTools::For(0, ncells, [&](vtkIdType b, vtkIdType e) {
      std::vector<double>& mx = partial.Local();
      std::vector<double>& rx = partialRange.Local();
      if (mx.empty())
      {
        mx.assign(npts, 0.0);
        rx.assign(npts, 0.0);
      }
      for (vtkIdType c = b; c < e; ++c)
      {
        if (!mesh.IsVolumeCell(c))
        {
          continue;
        }
        const vtkIdType* ids = mesh.CellPoints(c);
        const int n = mesh.CellSize(c);
        double cmax = 0.0, plo = VTK_DOUBLE_MAX, phi = -VTK_DOUBLE_MAX, psum = 0.0;
        for (int a = 0; a < n; ++a)
        {
          cmax = std::max(cmax, st.PointInfo[3 * static_cast<size_t>(ids[a])]);
          const double pa = st.State[static_cast<size_t>(ids[a]) * NC + 3];
          plo = std::min(plo, pa);
          phi = std::max(phi, pa);
          psum += pa;
        }
        const double range = psum > 0.0 ? (phi - plo) * n / psum : 0.0;
        st.CellRange[c] = range;
        for (int a = 0; a < n; ++a)
        {
          mx[ids[a]] = std::max(mx[ids[a]], cmax);
          rx[ids[a]] = std::max(rx[ids[a]], range);
        }
      }
    });
    for (const std::vector<double>& mx : partial)
    {
      for (vtkIdType p = 0; p < static_cast<vtkIdType>(mx.size()); ++p)
      {
        st.LocalPeak[p] = std::max(st.LocalPeak[p], mx[p]);
      }
    }
    for (const std::vector<double>& rx : partialRange)
    {
      for (vtkIdType p = 0; p < static_cast<vtkIdType>(rx.size()); ++p)
      {
        localRange[p] = std::max(localRange[p], rx[p]);
      }
    }
  }
  {
    double* outMn = st.NormalMach->GetPointer(0);
    for (vtkIdType p = 0; p < npts; ++p)
    {
      if (localRange[p] < FlatPressure)
      {
        outMn[p] = 0.0;
      }
    }
  }
}

//------------------------------------------------------------------------------
void vtkShockSensor::MarkShockCells(Execution& run, FlowState& st)
{
  vtkARMeshKernels::MeshView& mesh = run.Mesh;
  const vtkIdType ncells = run.Mesh.NumberOfCells;
  double* mn = st.RawMach.data();

  // ---- Shock cells: Mn = 1 crosses the cell, and the noise filters pass.
  st.ShockCells->SetName("ShockCells");
  st.ShockCells->SetNumberOfTuples(ncells);
  vtkARParallel::AdviseHugePages(st.ShockCells);
  unsigned char* sc = st.ShockCells->GetPointer(0);
  const double gradLimit = this->PressureGradientThreshold * st.GradMax;
  const bool compressionOnly = this->CompressionOnly;
  const double localFraction = this->LocalPeakFraction;
  const double machLo = this->UpstreamMachRange[0];
  const double machHi = this->UpstreamMachRange[1];
  vtkSMPTools::For(0, ncells, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType c = b; c < e; ++c)
    {
      sc[c] = 0;
      if (!mesh.IsVolumeCell(c) || mesh.CellSize(c) > vtkARMeshKernels::MaxCellPoints)
      {
        continue;
      }
      const vtkIdType* ids = mesh.CellPoints(c);
      const int n = mesh.CellSize(c);
      double lo = mn[ids[0]], hi = lo, gsum = 0.0, vgsum = 0.0, machMax = 0.0, peak = 0.0;
      for (int a = 0; a < n; ++a)
      {
        const double m = mn[ids[a]];
        lo = std::min(lo, m);
        hi = std::max(hi, m);
        const double* info = &st.PointInfo[3 * static_cast<size_t>(ids[a])];
        gsum += info[0];
        vgsum += info[1];
        machMax = std::max(machMax, info[2]);
        peak = std::max(peak, st.LocalPeak[ids[a]]);
      }
      const bool crossed = (lo < 1.0 && hi >= 1.0) || (lo <= 1.0 && hi > 1.0);
      const bool strong = gsum / n >= gradLimit && gsum / n >= localFraction * peak && gsum > 0.0 &&
        st.CellRange[c] >= FlatPressure;
      const bool compression = !compressionOnly || vgsum > 0.0;
      const bool upstream = machMax >= machLo && machMax <= machHi;
      if (!(crossed && strong && compression && upstream))
      {
        continue;
      }
      // Through a shock the normal Mach number falls as the pressure rises:
      // grad(Mn) . grad(p) < 0 in the cell. A crossing of Mn = 1 made by
      // noise in the direction of a weak grad p has no such order.
      double W[vtkARMeshKernels::MaxCellPoints][3];
      int nw;
      double measure;
      if (!vtkARMeshKernels::GradientOperator(mesh, c, W, nw, measure))
      {
        continue;
      }
      double gm[3] = { 0.0, 0.0, 0.0 }, gp[3] = { 0.0, 0.0, 0.0 };
      for (int a = 0; a < nw; ++a)
      {
        const double m = mn[ids[a]];
        const double pa = st.State[static_cast<size_t>(ids[a]) * NC + 3];
        for (int k = 0; k < 3; ++k)
        {
          gm[k] += W[a][k] * m;
          gp[k] += W[a][k] * pa;
        }
      }
      sc[c] = (gm[0] * gp[0] + gm[1] * gp[1] + gm[2] * gp[2] < 0.0) ? 1 : 0;
    }
  });
}

//------------------------------------------------------------------------------
void vtkShockSensor::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "VariableSet: " << this->VariableSet << "\n";
  os << indent << "Gamma: " << this->Gamma << "\n";
  os << indent << "GasConstant: " << this->GasConstant << "\n";
  os << indent << "PressureGradientThreshold: " << this->PressureGradientThreshold << "\n";
  os << indent << "LocalPeakFraction: " << this->LocalPeakFraction << "\n";
  os << indent << "CompressionOnly: " << this->CompressionOnly << "\n";
  os << indent << "UpstreamMachRange: " << this->UpstreamMachRange[0] << " "
     << this->UpstreamMachRange[1] << "\n";
}
