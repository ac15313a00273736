// SPDX-License-Identifier: BSD-3-Clause
#include "ARTetGeometry.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

namespace ar
{
namespace
{
Eigen::Vector3d V(const double p[3])
{
  return Eigen::Vector3d(p[0], p[1], p[2]);
}
}

double TetSignedVolume(const double p0[3], const double p1[3], const double p2[3], const double p3[3])
{
  const Eigen::Vector3d a = V(p1) - V(p0), b = V(p2) - V(p0), c = V(p3) - V(p0);
  return a.dot(b.cross(c)) / 6.0;
}

void TetDihedralAngles(
  const double p0[3], const double p1[3], const double p2[3], const double p3[3], double angles[6])
{
  const Eigen::Vector3d x[4] = { V(p0), V(p1), V(p2), V(p3) };
  // Outward-independent face normals: n_f is the normal of the face opposite
  // vertex f, oriented away from that vertex.
  Eigen::Vector3d n[4];
  for (int f = 0; f < 4; ++f)
  {
    const Eigen::Vector3d& a = x[(f + 1) % 4];
    const Eigen::Vector3d& b = x[(f + 2) % 4];
    const Eigen::Vector3d& c = x[(f + 3) % 4];
    Eigen::Vector3d nf = (b - a).cross(c - a);
    if (nf.dot(x[f] - a) > 0.0)
    {
      nf = -nf;
    }
    const double len = nf.norm();
    n[f] = len > 0.0 ? Eigen::Vector3d(nf / len) : Eigen::Vector3d::Zero();
  }
  // The dihedral angle at edge (i,j) lies between the two faces that contain
  // the edge, i.e. the faces opposite the two other vertices k and l:
  // angle = pi - angle(n_k, n_l).
  static const int edges[6][2] = { { 0, 1 }, { 0, 2 }, { 0, 3 }, { 1, 2 }, { 1, 3 }, { 2, 3 } };
  for (int e = 0; e < 6; ++e)
  {
    int other[2], m = 0;
    for (int v = 0; v < 4; ++v)
    {
      if (v != edges[e][0] && v != edges[e][1])
      {
        other[m++] = v;
      }
    }
    const double c = std::clamp(n[other[0]].dot(n[other[1]]), -1.0, 1.0);
    angles[e] = 180.0 - std::acos(c) * 180.0 / M_PI;
  }
}

double TotalSignedVolume(const TetMesh& mesh)
{
  double total = 0.0;
  const std::size_t nt = mesh.NumberOfTetrahedra();
  for (std::size_t t = 0; t < nt; ++t)
  {
    const double* p[4];
    for (int k = 0; k < 4; ++k)
    {
      p[k] = &mesh.Points[3 * static_cast<std::size_t>(mesh.Tetrahedra[4 * t + k])];
    }
    total += TetSignedVolume(p[0], p[1], p[2], p[3]);
  }
  return total;
}

TetMeshStatistics ComputeStatistics(const TetMesh& mesh)
{
  TetMeshStatistics s;
  s.MinVolume = std::numeric_limits<double>::max();
  s.MinDihedral = 180.0;
  s.MaxDihedral = 0.0;
  const std::size_t nt = mesh.NumberOfTetrahedra();
  for (std::size_t t = 0; t < nt; ++t)
  {
    const double* p[4];
    for (int k = 0; k < 4; ++k)
    {
      p[k] = &mesh.Points[3 * static_cast<std::size_t>(mesh.Tetrahedra[4 * t + k])];
    }
    const double v = TetSignedVolume(p[0], p[1], p[2], p[3]);
    s.TotalVolume += v;
    s.MinVolume = std::min(s.MinVolume, v);
    s.NumberOfNonPositive += v <= 0.0 ? 1 : 0;
    double a[6];
    TetDihedralAngles(p[0], p[1], p[2], p[3], a);
    for (double ai : a)
    {
      s.MinDihedral = std::min(s.MinDihedral, ai);
      s.MaxDihedral = std::max(s.MaxDihedral, ai);
    }
  }
  if (nt == 0)
  {
    s.MinVolume = 0.0;
    s.MinDihedral = 0.0;
  }
  return s;
}
}
