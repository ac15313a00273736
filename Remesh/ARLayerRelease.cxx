// SPDX-License-Identifier: BSD-3-Clause
#include "ARLayerRelease.h"

#include "ARTetGeometry.h"
#include "ARUnionFind.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace ar
{
namespace
{
/// A face by its sorted point ids (a triangle's fourth id is -1), and who
/// has it: a cell (>= 0), a tetrahedron or another cell (-1), or an other
/// cell's quadrilateral (-2).
struct FaceUse
{
  std::array<std::int64_t, 4> Key;
  std::int64_t User;
  bool operator<(const FaceUse& o) const { return Key < o.Key || (Key == o.Key && User < o.User); }
};

FaceUse Use(std::initializer_list<std::int64_t> ids, std::int64_t user)
{
  FaceUse f{ { -1, -1, -1, -1 }, user };
  std::copy(ids.begin(), ids.end(), f.Key.begin());
  std::sort(f.Key.begin(), f.Key.begin() + ids.size());
  return f;
}

/// The faces of cell `c` (pts: its ids), quads first.
void CellFaces(const std::int64_t* p, int size, std::int64_t c, std::vector<FaceUse>& quads, std::vector<FaceUse>& tris)
{
  if (size == 6)
  {
    quads.push_back(Use({ p[0], p[1], p[4], p[3] }, c));
    quads.push_back(Use({ p[1], p[2], p[5], p[4] }, c));
    quads.push_back(Use({ p[2], p[0], p[3], p[5] }, c));
    tris.push_back(Use({ p[0], p[1], p[2] }, c));
    tris.push_back(Use({ p[3], p[4], p[5] }, c));
  }
  else
  {
    quads.push_back(Use({ p[0], p[1], p[2], p[3] }, c));
    for (int k = 0; k < 4; ++k)
    {
      tris.push_back(Use({ p[k], p[(k + 1) % 4], p[4] }, c));
    }
  }
}

/// The cell split by the smallest-id rule (ARLayerRelease.h); false where a
/// tetrahedron would not be positive, or the three (two) not alike.
bool Split(const double* X, const std::int64_t* p, int size, std::vector<std::array<std::int64_t, 4>>& out)
{
  out.clear();
  if (size == 6)
  {
    // Rotate (and, when it is on top, flip) so that the smallest id is q0.
    const int m = static_cast<int>(std::min_element(p, p + 6) - p);
    std::array<std::int64_t, 6> q;
    const int r = m % 3;
    const bool top = m >= 3;
    for (int k = 0; k < 3; ++k)
    {
      q[k] = p[(top ? 3 : 0) + (r + k) % 3];
      q[k + 3] = p[(top ? 0 : 3) + (r + k) % 3];
    }
    if (std::min(q[1], q[5]) < std::min(q[2], q[4]))
    {
      out = { { q[0], q[1], q[2], q[5] }, { q[0], q[1], q[5], q[4] }, { q[0], q[4], q[5], q[3] } };
    }
    else
    {
      out = { { q[0], q[1], q[2], q[4] }, { q[0], q[4], q[2], q[5] }, { q[0], q[4], q[5], q[3] } };
    }
  }
  else
  {
    const int m = static_cast<int>(std::min_element(p, p + 4) - p);
    if (m % 2 == 0)
    {
      out = { { p[0], p[1], p[2], p[4] }, { p[0], p[2], p[3], p[4] } };
    }
    else
    {
      out = { { p[1], p[2], p[3], p[4] }, { p[1], p[3], p[0], p[4] } };
    }
  }
  // The sign of each, against the cell's size: all alike and clearly nonzero.
  double longest = 0.0;
  for (int i = 0; i < size; ++i)
  {
    for (int j = i + 1; j < size; ++j)
    {
      double d2 = 0.0;
      for (int k = 0; k < 3; ++k)
      {
        const double d = X[3 * p[i] + k] - X[3 * p[j] + k];
        d2 += d * d;
      }
      longest = std::max(longest, d2);
    }
  }
  const double floor = 1e-12 * std::pow(longest, 1.5);
  int sign = 0;
  for (auto& t : out)
  {
    const double v = TetSignedVolume(&X[3 * t[0]], &X[3 * t[1]], &X[3 * t[2]], &X[3 * t[3]]);
    const int s = v > floor ? 1 : v < -floor ? -1 : 0;
    if (s == 0 || (sign != 0 && s != sign))
    {
      return false;
    }
    sign = s;
  }
  if (sign < 0)
  {
    for (auto& t : out)
    {
      std::swap(t[1], t[2]);
    }
  }
  return true;
}
}

LayerRelease ReleaseFloatingLayers(const double* points, const std::int64_t* tets, std::size_t nTets,
  const LayerCells& cells, const std::vector<std::int64_t>& otherFaces)
{
  LayerRelease out;
  const std::size_t n = cells.Sizes.size();
  out.Group.assign(n, -1);
  if (n == 0)
  {
    return out;
  }
  std::vector<std::size_t> first(n + 1, 0);
  for (std::size_t c = 0; c < n; ++c)
  {
    first[c + 1] = first[c] + static_cast<std::size_t>(cells.Sizes[c]);
  }
  // ---- The faces: of the cells, of the other cells, of the tetrahedra on
  // the cells' points.
  std::vector<FaceUse> quads, tris;
  std::int64_t maxId = -1;
  for (std::size_t c = 0; c < n; ++c)
  {
    CellFaces(&cells.Ids[first[c]], cells.Sizes[c], static_cast<std::int64_t>(c), quads, tris);
    for (std::size_t k = first[c]; k < first[c + 1]; ++k)
    {
      maxId = std::max(maxId, cells.Ids[k]);
    }
  }
  std::vector<char> onCell(static_cast<std::size_t>(maxId + 1), 0);
  for (const std::int64_t id : cells.Ids)
  {
    onCell[id] = 1;
  }
  auto on = [&](std::int64_t id) { return id <= maxId && onCell[id]; };
  for (std::size_t pos = 0; pos < otherFaces.size();)
  {
    const auto m = static_cast<std::size_t>(otherFaces[pos]);
    const std::int64_t* f = &otherFaces[pos + 1];
    if (m == 3 && on(f[0]) && on(f[1]) && on(f[2]))
    {
      tris.push_back(Use({ f[0], f[1], f[2] }, -1));
    }
    else if (m == 4 && on(f[0]) && on(f[1]) && on(f[2]) && on(f[3]))
    {
      quads.push_back(Use({ f[0], f[1], f[2], f[3] }, -2));
    }
    pos += m + 1;
  }
  static const int tetFace[4][3] = { { 1, 2, 3 }, { 0, 2, 3 }, { 0, 1, 3 }, { 0, 1, 2 } };
  for (std::size_t t = 0; t < nTets; ++t)
  {
    const std::int64_t* v = &tets[4 * t];
    for (const auto& f : tetFace)
    {
      if (on(v[f[0]]) && on(v[f[1]]) && on(v[f[2]]))
      {
        tris.push_back(Use({ v[f[0]], v[f[1]], v[f[2]] }, -1));
      }
    }
  }
  std::sort(quads.begin(), quads.end());
  std::sort(tris.begin(), tris.end());

  // ---- Groups through shared quads; a quad of one cell only (the domain
  // boundary), of three, or of an other cell locks its group.
  UnionFind groups(n);
  std::vector<char> locked(n, 0);
  for (std::size_t i = 0; i < quads.size();)
  {
    std::size_t j = i;
    while (j < quads.size() && quads[j].Key == quads[i].Key)
    {
      ++j;
    }
    // Users sort ascending: an other cell's quad (-2) comes first.
    const bool bad = (j - i) != 2 || quads[i].User < 0;
    for (std::size_t k = i; k < j; ++k)
    {
      if (quads[k].User >= 0)
      {
        locked[quads[k].User] |= bad ? 1 : 0;
        groups.Union(quads[k].User, quads[j - 1].User); // the last has the largest user, a cell
      }
    }
    i = j;
  }
  // A triangle of one 3-D cell only is on the domain boundary.
  for (std::size_t i = 0; i < tris.size();)
  {
    std::size_t j = i;
    while (j < tris.size() && tris[j].Key == tris[i].Key)
    {
      ++j;
    }
    if (j - i == 1 && tris[i].User >= 0)
    {
      locked[tris[i].User] = 1;
    }
    i = j;
  }
  // ---- A group with a locked cell stays locked; the others split.
  std::vector<char> groupLocked(n, 0);
  for (std::size_t c = 0; c < n; ++c)
  {
    if (locked[c])
    {
      groupLocked[groups.Find(static_cast<std::int64_t>(c))] = 1;
    }
  }
  std::vector<std::vector<std::array<std::int64_t, 4>>> split(n);
  for (std::size_t c = 0; c < n; ++c)
  {
    const std::int64_t root = groups.Find(static_cast<std::int64_t>(c));
    if (!groupLocked[root] && !Split(points, &cells.Ids[first[c]], cells.Sizes[c], split[c]))
    {
      groupLocked[root] = 1;
    }
  }
  std::vector<std::int64_t> idOfRoot(n, -1);
  for (std::size_t c = 0; c < n; ++c)
  {
    const std::int64_t root = groups.Find(static_cast<std::int64_t>(c));
    if (groupLocked[root])
    {
      continue;
    }
    if (idOfRoot[root] < 0)
    {
      idOfRoot[root] = out.NumberOfGroups++;
    }
    out.Group[c] = idOfRoot[root];
    for (const auto& t : split[c])
    {
      out.Tetrahedra.insert(out.Tetrahedra.end(), t.begin(), t.end());
      out.TetrahedronCell.push_back(static_cast<std::int64_t>(c));
    }
  }
  return out;
}
}
