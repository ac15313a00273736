// SPDX-License-Identifier: BSD-3-Clause
//
// BenchCavity: times ar::RemeshLocalCavity (LocalCavity, LocalCavity with 5
// prism layers per side, and FullDomain) on
// Kuhn-subdivided unit cubes with a planar feature surface, and prints a
// Markdown table. A benchmark, not a test.
//
//   BenchCavity [n ...]     cubes per side, default 30 55 (162,000 and 998,250 tetrahedra)
//
// The surface: the plane z = 0.5 + 0.2 (x - 0.5) over [0.1, 0.9]^2,
// triangulated at the mesh's edge length 1/n. Each row runs once (TetGen
// dominates and does not vary much). The last two rows: the same plane over
// x in [0.1, 0.35] and [0.65, 0.9] only, two cavities refilled as two pieces,
// one TetGen process at a time and then two at once (Threads).

#include "BenchClock.h"
#include "ARCavity.h"
#include "ARTetGen.h"
#include "ARTetGeometry.h"
#include "../Cxx/ARTestMeshes.h"

#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

namespace
{
using artest::Now;
using artest::PeakRSSMB;

/// Runs the `tetgen` program on the files at `prefix` and formats a row
/// comparing its throughput with ours.
std::string Standalone(const std::string& prefix, const ar::TetGenOptions& quality, const char* mode,
  std::size_t inputTets, double oursPerSecond)
{
  std::string switches = ar::TetGenSwitches(quality);
  if (!switches.empty() && switches.back() == 'Q')
    switches.pop_back();
  const std::string command = "tetgen -" + switches + "mNEF " + prefix + ".smesh 2>&1";
  const double t0 = Now();
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  if (!pipe)
    return std::string("| ") + mode + " | cannot run tetgen |";
  char line[512];
  long tets = -1;
  while (std::fgets(line, sizeof(line), pipe.get()))
  {
    const char* key = std::strstr(line, "Mesh tetrahedra:");
    if (key)
      tets = std::atol(key + std::strlen("Mesh tetrahedra:"));
  }
  const int status = pclose(pipe.release());
  const double dt = Now() - t0;
  if (tets < 0 || status != 0)
    return std::string("| ") + mode + " | tetgen not found or failed: `" + command + "` |";
  char row[512];
  std::snprintf(row, sizeof(row), "| %s | %zu | %ld | %.2f | %.3g | %.3g | %.0f %% |", mode, inputTets, tets, dt,
    tets / dt, oursPerSecond, 100.0 * oursPerSecond / (tets / dt));
  return row;
}
}

int main(int argc, char* argv[])
{
  std::vector<std::string> standalone;
  std::vector<int> sizes;
  for (int i = 1; i < argc; ++i)
    sizes.push_back(std::atoi(argv[i]));
  if (sizes.empty())
    sizes = { 30, 55 };
  std::printf("| mode | input tets | surface triangles | s | setup | removal | cavity | refill (runs, pieces) | layers | assembly | new tets (TetGen) | prisms | pyramids + closure tets | new tets/s in TetGen | kept tets | peak RSS MB |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
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
    // Two strips of the plane, far enough apart for two cavities.
    std::vector<std::int64_t> strips;
    for (std::size_t t = 0; t < tris.size() / 3; ++t)
    {
      double x = 0.0;
      for (int k = 0; k < 3; ++k)
        x += pts[3 * tris[3 * t + k]] / 3.0;
      if (x < 0.35 || x > 0.65)
        strips.insert(strips.end(), &tris[3 * t], &tris[3 * t] + 3);
    }
    for (int mode = 0; mode < 5; ++mode)
    {
      static const char* names[5] = { "LocalCavity", "LocalCavity + prisms", "FullDomain",
        "LocalCavity, two strips, 1 process", "LocalCavity, two strips, 2 processes" };
      const std::vector<std::int64_t>& surface = mode >= 3 ? strips : tris;
      ar::CavityOptions o;
      o.FullDomain = mode == 2;
      o.Threads = mode == 3 ? 1 : (mode == 4 ? 2 : 0);
      if (mode == 1)
      {
        o.Layers.NumberOfLayers = 5;
        o.Layers.FirstLayerThickness = 0.05 / n;
        o.Layers.GrowthRatio = 1.2;
      }
      const std::string prefix = "/tmp/BenchCavity_" + std::to_string(n) + "_" + std::to_string(mode);
      if (mode < 3)
        o.RefillFilesPrefix = prefix;
      ar::CavityRemesh r;
      std::string error;
      const double t0 = Now();
      const bool ok = ar::RemeshLocalCavity(cube, pts.data(), pts.size() / 3, surface.data(), surface.size() / 3, o, r, error);
      const double dt = Now() - t0;
      std::size_t fresh = 0, kept = 0, closure = 0;
      for (std::size_t t = 0; t < r.SourceCell.size(); ++t)
      {
        const bool layer = !r.TetrahedronLayer.empty() && r.TetrahedronLayer[t] >= 0;
        (r.SourceCell[t] >= 0 ? kept : layer ? closure : fresh) += 1;
      }
      const std::size_t prisms = r.Prisms.size() / 6, pyramids = r.Pyramids.size() / 5 + closure;
      if (!ok)
        std::printf("| %s | %zu | %zu | failed: %s |\n", names[mode], cube.NumberOfTetrahedra(), surface.size() / 3, error.c_str());
      else
      {
        const auto& s = r.Seconds;
        std::printf("| %s | %zu | %zu | %.2f | %.2f | %.2f | %.2f | %.2f (%d, %zu) | %.2f | %.2f | %zu | %zu | %zu | %.3g | %zu | %.0f |\n",
          names[mode], cube.NumberOfTetrahedra(), surface.size() / 3, dt, s.Setup, s.Removal, s.Cavity, s.Refill,
          r.RefillAttempts, r.RefillPieces, s.Layers, s.Assembly, fresh, prisms, pyramids, fresh / s.Refill, kept, PeakRSSMB());
      }
      std::fflush(stdout);
      if (ok && mode < 3)
        standalone.push_back(Standalone(prefix, o.Quality, names[mode], cube.NumberOfTetrahedra(), fresh / r.Seconds.Refill));
    }
  }
  std::printf("\nThe same refills by the `tetgen` program (Debian's, 1.5.0) on the complexes written with\n"
              "RefillFilesPrefix, output files off (-NEF):\n\n");
  std::printf("| refill | input tets | tetgen tets | tetgen s | tetgen tets/s | ours tets/s | ours / tetgen |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|\n");
  for (const std::string& row : standalone)
    std::printf("%s\n", row.c_str());
  return 0;
}
