// SPDX-License-Identifier: BSD-3-Clause
//
// BenchPrismLayers: times ar::BuildPrismLayers against the number of surface
// triangles and prints a Markdown table; the time per triangle should stay
// flat (linear growth). A benchmark, not a test.
//
//   BenchPrismLayers [m ...]   grid cells per side, default 50 100 200 400 700
//                              (5,000 to 980,000 triangles)
//
// The surface: z = 0.5 + 0.05 sin(2 pi x) sin(2 pi y) over [0.1, 0.9]^2 (a
// curved, open surface, so normals are smoothed, the border is closed with
// pyramids and the concave sides are checked), 2 m^2 triangles, edge h =
// 0.8 / m. Layers: 5 per side, the first 0.05 h thick, growth 1.2; the
// obstacles are the unit cube's 12 boundary triangles. Each row is the best
// of 3 runs.

#include "BenchClock.h"
#include "ARPrismLayers.h"
#include "../Cxx/ARTestMeshes.h"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace
{
using artest::BoxTriangles;
using artest::Now;
using artest::PeakRSSMB;

}

int main(int argc, char* argv[])
{
  std::vector<int> sizes;
  for (int i = 1; i < argc; ++i)
    sizes.push_back(std::atoi(argv[i]));
  if (sizes.empty())
    sizes = { 50, 100, 200, 400, 700 };
  const std::vector<double> box = BoxTriangles();
  std::printf("| surface triangles | prisms | pyramids | closure tets | s | us per triangle | shrink rounds | peak RSS MB |\n");
  std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int m : sizes)
  {
    const artest::Surface s = artest::Grid(m, m, 0.1, 0.9, 0.1, 0.9, [](double x, double y) {
      return std::array<double, 3>{ x, y, 0.5 + 0.05 * std::sin(2 * M_PI * x) * std::sin(2 * M_PI * y) };
    });
    ar::PrismLayerOptions o;
    o.NumberOfLayers = 5;
    o.FirstLayerThickness = 0.05 * 0.8 / m;
    o.GrowthRatio = 1.2;
    double best = 1e300;
    ar::PrismStack stack;
    std::string error;
    bool ok = true;
    for (int run = 0; run < 3 && ok; ++run)
    {
      const double t0 = Now();
      ok = ar::BuildPrismLayers(s.Points.data(), s.Points.size() / 3, s.Triangles.data(), s.Triangles.size() / 3,
        box.data(), box.size() / 9, o, stack, error);
      best = std::min(best, Now() - t0);
    }
    const std::size_t nTri = s.Triangles.size() / 3;
    if (!ok)
      std::printf("| %zu | failed: %s |\n", nTri, error.c_str());
    else
      std::printf("| %zu | %zu | %zu | %zu | %.3f | %.2f | %d | %.0f |\n", nTri, stack.Prisms.size() / 6,
        stack.Pyramids.size() / 5, stack.Tetrahedra.size() / 4, best, 1e6 * best / nTri, stack.ShrinkRounds, PeakRSSMB());
    std::fflush(stdout);
  }
  return 0;
}
