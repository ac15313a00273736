// SPDX-License-Identifier: BSD-3-Clause
//
// BenchCavity: times ar::RemeshLocalCavity (LocalCavity, LocalCavity with
// prism layers, FullDomain) on Kuhn-subdivided unit cubes with a planar
// feature surface, and prints a Markdown table. A benchmark, not a test.
//
//   BenchCavity [n ...]     cubes per side, default 30 55 (162,000 and 998,250 tetrahedra)
//
// The surface: the plane z = 0.5 + 0.2 (x - 0.5) over [0.1, 0.9]^2,
// triangulated at the mesh's edge length 1/n. The prism variant puts 5
// layers on each side of it, the first 0.05/n thick, growth 1.2 (0.37/n in
// all per side). Each row runs once (TetGen dominates and does not vary much).

#include "ARCavity.h"
#include "ARTetGeometry.h"
#include "../Cxx/ARTestMeshes.h"

#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace
{
double Now()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double PeakRSSMB()
{
  rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_maxrss / 1024.0;
}

}

int main(int argc, char* argv[])
{
  std::vector<int> sizes;
  for (int i = 1; i < argc; ++i)
    sizes.push_back(std::atoi(argv[i]));
  if (sizes.empty())
    sizes = { 30, 55 };
  std::printf("| mode | input tets | surface triangles | s | new tets (TetGen) | prisms | pyramids + closure tets | new cells/s | kept tets | peak RSS MB |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int n : sizes)
  {
    const ar::TetMesh cube = artest::KuhnCube(n);
    const int m = static_cast<int>(0.8 * n);
    std::vector<double> pts;
    std::vector<std::int64_t> tris;
    for (int j = 0; j <= m; ++j)
      for (int i = 0; i <= m; ++i)
      {
        const double x = 0.1 + 0.8 * i / m, y = 0.1 + 0.8 * j / m;
        pts.insert(pts.end(), { x, y, 0.5 + 0.2 * (x - 0.5) });
      }
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i)
      {
        const std::int64_t a = i + (m + 1) * j, b = a + 1, c = a + m + 2, d = a + m + 1;
        tris.insert(tris.end(), { a, b, c, a, c, d });
      }
    for (int mode = 0; mode < 3; ++mode)
    {
      static const char* names[3] = { "LocalCavity", "LocalCavity + prisms", "FullDomain" };
      ar::CavityOptions o;
      o.FullDomain = mode == 2;
      if (mode == 1)
      {
        o.Layers.NumberOfLayers = 5;
        o.Layers.FirstLayerThickness = 0.05 / n;
        o.Layers.GrowthRatio = 1.2;
      }
      ar::CavityRemesh r;
      std::string error;
      const double t0 = Now();
      const bool ok = ar::RemeshLocalCavity(cube, pts.data(), pts.size() / 3, tris.data(), tris.size() / 3, o, r, error);
      const double dt = Now() - t0;
      std::size_t fresh = 0, kept = 0, closure = 0;
      for (std::size_t t = 0; t < r.SourceCell.size(); ++t)
      {
        const bool layer = !r.TetrahedronLayer.empty() && r.TetrahedronLayer[t] >= 0;
        (r.SourceCell[t] >= 0 ? kept : layer ? closure : fresh) += 1;
      }
      const std::size_t prisms = r.Prisms.size() / 6, pyramids = r.Pyramids.size() / 5 + closure;
      if (!ok)
        std::printf("| %s | %zu | %zu | failed: %s |\n", names[mode], cube.NumberOfTetrahedra(), tris.size() / 3, error.c_str());
      else
        std::printf("| %s | %zu | %zu | %.2f | %zu | %zu | %zu | %.3g | %zu | %.0f |\n", names[mode],
          cube.NumberOfTetrahedra(), tris.size() / 3, dt, fresh, prisms, pyramids,
          (fresh + prisms + pyramids) / dt, kept, PeakRSSMB());
      std::fflush(stdout);
    }
  }
  return 0;
}
