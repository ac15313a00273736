// C++ tests of vtkWeightFunction and vtkShockSensor on small meshes whose
// answers are known exactly: linear fields on every linear 3-D cell type, the
// definition of W on fields whose normalized gradients are known in closed
// form, and every kind of bad input.
#include "vtkShockSensor.h"
#include "vtkWeightFunction.h"

#include "vtkCallbackCommand.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkCommand.h"
#include "vtkDataArraySelection.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

namespace
{
/// Collects the error and warning messages of an algorithm.
struct Messages
{
  std::string Errors, Warnings;
  vtkNew<vtkCallbackCommand> Callback;
  explicit Messages(vtkObject* obj)
  {
    this->Callback->SetClientData(this);
    this->Callback->SetCallback([](vtkObject*, unsigned long event, void* cd, void* msg) {
      auto* self = static_cast<Messages*>(cd);
      (event == vtkCommand::ErrorEvent ? self->Errors : self->Warnings) += static_cast<char*>(msg);
    });
    obj->AddObserver(vtkCommand::ErrorEvent, this->Callback);
    obj->AddObserver(vtkCommand::WarningEvent, this->Callback);
  }
};

/// An n x n x n grid of the unit cube cut into cells of the given type
/// (hexahedra, wedges (2 per hex), pyramids (6 per hex, with a centre point),
/// tetrahedra (6 per hex) or polyhedra (hexahedral polyhedra)).
vtkSmartPointer<vtkUnstructuredGrid> MakeGrid(int n, int cellType)
{
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  const double h = 1.0 / n;
  auto id = [n](int i, int j, int k) { return static_cast<vtkIdType>(i + (n + 1) * (j + (n + 1) * k)); };
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        pts->InsertNextPoint(i * h, j * h, k * h);
  grid->SetPoints(pts);
  grid->Allocate();
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        const vtkIdType v[8] = { id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k),
          id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1) };
        if (cellType == VTK_HEXAHEDRON)
        {
          grid->InsertNextCell(VTK_HEXAHEDRON, 8, v);
        }
        else if (cellType == VTK_WEDGE)
        {
          const vtkIdType w0[6] = { v[0], v[1], v[3], v[4], v[5], v[7] };
          const vtkIdType w1[6] = { v[1], v[2], v[3], v[5], v[6], v[7] };
          grid->InsertNextCell(VTK_WEDGE, 6, w0);
          grid->InsertNextCell(VTK_WEDGE, 6, w1);
        }
        else if (cellType == VTK_TETRA)
        {
          // Six tetrahedra around the diagonal v0-v6.
          const int t[6][4] = { { 0, 1, 2, 6 }, { 0, 2, 3, 6 }, { 0, 3, 7, 6 }, { 0, 7, 4, 6 },
            { 0, 4, 5, 6 }, { 0, 5, 1, 6 } };
          for (const auto& tt : t)
          {
            const vtkIdType ids[4] = { v[tt[0]], v[tt[1]], v[tt[2]], v[tt[3]] };
            grid->InsertNextCell(VTK_TETRA, 4, ids);
          }
        }
        else if (cellType == VTK_PYRAMID)
        {
          const vtkIdType c =
            grid->GetPoints()->InsertNextPoint((i + 0.5) * h, (j + 0.5) * h, (k + 0.5) * h);
          const int f[6][4] = { { 0, 3, 2, 1 }, { 4, 5, 6, 7 }, { 0, 1, 5, 4 }, { 1, 2, 6, 5 },
            { 2, 3, 7, 6 }, { 3, 0, 4, 7 } };
          for (const auto& ff : f)
          {
            const vtkIdType ids[5] = { v[ff[0]], v[ff[1]], v[ff[2]], v[ff[3]], c };
            grid->InsertNextCell(VTK_PYRAMID, 5, ids);
          }
        }
        else if (cellType == VTK_POLYHEDRON)
        {
          const int f[6][4] = { { 0, 3, 2, 1 }, { 4, 5, 6, 7 }, { 0, 1, 5, 4 }, { 1, 2, 6, 5 },
            { 2, 3, 7, 6 }, { 3, 0, 4, 7 } };
          vtkIdType faces[6 * 5];
          for (int q = 0; q < 6; ++q)
          {
            faces[5 * q] = 4;
            for (int r = 0; r < 4; ++r)
            {
              faces[5 * q + 1 + r] = v[f[q][r]];
            }
          }
          grid->InsertNextCell(VTK_POLYHEDRON, 8, v, 6, faces);
        }
      }
  return grid;
}

vtkSmartPointer<vtkDoubleArray> PointField(
  vtkUnstructuredGrid* grid, const char* name, int nc, const std::function<void(const double*, double*)>& f)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(nc);
  a->SetNumberOfTuples(grid->GetNumberOfPoints());
  for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); ++p)
  {
    double x[3], v[3];
    grid->GetPoint(p, x);
    f(x, v);
    a->SetTypedTuple(p, v);
  }
  grid->GetPointData()->AddArray(a);
  return a;
}

/// Uniform flow V, uniform density, linear pressure p0 + g.x: the exact normal
/// Mach number is V.g / (a |g|) with a evaluated from the local p.
void AddLinearFlow(vtkUnstructuredGrid* grid, const double V[3], const double g[3])
{
  PointField(grid, "U", 3, [&](const double*, double* v) { v[0] = V[0]; v[1] = V[1]; v[2] = V[2]; });
  PointField(grid, "p", 1, [&](const double* x, double* v) { v[0] = 1e5 + g[0] * x[0] + g[1] * x[1] + g[2] * x[2]; });
  PointField(grid, "rho", 1, [&](const double*, double* v) { v[0] = 1.2; });
}

void SelectPrimitive(vtkShockSensor* s)
{
  s->SetInputArrayToProcess(vtkShockSensor::VELOCITY, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "U");
  s->SetInputArrayToProcess(vtkShockSensor::PRESSURE, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "p");
  s->SetInputArrayToProcess(vtkShockSensor::DENSITY, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "rho");
}
}

//------------------------------------------------------------------------------
class LinearFieldOnCellType : public ::testing::TestWithParam<int>
{
};

TEST_P(LinearFieldOnCellType, NormalMachIsExact)
{
  auto grid = MakeGrid(3, GetParam());
  const double V[3] = { 300.0, 40.0, -20.0 };
  const double g[3] = { 2000.0, -500.0, 1000.0 };
  AddLinearFlow(grid, V, g);
  vtkNew<vtkShockSensor> sensor;
  Messages msg(sensor);
  sensor->SetInputData(grid);
  SelectPrimitive(sensor);
  sensor->Update();
  ASSERT_TRUE(msg.Errors.empty()) << msg.Errors;
  vtkUnstructuredGrid* out = sensor->GetOutput();
  auto* mn = vtkDoubleArray::SafeDownCast(out->GetPointData()->GetArray("NormalMach"));
  ASSERT_NE(mn, nullptr);
  const double gmag = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  const double vg = V[0] * g[0] + V[1] * g[1] + V[2] * g[2];
  for (vtkIdType p = 0; p < out->GetNumberOfPoints(); ++p)
  {
    double x[3];
    out->GetPoint(p, x);
    const double pressure = 1e5 + g[0] * x[0] + g[1] * x[1] + g[2] * x[2];
    const double expected = vg / (std::sqrt(1.4 * pressure / 1.2) * gmag);
    ASSERT_NEAR(mn->GetValue(p), expected, 1e-9 * std::abs(expected)) << "point " << p;
  }
  // Mn is about 0.71 < 1 everywhere: no shock cell.
  auto* sc = vtkUnsignedCharArray::SafeDownCast(out->GetCellData()->GetArray("ShockCells"));
  ASSERT_NE(sc, nullptr);
  EXPECT_EQ(sc->GetRange()[1], 0.0);
  // The input is untouched.
  EXPECT_EQ(grid->GetPointData()->GetArray("NormalMach"), nullptr);
}

INSTANTIATE_TEST_SUITE_P(AllLinearCells, LinearFieldOnCellType,
  ::testing::Values(VTK_TETRA, VTK_PYRAMID, VTK_WEDGE, VTK_HEXAHEDRON, VTK_POLYHEDRON));

//------------------------------------------------------------------------------
TEST(ShockSensor, ShockCellsStraddleUnityAndFiltersApply)
{
  // Normal Mach number falling linearly along x through 1 at x = 0.5 while
  // the pressure rises (a compression, as in a shock): only the cells with
  // vertices on both sides of x = 0.55 are shock cells.
  auto grid = MakeGrid(8, VTK_HEXAHEDRON);
  const double gp = 1000.0;
  PointField(grid, "p", 1, [&](const double* x, double* v) { v[0] = 1e5 + gp * x[0]; });
  PointField(grid, "rho", 1, [&](const double*, double* v) { v[0] = 1.2; });
  PointField(grid, "U", 3, [&](const double* x, double* v) {
    const double a = std::sqrt(1.4 * (1e5 + gp * x[0]) / 1.2);
    v[0] = a * (1.44 - 0.8 * x[0]); // Mn = 1.44 - 0.8 x: equals 1 at x = 0.55
    v[1] = 0.0;
    v[2] = 0.0;
  });
  vtkNew<vtkShockSensor> sensor;
  sensor->SetInputData(grid);
  SelectPrimitive(sensor);
  sensor->SetUpstreamMachRange(0.0, 10.0);
  sensor->Update();
  auto* sc = vtkUnsignedCharArray::SafeDownCast(sensor->GetOutput()->GetCellData()->GetArray("ShockCells"));
  ASSERT_NE(sc, nullptr);
  vtkIdType count = 0;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    double b[6];
    grid->GetCell(c)->GetBounds(b);
    // Mn = 1 at x = 0.55, inside the layer of cells 0.5 < x < 0.625.
    const bool expected = b[0] < 0.55 && b[1] > 0.55;
    EXPECT_EQ(sc->GetValue(c) != 0, expected) << "cell " << c;
    count += sc->GetValue(c);
  }
  EXPECT_EQ(count, 64);

  // Mn rising where p rises is not a shock: no cell.
  {
    auto rising = MakeGrid(8, VTK_HEXAHEDRON);
    PointField(rising, "p", 1, [&](const double* x, double* v) { v[0] = 1e5 + gp * x[0]; });
    PointField(rising, "rho", 1, [&](const double*, double* v) { v[0] = 1.2; });
    PointField(rising, "U", 3, [&](const double* x, double* v) {
      v[0] = std::sqrt(1.4 * (1e5 + gp * x[0]) / 1.2) * (0.6 + 0.8 * x[0]);
      v[1] = v[2] = 0.0;
    });
    vtkNew<vtkShockSensor> s2;
    s2->SetInputData(rising);
    SelectPrimitive(s2);
    s2->SetUpstreamMachRange(0.0, 10.0);
    s2->Update();
    EXPECT_EQ(s2->GetOutput()->GetCellData()->GetArray("ShockCells")->GetRange()[1], 0.0);
  }

  // The upstream-Mach window: the local Mach number of this flow is at most
  // 1.4, so a window [5, 10] removes every cell.
  sensor->SetUpstreamMachRange(5.0, 10.0);
  sensor->Update();
  sc = vtkUnsignedCharArray::SafeDownCast(sensor->GetOutput()->GetCellData()->GetArray("ShockCells"));
  EXPECT_EQ(sc->GetRange()[1], 0.0);
  sensor->SetUpstreamMachRange(0.0, 10.0);
  sensor->SetPressureGradientThreshold(1.0); // uniform |grad p| equals its max: cells pass
  sensor->Update();
  sc = vtkUnsignedCharArray::SafeDownCast(sensor->GetOutput()->GetCellData()->GetArray("ShockCells"));
  EXPECT_EQ(sc->GetRange()[1], 1.0);
}

TEST(ShockSensor, ConservedAndTemperatureVariableSetsAgree)
{
  auto grid = MakeGrid(4, VTK_TETRA);
  const double V[3] = { 500.0, 100.0, 0.0 };
  const double g[3] = { -3000.0, 2000.0, 500.0 };
  AddLinearFlow(grid, V, g);
  const double R = 287.0, gamma = 1.4;
  PointField(grid, "T", 1, [&](const double* x, double* v) { v[0] = (1e5 + g[0] * x[0] + g[1] * x[1] + g[2] * x[2]) / (1.2 * R); });
  PointField(grid, "rhoU", 3, [&](const double*, double* v) { v[0] = 1.2 * V[0]; v[1] = 1.2 * V[1]; v[2] = 1.2 * V[2]; });
  PointField(grid, "rhoE", 1, [&](const double* x, double* v) {
    const double p = 1e5 + g[0] * x[0] + g[1] * x[1] + g[2] * x[2];
    v[0] = p / (gamma - 1.0) + 0.5 * 1.2 * (V[0] * V[0] + V[1] * V[1] + V[2] * V[2]);
  });
  vtkNew<vtkShockSensor> ref, withT, cons;
  for (vtkShockSensor* s : { ref.Get(), withT.Get(), cons.Get() })
  {
    s->SetInputData(grid);
  }
  SelectPrimitive(ref);
  withT->SetVariableSet(vtkShockSensor::VELOCITY_PRESSURE_TEMPERATURE);
  withT->SetGasConstant(R);
  cons->SetVariableSet(vtkShockSensor::CONSERVED);
  for (vtkShockSensor* s : { ref.Get(), withT.Get(), cons.Get() })
  {
    s->Update();
  }
  auto* a = ref->GetOutput()->GetPointData()->GetArray("NormalMach");
  auto* b = withT->GetOutput()->GetPointData()->GetArray("NormalMach");
  auto* c = cons->GetOutput()->GetPointData()->GetArray("NormalMach");
  ASSERT_TRUE(a && b && c);
  for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); ++p)
  {
    EXPECT_NEAR(b->GetComponent(p, 0), a->GetComponent(p, 0), 1e-9);
    EXPECT_NEAR(c->GetComponent(p, 0), a->GetComponent(p, 0), 1e-9);
  }
}

TEST(ShockSensor, CellDataGivesTheSameLinearAnswer)
{
  // A linear cell field averaged to the points is linear again away from the
  // boundary; check interior points only.
  auto grid = MakeGrid(6, VTK_HEXAHEDRON);
  const double V[3] = { 300.0, 0.0, 0.0 };
  const double g[3] = { 1000.0, 0.0, 0.0 };
  for (const char* name : { "U", "p", "rho" })
  {
    auto a = vtkSmartPointer<vtkDoubleArray>::New();
    a->SetName(name);
    a->SetNumberOfComponents(name[0] == 'U' ? 3 : 1);
    a->SetNumberOfTuples(grid->GetNumberOfCells());
    for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
    {
      double b[6];
      grid->GetCell(c)->GetBounds(b);
      const double xc = 0.5 * (b[0] + b[1]);
      const double v[3] = { name[0] == 'U' ? V[0] : (name[0] == 'p' ? 1e5 + g[0] * xc : 1.2), 0, 0 };
      a->SetTypedTuple(c, v);
    }
    grid->GetCellData()->AddArray(a);
  }
  vtkNew<vtkShockSensor> sensor;
  sensor->SetInputData(grid);
  sensor->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "U");
  sensor->SetInputArrayToProcess(1, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "p");
  sensor->SetInputArrayToProcess(2, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "rho");
  sensor->Update();
  auto* mn = sensor->GetOutput()->GetPointData()->GetArray("NormalMach");
  ASSERT_NE(mn, nullptr);
  int checked = 0;
  for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); ++p)
  {
    double x[3];
    grid->GetPoint(p, x);
    if (x[0] > 0.2 && x[0] < 0.8)
    {
      const double a = std::sqrt(1.4 * (1e5 + g[0] * x[0]) / 1.2);
      EXPECT_NEAR(mn->GetComponent(p, 0), V[0] / a, 1e-9);
      ++checked;
    }
  }
  EXPECT_GT(checked, 0);
}

//------------------------------------------------------------------------------
TEST(WeightFunction, MatchesTheClosedFormOfEq1)
{
  // q1 = 1000 + x, q2 = 1000 + y on tetrahedra: the gradients are exact, so
  // r_1x = 1/(|qbar1| + eps), r_2y = 1/(|qbar2| + eps), all others 0, and
  // W = 1 + (n_1x (+) n_2y) / 1 with n = r / max r: checked cell by cell.
  auto grid = MakeGrid(4, VTK_TETRA);
  PointField(grid, "q1", 1, [](const double* x, double* v) { v[0] = 1000.0 + x[0]; });
  PointField(grid, "q2", 1, [](const double* x, double* v) { v[0] = 1000.0 + x[1]; });
  const double eps = 0.5;
  vtkNew<vtkWeightFunction> wf;
  Messages msg(wf);
  wf->SetInputData(grid);
  wf->AddVariable("q1");
  wf->AddVariable("q2");
  wf->SetEpsilon(eps);
  wf->Update();
  ASSERT_TRUE(msg.Errors.empty()) << msg.Errors;
  auto* W = wf->GetOutput()->GetCellData()->GetArray("WeightFunction");
  ASSERT_NE(W, nullptr);
  const vtkIdType nc = grid->GetNumberOfCells();
  std::vector<double> r1(nc), r2(nc);
  double m1 = 0, m2 = 0;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < nc; ++c)
  {
    grid->GetCellPoints(c, ids);
    double xm = 0, ym = 0;
    for (vtkIdType a = 0; a < ids->GetNumberOfIds(); ++a)
    {
      double x[3];
      grid->GetPoint(ids->GetId(a), x);
      xm += x[0] / 4;
      ym += x[1] / 4;
    }
    r1[c] = 1.0 / (1000.0 + xm + eps);
    r2[c] = 1.0 / (1000.0 + ym + eps);
    m1 = std::max(m1, r1[c]);
    m2 = std::max(m2, r2[c]);
  }
  for (vtkIdType c = 0; c < nc; ++c)
  {
    const double a = r1[c] / m1, b = r2[c] / m2;
    const double expected = 1.0 + (a + b - a * b);
    ASSERT_NEAR(W->GetComponent(c, 0), expected, 1e-6) << "cell " << c;
  }
}

TEST(WeightFunction, OneWhereNothingVariesAndHighestAtTheJump)
{
  auto grid = MakeGrid(10, VTK_HEXAHEDRON);
  PointField(grid, "rho", 1, [](const double* x, double* v) { v[0] = 1.5 + 0.5 * std::tanh((x[0] - 0.55) / 0.03); });
  PointField(grid, "c", 1, [](const double*, double* v) { v[0] = 7.0; });
  vtkNew<vtkWeightFunction> wf;
  wf->SetInputData(grid);
  wf->AddVariable("rho");
  wf->AddVariable("c");
  wf->ComputePointWeightOn();
  wf->Update();
  auto* W = wf->GetOutput()->GetCellData()->GetArray("WeightFunction");
  auto* Wp = wf->GetOutput()->GetPointData()->GetArray("WeightFunction");
  ASSERT_TRUE(W && Wp);
  double best = 0, bestX = -1;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    double b[6];
    grid->GetCell(c)->GetBounds(b);
    const double w = W->GetComponent(c, 0);
    EXPECT_GE(w, 1.0);
    EXPECT_LE(w, 2.0);
    if (b[1] < 0.3 || b[0] > 0.8)
    {
      EXPECT_LT(w, 1.0 + 1e-3) << "far from the jump, cell " << c;
    }
    if (w > best)
    {
      best = w;
      bestX = 0.5 * (b[0] + b[1]);
    }
  }
  EXPECT_NEAR(best, 2.0, 1e-12); // the strongest cell reaches the top of [1, 2]
  EXPECT_NEAR(bestX, 0.55, 0.05);
  EXPECT_GE(Wp->GetRange()[0], 1.0);
  EXPECT_LE(Wp->GetRange()[1], 2.0);
}

//------------------------------------------------------------------------------
namespace
{
/// Runs `filter` on `grid`, expects an error containing `fragment`, and the
/// output to be the input unchanged (same cells, no new array).
void ExpectRefused(vtkUnstructuredGridAlgorithm* filter, vtkUnstructuredGrid* grid, const std::string& fragment)
{
  Messages msg(filter);
  filter->SetInputData(grid);
  filter->Update();
  EXPECT_NE(msg.Errors.find(fragment), std::string::npos) << "errors were: " << msg.Errors;
  vtkUnstructuredGrid* out = vtkUnstructuredGrid::SafeDownCast(filter->GetOutputDataObject(0));
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(out->GetNumberOfCells(), grid->GetNumberOfCells());
  EXPECT_EQ(out->GetPointData()->GetNumberOfArrays(), grid->GetPointData()->GetNumberOfArrays());
  EXPECT_EQ(out->GetCellData()->GetNumberOfArrays(), grid->GetCellData()->GetNumberOfArrays());
}

vtkSmartPointer<vtkUnstructuredGrid> FlowGrid()
{
  auto grid = MakeGrid(3, VTK_TETRA);
  const double V[3] = { 300, 0, 0 }, g[3] = { 100, 0, 0 };
  AddLinearFlow(grid, V, g);
  return grid;
}
}

TEST(BadInput, ShockSensorMissingArray)
{
  vtkNew<vtkShockSensor> s;
  SelectPrimitive(s);
  s->SetInputArrayToProcess(vtkShockSensor::PRESSURE, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "nope");
  ExpectRefused(s, FlowGrid(), "Pressure array 'nope'");
}

TEST(BadInput, ShockSensorWrongComponents)
{
  vtkNew<vtkShockSensor> s;
  SelectPrimitive(s);
  s->SetInputArrayToProcess(vtkShockSensor::VELOCITY, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "p");
  ExpectRefused(s, FlowGrid(), "has 1 components; it needs 3");
}

TEST(BadInput, ShockSensorNaN)
{
  auto grid = FlowGrid();
  vtkDoubleArray::SafeDownCast(grid->GetPointData()->GetArray("U"))->SetComponent(5, 1, std::nan(""));
  vtkNew<vtkShockSensor> s;
  SelectPrimitive(s);
  ExpectRefused(s, grid, "'U' holds NaN or Inf (point 5)");
}

TEST(BadInput, ShockSensorInf)
{
  auto grid = FlowGrid();
  vtkDoubleArray::SafeDownCast(grid->GetPointData()->GetArray("rho"))->SetValue(7, std::numeric_limits<double>::infinity());
  vtkNew<vtkShockSensor> s;
  SelectPrimitive(s);
  ExpectRefused(s, grid, "'rho' holds NaN or Inf (point 7)");
}

TEST(BadInput, ShockSensorNonPositivePressureAndDensity)
{
  auto grid = FlowGrid();
  vtkDoubleArray::SafeDownCast(grid->GetPointData()->GetArray("p"))->SetValue(3, 0.0);
  vtkNew<vtkShockSensor> s;
  SelectPrimitive(s);
  ExpectRefused(s, grid, "Pressure array 'p' is 0 at point 3");
  auto grid2 = FlowGrid();
  vtkDoubleArray::SafeDownCast(grid2->GetPointData()->GetArray("rho"))->SetValue(4, -1.0);
  vtkNew<vtkShockSensor> s2;
  SelectPrimitive(s2);
  ExpectRefused(s2, grid2, "Density array 'rho' is -1 at point 4");
}

TEST(BadInput, ShockSensorNegativeDerivedPressure)
{
  auto grid = FlowGrid();
  PointField(grid, "rhoU", 3, [](const double*, double* v) { v[0] = 360; v[1] = v[2] = 0; });
  PointField(grid, "rhoE", 1, [](const double*, double* v) { v[0] = 1.0; }); // far below kinetic energy
  vtkNew<vtkShockSensor> s;
  s->SetVariableSet(vtkShockSensor::CONSERVED);
  ExpectRefused(s, grid, "derived from the conserved variables");
}

TEST(BadInput, ShockSensorBadGamma)
{
  vtkNew<vtkShockSensor> s;
  SelectPrimitive(s);
  s->SetGamma(1.0);
  ExpectRefused(s, FlowGrid(), "Gamma must be greater than 1");
}

TEST(BadInput, EmptyMesh)
{
  vtkNew<vtkUnstructuredGrid> empty;
  vtkNew<vtkShockSensor> s;
  ExpectRefused(s, empty, "The input mesh is empty");
  vtkNew<vtkWeightFunction> w;
  w->AddVariable("rho");
  ExpectRefused(w, empty, "The input mesh is empty");
}

TEST(BadInput, SurfaceOnlyMesh)
{
  // Two triangles: no 3-D cell.
  vtkNew<vtkUnstructuredGrid> tri;
  vtkNew<vtkPoints> pts;
  pts->InsertNextPoint(0, 0, 0);
  pts->InsertNextPoint(1, 0, 0);
  pts->InsertNextPoint(0, 1, 0);
  pts->InsertNextPoint(1, 1, 0);
  tri->SetPoints(pts);
  const vtkIdType a[3] = { 0, 1, 2 }, b[3] = { 1, 3, 2 };
  tri->InsertNextCell(VTK_TRIANGLE, 3, a);
  tri->InsertNextCell(VTK_TRIANGLE, 3, b);
  const double V[3] = { 300, 0, 0 }, g[3] = { 100, 0, 0 };
  AddLinearFlow(tri, V, g);
  vtkNew<vtkShockSensor> s;
  SelectPrimitive(s);
  ExpectRefused(s, tri, "no linear 3-D cells");
  vtkNew<vtkWeightFunction> w;
  w->AddVariable("p");
  ExpectRefused(w, tri, "no linear 3-D cells");
}

TEST(BadInput, WeightFunctionNoVariableAndMissingVariable)
{
  // No variable selected: the flow grid's rho, U, p by name (it has no
  // conserved variables); a grid without such names is refused.
  vtkNew<vtkWeightFunction> automatic;
  automatic->SetInputData(FlowGrid());
  automatic->Update();
  auto* used = vtkStringArray::SafeDownCast(automatic->GetOutput()->GetFieldData()->GetAbstractArray("VariablesUsed"));
  ASSERT_NE(used, nullptr);
  ASSERT_EQ(used->GetNumberOfValues(), 3);
  EXPECT_EQ(used->GetValue(0), "rho");
  EXPECT_EQ(used->GetValue(1), "U");
  EXPECT_EQ(used->GetValue(2), "p");
  EXPECT_NE(automatic->GetOutput()->GetCellData()->GetArray("WeightFunction"), nullptr);
  auto unnamed = MakeGrid(2, VTK_TETRA);
  PointField(unnamed, "q", 1, [](const double* x, double* v) { v[0] = 1.0 + x[0]; });
  vtkNew<vtkWeightFunction> w;
  ExpectRefused(w, unnamed, "No variable is selected, and the input has neither");
  vtkNew<vtkWeightFunction> w2;
  w2->AddVariable("p");
  w2->AddVariable("Mach");
  ExpectRefused(w2, FlowGrid(), "Variable 'Mach' is not a numeric point or cell array");
}

TEST(BadInput, WeightFunctionNaN)
{
  auto grid = FlowGrid();
  vtkDoubleArray::SafeDownCast(grid->GetPointData()->GetArray("p"))->SetValue(2, std::nan(""));
  vtkNew<vtkWeightFunction> w;
  w->AddVariable("p");
  ExpectRefused(w, grid, "'p' holds NaN or Inf (point 2)");
}

TEST(BadInput, DegenerateCellsAreNeutralNotFatal)
{
  // A flat tetrahedron among good ones: W = 1 there, and no crash.
  auto grid = MakeGrid(2, VTK_TETRA);
  const vtkIdType flat[4] = { 0, 1, 2, 2 };
  grid->InsertNextCell(VTK_TETRA, 4, flat);
  PointField(grid, "q", 1, [](const double* x, double* v) { v[0] = 1.0 + x[0] * x[0]; });
  vtkNew<vtkWeightFunction> w;
  w->SetInputData(grid);
  w->AddVariable("q");
  w->Update();
  auto* W = w->GetOutput()->GetCellData()->GetArray("WeightFunction");
  ASSERT_NE(W, nullptr);
  EXPECT_EQ(W->GetComponent(grid->GetNumberOfCells() - 1, 0), 1.0);
  EXPECT_GT(W->GetRange()[1], 1.5);
}
