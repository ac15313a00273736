// SPDX-License-Identifier: BSD-3-Clause
#include "vtkARInputChecks.h"

#include "vtkArrayDispatch.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkDataArrayRange.h"
#include "vtkDoubleArray.h"
#include "vtkGenericCell.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkSMPTools.h"
#include "vtkStaticPointLocator.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <vtksys/SystemInformation.hxx>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

namespace
{
bool Unbounded(double hi)
{
  return hi >= static_cast<double>(VTK_INT_MAX);
}

/// A 3-D cell type (explicit: vtkCellTypes::GetDimension builds a cell per call).
bool IsVolumeType(int type)
{
  switch (type)
  {
    case VTK_TETRA:
    case VTK_VOXEL:
    case VTK_HEXAHEDRON:
    case VTK_WEDGE:
    case VTK_PYRAMID:
    case VTK_PENTAGONAL_PRISM:
    case VTK_HEXAGONAL_PRISM:
    case VTK_POLYHEDRON:
    case VTK_CONVEX_POINT_SET:
    case VTK_QUADRATIC_TETRA:
    case VTK_QUADRATIC_HEXAHEDRON:
    case VTK_QUADRATIC_WEDGE:
    case VTK_QUADRATIC_PYRAMID:
    case VTK_TRIQUADRATIC_HEXAHEDRON:
      return true;
    default:
      return false;
  }
}
}

//------------------------------------------------------------------------------
vtkARInputChecks::Properties& vtkARInputChecks::Properties::Range(
  const char* name, double value, double lo, bool loOpen, double hi, const char* meaning)
{
  const bool aboveLo = loOpen ? value > lo : value >= lo;
  const bool belowHi = Unbounded(hi) ? std::isfinite(value) : value <= hi;
  if (aboveLo && belowHi)
  {
    return *this;
  }
  this->Text << name << " is " << value << "; it must ";
  if (Unbounded(hi))
  {
    this->Text << (loOpen ? "be greater than " : "be at least ") << lo << " (and finite)";
  }
  else
  {
    this->Text << "lie in " << (loOpen ? "(" : "[") << lo << ", " << hi << "]";
  }
  if (meaning && *meaning)
  {
    this->Text << " (" << meaning << ")";
  }
  this->Text << ". ";
  return *this;
}

vtkARInputChecks::Properties& vtkARInputChecks::Properties::InRange(
  const char* name, double value, double lo, double hi, const char* meaning)
{
  return this->Range(name, value, lo, false, hi, meaning);
}

vtkARInputChecks::Properties& vtkARInputChecks::Properties::AboveAndAtMost(
  const char* name, double value, double lo, double hi, const char* meaning)
{
  return this->Range(name, value, lo, true, hi, meaning);
}

vtkARInputChecks::Properties& vtkARInputChecks::Properties::OneOf(
  const char* name, int value, std::initializer_list<const char*> names)
{
  if (value >= 0 && value < static_cast<int>(names.size()))
  {
    return *this;
  }
  this->Text << name << " is " << value << "; it must be ";
  int k = 0;
  for (const char* n : names)
  {
    this->Text << (k == 0 ? "" : (k + 1 == static_cast<int>(names.size()) ? " or " : ", ")) << k << " ("
               << n << ")";
    ++k;
  }
  this->Text << ". ";
  return *this;
}

vtkARInputChecks::Properties& vtkARInputChecks::Properties::Add(const std::string& sentence)
{
  if (!sentence.empty())
  {
    this->Text << sentence << (sentence.back() == ' ' ? "" : " ");
  }
  return *this;
}

//------------------------------------------------------------------------------
namespace
{
struct NonFiniteWorker
{
  template <typename ArrayT>
  void operator()(ArrayT* array, vtkIdType& first, vtkIdType& count)
  {
    const auto tuples = vtk::DataArrayTupleRange<3>(array);
    const vtkIdType n = static_cast<vtkIdType>(tuples.size());
    std::atomic<vtkIdType> lowest(n), bad(0);
    vtkSMPTools::For(0, n, [&](vtkIdType b, vtkIdType e) {
      vtkIdType mine = n, many = 0;
      for (vtkIdType i = b; i < e; ++i)
      {
        const auto t = tuples[i];
        if (!std::isfinite(static_cast<double>(t[0])) || !std::isfinite(static_cast<double>(t[1])) ||
          !std::isfinite(static_cast<double>(t[2])))
        {
          mine = std::min(mine, i);
          ++many;
        }
      }
      vtkIdType seen = lowest.load();
      while (mine < seen && !lowest.compare_exchange_weak(seen, mine))
      {
      }
      bad += many;
    });
    first = lowest.load() < n ? lowest.load() : -1;
    count = bad.load();
  }
};

void FindNonFinite(vtkDataArray* data, vtkIdType& first, vtkIdType& count)
{
  first = -1;
  count = 0;
  if (!data || data->GetNumberOfTuples() == 0)
  {
    return;
  }
  NonFiniteWorker worker;
  if (!vtkArrayDispatch::Dispatch::Execute(data, worker, first, count))
  {
    worker(data, first, count);
  }
}

std::string NonFiniteMessage(vtkIdType first, vtkIdType count, const double x[3], const char* what)
{
  if (first < 0)
  {
    return std::string();
  }
  std::ostringstream msg;
  msg << "Point " << first << " of " << what << " has a non-finite coordinate (NaN or Inf): (" << x[0] << ", "
      << x[1] << ", " << x[2] << ")";
  if (count > 1)
  {
    msg << ", and " << (count - 1) << " more point" << (count > 2 ? "s" : "") << " too";
  }
  msg << ": every coordinate must be finite. ";
  return msg.str();
}
}

vtkIdType vtkARInputChecks::FirstNonFinitePoint(vtkPoints* points)
{
  vtkIdType first, count;
  FindNonFinite(points ? points->GetData() : nullptr, first, count);
  return first;
}

vtkIdType vtkARInputChecks::FirstNonFinitePoint(const double* xyz, vtkIdType n)
{
  std::atomic<vtkIdType> lowest(n);
  vtkSMPTools::For(0, n, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType i = b; i < e; ++i)
    {
      const double* x = xyz + 3 * i;
      if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
      {
        vtkIdType seen = lowest.load();
        while (i < seen && !lowest.compare_exchange_weak(seen, i))
        {
        }
        return;
      }
    }
  });
  return lowest.load() < n ? lowest.load() : -1;
}

std::string vtkARInputChecks::NonFinitePoints(vtkDataSet* data, const char* what)
{
  auto* set = vtkPointSet::SafeDownCast(data);
  if (!set || !set->GetPoints())
  {
    return std::string();
  }
  vtkIdType first, count;
  FindNonFinite(set->GetPoints()->GetData(), first, count);
  double x[3] = { 0.0, 0.0, 0.0 };
  if (first >= 0)
  {
    set->GetPoints()->GetPoint(first, x);
  }
  return NonFiniteMessage(first, count, x, what);
}

std::string vtkARInputChecks::NonFinitePoints(const double* xyz, vtkIdType n, const char* what)
{
  const vtkIdType first = FirstNonFinitePoint(xyz, n);
  vtkIdType count = 0;
  for (vtkIdType i = first < 0 ? n : first; i < n; ++i)
  {
    const double* x = xyz + 3 * i;
    count += (std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2])) ? 0 : 1;
  }
  return NonFiniteMessage(first, count, first >= 0 ? xyz + 3 * first : nullptr, what);
}

//------------------------------------------------------------------------------
std::string vtkARInputChecks::DuplicatedPoints(vtkUnstructuredGrid* grid)
{
  if (!grid || !grid->GetPoints() || grid->GetNumberOfPoints() < 2 || grid->GetNumberOfCells() == 0)
  {
    return std::string();
  }
  const vtkIdType n = grid->GetNumberOfPoints();
  vtkNew<vtkStaticPointLocator> locator;
  locator->SetDataSet(grid);
  locator->BuildLocator();
  std::vector<vtkIdType> merged(n);
  locator->MergePoints(0.0, merged.data()); // exact coincidence
  bool any = false;
  for (vtkIdType p = 0; p < n && !any; ++p)
  {
    any = merged[p] != p;
  }
  if (!any)
  {
    return std::string(); // no two points at the same place (the usual case: nothing more to do)
  }
  // The points 3-D cells use (orphans and points of 2-D patch faces only do
  // not make a crack).
  std::vector<char> used(n, 0);
  vtkNew<vtkIdList> ids;
  {
    vtkUnsignedCharArray* types = grid->GetCellTypesArray();
    auto cells = vtk::TakeSmartPointer(grid->GetCells()->NewIterator());
    vtkIdType c = 0, npts;
    const vtkIdType* pts;
    for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell(), ++c)
    {
      if (IsVolumeType(types->GetValue(c)))
      {
        cells->GetCurrentCell(npts, pts);
        for (vtkIdType k = 0; k < npts; ++k)
        {
          used[pts[k]] = 1;
        }
      }
    }
  }
  // Per representative: the first used point there; a second one is a duplicate.
  std::vector<vtkIdType> firstUsed(n, -1);
  std::vector<char> duplicate(n, 0);
  vtkIdType duplicates = 0, example = -1, twin = -1;
  double lo[3] = { VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, VTK_DOUBLE_MAX };
  double hi[3] = { -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX };
  for (vtkIdType p = 0; p < n; ++p)
  {
    if (!used[p])
    {
      continue;
    }
    vtkIdType& f = firstUsed[merged[p]];
    if (f < 0)
    {
      f = p;
      continue;
    }
    ++duplicates;
    duplicate[p] = duplicate[f] = 1;
    if (example < 0)
    {
      example = p;
      twin = f;
    }
    double x[3];
    grid->GetPoint(p, x);
    for (int k = 0; k < 3; ++k)
    {
      lo[k] = std::min(lo[k], x[k]);
      hi[k] = std::max(hi[k], x[k]);
    }
  }
  if (duplicates == 0)
  {
    return std::string();
  }
  // The faces of the cells at the duplicates, by their point ids and by their
  // merged ids: a face used once by its ids but twice by its location is a
  // face of the crack (counted once per side).
  std::map<std::vector<vtkIdType>, int> byIds, byPlace;
  vtkNew<vtkGenericCell> cell;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    if (!IsVolumeType(grid->GetCellType(c)))
    {
      continue;
    }
    grid->GetCellPoints(c, ids);
    bool touches = false;
    for (vtkIdType k = 0; k < ids->GetNumberOfIds() && !touches; ++k)
    {
      touches = duplicate[ids->GetId(k)] != 0;
    }
    if (!touches)
    {
      continue;
    }
    grid->GetCell(c, cell);
    for (int f = 0; f < cell->GetNumberOfFaces(); ++f)
    {
      vtkIdList* face = cell->GetFace(f)->GetPointIds();
      std::vector<vtkIdType> key(face->GetPointer(0), face->GetPointer(0) + face->GetNumberOfIds());
      std::vector<vtkIdType> place(key.size());
      std::transform(key.begin(), key.end(), place.begin(), [&](vtkIdType p) { return merged[p]; });
      std::sort(key.begin(), key.end());
      std::sort(place.begin(), place.end());
      ++byIds[key];
      ++byPlace[place];
    }
  }
  vtkIdType crackFaces = 0;
  for (const auto& [key, uses] : byIds)
  {
    std::vector<vtkIdType> place(key.size());
    std::transform(key.begin(), key.end(), place.begin(), [&](vtkIdType p) { return merged[p]; });
    std::sort(place.begin(), place.end());
    crackFaces += (uses == 1 && byPlace[place] >= 2) ? 1 : 0;
  }
  double x[3];
  grid->GetPoint(example, x);
  std::ostringstream msg;
  msg << "The volume mesh is not conforming: " << duplicates << " of its points are duplicated (they lie "
      << "exactly where another point of a 3-D cell lies; the first, point " << example << " at (" << x[0] << ", "
      << x[1] << ", " << x[2] << "), duplicates point " << twin << "), so " << crackFaces
      << " faces between cells are used by one cell each: a crack through the mesh, spanning x [" << lo[0] << ", "
      << hi[0] << "], y [" << lo[1] << ", " << hi[1] << "], z [" << lo[2] << ", " << hi[2]
      << "]. Merge the duplicated points (e.g. Clean to Grid) or fix the mesh where it was made. ";
  return msg.str();
}

//------------------------------------------------------------------------------
double vtkARInputChecks::PhysicalMemory()
{
  vtksys::SystemInformation info;
  info.RunMemoryCheck();
  return static_cast<double>(info.GetTotalPhysicalMemory()) * 1024.0 * 1024.0; // MiB
}

double vtkARInputChecks::MaximumElements()
{
  const double memory = PhysicalMemory();
  // Unknown memory: a 16 GiB machine's cap.
  return 0.5 * (memory > 0.0 ? memory : 16.0 * 1024.0 * 1024.0 * 1024.0) / BytesPerElement;
}
