// Test meshes shared by the C++ tests and benchmarks.
#ifndef ARTestMeshes_h
#define ARTestMeshes_h

#include "ARCavity.h"
#include "ARTetGeometry.h"
#include "ARTetMesh.h"

#include <algorithm>
#include <array>
#include <functional>
#include <utility>
#include <vector>

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

/// A triangulated surface: points (x y z) and triangles (3 ids).
struct Surface
{
  std::vector<double> Points;
  std::vector<std::int64_t> Triangles;
};

/// A triangulated grid over (u, v) in [u0,u1] x [v0,v1], mapped by `map`;
/// its triangles' normals point along map_u x map_v.
inline Surface Grid(int nu, int nv, double u0, double u1, double v0, double v1,
  const std::function<std::array<double, 3>(double, double)>& map)
{
  Surface s;
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i)
    {
      const auto x = map(u0 + (u1 - u0) * i / nu, v0 + (v1 - v0) * j / nv);
      s.Points.insert(s.Points.end(), x.begin(), x.end());
    }
  auto id = [nu](int i, int j) { return static_cast<std::int64_t>(i + (nu + 1) * j); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i)
      s.Triangles.insert(s.Triangles.end(), { id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1) });
  return s;
}


/// The unit cube's 12 boundary triangles, 9 coordinates each, outward.
inline std::vector<double> BoxTriangles()
{
  std::vector<double> b;
  const double c[8][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 } };
  const int q[6][4] = { { 0, 3, 2, 1 }, { 4, 5, 6, 7 }, { 0, 1, 5, 4 }, { 1, 2, 6, 5 }, { 2, 3, 7, 6 }, { 3, 0, 4, 7 } };
  for (const auto& f : q)
    for (const int t : { 0, 1 })
      for (const int k : { f[0], f[t + 1], f[t + 2] })
        b.insert(b.end(), c[k], c[k] + 3);
  return b;
}
/// The smallest dihedral angle of a cavity remesh's new tetrahedra: [0] the
/// layer stack's closure tetrahedra, [1] TetGen's (180 where there are none).
inline std::array<double, 2> ClosureAndRefillAngles(const ar::CavityRemesh& r)
{
  std::array<double, 2> worst = { 180.0, 180.0 };
  for (std::size_t t = 0; t < r.SourceCell.size(); ++t)
  {
    if (r.SourceCell[t] >= 0)
      continue;
    const std::int64_t* q = &r.Mesh.Tetrahedra[4 * t];
    double angles[6];
    ar::TetDihedralAngles(&r.Mesh.Points[3 * q[0]], &r.Mesh.Points[3 * q[1]], &r.Mesh.Points[3 * q[2]],
      &r.Mesh.Points[3 * q[3]], angles);
    const bool closure = t < r.TetrahedronLayer.size() && r.TetrahedronLayer[t] >= 0;
    double& w = worst[closure ? 0 : 1];
    w = std::min(w, *std::min_element(angles, angles + 6));
  }
  return worst;
}
}

#endif
