// SPDX-License-Identifier: BSD-3-Clause
//
// BenchQuadricFit: times the template fits of vtkQuadricFit on synthetic
// medial points and prints a Markdown table. A benchmark, not a test: it
// asserts nothing (a row whose RMS residual is far from the noise is flagged).
//
//   BenchQuadricFit [--reps N] [size ...]     sizes are point counts, default 1e5
//
// For each size, template (plane, quadric, cone, quartic) and refinement
// (off: Eq. 4 only; on: Eq. 4 then the orthogonal-distance refinement):
// - "fit": ar::FitSurface alone (the Remesh core);
// - "filter": vtkQuadricFit::Update() on the same points as a vtkPolyData:
//   gathering, validation, the fit, meshing at the median LocalSize, and
//   trimming to the cluster (no Domain);
// - "filter + Domain": the same with a Domain, a box of 10 x 10 x 10 voxels
//   (vtkImageData) 10 % smaller on every side than the points' bounding box,
//   which cuts the surface all round.
// The points: n samples of the exact surface over a patch of about unit area,
// with Gaussian noise 0.002 along the normal, LocalSize about the point
// spacing sqrt(area / n) (so the mesh has about 2.3 n triangles), Weight =
// 1 / LocalSize. Timing: one warm-up, then the best wall-clock time of
// --reps runs (default 3).

#include "BenchClock.h"
#include "ARSurfaceFit.h"
#include "vtkQuadricFit.h"

#include "vtkDoubleArray.h"
#include "vtkImageData.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

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

constexpr double Pi = 3.14159265358979323846;
constexpr double Noise = 0.002;

double Best(int reps, const std::function<void()>& run)
{
  run(); // warm-up
  double best = 1e300;
  for (int r = 0; r < reps; ++r)
  {
    const double t0 = Now();
    run();
    best = std::min(best, Now() - t0);
  }
  return best;
}

struct Cloud
{
  std::vector<double> X, W, L;
};

/// n noisy samples of the template's test surface; local size = spacing.
Cloud Make(ar::SurfaceTemplate t, std::size_t n, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.5, 0.5), jitter(0.9, 1.1);
  std::normal_distribution<double> noise(0.0, Noise);
  Cloud c;
  c.X.reserve(3 * n);
  double area = 1.0;
  const double th = 30.0 * Pi / 180.0;
  if (t == ar::SurfaceTemplate::Cone)
  {
    area = Pi * (1.5 * 1.5 - 0.5 * 0.5) * std::sin(th);
  }
  const double spacing = std::sqrt(area / static_cast<double>(n));
  for (std::size_t j = 0; j < n; ++j)
  {
    double p[3], nrm[3];
    const double x = u(rng), y = u(rng);
    switch (t)
    {
      case ar::SurfaceTemplate::Cone:
      {
        // apex (0.1, -0.2, 0.3), axis x, half-angle 30 degrees, s in [0.5, 1.5]
        const double s = 1.0 + x, phi = 2.0 * Pi * (y + 0.5);
        const double r = s * std::sin(th);
        p[0] = 0.1 + s * std::cos(th);
        p[1] = -0.2 + r * std::cos(phi);
        p[2] = 0.3 + r * std::sin(phi);
        nrm[0] = -std::sin(th);
        nrm[1] = std::cos(th) * std::cos(phi);
        nrm[2] = std::cos(th) * std::sin(phi);
        break;
      }
      default:
      {
        double f = 0.0, fx = 0.0, fy = 0.0;
        if (t == ar::SurfaceTemplate::Plane)
        {
          f = 0.3 * x - 0.2 * y;
          fx = 0.3;
          fy = -0.2;
        }
        else if (t == ar::SurfaceTemplate::Quadric)
        {
          f = 0.4 * x * x + 0.2 * x * y - 0.3 * y * y;
          fx = 0.8 * x + 0.2 * y;
          fy = 0.2 * x - 0.6 * y;
        }
        else
        {
          f = 0.4 * x * x - 0.3 * y * y + 0.5 * x * x * x * y - 0.8 * y * y * y * y;
          fx = 0.8 * x + 1.5 * x * x * y;
          fy = -0.6 * y + 0.5 * x * x * x - 3.2 * y * y * y;
        }
        const double g = std::sqrt(1.0 + fx * fx + fy * fy);
        p[0] = x;
        p[1] = y;
        p[2] = f;
        nrm[0] = -fx / g;
        nrm[1] = -fy / g;
        nrm[2] = 1.0 / g;
      }
    }
    const double e = noise(rng);
    const double l = spacing * jitter(rng);
    for (int k = 0; k < 3; ++k)
    {
      c.X.push_back(p[k] + e * nrm[k]);
    }
    c.L.push_back(l);
    c.W.push_back(1.0 / l);
  }
  return c;
}

vtkSmartPointer<vtkPolyData> AsPolyData(const Cloud& c)
{
  const vtkIdType n = static_cast<vtkIdType>(c.W.size());
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkDoubleArray> xyz;
  xyz->SetNumberOfComponents(3);
  xyz->SetNumberOfTuples(n);
  std::copy(c.X.begin(), c.X.end(), xyz->GetPointer(0));
  vtkNew<vtkPoints> pts;
  pts->SetData(xyz);
  pd->SetPoints(pts);
  vtkNew<vtkIntArray> ids;
  ids->SetName("ClusterId");
  ids->SetNumberOfTuples(n);
  ids->FillValue(0);
  vtkNew<vtkDoubleArray> size, weight;
  size->SetName("LocalSize");
  weight->SetName("Weight");
  size->SetNumberOfTuples(n);
  weight->SetNumberOfTuples(n);
  std::copy(c.L.begin(), c.L.end(), size->GetPointer(0));
  std::copy(c.W.begin(), c.W.end(), weight->GetPointer(0));
  pd->GetPointData()->AddArray(ids);
  pd->GetPointData()->AddArray(size);
  pd->GetPointData()->AddArray(weight);
  return pd;
}
}

int main(int argc, char* argv[])
{
  int reps = 3;
  std::vector<double> sizes;
  for (int i = 1; i < argc; ++i)
  {
    if (!std::strcmp(argv[i], "--reps") && i + 1 < argc)
    {
      reps = std::max(1, std::atoi(argv[++i]));
    }
    else
    {
      sizes.push_back(std::atof(argv[i]));
    }
  }
  if (sizes.empty())
  {
    sizes.push_back(1e5);
  }

  std::printf("| points | template | refinement | fit (s) | filter: fit + mesh + trim (s) | "
              "triangles | filter + Domain (s) | triangles | RMS residual | iterations |\n");
  std::printf("|---:|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
  const ar::SurfaceTemplate templates[] = { ar::SurfaceTemplate::Plane,
    ar::SurfaceTemplate::Quadric, ar::SurfaceTemplate::Cone, ar::SurfaceTemplate::Quartic };
  for (double size : sizes)
  {
    const std::size_t n = static_cast<std::size_t>(size);
    for (ar::SurfaceTemplate t : templates)
    {
      const Cloud cloud = Make(t, n, 7);
      vtkSmartPointer<vtkPolyData> input = AsPolyData(cloud);
      double b[6];
      input->GetBounds(b);
      vtkNew<vtkImageData> box;
      box->SetDimensions(11, 11, 11);
      box->SetOrigin(b[0] + 0.1 * (b[1] - b[0]), b[2] + 0.1 * (b[3] - b[2]), b[4] + 0.1 * (b[5] - b[4]));
      box->SetSpacing(0.08 * (b[1] - b[0]), 0.08 * (b[3] - b[2]), 0.08 * (b[5] - b[4]));
      for (bool refine : { false, true })
      {
        ar::SurfaceFitOptions options;
        options.Template = t;
        options.GeometricRefinement = refine;
        ar::SurfaceFitResult fit;
        std::string error;
        bool ok = true;
        const double fitSeconds = Best(reps, [&]() {
          ok = ar::FitSurface(cloud.X.data(), cloud.W.data(), n, options, fit, error);
        });
        vtkNew<vtkQuadricFit> filter;
        filter->SetInputData(input);
        filter->SetTemplate(static_cast<int>(t));
        filter->SetGeometricRefinement(refine);
        const double filterSeconds = Best(reps, [&]() {
          filter->Modified();
          filter->Update();
        });
        const vtkIdType triangles = filter->GetOutput()->GetNumberOfCells();
        vtkNew<vtkQuadricFit> clipped;
        clipped->SetInputData(input);
        clipped->SetDomainData(box);
        clipped->SetTemplate(static_cast<int>(t));
        clipped->SetGeometricRefinement(refine);
        const double domainSeconds = Best(reps, [&]() {
          clipped->Modified();
          clipped->Update();
        });
        const vtkIdType inside = clipped->GetOutput()->GetNumberOfCells();
        // Eq. 4 alone leaves a bias on the curved templates; the refined fit
        // should be at the noise level.
        const bool plausible = ok && (!refine || std::abs(fit.RMSResidual - Noise) < 0.25 * Noise);
        std::printf("| %zu | %s | %s | %.3f | %.3f | %lld | %.3f | %lld | %.5f%s | %d |\n", n,
          ar::SurfaceTemplateName(t), refine ? "on" : "off", fitSeconds, filterSeconds,
          static_cast<long long>(triangles), domainSeconds, static_cast<long long>(inside),
          fit.RMSResidual, plausible ? "" : " (?)", fit.Iterations);
        std::fflush(stdout);
      }
    }
  }
  return 0;
}
