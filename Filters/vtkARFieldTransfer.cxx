// SPDX-License-Identifier: BSD-3-Clause
#include "vtkARFieldTransfer.h"
#include "vtkARMeshKernels.h"
#include "vtkARParallel.h"

#include "vtkAbstractArray.h"
#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkDataSetAttributesFieldList.h"
#include "vtkGenericCell.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPThreadLocalObject.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkStaticCellLocator.h"
#include "vtkStaticPointLocator.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <string>

//------------------------------------------------------------------------------
namespace
{
/// One array of a field transfer: as vtkDataSetAttributes::CopyData
/// (CopyTuple: InsertTuple) and InterpolatePoint (InterpolateTuple, or the
/// nearest tuple for an attribute flagged 2) do it, tuple by tuple.
void TransferArray(vtkAbstractArray* from, vtkAbstractArray* to, bool nearest,
  const vtkARFieldTransfer::TupleSources& sources)
{
  const vtkIdType n = sources.Size();
  const int width = sources.Width;
  if (to->GetNumberOfTuples() < n)
  {
    to->SetNumberOfTuples(n); // then InsertTuple and InterpolateTuple write in place, safe on threads
    vtkARParallel::AdviseHugePages(to);
  }
  auto fill = [&](vtkIdType b, vtkIdType e, vtkIdList* ids) {
    for (vtkIdType i = b; i < e; ++i)
    {
      const vtkIdType* src = &sources.Ids[static_cast<std::size_t>(i) * width];
      if (src[0] < 0)
      {
        continue;
      }
      if (width == 1 || src[1] < 0)
      {
        to->InsertTuple(i, src[0], from);
        continue;
      }
      double* w = const_cast<double*>(&sources.Weights[static_cast<std::size_t>(i) * width]);
      int m = 2; // the tuples interpolated: up to the first negative id
      while (m < width && src[m] >= 0)
      {
        ++m;
      }
      if (nearest)
      {
        // vtkDataSetAttributes::InterpolatePoint's rule, its integer
        // maxWeight included (the last tuple of positive weight wins).
        vtkIdType maxId = src[0];
        vtkIdType maxWeight = 0;
        for (int j = 0; j < m; ++j)
        {
          if (w[j] > maxWeight)
          {
            maxWeight = static_cast<vtkIdType>(w[j]);
            maxId = src[j];
          }
        }
        to->InsertTuple(i, maxId, from);
        continue;
      }
      ids->SetNumberOfIds(m);
      std::copy(src, src + m, ids->GetPointer(0));
      to->InterpolateTuple(i, ids, from, w);
    }
  };
  if (vtkDataArray::SafeDownCast(from) && vtkDataArray::SafeDownCast(to))
  {
    vtkSMPThreadLocalObject<vtkIdList> local;
    vtkSMPTools::For(0, n, [&](vtkIdType b, vtkIdType e) {
      fill(b, e, local.Local());
    });
  }
  else
  {
    vtkNew<vtkIdList> ids;
    fill(0, n, ids);
  }
  to->Modified();
}

/// Whether `to` interpolates the attribute that its array `index` is by
/// taking the nearest tuple (vtkDataSetAttributes' INTERPOLATE flag 2).
bool NearestFor(vtkDataSetAttributes* attributes, int index, vtkDataSetAttributes* to)
{
  const int attribute = attributes->IsArrayAnAttribute(index);
  return attribute != -1 && to->GetCopyAttribute(attribute, vtkDataSetAttributes::INTERPOLATE) == 2;
}
}

//------------------------------------------------------------------------------
void vtkARFieldTransfer::TransferData(
  vtkDataSetAttributes* from, vtkDataSetAttributes* to, const TupleSources& sources)
{
  // CopyAllocate and InterpolateAllocate give each output array the name of
  // the input array it is made for: pair them by name when names are unique.
  std::map<std::string, int> named;
  bool unique = true;
  for (int k = 0; k < from->GetNumberOfArrays() && unique; ++k)
  {
    const char* name = from->GetAbstractArray(k)->GetName();
    unique = name && *name && named.emplace(name, k).second;
  }
  std::vector<std::pair<int, int>> pairs; // (from, to) array indices
  for (int k = 0; k < to->GetNumberOfArrays() && unique; ++k)
  {
    const char* name = to->GetAbstractArray(k)->GetName();
    const auto it = name ? named.find(name) : named.end();
    unique = it != named.end();
    if (unique)
    {
      pairs.emplace_back(it->second, k);
    }
  }
  if (unique)
  {
    for (const auto& p : pairs)
    {
      TransferArray(from->GetAbstractArray(p.first), to->GetAbstractArray(p.second),
        NearestFor(to, p.second, to), sources);
    }
    return;
  }
  // Ambiguous names: vtkDataSetAttributes' own calls, tuple by tuple.
  vtkNew<vtkIdList> ids;
  const int width = sources.Width;
  for (vtkIdType i = 0; i < sources.Size(); ++i)
  {
    const vtkIdType* src = &sources.Ids[static_cast<std::size_t>(i) * width];
    if (src[0] < 0)
    {
      continue;
    }
    if (width == 1 || src[1] < 0)
    {
      to->CopyData(from, src[0], i);
      continue;
    }
    int m = 2;
    while (m < width && src[m] >= 0)
    {
      ++m;
    }
    ids->SetNumberOfIds(m);
    std::copy(src, src + m, ids->GetPointer(0));
    to->InterpolatePoint(from, i, ids, const_cast<double*>(&sources.Weights[static_cast<std::size_t>(i) * width]));
  }
}

//------------------------------------------------------------------------------
void vtkARFieldTransfer::TransferData(const vtkDataSetAttributesFieldList& list, int index,
  vtkDataSetAttributes* from, vtkDataSetAttributes* to, const TupleSources& sources)
{
  list.TransformData(index, from, to, [&](vtkAbstractArray* in, vtkAbstractArray* out) {
    // vtkDataSetAttributesFieldList::InterpolatePoint asks the input whether
    // the array is an attribute, the output how to interpolate it.
    int k = 0;
    while (k < from->GetNumberOfArrays() && from->GetAbstractArray(k) != in)
    {
      ++k;
    }
    TransferArray(in, out, k < from->GetNumberOfArrays() && NearestFor(from, k, to), sources);
  });
}

//------------------------------------------------------------------------------
struct vtkARFieldTransfer::TetLocator::vtkInternals
{
  static constexpr double Tolerance = 1e-10; // on the barycentric coordinates
  static constexpr int MaxSteps = 1000;

  vtkSmartPointer<vtkUnstructuredGrid> Tets;
  vtkARMeshKernels::MeshView Mesh;
  std::vector<vtkIdType> LinkOffsets, Links; // the tetrahedra of each point, by increasing id
  vtkNew<vtkPolyData> VertexSet;             // the points used by a tetrahedron
  std::vector<vtkIdType> VertexId;           // their ids in Tets
  vtkNew<vtkStaticPointLocator> Vertices;
  mutable vtkSmartPointer<vtkStaticCellLocator> Cells; // the fallback, built when first needed
  mutable vtkIdType Fallbacks = 0;

  /// x's barycentric coordinates in cell c (false: a flat cell).
  bool Barycentric(vtkIdType c, const double x[3], double b[4]) const
  {
    const vtkIdType* v = this->Mesh.CellPoints(c);
    const double* p[4] = { this->Mesh.X + 3 * v[0], this->Mesh.X + 3 * v[1], this->Mesh.X + 3 * v[2],
      this->Mesh.X + 3 * v[3] };
    double sum = 0.0;
    for (int i = 0; i < 4; ++i)
    {
      // the signed volume of the tetrahedron with x in place of corner i
      const double* q[4] = { p[0], p[1], p[2], p[3] };
      q[i] = x;
      const double a[3] = { q[1][0] - q[0][0], q[1][1] - q[0][1], q[1][2] - q[0][2] };
      const double e[3] = { q[2][0] - q[0][0], q[2][1] - q[0][1], q[2][2] - q[0][2] };
      const double f[3] = { q[3][0] - q[0][0], q[3][1] - q[0][1], q[3][2] - q[0][2] };
      b[i] = a[0] * (e[1] * f[2] - e[2] * f[1]) + a[1] * (e[2] * f[0] - e[0] * f[2]) +
        a[2] * (e[0] * f[1] - e[1] * f[0]);
      sum += b[i];
    }
    if (!(std::abs(sum) > 0.0))
    {
      return false;
    }
    for (int i = 0; i < 4; ++i)
    {
      b[i] /= sum;
    }
    return true;
  }

  /// The cell across the face of c opposite its corner i, -1 if none: the
  /// cell other than c in all three corners' (sorted) links, which are
  /// contiguous, so the cells themselves need not be read.
  vtkIdType Neighbour(vtkIdType c, int i) const
  {
    const vtkIdType* v = this->Mesh.CellPoints(c);
    const vtkIdType* at[3];
    const vtkIdType* end[3];
    for (int k = 0; k < 3; ++k)
    {
      const vtkIdType p = v[(i + 1 + k) % 4];
      at[k] = this->Links.data() + this->LinkOffsets[p];
      end[k] = this->Links.data() + this->LinkOffsets[p + 1];
    }
    while (at[0] < end[0] && at[1] < end[1] && at[2] < end[2])
    {
      const vtkIdType a = *at[0], b = *at[1], d = *at[2];
      if (a == b && b == d)
      {
        if (a != c)
        {
          return a;
        }
        ++at[0], ++at[1], ++at[2];
        continue;
      }
      const vtkIdType lo = std::max(a, std::max(b, d));
      for (int k = 0; k < 3; ++k)
      {
        at[k] = std::lower_bound(at[k], end[k], lo);
      }
    }
    return -1;
  }

  vtkIdType CellOfPoint(vtkIdType p) const
  {
    return p >= 0 && p + 1 < static_cast<vtkIdType>(this->LinkOffsets.size()) &&
        this->LinkOffsets[p] < this->LinkOffsets[p + 1]
      ? this->Links[this->LinkOffsets[p]]
      : -1;
  }

  /// Of the cells that hold x on a face, an edge or a corner of c (b: its
  /// barycentric coordinates in c), the one that comes first by its
  /// corners' coordinates (sorted), and its coordinates in `w`: so that the
  /// answer does not depend on the side the walk came from (a new cell's
  /// centre within round-off of an old face, found from another start in
  /// the distributed run's gathered cells, took the other side's value).
  vtkIdType Canonical(vtkIdType c, const double x[3], const double b[4], double w[4]) const
  {
    // The cells with every corner of c that weighs (they hold x's support).
    std::vector<vtkIdType> support;
    const vtkIdType* v = this->Mesh.CellPoints(c);
    for (int k = 0; k < 4; ++k)
    {
      if (b[k] > Tolerance)
      {
        support.push_back(v[k]);
      }
    }
    auto key = [&](vtkIdType cell) {
      const vtkIdType* q = this->Mesh.CellPoints(cell);
      std::array<std::array<double, 3>, 4> corners;
      for (int k = 0; k < 4; ++k)
      {
        std::copy(this->Mesh.X + 3 * q[k], this->Mesh.X + 3 * q[k] + 3, corners[k].begin());
      }
      std::sort(corners.begin(), corners.end());
      return corners;
    };
    vtkIdType best = c;
    auto bestKey = key(c);
    std::copy(b, b + 4, w);
    const vtkIdType* first = this->Links.data() + this->LinkOffsets[support[0]];
    const vtkIdType* last = this->Links.data() + this->LinkOffsets[support[0] + 1];
    for (const vtkIdType* a = first; a != last; ++a)
    {
      const vtkIdType* q = this->Mesh.CellPoints(*a);
      if (*a == c || !std::all_of(support.begin(), support.end(), [&](vtkIdType p) { return std::find(q, q + 4, p) != q + 4; }))
      {
        continue;
      }
      double e[4];
      if (!this->Barycentric(*a, x, e) || *std::min_element(e, e + 4) < -Tolerance)
      {
        continue;
      }
      const auto k = key(*a);
      if (k < bestKey)
      {
        best = *a;
        bestKey = k;
        std::copy(e, e + 4, w);
      }
    }
    return best;
  }

  /// The walk from `start` (< 0: the nearest vertex's cell); -1 if it fails.
  vtkIdType Walk(const double x[3], vtkIdType start, double w[4]) const
  {
    vtkIdType c = start;
    if (c < 0)
    {
      const vtkIdType v = this->Vertices->FindClosestPoint(x);
      c = v >= 0 ? this->CellOfPoint(this->VertexId[v]) : -1;
    }
    for (int step = 0; c >= 0 && step < MaxSteps; ++step)
    {
      double b[4];
      if (!this->Barycentric(c, x, b))
      {
        return -1;
      }
      int order[4] = { 0, 1, 2, 3 };
      std::sort(order, order + 4, [&](int i, int j) { return b[i] < b[j] || (b[i] == b[j] && i < j); });
      if (b[order[0]] >= -Tolerance)
      {
        if (b[order[0]] > Tolerance)
        {
          std::copy(b, b + 4, w);
          return c;
        }
        return this->Canonical(c, x, b, w);
      }
      vtkIdType next = -1;
      for (int k = 0; k < 4 && next < 0 && b[order[k]] < -Tolerance; ++k)
      {
        next = this->Neighbour(c, order[k]);
      }
      c = next;
    }
    return -1;
  }
};

vtkARFieldTransfer::TetLocator::TetLocator()
  : Internals(new vtkInternals)
{
}

vtkARFieldTransfer::TetLocator::~TetLocator() = default;

void vtkARFieldTransfer::TetLocator::Build(vtkUnstructuredGrid* tets)
{
  vtkInternals& in = *this->Internals;
  in.Tets = tets;
  in.Cells = nullptr;
  std::string error;
  in.Mesh.Build(tets, error);
  const vtkIdType np = in.Mesh.NumberOfPoints, nc = in.Mesh.NumberOfCells;
  // Point-to-cell links, each point's cells by increasing id (so that the
  // walk's start does not depend on how the links were built).
  vtkARMeshKernels::PointCells(in.Mesh, nullptr, in.LinkOffsets, in.Links);
  // The used points, for the nearest-vertex start.
  in.VertexId.clear();
  for (vtkIdType p = 0; p < np; ++p)
  {
    if (in.LinkOffsets[p] < in.LinkOffsets[p + 1])
    {
      in.VertexId.push_back(p);
    }
  }
  vtkNew<vtkPoints> used;
  used->SetDataTypeToDouble();
  used->SetNumberOfPoints(static_cast<vtkIdType>(in.VertexId.size()));
  for (std::size_t k = 0; k < in.VertexId.size(); ++k)
  {
    used->SetPoint(static_cast<vtkIdType>(k), in.Mesh.X + 3 * in.VertexId[k]);
  }
  in.VertexSet->Initialize();
  in.VertexSet->SetPoints(used);
  in.Vertices->SetDataSet(in.VertexSet);
  in.Vertices->BuildLocator();
}

void vtkARFieldTransfer::TetLocator::Locate(
  vtkIdType n, const double* x, const vtkIdType* start, vtkIdType* cell, double* weights) const
{
  const vtkInternals& in = *this->Internals;
  in.Fallbacks = 0;
  if (in.Mesh.NumberOfCells == 0)
  {
    std::fill(cell, cell + n, -1);
    return;
  }
  // The queries in Morton order of their points, so that neighbouring
  // queries walk through the same cells (memory, not arithmetic, is the
  // cost); each answer is independent of the others, so the order changes
  // no result.
  double lo[3], hi[3];
  {
    double bounds[6];
    in.Tets->GetPoints()->GetBounds(bounds);
    for (int d = 0; d < 3; ++d)
    {
      lo[d] = bounds[2 * d];
      hi[d] = bounds[2 * d + 1] > bounds[2 * d] ? bounds[2 * d + 1] : bounds[2 * d] + 1.0;
    }
  }
  std::vector<std::pair<std::uint64_t, vtkIdType>> order(static_cast<std::size_t>(n));
  vtkSMPTools::For(0, n, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType q = b; q < e; ++q)
    {
      std::uint64_t key = 0;
      for (int d = 0; d < 3; ++d)
      {
        const double t = std::min(std::max((x[3 * q + d] - lo[d]) / (hi[d] - lo[d]), 0.0), 1.0);
        std::uint64_t v = static_cast<std::uint64_t>(t * 2097151.0); // 21 bits
        // spread the 21 bits to every third position
        v = (v | (v << 32)) & 0x1f00000000ffffULL;
        v = (v | (v << 16)) & 0x1f0000ff0000ffULL;
        v = (v | (v << 8)) & 0x100f00f00f00f00fULL;
        v = (v | (v << 4)) & 0x10c30c30c30c30c3ULL;
        v = (v | (v << 2)) & 0x1249249249249249ULL;
        key |= v << d;
      }
      order[q] = { key, q };
    }
  });
  vtkSMPTools::Sort(order.begin(), order.end());
  // Fixed blocks of consecutive queries (the same whatever the number of
  // threads): a query with no start of its own walks from the previous
  // query's cell in its block, the first from its nearest vertex's; a walk
  // that fails from a given start is tried again from the nearest vertex.
  const vtkIdType block = 256;
  vtkSMPTools::For(0, (n + block - 1) / block, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType k0 = b * block; k0 < std::min(n, e * block); k0 += block)
    {
      vtkIdType previous = -1;
      for (vtkIdType k = k0; k < std::min(n, k0 + block); ++k)
      {
        const vtkIdType q = order[k].second;
        const vtkIdType from = start && start[q] >= 0 ? start[q] : previous;
        double w[4];
        cell[q] = in.Walk(x + 3 * q, from, w);
        if (cell[q] < 0 && from >= 0)
        {
          cell[q] = in.Walk(x + 3 * q, -1, w);
        }
        if (cell[q] >= 0)
        {
          previous = cell[q];
          if (weights)
          {
            std::copy(w, w + 4, weights + 4 * q);
          }
        }
      }
    }
  });
  // The walks that failed, in query order on this thread.
  vtkNew<vtkGenericCell> gcell;
  for (vtkIdType q = 0; q < n; ++q)
  {
    if (cell[q] >= 0)
    {
      continue;
    }
    ++in.Fallbacks;
    if (!in.Cells)
    {
      in.Cells = vtkSmartPointer<vtkStaticCellLocator>::New();
      in.Cells->SetDataSet(in.Tets);
      in.Cells->BuildLocator();
    }
    double p[3] = { x[3 * q], x[3 * q + 1], x[3 * q + 2] };
    double pcoords[3], vtkWeights[VTK_CELL_SIZE];
    int subId;
    cell[q] = in.Cells->FindCell(p, 0.0, gcell, subId, pcoords, vtkWeights);
    if (cell[q] < 0)
    {
      double closest[3], dist2;
      in.Cells->FindClosestPoint(p, closest, gcell, cell[q], subId, dist2);
      std::copy(closest, closest + 3, p);
    }
    double w[4] = { 0.25, 0.25, 0.25, 0.25 };
    if (cell[q] >= 0 && weights && in.Barycentric(cell[q], p, w))
    {
      std::copy(w, w + 4, weights + 4 * q);
    }
    else if (weights)
    {
      std::fill(weights + 4 * q, weights + 4 * q + 4, 0.25);
    }
  }
}

vtkIdType vtkARFieldTransfer::TetLocator::CellOfPoint(vtkIdType p) const
{
  return this->Internals->CellOfPoint(p);
}

const vtkIdType* vtkARFieldTransfer::TetLocator::CellPoints(vtkIdType c) const
{
  return this->Internals->Mesh.CellPoints(c);
}

vtkIdType vtkARFieldTransfer::TetLocator::LastFallbacks() const
{
  return this->Internals->Fallbacks;
}
