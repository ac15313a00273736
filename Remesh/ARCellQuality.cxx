// SPDX-License-Identifier: BSD-3-Clause
#include "ARCellQuality.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace ar
{
namespace
{
/// The faces of a shape, outward (right-hand normals point out of a valid
/// cell), as VTK's cells list them; -1 ends a triangle.
struct Topology
{
  std::vector<std::array<int, 4>> Faces;
  std::vector<std::array<int, 3>> Corners; // per node: the three edge ends, positive order
  struct Edge
  {
    int A, B, F, G; // nodes A < B, the two faces that share the edge
  };
  std::vector<Edge> Edges;
};

Topology Make(std::vector<std::array<int, 4>> faces, std::vector<std::array<int, 3>> corners)
{
  Topology t;
  t.Faces = std::move(faces);
  t.Corners = std::move(corners);
  for (int f = 0; f < static_cast<int>(t.Faces.size()); ++f)
  {
    const auto& face = t.Faces[f];
    const int n = face[3] < 0 ? 3 : 4;
    for (int k = 0; k < n; ++k)
    {
      const int a = std::min(face[k], face[(k + 1) % n]), b = std::max(face[k], face[(k + 1) % n]);
      auto it = std::find_if(t.Edges.begin(), t.Edges.end(),
        [&](const Topology::Edge& e) { return e.A == a && e.B == b; });
      if (it == t.Edges.end())
      {
        t.Edges.push_back({ a, b, f, -1 });
      }
      else
      {
        it->G = f;
      }
    }
  }
  std::sort(t.Edges.begin(), t.Edges.end(),
    [](const Topology::Edge& x, const Topology::Edge& y) { return x.A < y.A || (x.A == y.A && x.B < y.B); });
  return t;
}

const Topology& Of(CellShape shape)
{
  static const Topology tet = Make({ { 1, 2, 3, -1 }, { 0, 3, 2, -1 }, { 0, 1, 3, -1 }, { 0, 2, 1, -1 } },
    { { 1, 2, 3 }, { 2, 0, 3 }, { 0, 1, 3 }, { 0, 2, 1 } });
  // The apex (node 4) has four edges; its entry is not used (see CellCornerJacobians).
  static const Topology pyramid =
    Make({ { 0, 3, 2, 1 }, { 0, 1, 4, -1 }, { 1, 2, 4, -1 }, { 2, 3, 4, -1 }, { 3, 0, 4, -1 } },
      { { 1, 3, 4 }, { 2, 0, 4 }, { 3, 1, 4 }, { 0, 2, 4 }, { 0, 0, 0 } });
  static const Topology wedge =
    Make({ { 0, 1, 2, -1 }, { 3, 5, 4, -1 }, { 0, 3, 4, 1 }, { 1, 4, 5, 2 }, { 2, 5, 3, 0 } },
      { { 2, 1, 3 }, { 0, 2, 4 }, { 1, 0, 5 }, { 4, 5, 0 }, { 5, 3, 1 }, { 3, 4, 2 } });
  static const Topology hexahedron = Make({ { 0, 4, 7, 3 }, { 1, 2, 6, 5 }, { 0, 1, 5, 4 },
                                            { 3, 7, 6, 2 }, { 0, 3, 2, 1 }, { 4, 5, 6, 7 } },
    { { 1, 3, 4 }, { 2, 0, 5 }, { 3, 1, 6 }, { 0, 2, 7 }, { 7, 5, 0 }, { 4, 6, 1 }, { 5, 7, 2 },
      { 6, 4, 3 } });
  switch (shape)
  {
    case CellShape::Tetrahedron:
      return tet;
    case CellShape::Pyramid:
      return pyramid;
    case CellShape::Wedge:
      return wedge;
    case CellShape::Hexahedron:
    default:
      return hexahedron;
  }
}

Eigen::Vector3d X(const double* points, int node)
{
  return Eigen::Vector3d(points[3 * node], points[3 * node + 1], points[3 * node + 2]);
}

/// Unit outward normal of a face (a quad's average normal: its diagonals'
/// cross product); zero for a face of zero area.
Eigen::Vector3d Normal(const double* points, const std::array<int, 4>& face)
{
  Eigen::Vector3d n;
  if (face[3] < 0)
  {
    n = (X(points, face[1]) - X(points, face[0])).cross(X(points, face[2]) - X(points, face[0]));
  }
  else
  {
    n = (X(points, face[2]) - X(points, face[0])).cross(X(points, face[3]) - X(points, face[1]));
  }
  const double len = n.norm();
  return len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
}

double Corner(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, bool scaled)
{
  const double det = a.dot(b.cross(c));
  if (!scaled)
  {
    return det;
  }
  const double lengths = a.norm() * b.norm() * c.norm();
  return lengths > 0.0 ? det / lengths : 0.0;
}
}

int NumberOfNodes(CellShape shape)
{
  return static_cast<int>(shape);
}

int NumberOfEdges(CellShape shape)
{
  return static_cast<int>(Of(shape).Edges.size());
}

const int* CellFace(CellShape shape, int f)
{
  return Of(shape).Faces[f].data();
}

int NumberOfFaces(CellShape shape)
{
  return static_cast<int>(Of(shape).Faces.size());
}

void CellEdge(CellShape shape, int e, int& a, int& b)
{
  const Topology::Edge& edge = Of(shape).Edges[e];
  a = edge.A;
  b = edge.B;
}

void CellDihedralAngles(CellShape shape, const double* points, double* angles)
{
  const Topology& t = Of(shape);
  std::array<Eigen::Vector3d, 6> n;
  for (std::size_t f = 0; f < t.Faces.size(); ++f)
  {
    n[f] = Normal(points, t.Faces[f]);
  }
  for (std::size_t e = 0; e < t.Edges.size(); ++e)
  {
    const Eigen::Vector3d& a = n[t.Edges[e].F];
    const Eigen::Vector3d& b = n[t.Edges[e].G];
    if (a.squaredNorm() == 0.0 || b.squaredNorm() == 0.0)
    {
      angles[e] = 0.0;
      continue;
    }
    angles[e] = std::acos(std::clamp(-a.dot(b), -1.0, 1.0)) * 180.0 / M_PI;
  }
}

void CellCornerJacobians(CellShape shape, const double* points, double* jacobians, bool scaled)
{
  const Topology& t = Of(shape);
  const int nNodes = NumberOfNodes(shape);
  for (int k = 0; k < nNodes; ++k)
  {
    const Eigen::Vector3d p = X(points, k);
    if (shape == CellShape::Pyramid && k == 4)
    {
      // The apex: over each triangle (b_i, b_i+1, centroid) of the base.
      const Eigen::Vector3d c = 0.25 * (X(points, 0) + X(points, 1) + X(points, 2) + X(points, 3));
      double worst = std::numeric_limits<double>::max();
      for (int i = 0; i < 4; ++i)
      {
        worst = std::min(worst, Corner(X(points, (i + 1) % 4) - p, X(points, i) - p, c - p, scaled));
      }
      jacobians[k] = worst;
      continue;
    }
    const auto& e = t.Corners[k];
    jacobians[k] = Corner(X(points, e[0]) - p, X(points, e[1]) - p, X(points, e[2]) - p, scaled);
  }
}

double CellAspectRatio(CellShape shape, const double* points)
{
  double shortest = std::numeric_limits<double>::max(), longest = 0.0;
  for (const Topology::Edge& e : Of(shape).Edges)
  {
    const double l = (X(points, e.A) - X(points, e.B)).norm();
    shortest = std::min(shortest, l);
    longest = std::max(longest, l);
  }
  return shortest > 0.0 ? longest / shortest : std::numeric_limits<double>::infinity();
}

double CellVolume(CellShape shape, const double* points)
{
  const Topology& t = Of(shape);
  double six = 0.0; // six times the volume: sum of det(a, b, c) over outward triangles
  const Eigen::Vector3d o = X(points, 0); // relative to a node, for round-off far from the origin
  auto add = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    six += (a - o).dot((b - o).cross(c - o));
  };
  for (const auto& face : t.Faces)
  {
    if (face[3] < 0)
    {
      add(X(points, face[0]), X(points, face[1]), X(points, face[2]));
      continue;
    }
    const Eigen::Vector3d m =
      0.25 * (X(points, face[0]) + X(points, face[1]) + X(points, face[2]) + X(points, face[3]));
    for (int k = 0; k < 4; ++k)
    {
      add(X(points, face[k]), X(points, face[(k + 1) % 4]), m);
    }
  }
  return six / 6.0;
}

double CellStepLength(CellShape shape, const double* points, int skipAxis)
{
  double area = 0.0;
  for (const auto& face : Of(shape).Faces)
  {
    const Eigen::Vector3d n = face[3] < 0
      ? Eigen::Vector3d((X(points, face[1]) - X(points, face[0])).cross(X(points, face[2]) - X(points, face[0])))
      : Eigen::Vector3d((X(points, face[2]) - X(points, face[0])).cross(X(points, face[3]) - X(points, face[1])));
    const double a = 0.5 * n.norm();
    // A face in a plane normal to skipAxis: its normal's other components
    // vanish (to round-off: under 1e-6 of its length).
    if (skipAxis >= 0 && skipAxis < 3 && a > 0.0 &&
      std::hypot(n[(skipAxis + 1) % 3], n[(skipAxis + 2) % 3]) <= 1e-6 * n.norm())
    {
      continue;
    }
    area += a;
  }
  return area > 0.0 ? 2.0 * std::abs(CellVolume(shape, points)) / area : 0.0;
}

CellQuality ComputeCellQuality(CellShape shape, const double* points, bool scaledJacobian)
{
  CellQuality q;
  double jacobians[8];
  const int nNodes = NumberOfNodes(shape);
  // The extreme angles from the extreme cosines: two arc cosines per cell
  // instead of one per edge (acos decreases, so CellDihedralAngles' extremes
  // bit for bit; an edge at a face of zero area counts as 0 degrees).
  const Topology& t = Of(shape);
  std::array<Eigen::Vector3d, 6> n;
  for (std::size_t f = 0; f < t.Faces.size(); ++f)
  {
    n[f] = Normal(points, t.Faces[f]);
  }
  double most = -std::numeric_limits<double>::infinity(), least = std::numeric_limits<double>::infinity();
  bool flat = false;
  for (const Topology::Edge& e : t.Edges)
  {
    const Eigen::Vector3d& a = n[e.F];
    const Eigen::Vector3d& b = n[e.G];
    if (a.squaredNorm() == 0.0 || b.squaredNorm() == 0.0)
    {
      flat = true;
      continue;
    }
    const double c = std::clamp(-a.dot(b), -1.0, 1.0);
    most = std::max(most, c);
    least = std::min(least, c);
  }
  q.MinDihedralAngle = flat ? 0.0 : std::acos(most) * 180.0 / M_PI;
  q.MaxDihedralAngle = least <= 1.0 ? std::acos(least) * 180.0 / M_PI : 0.0;
  CellCornerJacobians(shape, points, jacobians, false);
  q.MinCornerJacobian = *std::min_element(jacobians, jacobians + nNodes);
  if (scaledJacobian)
  {
    CellCornerJacobians(shape, points, jacobians, true);
    q.MinScaledJacobian = *std::min_element(jacobians, jacobians + nNodes);
  }
  q.AspectRatio = CellAspectRatio(shape, points);
  return q;
}
}
