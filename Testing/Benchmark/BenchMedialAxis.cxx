// SPDX-License-Identifier: BSD-3-Clause
//
// BenchMedialAxis: times vtkMedialAxisDelaunay beside vtkDelaunay3D on the
// same surface points and prints a Markdown table. A benchmark, not a test.
//
//   BenchMedialAxis [--reps N] [--vtk-max N] [size ...]   sizes: surface points, default 1e5 1e6
//
// The surface: a thick spherical shell (outer radius 1, inner 0.6; normals
// out of the shell region), each sphere a vtkSphereSource with its points
// moved along the normal by uniform noise of +-5 % of the edge length (a real
// isosurface is not cospherical). Rows, each in its own forked process so
// that the peak RSS is the row's own:
// - "CGAL Delaunay": ar::DelaunayTetrahedralize alone (the reference);
// - "medial core": ar::ComputeMedialSheet (Delaunay, interior test,
//   pruning, sheets);
// - "filter, no smoothing" / "filter, windowed sinc": vtkMedialAxisDelaunay::Update()
//   on the vtkPolyData, normals included;
// - "vtkDelaunay3D": on the same points (sizes up to --vtk-max, default 1e5:
//   it needs minutes at 1e5 points; one run, no repetition).
// Timing: the best wall-clock time of --reps runs (default 3) after a warm-up,
// except vtkDelaunay3D.

#include "BenchClock.h"
#include "ARDelaunay.h"
#include "ARMedialAxis.h"
#include "vtkMedialAxisDelaunay.h"

#include "vtkAppendPolyData.h"
#include "vtkDataArray.h"
#include "vtkDelaunay3D.h"
#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataNormals.h"
#include "vtkReverseSense.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"
#include "vtkCellArray.h"
#include "vtkUnstructuredGrid.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace
{
using artest::Now;
using artest::PeakRSSMB;

/// One sphere with about n points, noised along the normals; `inward` flips
/// the normals (and the triangles) so that they point out of the shell.
vtkSmartPointer<vtkPolyData> NoisySphere(double radius, long n, bool inward, unsigned seed)
{
  const int res = std::max(8, static_cast<int>(std::sqrt(static_cast<double>(n))));
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(radius);
  sphere->SetThetaResolution(res);
  sphere->SetPhiResolution(res);
  sphere->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  sphere->Update();
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->DeepCopy(sphere->GetOutput());
  const double edge = 3.14159265358979 * radius / res;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-0.05 * edge, 0.05 * edge);
  vtkPoints* pts = pd->GetPoints();
  for (vtkIdType i = 0; i < pts->GetNumberOfPoints(); ++i)
  {
    double x[3];
    pts->GetPoint(i, x);
    const double r = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    const double s = (r + noise(rng)) / r;
    pts->SetPoint(i, s * x[0], s * x[1], s * x[2]);
  }
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputData(pd);
  normals->SplittingOff();
  normals->ConsistencyOn();
  normals->AutoOrientNormalsOn();
  normals->Update();
  pd->DeepCopy(normals->GetOutput());
  if (inward)
  {
    vtkNew<vtkReverseSense> reverse;
    reverse->SetInputData(pd);
    reverse->ReverseCellsOn();
    reverse->ReverseNormalsOn();
    reverse->Update();
    pd->DeepCopy(reverse->GetOutput());
  }
  return pd;
}

vtkSmartPointer<vtkPolyData> Shell(long n)
{
  // Point counts in proportion to the spheres' areas (1 : 0.36).
  const long outer = static_cast<long>(n / 1.36);
  vtkNew<vtkAppendPolyData> append;
  append->AddInputData(NoisySphere(1.0, outer, false, 1));
  append->AddInputData(NoisySphere(0.6, n - outer, true, 2));
  append->Update();
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->DeepCopy(append->GetOutput());
  return pd;
}

struct Row
{
  char Name[64] = "";
  long Points = 0;
  double Seconds = -1.0;
  long Tetrahedra = 0;
  long Triangles = 0;
  double RSS = 0.0;
  char Note[96] = "";
};

Row RunRow(const std::string& name, vtkPolyData* surface, int reps)
{
  Row row;
  std::snprintf(row.Name, sizeof(row.Name), "%s", name.c_str());
  row.Points = surface->GetNumberOfPoints();
  std::vector<double> xyz(3 * row.Points), nrm(3 * row.Points);
  for (vtkIdType i = 0; i < row.Points; ++i)
  {
    surface->GetPoint(i, &xyz[3 * i]);
    surface->GetPointData()->GetNormals()->GetTuple(i, &nrm[3 * i]);
  }
  std::vector<std::int64_t> tris;
  {
    vtkIdType npts;
    const vtkIdType* ids;
    vtkCellArray* polys = surface->GetPolys();
    for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
    {
      if (npts == 3)
      {
        tris.insert(tris.end(), { ids[0], ids[1], ids[2] });
      }
    }
  }
  std::function<void()> run;
  if (name == "CGAL Delaunay")
  {
    run = [&]() {
      ar::TetMesh mesh;
      std::string error;
      ar::DelaunayTetrahedralize(xyz.data(), row.Points, mesh, error);
      row.Tetrahedra = static_cast<long>(mesh.NumberOfTetrahedra());
    };
  }
  else if (name == "medial core")
  {
    run = [&]() {
      ar::MedialSheet sheet;
      std::string error;
      ar::ComputeMedialSheet(xyz.data(), row.Points, nrm.data(), tris.data(), tris.size() / 3, {},
        nullptr, sheet, error);
      row.Tetrahedra = static_cast<long>(sheet.NumberOfTetrahedra);
      row.Triangles = static_cast<long>(sheet.Triangles.size() / 3);
    };
  }
  else if (name.rfind("filter", 0) == 0)
  {
    run = [&]() {
      vtkNew<vtkMedialAxisDelaunay> filter;
      filter->SetInputData(surface);
      filter->SetSmoothing(name.find("sinc") != std::string::npos
          ? vtkMedialAxisDelaunay::WINDOWED_SINC
          : vtkMedialAxisDelaunay::NO_SMOOTHING);
      filter->Update();
      row.Triangles = filter->GetOutput()->GetNumberOfCells();
      vtkDataArray* tets = filter->GetOutput()->GetFieldData()->GetArray("DelaunayTetrahedra");
      row.Tetrahedra = tets ? static_cast<long>(tets->GetComponent(0, 0)) : 0;
    };
  }
  else // vtkDelaunay3D
  {
    reps = 0;
    run = [&]() {
      vtkNew<vtkPolyData> cloud;
      cloud->SetPoints(surface->GetPoints());
      vtkNew<vtkDelaunay3D> delaunay;
      delaunay->SetInputData(cloud);
      delaunay->Update();
      row.Tetrahedra = delaunay->GetOutput()->GetNumberOfCells();
    };
  }
  if (reps > 0)
  {
    run(); // warm-up
  }
  double best = 1e300;
  for (int r = 0; r < std::max(1, reps); ++r)
  {
    const double t0 = Now();
    run();
    best = std::min(best, Now() - t0);
  }
  row.Seconds = best;
  row.RSS = PeakRSSMB();
  return row;
}

Row RunForked(const std::string& name, vtkPolyData* surface, int reps)
{
  int fds[2];
  if (pipe(fds) != 0)
  {
    std::perror("pipe");
    std::exit(1);
  }
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid == 0)
  {
    close(fds[0]);
    const Row row = RunRow(name, surface, reps);
    const ssize_t w = write(fds[1], &row, sizeof(row));
    close(fds[1]);
    _exit(w == static_cast<ssize_t>(sizeof(row)) ? 0 : 2);
  }
  close(fds[1]);
  Row row;
  const ssize_t got = read(fds[0], &row, sizeof(row));
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (got != static_cast<ssize_t>(sizeof(row)))
  {
    row = Row();
    std::snprintf(row.Name, sizeof(row.Name), "%s", name.c_str());
    row.Points = surface->GetNumberOfPoints();
    std::snprintf(row.Note, sizeof(row.Note), "child failed (status %d)", status);
  }
  return row;
}
}

int main(int argc, char* argv[])
{
  int reps = 3;
  long vtkMax = 100000;
  std::vector<long> sizes;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--reps" && i + 1 < argc)
    {
      reps = std::atoi(argv[++i]);
    }
    else if (a == "--vtk-max" && i + 1 < argc)
    {
      vtkMax = static_cast<long>(std::atof(argv[++i]));
    }
    else if (a == "-h" || a == "--help")
    {
      std::printf("usage: BenchMedialAxis [--reps N] [--vtk-max N] [size ...]\n");
      return 0;
    }
    else
    {
      sizes.push_back(static_cast<long>(std::atof(a.c_str())));
    }
  }
  if (sizes.empty())
  {
    sizes = { 100000, 1000000 };
  }
  vtkSMPTools::Initialize();
  std::printf("BenchMedialAxis: thick spherical shell, %d reps (best of), SMP backend %s, "
              "one forked process per row\n\n",
    reps, vtkSMPTools::GetBackend());
  std::printf("| step | surface points | s | points/s | tetrahedra | sheet triangles | peak RSS MB | note |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---|\n");
  for (long n : sizes)
  {
    vtkSmartPointer<vtkPolyData> shell = Shell(n);
    std::vector<std::string> names = { "CGAL Delaunay", "medial core", "filter, no smoothing",
      "filter, windowed sinc" };
    if (n <= vtkMax)
    {
      names.push_back("vtkDelaunay3D");
    }
    double filterTime = 0.0;
    for (const std::string& name : names)
    {
      Row row = RunForked(name, shell, reps);
      if (name == "filter, no smoothing")
      {
        filterTime = row.Seconds;
      }
      if (name == "vtkDelaunay3D" && filterTime > 0.0 && row.Seconds > 0.0)
      {
        std::snprintf(row.Note, sizeof(row.Note), "%.0fx the whole filter's time",
          row.Seconds / filterTime);
      }
      std::printf("| %s | %ld | %.3f | %.3g | %ld | %ld | %.0f | %s |\n", row.Name, row.Points,
        row.Seconds, row.Seconds > 0 ? row.Points / row.Seconds : 0.0, row.Tetrahedra,
        row.Triangles, row.RSS, row.Note);
      std::fflush(stdout);
    }
  }
  return 0;
}
