// Test meshes shared by the C++ tests and benchmarks.
#ifndef ARTestMeshes_h
#define ARTestMeshes_h

#include "ARTetGeometry.h"
#include "ARTetMesh.h"

#include <functional>
#include <utility>

namespace artest
{
/// Kuhn (6-tetrahedra) subdivision of [0,1]^3 in n^3 cubes, keeping the cubes
/// for which keep(i, j, k) holds.
inline ar::TetMesh KuhnCube(int n, const std::function<bool(int, int, int)>& keep = nullptr)
{
  ar::TetMesh m;
  auto id = [n](int i, int j, int k) { return static_cast<std::int64_t>(i + (n + 1) * (j + (n + 1) * static_cast<std::int64_t>(k))); };
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        m.Points.insert(m.Points.end(), { double(i) / n, double(j) / n, double(k) / n });
  static const int perms[6][3] = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 }, { 2, 0, 1 }, { 2, 1, 0 } };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        if (keep && !keep(i, j, k))
          continue;
        for (const auto& p : perms)
        {
          int c[3] = { i, j, k };
          std::int64_t v[4];
          v[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s)
          {
            ++c[p[s]];
            v[s + 1] = id(c[0], c[1], c[2]);
          }
          const double* x[4] = { &m.Points[3 * v[0]], &m.Points[3 * v[1]], &m.Points[3 * v[2]], &m.Points[3 * v[3]] };
          if (ar::TetSignedVolume(x[0], x[1], x[2], x[3]) < 0)
            std::swap(v[1], v[2]);
          m.Tetrahedra.insert(m.Tetrahedra.end(), v, v + 4);
        }
      }
  return m;
}

}

#endif
