// SPDX-License-Identifier: BSD-3-Clause
//
// BenchSensors: times vtkWeightFunction and vtkShockSensor on generated
// tetrahedral meshes, beside VTK's own vtkGradientFilter on the same field,
// and prints a Markdown table. A benchmark, not a test: it asserts nothing
// (a row whose sanity check is implausible is flagged, that is all).
//
//   BenchSensors [options] [size ...]      sizes are target tet counts, default 1e5 1e6 5e6
//     --quick          1e5 only
//     --reps N         timed repetitions after the warm-up (best is reported), default 3
//     --only NAME      gradient | weight | shock | cluster (repeatable); default all three
//     --shuffle        number the points and the cells in random order (worst-case locality)
//     --float          store coordinates and fields as float (as many readers deliver them)
//     --no-fork        run every row in this process (for valgrind/gdb); peak memory is
//                      then the cumulative process peak
//
// The mesh: the unit cube cut into n^3 hexahedra, each split into the 6
// positively oriented Kuhn tetrahedra around its main diagonal (conforming,
// translation-invariant), written straight into vtkCellArray offsets and
// connectivity arrays. n = round(cbrt(size / 6)): 1e5 -> 26 (105,456 tets),
// 1e6 -> 55 (998,250), 5e6 -> 94 (4,983,504).
//
// The field: a smeared planar oblique shock in a Mach 2 stream (shock angle
// 40 deg, tilted 20 deg out of the x-y plane), Rankine-Hugoniot states on both
// sides, blended with tanh over 2 cell widths, plus a 1 % density ripple so
// that the weight function has something to see away from the shock. Point
// arrays rho, U (3), p, rhoU (3), rhoE.
//
// Every (size, filter) row runs in its own forked child, so its peak RSS
// (VmHWM) is its own: the mesh (inherited from the parent, counted in full)
// plus what the filter allocates. "+MB" is the part above the mesh.
// Timing: one warm-up Update(), then the best of --reps wall-clock Update()s
// (std::chrono::steady_clock); if the warm-up takes more than 20 s only one
// timed run follows. CPU/wall is the process CPU time over wall time of that
// best run: about 2 when both cores work.
//
// The threads column is what vtkSMPTools reports after the filter ran:
// GetBackend() and GetEstimatedNumberOfThreads(). vtkGradientFilter runs with
// whatever backend the process has (ParaView's VTK defaults to Sequential);
// the sensors switch to STDThread themselves unless VTK_SMP_BACKEND_IN_USE is
// set. Set VTK_SMP_BACKEND_IN_USE=STDThread to thread vtkGradientFilter too,
// or =Sequential to see the sensors on one core.

#include "BenchClock.h"
#include "vtkFeatureCluster.h"
#include "vtkShockSensor.h"
#include "vtkWeightFunction.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkGradientFilter.h"
#include "vtkIdTypeArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <numeric>
#include <random>
#include <string>
#include <vector>

namespace
{
using artest::Now;

struct Options
{
  std::vector<double> Sizes;
  int Reps = 3;
  std::vector<std::string> Only;
  bool Shuffle = false;
  bool Float = false;
  bool Fork = true;
};

/// One row of the table; plain data so that a child can write it to a pipe.
struct Row
{
  char Filter[32] = "";
  long long Cells = 0;
  long long Points = 0;
  double Seconds = 0.0;
  double CpuRatio = 0.0;
  int Runs = 0;
  double PeakMB = 0.0;
  double ExtraMB = 0.0;
  int Threads = 0;
  char Backend[24] = "";
  char Check[80] = "";
  bool Ok = false;
};

/// The first three fields of /proc/loadavg: other work on the machine skews
/// the timings (CPU/wall well below 2 on a 2-core machine is the sign).
std::string LoadAverage()
{
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return in ? a + " " + b + " " + c : std::string("unknown");
}

double CpuNow()
{
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/// A "VmXXX:   1234 kB" line of /proc/self/status, in MB (or -1).
double StatusMB(const char* key)
{
  std::ifstream in("/proc/self/status");
  std::string line;
  const size_t len = std::strlen(key);
  while (std::getline(in, line))
  {
    if (line.compare(0, len, key) == 0 && line.size() > len && line[len] == ':')
    {
      return std::atof(line.c_str() + len + 1) / 1024.0;
    }
  }
  if (std::strcmp(key, "VmHWM") == 0)
  {
    rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_maxrss / 1024.0;
  }
  return -1.0;
}

//------------------------------------------------------------------------------
// Mesh and field.

/// Kuhn's 6 tetrahedra of the unit cube (corner index = x + 2y + 4z), each
/// ordered so that VTK sees a positive volume.
std::array<std::array<int, 4>, 6> KuhnTets()
{
  std::array<std::array<int, 4>, 6> tets;
  int axes[3] = { 0, 1, 2 };
  int t = 0;
  do
  {
    int corner[4] = { 0, 0, 0, 7 };
    corner[1] = 1 << axes[0];
    corner[2] = corner[1] | (1 << axes[1]);
    double x[4][3];
    for (int a = 0; a < 4; ++a)
    {
      for (int k = 0; k < 3; ++k)
      {
        x[a][k] = (corner[a] >> k) & 1;
      }
    }
    double e[3][3];
    for (int a = 0; a < 3; ++a)
    {
      for (int k = 0; k < 3; ++k)
      {
        e[a][k] = x[a + 1][k] - x[0][k];
      }
    }
    const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
      e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
      e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
    if (det < 0.0)
    {
      std::swap(corner[1], corner[2]);
    }
    tets[t++] = { corner[0], corner[1], corner[2], corner[3] };
  } while (std::next_permutation(axes, axes + 3));
  return tets;
}

/// Smeared oblique shock: fills rho, U, p at x.
struct ShockField
{
  static constexpr double Gamma = 1.4;
  double N[3];         // shock normal, pointing downstream
  double X0[3] = { 0.5, 0.5, 0.5 };
  double Delta;        // smearing width
  double Rho1 = 1.0, P1 = 1.0 / Gamma, U1[3] = { 2.0, 0.0, 0.0 }; // Mach 2, a = 1
  double Rho2, P2, U2[3];

  explicit ShockField(double h)
  {
    const double pi = 3.14159265358979323846;
    const double beta = 40.0 * pi / 180.0, phi = 20.0 * pi / 180.0;
    N[0] = std::sin(beta);
    N[1] = -std::cos(beta) * std::cos(phi);
    N[2] = -std::cos(beta) * std::sin(phi);
    Delta = 2.0 * h;
    const double un1 = U1[0] * N[0] + U1[1] * N[1] + U1[2] * N[2];
    const double mn2 = un1 * un1 / (Gamma * P1 / Rho1); // normal Mach number squared
    P2 = P1 * (1.0 + 2.0 * Gamma / (Gamma + 1.0) * (mn2 - 1.0));
    Rho2 = Rho1 * (Gamma + 1.0) * mn2 / ((Gamma - 1.0) * mn2 + 2.0);
    const double un2 = un1 * Rho1 / Rho2;
    for (int k = 0; k < 3; ++k)
    {
      U2[k] = U1[k] + (un2 - un1) * N[k];
    }
  }

  void Eval(const double x[3], double& rho, double U[3], double& p) const
  {
    const double s = (x[0] - X0[0]) * N[0] + (x[1] - X0[1]) * N[1] + (x[2] - X0[2]) * N[2];
    const double t = 0.5 * (1.0 + std::tanh(s / Delta));
    const double pi = 3.14159265358979323846;
    const double ripple = 1.0 + 0.01 * std::sin(2.0 * pi * x[0]) * std::sin(2.0 * pi * x[1]) *
        std::cos(2.0 * pi * x[2]);
    rho = ((1.0 - t) * Rho1 + t * Rho2) * ripple;
    p = (1.0 - t) * P1 + t * P2;
    for (int k = 0; k < 3; ++k)
    {
      U[k] = (1.0 - t) * U1[k] + t * U2[k];
    }
  }
};

template <typename ArrayT>
vtkSmartPointer<ArrayT> NewArray(const char* name, int nc, vtkIdType n)
{
  auto a = vtkSmartPointer<ArrayT>::New();
  a->SetName(name);
  a->SetNumberOfComponents(nc);
  a->SetNumberOfTuples(n);
  return a;
}

template <typename ArrayT>
vtkSmartPointer<vtkUnstructuredGrid> BuildMeshT(int n, bool shuffle)
{
  using T = typename ArrayT::ValueType;
  const vtkIdType np1 = n + 1;
  const vtkIdType npts = np1 * np1 * np1;
  const vtkIdType ncells = 6 * static_cast<vtkIdType>(n) * n * n;
  const double h = 1.0 / n;

  // Point numbering: structured (i fastest), or a random permutation.
  std::vector<vtkIdType> pointId;
  if (shuffle)
  {
    pointId.resize(npts);
    std::iota(pointId.begin(), pointId.end(), vtkIdType(0));
    std::shuffle(pointId.begin(), pointId.end(), std::mt19937_64(12345));
  }
  auto pid = [&](vtkIdType i) { return shuffle ? pointId[i] : i; };

  auto coords = NewArray<ArrayT>("Points", 3, npts);
  auto rhoA = NewArray<ArrayT>("rho", 1, npts);
  auto UA = NewArray<ArrayT>("U", 3, npts);
  auto pA = NewArray<ArrayT>("p", 1, npts);
  auto rhoUA = NewArray<ArrayT>("rhoU", 3, npts);
  auto rhoEA = NewArray<ArrayT>("rhoE", 1, npts);
  T* X = coords->GetPointer(0);
  T* rho = rhoA->GetPointer(0);
  T* U = UA->GetPointer(0);
  T* P = pA->GetPointer(0);
  T* rhoU = rhoUA->GetPointer(0);
  T* rhoE = rhoEA->GetPointer(0);
  const ShockField field(h);
  for (vtkIdType k = 0, i = 0; k < np1; ++k)
  {
    for (vtkIdType j = 0; j < np1; ++j)
    {
      for (vtkIdType l = 0; l < np1; ++l, ++i)
      {
        const vtkIdType q = pid(i);
        const double x[3] = { l * h, j * h, k * h };
        double r, u[3], p;
        field.Eval(x, r, u, p);
        const double u2 = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
        for (int c = 0; c < 3; ++c)
        {
          X[3 * q + c] = static_cast<T>(x[c]);
          U[3 * q + c] = static_cast<T>(u[c]);
          rhoU[3 * q + c] = static_cast<T>(r * u[c]);
        }
        rho[q] = static_cast<T>(r);
        P[q] = static_cast<T>(p);
        rhoE[q] = static_cast<T>(p / (ShockField::Gamma - 1.0) + 0.5 * r * u2);
      }
    }
  }

  // Cells: 6 Kuhn tets per hexahedron, cell order structured or shuffled.
  const auto tets = KuhnTets();
  vtkIdType cornerOffset[8];
  for (int c = 0; c < 8; ++c)
  {
    cornerOffset[c] = (c & 1) + ((c >> 1) & 1) * np1 + ((c >> 2) & 1) * np1 * np1;
  }
  vtkNew<vtkIdTypeArray> offsets;
  vtkNew<vtkIdTypeArray> conn;
  offsets->SetNumberOfValues(ncells + 1);
  conn->SetNumberOfValues(4 * ncells);
  vtkIdType* off = offsets->GetPointer(0);
  vtkIdType* cn = conn->GetPointer(0);
  for (vtkIdType c = 0; c <= ncells; ++c)
  {
    off[c] = 4 * c;
  }
  std::vector<vtkIdType> cellSlot;
  if (shuffle)
  {
    cellSlot.resize(ncells);
    std::iota(cellSlot.begin(), cellSlot.end(), vtkIdType(0));
    std::shuffle(cellSlot.begin(), cellSlot.end(), std::mt19937_64(54321));
  }
  vtkIdType cell = 0;
  for (vtkIdType k = 0; k < n; ++k)
  {
    for (vtkIdType j = 0; j < n; ++j)
    {
      for (vtkIdType l = 0; l < n; ++l)
      {
        const vtkIdType base = l + j * np1 + k * np1 * np1;
        for (const auto& t : tets)
        {
          vtkIdType* dst = cn + 4 * (shuffle ? cellSlot[cell] : cell);
          for (int a = 0; a < 4; ++a)
          {
            dst[a] = pid(base + cornerOffset[t[a]]);
          }
          ++cell;
        }
      }
    }
  }
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, conn);
  vtkNew<vtkUnsignedCharArray> types;
  types->SetNumberOfValues(ncells);
  std::fill_n(types->GetPointer(0), ncells, static_cast<unsigned char>(VTK_TETRA));

  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->SetData(coords);
  grid->SetPoints(points);
  grid->SetCells(types, cells);
  vtkPointData* pd = grid->GetPointData();
  for (vtkDataArray* a : { static_cast<vtkDataArray*>(rhoA), static_cast<vtkDataArray*>(UA),
         static_cast<vtkDataArray*>(pA), static_cast<vtkDataArray*>(rhoUA),
         static_cast<vtkDataArray*>(rhoEA) })
  {
    pd->AddArray(a);
  }
  return grid;
}

vtkSmartPointer<vtkUnstructuredGrid> BuildMesh(int n, bool shuffle, bool useFloat)
{
  return useFloat ? BuildMeshT<vtkFloatArray>(n, shuffle) : BuildMeshT<vtkDoubleArray>(n, shuffle);
}

//------------------------------------------------------------------------------
// The three filters. Each returns the configured algorithm and, after a run,
// a one-line sanity check of its output.

struct Bench
{
  const char* Name;
  vtkSmartPointer<vtkAlgorithm> (*Make)(vtkUnstructuredGrid*);
  bool (*Check)(vtkAlgorithm*, char* text, size_t len);
};

vtkSmartPointer<vtkAlgorithm> MakeGradient(vtkUnstructuredGrid* grid)
{
  auto f = vtkSmartPointer<vtkGradientFilter>::New();
  f->SetInputData(grid);
  f->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "p");
  return f;
}

bool CheckGradient(vtkAlgorithm* f, char* text, size_t len)
{
  auto* out = vtkUnstructuredGrid::SafeDownCast(f->GetOutputDataObject(0));
  vtkDataArray* g = out ? out->GetPointData()->GetArray("Gradients") : nullptr;
  if (!g)
  {
    std::snprintf(text, len, "no Gradients array");
    return false;
  }
  double gmax = 0.0;
  for (vtkIdType i = 0; i < g->GetNumberOfTuples(); ++i)
  {
    double v[3];
    g->GetTuple(i, v);
    gmax = std::max(gmax, std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
  }
  std::snprintf(text, len, "max abs(grad p) %.3g", gmax);
  return gmax > 0.0;
}

vtkSmartPointer<vtkAlgorithm> MakeWeight(vtkUnstructuredGrid* grid)
{
  auto f = vtkSmartPointer<vtkWeightFunction>::New();
  f->SetInputData(grid);
  f->AddVariable("rho");
  f->AddVariable("rhoU");
  f->AddVariable("rhoE");
  return f;
}

bool CheckWeight(vtkAlgorithm* f, char* text, size_t len)
{
  auto* out = vtkUnstructuredGrid::SafeDownCast(f->GetOutputDataObject(0));
  vtkDataArray* w = out ? out->GetCellData()->GetArray("WeightFunction") : nullptr;
  if (!w)
  {
    std::snprintf(text, len, "no WeightFunction array");
    return false;
  }
  vtkIdType high = 0;
  double wmax = 0.0;
  for (vtkIdType i = 0; i < w->GetNumberOfTuples(); ++i)
  {
    const double v = w->GetComponent(i, 0);
    high += v > 1.5 ? 1 : 0;
    wmax = std::max(wmax, v);
  }
  std::snprintf(text, len, "W > 1.5 in %.2f%% of cells, max %.3f",
    100.0 * high / std::max<vtkIdType>(1, w->GetNumberOfTuples()), wmax);
  return high > 0 && wmax <= 2.0;
}

vtkSmartPointer<vtkAlgorithm> MakeShock(vtkUnstructuredGrid* grid)
{
  auto f = vtkSmartPointer<vtkShockSensor>::New();
  f->SetInputData(grid); // defaults: point arrays U, p, rho
  return f;
}

bool CheckShock(vtkAlgorithm* f, char* text, size_t len)
{
  auto* out = vtkUnstructuredGrid::SafeDownCast(f->GetOutputDataObject(0));
  vtkDataArray* s = out ? out->GetCellData()->GetArray("ShockCells") : nullptr;
  vtkDataArray* mn = out ? out->GetPointData()->GetArray("NormalMach") : nullptr;
  if (!s || !mn)
  {
    std::snprintf(text, len, "no ShockCells/NormalMach array");
    return false;
  }
  vtkIdType shock = 0;
  for (vtkIdType i = 0; i < s->GetNumberOfTuples(); ++i)
  {
    shock += s->GetComponent(i, 0) != 0.0 ? 1 : 0;
  }
  double range[2];
  mn->GetRange(range, 0);
  std::snprintf(text, len, "%.2f%% shock cells, Mn in [%.2f, %.2f]",
    100.0 * shock / std::max<vtkIdType>(1, s->GetNumberOfTuples()), range[0], range[1]);
  return shock > 0 && range[0] < 1.0 && range[1] > 1.0;
}

vtkSmartPointer<vtkAlgorithm> MakeCluster(vtkUnstructuredGrid* grid)
{
  // The middle of the pressure jump (P1 = 0.714, P2 = 1.258): a band a few
  // cells thick around the shock, one dilation ring.
  auto f = vtkSmartPointer<vtkFeatureCluster>::New();
  f->SetInputData(grid);
  f->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "p");
  f->SetSensorRange(0.85, 1.12);
  f->SetDilationRings(1);
  return f;
}

bool CheckCluster(vtkAlgorithm* f, char* text, size_t len)
{
  auto* out = vtkUnstructuredGrid::SafeDownCast(f->GetOutputDataObject(0));
  auto* medial = vtkDataSet::SafeDownCast(f->GetOutputDataObject(1));
  vtkDataArray* mask = out ? out->GetPointData()->GetArray("FeatureMask") : nullptr;
  if (!mask || !medial)
  {
    std::snprintf(text, len, "no FeatureMask / medial points");
    return false;
  }
  vtkIdType selected = 0;
  for (vtkIdType i = 0; i < mask->GetNumberOfTuples(); ++i)
  {
    selected += mask->GetComponent(i, 0) != 0.0 ? 1 : 0;
  }
  std::snprintf(text, len, "%.2f%% of nodes in clusters, %lld medial points",
    100.0 * selected / std::max<vtkIdType>(1, mask->GetNumberOfTuples()),
    static_cast<long long>(medial->GetNumberOfPoints()));
  return selected > 0 && medial->GetNumberOfPoints() > 0;
}

const Bench Benches[] = {
  { "vtkGradientFilter (p)", &MakeGradient, &CheckGradient },
  { "WeightFunction (5 var)", &MakeWeight, &CheckWeight },
  { "ShockSensor", &MakeShock, &CheckShock },
  { "FeatureCluster (p band)", &MakeCluster, &CheckCluster },
};
const char* BenchKeys[] = { "gradient", "weight", "shock", "cluster" };

Row RunBench(const Bench& bench, vtkUnstructuredGrid* grid, int reps)
{
  Row row;
  std::snprintf(row.Filter, sizeof(row.Filter), "%s", bench.Name);
  row.Cells = grid->GetNumberOfCells();
  row.Points = grid->GetNumberOfPoints();
  const double baseMB = StatusMB("VmRSS");

  vtkSmartPointer<vtkAlgorithm> f = bench.Make(grid);
  const double w0 = Now();
  f->Update(); // warm-up: first touch of the pages, thread pool start-up
  const double warm = Now() - w0;
  if (warm > 20.0)
  {
    reps = 1;
  }
  double best = warm, bestCpu = 0.0;
  bool haveBest = false;
  for (int r = 0; r < reps; ++r)
  {
    f->Modified();
    const double c0 = CpuNow();
    const double t0 = Now();
    f->Update();
    const double t = Now() - t0;
    const double c = CpuNow() - c0;
    if (!haveBest || t < best)
    {
      best = t;
      bestCpu = c;
      haveBest = true;
    }
  }
  row.Seconds = best;
  row.CpuRatio = haveBest && best > 0.0 ? bestCpu / best : 0.0;
  row.Runs = haveBest ? reps : 0;
  row.Ok = bench.Check(f, row.Check, sizeof(row.Check));
  row.PeakMB = StatusMB("VmHWM");
  row.ExtraMB = row.PeakMB - baseMB;
  row.Threads = vtkSMPTools::GetEstimatedNumberOfThreads();
  std::snprintf(row.Backend, sizeof(row.Backend), "%s", vtkSMPTools::GetBackend());
  return row;
}

/// Runs one row in a forked child so that its peak RSS is its own.
Row RunForked(const Bench& bench, vtkUnstructuredGrid* grid, int reps)
{
  int fds[2];
  if (pipe(fds) != 0)
  {
    std::perror("pipe");
    std::exit(1);
  }
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = fork();
  if (pid < 0)
  {
    std::perror("fork");
    std::exit(1);
  }
  if (pid == 0)
  {
    close(fds[0]);
    const Row row = RunBench(bench, grid, reps);
    const char* p = reinterpret_cast<const char*>(&row);
    size_t left = sizeof(row);
    while (left > 0)
    {
      const ssize_t w = write(fds[1], p, left);
      if (w <= 0)
      {
        _exit(2);
      }
      p += w;
      left -= static_cast<size_t>(w);
    }
    close(fds[1]);
    std::fflush(stdout);
    std::fflush(stderr);
    _exit(0); // skip destructors and atexit handlers of the copied process
  }
  close(fds[1]);
  Row row;
  char* p = reinterpret_cast<char*>(&row);
  size_t got = 0;
  while (got < sizeof(row))
  {
    const ssize_t r = read(fds[0], p + got, sizeof(row) - got);
    if (r <= 0)
    {
      break;
    }
    got += static_cast<size_t>(r);
  }
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (got != sizeof(row))
  {
    row = Row();
    std::snprintf(row.Filter, sizeof(row.Filter), "%s", bench.Name);
    row.Cells = grid->GetNumberOfCells();
    row.Points = grid->GetNumberOfPoints();
    if (WIFSIGNALED(status))
    {
      std::snprintf(row.Check, sizeof(row.Check), "FAILED: killed by signal %d", WTERMSIG(status));
    }
    else
    {
      std::snprintf(row.Check, sizeof(row.Check), "FAILED: exit status %d", WEXITSTATUS(status));
    }
  }
  return row;
}

void PrintRow(const Row& r)
{
  if (r.Runs == 0 && r.Seconds == 0.0)
  {
    std::printf(
      "| %s | %lld | %lld | - | - | - | - | - | - | %s |\n", r.Filter, r.Cells, r.Points, r.Check);
    return;
  }
  std::printf("| %s | %lld | %lld | %.4f | %.3g | %.2f | %.0f | +%.0f | %d %s | %s%s |\n",
    r.Filter, r.Cells, r.Points, r.Seconds, r.Cells / r.Seconds, r.CpuRatio, r.PeakMB, r.ExtraMB,
    r.Threads, r.Backend, r.Ok ? "" : "SUSPECT: ", r.Check);
  std::fflush(stdout);
}

void Usage(const char* argv0)
{
  std::fprintf(stderr,
    "usage: %s [--quick] [--reps N] [--only gradient|weight|shock|cluster] [--shuffle] [--float] "
    "[--no-fork] [size ...]\n"
    "  sizes are target tetrahedron counts (e.g. 1e5 1e6 5e6, the default)\n",
    argv0);
}
}

int main(int argc, char* argv[])
{
  Options opt;
  bool quick = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--quick")
    {
      quick = true;
    }
    else if (a == "--reps" && i + 1 < argc)
    {
      opt.Reps = std::max(1, std::atoi(argv[++i]));
    }
    else if (a == "--only" && i + 1 < argc)
    {
      opt.Only.emplace_back(argv[++i]);
    }
    else if (a == "--shuffle")
    {
      opt.Shuffle = true;
    }
    else if (a == "--float")
    {
      opt.Float = true;
    }
    else if (a == "--no-fork")
    {
      opt.Fork = false;
    }
    else if (a == "-h" || a == "--help")
    {
      Usage(argv[0]);
      return 0;
    }
    else
    {
      char* end = nullptr;
      const double s = std::strtod(a.c_str(), &end);
      if (end == a.c_str() || *end != '\0' || !(s >= 6.0) || s > 2e9)
      {
        std::fprintf(stderr, "bad argument '%s'\n", a.c_str());
        Usage(argv[0]);
        return 1;
      }
      opt.Sizes.push_back(s);
    }
  }
  if (quick)
  {
    opt.Sizes = { 1e5 };
  }
  if (opt.Sizes.empty())
  {
    opt.Sizes = { 1e5, 1e6, 5e6 };
  }
  for (const std::string& o : opt.Only)
  {
    if (std::find_if(std::begin(BenchKeys), std::end(BenchKeys),
          [&](const char* k) { return o == k; }) == std::end(BenchKeys))
    {
      std::fprintf(stderr, "unknown filter '%s'\n", o.c_str());
      Usage(argv[0]);
      return 1;
    }
  }

  const char* env = std::getenv("VTK_SMP_BACKEND_IN_USE");
  std::printf("# BenchSensors: %ld hardware threads, VTK_SMP_BACKEND_IN_USE=%s, %s, %s numbering, "
              "best of %d after 1 warm-up, %s, load average %s\n\n",
    sysconf(_SC_NPROCESSORS_ONLN), env ? env : "(unset)", opt.Float ? "float" : "double",
    opt.Shuffle ? "shuffled" : "structured", opt.Reps,
    opt.Fork ? "one forked process per row (own peak RSS)"
             : "single process (peak RSS is cumulative)",
    LoadAverage().c_str());

  std::vector<Row> rows;
  for (double size : opt.Sizes)
  {
    const int n = std::max(1, static_cast<int>(std::lround(std::cbrt(size / 6.0))));
    const double rss0 = StatusMB("VmRSS");
    const double t0 = Now();
    vtkSmartPointer<vtkUnstructuredGrid> grid = BuildMesh(n, opt.Shuffle, opt.Float);
    const double t = Now() - t0;
    char line[256];
    std::snprintf(line, sizeof(line),
      "mesh %.0e: n = %d, %lld tets, %lld points, generated in %.3f s, %.0f MB", size, n,
      static_cast<long long>(grid->GetNumberOfCells()),
      static_cast<long long>(grid->GetNumberOfPoints()), t, StatusMB("VmRSS") - rss0);
    std::printf("%s\n", line);
    std::fflush(stdout);
    for (size_t b = 0; b < sizeof(Benches) / sizeof(Benches[0]); ++b)
    {
      if (!opt.Only.empty() &&
        std::find(opt.Only.begin(), opt.Only.end(), BenchKeys[b]) == opt.Only.end())
      {
        continue;
      }
      rows.push_back(opt.Fork ? RunForked(Benches[b], grid, opt.Reps)
                              : RunBench(Benches[b], grid, opt.Reps));
      std::fprintf(stderr, "  done: %s, %lld cells, %.4f s\n", rows.back().Filter,
        rows.back().Cells, rows.back().Seconds);
    }
  }

  std::printf("\n| filter | cells | points | seconds | cells/s | CPU/wall | peak RSS MB | "
              "MB over mesh | threads | check |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---|---|\n");
  for (const Row& r : rows)
  {
    PrintRow(r);
  }
  std::printf("\nload average at the end: %s\n", LoadAverage().c_str());
  if (!opt.Fork)
  {
    std::printf("\n(peak RSS is the cumulative process peak: run without --no-fork for per-row "
                "peaks)\n");
  }
  return 0;
}
