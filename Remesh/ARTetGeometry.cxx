// SPDX-License-Identifier: BSD-3-Clause
#include "ARTetGeometry.h"
#include "ARParallelFor.h"
#include "ARHugePages.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <array>
#include <atomic>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

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

namespace
{
double MinDihedral(const TetMesh& mesh, std::size_t t)
{
  const std::int64_t* v = &mesh.Tetrahedra[4 * t];
  double angles[6];
  TetDihedralAngles(&mesh.Points[3 * v[0]], &mesh.Points[3 * v[1]], &mesh.Points[3 * v[2]],
    &mesh.Points[3 * v[3]], angles);
  return *std::min_element(angles, angles + 6);
}

/// Whether tetrahedron t has a dihedral angle below the one whose cosine is
/// `cosBound`: TetDihedralAngles' test without its six arc cosines (the
/// angle at an edge is 180 degrees less the angle between the outward
/// normals of its two faces, so it is below the bound where their dot
/// product is below -cosBound). A degenerate face counts as 90 degrees, as there.
/// With minStep > 0, also where its step length 2V / (sum of face areas) is
/// below minStep, from the same face normals.
bool IsThin(const TetMesh& mesh, std::size_t t, double cosBound, double minStep)
{
  const std::int64_t* v = &mesh.Tetrahedra[4 * t];
  const Eigen::Vector3d x[4] = { V(&mesh.Points[3 * v[0]]), V(&mesh.Points[3 * v[1]]), V(&mesh.Points[3 * v[2]]),
    V(&mesh.Points[3 * v[3]]) };
  Eigen::Vector3d n[4];
  double twiceArea = 0.0, sixVolume = 0.0;
  for (int f = 0; f < 4; ++f)
  {
    const Eigen::Vector3d& a = x[(f + 1) % 4];
    Eigen::Vector3d nf = (x[(f + 2) % 4] - a).cross(x[(f + 3) % 4] - a);
    const double side = nf.dot(x[f] - a);
    if (side > 0.0)
    {
      nf = -nf;
    }
    if (f == 0)
    {
      sixVolume = std::abs(side);
    }
    const double len = nf.norm();
    twiceArea += len;
    n[f] = len > 0.0 ? Eigen::Vector3d(nf / len) : Eigen::Vector3d::Zero();
  }
  for (int k = 0; k < 4; ++k)
  {
    for (int l = k + 1; l < 4; ++l)
    {
      if (std::clamp(n[k].dot(n[l]), -1.0, 1.0) < -cosBound)
      {
        return true;
      }
    }
  }
  // 2V / sum(A) = (sixVolume / 3) / (twiceArea / 2)
  return minStep > 0.0 && 2.0 * sixVolume < 3.0 * minStep * twiceArea;
}

/// Tetrahedron t's explicit step length 2V / (sum of its face areas), as IsThin takes it.
double StepLength(const TetMesh& mesh, std::size_t t)
{
  const std::int64_t* v = &mesh.Tetrahedra[4 * t];
  const Eigen::Vector3d x[4] = { V(&mesh.Points[3 * v[0]]), V(&mesh.Points[3 * v[1]]), V(&mesh.Points[3 * v[2]]),
    V(&mesh.Points[3 * v[3]]) };
  double twiceArea = 0.0;
  for (int f = 0; f < 4; ++f)
  {
    const Eigen::Vector3d& a = x[(f + 1) % 4];
    twiceArea += (x[(f + 2) % 4] - a).cross(x[(f + 3) % 4] - a).norm();
  }
  const double sixVolume = std::abs((x[2] - x[1]).cross(x[3] - x[1]).dot(x[0] - x[1]));
  return twiceArea > 0.0 ? 2.0 * sixVolume / (3.0 * twiceArea) : 0.0;
}

/// A star's measures with point `p` at `x`: its smallest dihedral angle and
/// its smallest score, the angle or, with a step bound, min(angle, minAngle
/// * step / minStep) (a tetrahedron at half the bound's step scores half the
/// angle bound); both -1 if a tetrahedron is not positive.
struct StarMeasure
{
  double Angle = 180.0;
  double Score = 180.0;
};
StarMeasure MeasureStar(TetMesh& mesh, const std::vector<std::size_t>& star, std::int64_t p, const double x[3],
  double minAngle, double minStep)
{
  double saved[3];
  std::copy(&mesh.Points[3 * p], &mesh.Points[3 * p] + 3, saved);
  std::copy(x, x + 3, &mesh.Points[3 * p]);
  StarMeasure m;
  for (std::size_t t : star)
  {
    const std::int64_t* v = &mesh.Tetrahedra[4 * t];
    if (!(TetSignedVolume(&mesh.Points[3 * v[0]], &mesh.Points[3 * v[1]], &mesh.Points[3 * v[2]],
            &mesh.Points[3 * v[3]]) > 0.0))
    {
      m.Angle = m.Score = -1.0;
      break;
    }
    const double angle = MinDihedral(mesh, t);
    m.Angle = std::min(m.Angle, angle);
    m.Score = std::min(m.Score, minStep > 0.0 ? std::min(angle, minAngle * StepLength(mesh, t) / minStep) : angle);
  }
  std::copy(saved, saved + 3, &mesh.Points[3 * p]);
  return m;
}
/// Flags the free points (ids >= firstFree) of tetrahedra under minAngle or
/// (minStep > 0) under minStep; false if there are none. `thin` holds each
/// tetrahedron's state from the pass before: empty, every tetrahedron is
/// tested; otherwise only those with a point flagged in `moved` (the others'
/// corners have not moved since, so their state stands).
bool MarkSliverPoints(const TetMesh& mesh, std::size_t firstFree, double minAngle, double minStep,
  std::size_t threads, const std::vector<char>& moved, std::vector<char>& thin, std::vector<char>& candidate)
{
  // The thin tetrahedra found on threads (each writes its own flag), their
  // free points flagged after.
  const std::size_t nT = mesh.NumberOfTetrahedra();
  const bool all = thin.size() != nT;
  if (all)
  {
    thin.assign(nT, 0);
  }
  const double cosBound = std::cos(minAngle * M_PI / 180.0);
  ParallelFor(
    nT,
    [&](std::size_t first, std::size_t last) {
      for (std::size_t t = first; t < last; ++t)
      {
        const std::int64_t* v = &mesh.Tetrahedra[4 * t];
        if (!all && std::none_of(v, v + 4, [&](std::int64_t p) { return moved[p] != 0; }))
        {
          continue;
        }
        thin[t] = std::any_of(v, v + 4, [&](std::int64_t p) { return static_cast<std::size_t>(p) >= firstFree; }) &&
          IsThin(mesh, t, cosBound, minStep);
      }
    },
    threads, 20000);
  candidate.assign(mesh.NumberOfPoints(), 0);
  bool any = false;
  for (std::size_t t = 0; t < nT; ++t)
  {
    const std::int64_t* v = &mesh.Tetrahedra[4 * t];
    for (int k = 0; k < 4 && thin[t]; ++k)
    {
      if (static_cast<std::size_t>(v[k]) >= firstFree)
      {
        candidate[v[k]] = 1;
        any = true;
      }
    }
  }
  return any;
}

/// Moves point p to the best of its tries (towards its star's centroid, or
/// compass steps around it) if that raises its star's smallest score
/// (MeasureStar) and keeps its smallest angle at least min(its old one,
/// minAngle).
bool MoveToBestTry(
  TetMesh& mesh, const std::vector<std::size_t>& star, std::size_t p, double minAngle, double minStep)
{
  const std::int64_t id = static_cast<std::int64_t>(p);
  const double x[3] = { mesh.Points[3 * p], mesh.Points[3 * p + 1], mesh.Points[3 * p + 2] };
  const StarMeasure now = MeasureStar(mesh, star, id, x, minAngle, minStep);
  double best = now.Score;
  const double floor = std::min(now.Angle, minAngle);
  // The centroid of the star's other points, and their mean distance from p.
  double c[3] = { 0.0, 0.0, 0.0 };
  double edge = 0.0;
  std::size_t n = 0;
  for (std::size_t t : star)
  {
    for (int k = 0; k < 4; ++k)
    {
      const std::int64_t q = mesh.Tetrahedra[4 * t + k];
      if (q == id)
      {
        continue;
      }
      double d2 = 0.0;
      for (int a = 0; a < 3; ++a)
      {
        c[a] += mesh.Points[3 * q + a];
        d2 += (mesh.Points[3 * q + a] - x[a]) * (mesh.Points[3 * q + a] - x[a]);
      }
      edge += std::sqrt(d2);
      ++n;
    }
  }
  if (n == 0)
  {
    return false;
  }
  edge /= static_cast<double>(n);
  std::vector<std::array<double, 3>> tries;
  for (double f : { 1.0, 0.5, 0.25 })
  {
    tries.push_back({ x[0] + f * (c[0] / n - x[0]), x[1] + f * (c[1] / n - x[1]), x[2] + f * (c[2] / n - x[2]) });
  }
  for (double step = 0.2 * edge; step > 0.01 * edge; step *= 0.5)
  {
    for (int a = 0; a < 3; ++a)
    {
      for (double sign : { 1.0, -1.0 })
      {
        std::array<double, 3> y = { x[0], x[1], x[2] };
        y[a] += sign * step;
        tries.push_back(y);
      }
    }
  }
  const std::array<double, 3>* chosen = nullptr;
  for (const auto& y : tries)
  {
    const StarMeasure m = MeasureStar(mesh, star, id, y.data(), minAngle, minStep);
    if (m.Score > best && m.Angle >= floor)
    {
      best = m.Score;
      chosen = &y;
    }
  }
  if (chosen)
  {
    std::copy(chosen->begin(), chosen->end(), &mesh.Points[3 * p]);
  }
  return chosen != nullptr;
}
}

std::size_t SmoothFreePointsAtSlivers(
  TetMesh& mesh, std::size_t firstFree, double minAngle, int passes, int threads, double minStep)
{
  const std::size_t nP = mesh.NumberOfPoints();
  std::vector<char> moved(nP, 0), movedLastPass(nP, 0), thin, candidate;
  for (int pass = 0; pass < passes &&
       MarkSliverPoints(mesh, firstFree, minAngle, minStep, static_cast<std::size_t>(std::max(0, threads)),
         movedLastPass, thin, candidate);
       ++pass)
  {
    std::fill(movedLastPass.begin(), movedLastPass.end(), char(0));
    // The stars of the flagged points.
    std::vector<std::vector<std::size_t>> star(nP);
    for (std::size_t t = 0; t < mesh.NumberOfTetrahedra(); ++t)
    {
      for (int k = 0; k < 4; ++k)
      {
        const std::int64_t p = mesh.Tetrahedra[4 * t + k];
        if (candidate[p])
        {
          star[p].push_back(t);
        }
      }
    }
    bool improved = false;
    for (std::size_t p = firstFree; p < nP; ++p)
    {
      if (candidate[p] && MoveToBestTry(mesh, star[p], p, minAngle, minStep))
      {
        moved[p] = 1;
        movedLastPass[p] = 1;
        improved = true;
      }
    }
    if (!improved)
    {
      break;
    }
  }
  return static_cast<std::size_t>(std::count(moved.begin(), moved.end(), char(1)));
}
}

namespace ar
{
namespace
{
/// TetFaceNeighbors with the faces' ids in U (32 bits where they fit: the
/// face list is the largest array here, 4 per tetrahedron).
template <typename U>
bool MatchFaces(const std::int64_t* tets, std::size_t nT, std::size_t nV, std::vector<std::int64_t>& neighbor,
  std::string& error, std::size_t threads)
{
  struct Face
  {
    U B, C, TetFace; // the face's two larger ids, and 4 t + f
    bool operator<(const Face& o) const { return B < o.B || (B == o.B && C < o.C); }
  };
  // A tetrahedron's ids sorted, with the corner each came from: face f
  // (opposite corner f) is keyed by the sorted triple left when corner f is
  // dropped, so the face dropping s[0] is in bucket s[1] and the other three
  // in bucket s[0].
  auto sortedTet = [&](std::size_t t, std::array<std::int64_t, 4>& s, std::array<int, 4>& local) {
    std::array<std::pair<std::int64_t, int>, 4> p;
    for (int k = 0; k < 4; ++k)
    {
      p[k] = { tets[4 * t + k], k };
    }
    std::sort(p.begin(), p.end());
    for (int k = 0; k < 4; ++k)
    {
      s[k] = p[k].first;
      local[k] = p[k].second;
    }
  };
  const std::size_t grain = 65536;
  std::vector<std::atomic<std::size_t>> next(nV + 1);
  ParallelFor(
    nV + 1,
    [&](std::size_t first, std::size_t last) {
      for (std::size_t v = first; v < last; ++v)
      {
        next[v].store(0, std::memory_order_relaxed);
      }
    },
    threads, grain);
  ParallelFor(
    nT,
    [&](std::size_t first, std::size_t last) {
      std::array<std::int64_t, 4> s;
      std::array<int, 4> local;
      for (std::size_t t = first; t < last; ++t)
      {
        sortedTet(t, s, local);
        next[static_cast<std::size_t>(s[1]) + 1].fetch_add(1, std::memory_order_relaxed);
        next[static_cast<std::size_t>(s[0]) + 1].fetch_add(3, std::memory_order_relaxed);
      }
    },
    threads, grain);
  std::vector<std::size_t> offset(nV + 1, 0);
  for (std::size_t v = 0; v < nV; ++v)
  {
    offset[v + 1] = offset[v] + next[v + 1].load(std::memory_order_relaxed);
    next[v].store(offset[v], std::memory_order_relaxed); // bucket v's next free slot
  }
  // Filled before read, so not value-initialized (every slot is written once).
  std::unique_ptr<Face[]> faces(new Face[4 * nT]);
  AdviseHugePages(faces.get(), 4 * nT * sizeof(Face));
  ParallelFor(
    nT,
    [&](std::size_t first, std::size_t last) {
      std::array<std::int64_t, 4> s;
      std::array<int, 4> local;
      for (std::size_t t = first; t < last; ++t)
      {
        sortedTet(t, s, local);
        const std::size_t base = 4 * t;
        auto put = [&](std::int64_t key, std::int64_t b, std::int64_t c, int corner) {
          faces[next[static_cast<std::size_t>(key)].fetch_add(1, std::memory_order_relaxed)] =
            Face{ static_cast<U>(b), static_cast<U>(c), static_cast<U>(base + static_cast<std::size_t>(corner)) };
        };
        put(s[1], s[2], s[3], local[0]);
        put(s[0], s[2], s[3], local[1]);
        put(s[0], s[1], s[3], local[2]);
        put(s[0], s[1], s[2], local[3]);
      }
    },
    threads, grain);
  AssignHuge(neighbor, 4 * nT, std::int64_t(-1));
  // Each bucket sorted by the other two ids; a face's entries are then
  // adjacent and each bucket writes its own faces' entries. Where a face is
  // in three tetrahedra or more, the lowest such bucket is reported, on any
  // number of threads.
  std::atomic<std::size_t> firstBad(nV);
  ParallelFor(
    nV,
    [&](std::size_t first, std::size_t last) {
      for (std::size_t v = first; v < last; ++v)
      {
        Face* begin = faces.get() + offset[v];
        Face* end = faces.get() + offset[v + 1];
        std::sort(begin, end);
        for (Face* i = begin; i != end;)
        {
          Face* j = i + 1;
          while (j != end && j->B == i->B && j->C == i->C)
          {
            ++j;
          }
          if (j - i > 2)
          {
            std::size_t seen = firstBad.load();
            while (v < seen && !firstBad.compare_exchange_weak(seen, v))
            {
            }
            return;
          }
          if (j - i == 2)
          {
            neighbor[i->TetFace] = static_cast<std::int64_t>((i + 1)->TetFace / 4);
            neighbor[(i + 1)->TetFace] = static_cast<std::int64_t>(i->TetFace / 4);
          }
          i = j;
        }
      }
    },
    threads, grain);
  const std::size_t bad = firstBad.load();
  if (bad < nV)
  {
    // (the bucket is sorted: its first face in three or more tetrahedra)
    const Face* begin = faces.get() + offset[bad];
    const Face* end = faces.get() + offset[bad + 1];
    std::ptrdiff_t most = 0;
    for (const Face* i = begin; i != end && most <= 2;)
    {
      const Face* j = i + 1;
      while (j != end && j->B == i->B && j->C == i->C)
      {
        ++j;
      }
      most = j - i;
      i = j;
    }
    error = "the volume mesh is not conforming: a face is shared by " + std::to_string(most) + " tetrahedra.";
    neighbor.clear();
    return false;
  }
  return true;
}
}

bool TetFaceNeighbors(const std::int64_t* tets, std::size_t nT, std::size_t nV,
  std::vector<std::int64_t>& neighbor, std::string& error, int threads)
{
  neighbor.clear();
  for (std::size_t k = 0; k < 4 * nT; ++k)
  {
    if (tets[k] < 0 || static_cast<std::size_t>(tets[k]) >= nV)
    {
      error = "tetrahedron " + std::to_string(k / 4) + " refers to a point that does not exist (" +
        std::to_string(tets[k]) + ").";
      return false;
    }
  }
  const std::size_t t = threads > 0 ? static_cast<std::size_t>(threads) : 0;
  if (nV <= std::numeric_limits<std::uint32_t>::max() && 4 * nT <= std::numeric_limits<std::uint32_t>::max())
  {
    return MatchFaces<std::uint32_t>(tets, nT, nV, neighbor, error, t);
  }
  return MatchFaces<std::uint64_t>(tets, nT, nV, neighbor, error, t);
}
}
