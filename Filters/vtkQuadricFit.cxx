// SPDX-License-Identifier: BSD-3-Clause
#include "vtkQuadricFit.h"

#include "ARSurfaceFit.h"
#include "vtkARInputChecks.h"
#include "vtkARMeshKernels.h"
#include "vtkARParallel.h"

#include "vtkAppendPolyData.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkClipPolyData.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkGenericCell.h"
#include "vtkGeometryFilter.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkImplicitPolyDataDistance.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkLine.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkStaticCleanPolyData.h"
#include "vtkStaticPointLocator.h"
#include "vtkStringArray.h"
#include "vtkTetra.h"
#include "vtkTriangleFilter.h"
#include "vtkUnsignedCharArray.h"
#include "vtkCellDataToPointData.h"
#include "vtkPolygon.h"
#include "vtkStaticCellLocator.h"
#include "vtkCellLocator.h"
#include "vtkExtractCells.h"
#include "vtkShockSensor.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkQuadricFit);

namespace
{
// Per selected point: x y z, Weight (NaN if absent), LocalSize (NaN if
// absent), the point's id in its rank's input.
constexpr int Stride = 6;

/// Median of a non-empty vector (the vector is reordered).
double Median(std::vector<double>& v)
{
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  return v[mid];
}


/// The one-component array of `domain` that ShockCentring reads: `name`
/// (point data first), or with "(automatic)" (or none) the pressure, else the
/// density, by the names solvers write (vtkShockSensor::FindKnownArray).
/// Null when there is none; `used` names it.
vtkDataArray* CentringArrayOf(vtkDataSet* domain, const char* name, bool& cellData, std::string& used)
{
  cellData = false;
  if (!domain)
  {
    return nullptr;
  }
  vtkDataArray* array = nullptr;
  if (!name || !*name || std::string(name) == vtkShockSensor::AutomaticArrayName)
  {
    int association = -1;
    for (const int idx : { vtkShockSensor::PRESSURE, vtkShockSensor::DENSITY })
    {
      array = array ? array : vtkShockSensor::FindKnownArray(idx, 1, domain, association);
    }
    cellData = association == vtkDataObject::FIELD_ASSOCIATION_CELLS;
  }
  else
  {
    for (vtkDataSetAttributes* data : { static_cast<vtkDataSetAttributes*>(domain->GetPointData()),
           static_cast<vtkDataSetAttributes*>(domain->GetCellData()) })
    {
      vtkDataArray* a = array ? nullptr : data->GetArray(name);
      if (a && a->GetNumberOfComponents() == 1)
      {
        array = a;
        cellData = data == static_cast<vtkDataSetAttributes*>(domain->GetCellData());
      }
    }
  }
  if (array)
  {
    used = array->GetName();
  }
  return array;
}

/// An array ProbeOnAllRanks interpolates: its name, whether it is cell data
/// (interpolated to the points first) and its number of components (every
/// rank must give the same, whether or not its piece has the array).
struct ProbedArray
{
  std::string Name;
  bool CellData = false;
  int Components = 1;
};

/**
 * The values of arrays of `domain` at `points` (x y z each), per array
 * Components values per point, NaN where none of this rank's cells holds a
 * point (or the array is missing). Under MPI every rank probes its own piece
 * and the values are averaged over the ranks that found the point (a point
 * in a ghost cell is found twice, with the same value up to round-off):
 * every rank must call this with the same points and arrays. The points
 * come in lines of `perLine`, each `reach` local sizes to either side of its
 * middle point: only the cells with a node within 2 local sizes of a sample
 * are searched (on 5e6 cells the locator over all of them would cost more
 * than the fit). The search is on threads; its values are the same on any
 * number of them. The first array decides where a point was found.
 */
std::vector<std::vector<double>> ProbeOnAllRanks(vtkDataSet* domain, const std::vector<ProbedArray>& arrays,
  const std::vector<double>& points, int perLine, double reach, double tolerance)
{
  const vtkIdType m = static_cast<vtkIdType>(points.size() / 3);
  std::vector<int> offsetOf(arrays.size() + 1, 0); // each array's first component among all of them
  for (std::size_t a = 0; a < arrays.size(); ++a)
  {
    offsetOf[a + 1] = offsetOf[a] + arrays[a].Components;
  }
  const int components = offsetOf.back();
  // per component the value sums, then per array the counts (a piece
  // without an array does not count for it)
  std::vector<double> acc((components + arrays.size()) * static_cast<std::size_t>(m), 0.0);
  vtkSmartPointer<vtkDataSet> source;
  vtkDataArray* values = nullptr; // the first array's, on the source's points
  if (domain && domain->GetNumberOfCells() > 0 && !arrays.empty())
  {
    // Only these arrays: the probe interpolates nothing else.
    source.TakeReference(domain->NewInstance());
    source->CopyStructure(domain);
    for (const ProbedArray& wanted : arrays)
    {
      vtkDataArray* a = wanted.CellData ? domain->GetCellData()->GetArray(wanted.Name.c_str())
                                        : domain->GetPointData()->GetArray(wanted.Name.c_str());
      if (!a || a->GetNumberOfComponents() != wanted.Components)
      {
        continue;
      }
      if (wanted.CellData)
      {
        vtkSmartPointer<vtkDataSet> cells;
        cells.TakeReference(domain->NewInstance());
        cells->CopyStructure(domain);
        cells->GetCellData()->AddArray(a);
        vtkNew<vtkCellDataToPointData> c2p;
        c2p->SetInputData(cells);
        c2p->Update();
        a = c2p->GetOutput()->GetPointData()->GetArray(wanted.Name.c_str());
      }
      if (a)
      {
        source->GetPointData()->AddArray(a);
      }
    }
    values = source->GetPointData()->GetArray(arrays[0].Name.c_str());
  }
  if (values && m > 0 && perLine > 0)
  {
    // vtkCellLocator, serial, on purpose: vtkStaticCellLocator builds its bins
    // with threads, and the order of the cells in a bin, so the cell it finds
    // for a point on a face (or within the tolerance of the boundary), varied
    // from run to run: the bundled cone's centring found 2411 to 2415 samples
    // (with one thread, the same every time), and vtkProbeFilter did too.
    vtkNew<vtkStaticPointLocator> nodes;
    nodes->SetDataSet(source);
    nodes->BuildLocator();
    const vtkIdType npts = source->GetNumberOfPoints();
    // The nodes within 2 local sizes of a sample: every cell that can hold
    // it has one (as wide cells are not searched). A band along the lines,
    // about seven times smaller than the balls about their middles it was
    // (the locator's build over the band was the probe's largest part).
    // Found per line, not per sample: the nodes in the ball about the line's
    // middle that reaches its ends, kept within that distance of the segment
    // (the samples, 1/8 of a local size apart, cover it; a node within it of
    // a sample is within it of the segment). One search per line instead of
    // one per sample (49): 1.0 -> 0.1 s on a 5e6-cell cube.
    // (on threads: a node near two lines is flagged by both, so the flags
    // are atomic; the set flagged is the same on any number)
    std::unique_ptr<std::atomic<char>[]> near(new std::atomic<char>[static_cast<std::size_t>(npts)]);
    vtkSMPTools::For(0, npts, [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType k = b; k < e; ++k)
      {
        near[k].store(0, std::memory_order_relaxed);
      }
    });
    const vtkIdType nLines = (m + perLine - 1) / perLine;
    vtkSMPTools::For(0, nLines, 16, [&](vtkIdType b, vtkIdType e) {
      vtkNew<vtkIdList> found;
      for (vtkIdType line = b; line < e; ++line)
      {
        const vtkIdType first = line * perLine, last = std::min(m, (line + 1) * perLine) - 1;
        const double* p0 = &points[3 * first];
        const double* p1 = &points[3 * last];
        // The line reaches `reach` local sizes to either side of its middle:
        // r is two local sizes (widened by 1e-9: the samples lie on the
        // segment up to round-off).
        const double half = 0.5 * std::sqrt(vtkMath::Distance2BetweenPoints(p0, p1));
        const double r = (1.0 + 1e-9) * 2.0 * half / reach;
        double c[3];
        for (int a = 0; a < 3; ++a)
        {
          c[a] = 0.5 * (p0[a] + p1[a]);
        }
        nodes->FindPointsWithinRadius((1.0 + 1e-9) * (r + half), c, found);
        for (vtkIdType k = 0; k < found->GetNumberOfIds(); ++k)
        {
          const vtkIdType id = found->GetId(k);
          double y[3], t;
          source->GetPoint(id, y);
          if (vtkLine::DistanceToLine(y, p0, p1, t) <= r * r) // (to the segment)
          {
            near[id].store(1, std::memory_order_relaxed);
          }
        }
      }
    });
    const vtkIdType ncells = source->GetNumberOfCells();
    std::vector<char> keep(static_cast<std::size_t>(ncells), 0);
    auto* grid = vtkUnstructuredGrid::SafeDownCast(source);
    vtkSMPTools::For(0, ncells, [&](vtkIdType b, vtkIdType e) {
      vtkNew<vtkIdList> ids;
      for (vtkIdType c = b; c < e; ++c)
      {
        vtkIdType npts;
        const vtkIdType* pts;
        if (grid)
        {
          grid->GetCellPoints(c, npts, pts, ids); // in place (the thread-safe overload)
        }
        else
        {
          source->GetCellPoints(c, ids);
          npts = ids->GetNumberOfIds();
          pts = ids->GetPointer(0);
        }
        for (vtkIdType k = 0; k < npts && !keep[c]; ++k)
        {
          keep[c] = near[pts[k]].load(std::memory_order_relaxed);
        }
      }
    });
    vtkNew<vtkIdList> cellIds;
    for (vtkIdType c = 0; c < ncells; ++c)
    {
      if (keep[c])
      {
        cellIds->InsertNextId(c);
      }
    }
    vtkNew<vtkExtractCells> extract;
    extract->SetInputData(source);
    extract->SetCellList(cellIds);
    extract->Update();
    vtkUnstructuredGrid* band = extract->GetOutput();
    std::vector<vtkDataArray*> probed(arrays.size(), nullptr);
    for (std::size_t a = 0; a < arrays.size(); ++a)
    {
      probed[a] = band->GetPointData()->GetArray(arrays[a].Name.c_str());
    }
    values = probed[0];
    vtkNew<vtkCellLocator> locator;
    locator->SetDataSet(band);
    if (band->GetNumberOfCells() > 0)
    {
      // Built here, once: FindCell on an empty or unbuilt locator would build
      // it on each thread at once.
      locator->BuildLocator();
    }
    // A sample on a face (or an edge, a corner) lies in several cells, which
    // interpolate it alike up to round-off. It takes the one cell that comes
    // first by its corners' coordinates, whatever the cells' numbering, and
    // is answered by the rank that owns that cell (with one ghost level the
    // owner holds every cell about it): so a partition, or the order of the
    // band's cells, changes no bit of the value. The locator's cell decides
    // alone where the sample is well inside it (every weight above 0.01);
    // otherwise the cells about its corners are the candidates.
    vtkUnsignedCharArray* ghosts = domain->GetCellGhostArray();
    const double tol2 = tolerance * tolerance;
    band->BuildLinks();
    // The samples on threads, each writing its own sums (vtkCellLocator's
    // FindCell with a cell of the thread's own is thread safe): the same
    // values on any number of threads.
    struct Scratch
    {
      vtkNew<vtkGenericCell> cell;
      std::vector<double> wts = std::vector<double>(VTK_CELL_SIZE);
      std::vector<vtkIdType> accepted, candidates, support;
      vtkNew<vtkIdList> corners;
    };
    auto cornerKey = [&](Scratch& z, vtkIdType c) {
      band->GetCellPoints(c, z.corners);
      std::vector<std::array<double, 3>> key(static_cast<std::size_t>(z.corners->GetNumberOfIds()));
      for (vtkIdType k = 0; k < z.corners->GetNumberOfIds(); ++k)
      {
        band->GetPoint(z.corners->GetId(k), key[k].data());
      }
      std::sort(key.begin(), key.end());
      return key;
    };
    // Whether cell c holds x: a tetrahedron by its barycentric coordinates
    // (closed, to round-off), another cell by EvaluatePosition.
    auto holds = [&](Scratch& z, vtkIdType c, const double x[3]) {
      if (band->GetCellType(c) == VTK_TETRA)
      {
        band->GetCellPoints(c, z.corners);
        double p[4][3], b[4];
        for (int k = 0; k < 4; ++k)
        {
          band->GetPoint(z.corners->GetId(k), p[k]);
        }
        return vtkTetra::BarycentricCoords(const_cast<double*>(x), p[0], p[1], p[2], p[3], b) != 0 &&
          *std::min_element(b, b + 4) >= -1e-12;
      }
      band->GetCell(c, z.cell);
      double pcoords[3], d2;
      int s = 0;
      return z.cell->EvaluatePosition(x, nullptr, s, pcoords, d2, z.wts.data()) == 1;
    };
    auto probe = [&](Scratch& z, vtkIdType i) {
      double x[3] = { points[3 * i], points[3 * i + 1], points[3 * i + 2] };
      double pc[3];
      int sub = 0;
      const vtkIdType first = locator->FindCell(x, tol2, z.cell, sub, pc, z.wts.data());
      if (first < 0)
      {
        return;
      }
      vtkIdType chosen = first;
      const double* w = z.wts.data();
      if (*std::min_element(w, w + z.cell->GetNumberOfPoints()) <= 0.01)
      {
        // The sample is near a face, an edge or a corner of the cell: the
        // cells that can hold it too are those with every corner that
        // weighs (above 0.01), e.g. the neighbour across that face.
        z.support.clear();
        for (vtkIdType k = 0; k < z.cell->GetNumberOfPoints(); ++k)
        {
          if (w[k] > 0.01)
          {
            z.support.push_back(z.cell->GetPointId(k));
          }
        }
        z.candidates.clear();
        vtkIdType nAround;
        vtkIdType* around;
        band->GetPointCells(z.support[0], nAround, around);
        for (vtkIdType k = 0; k < nAround; ++k)
        {
          band->GetCellPoints(around[k], z.corners);
          const vtkIdType* c0 = z.corners->GetPointer(0);
          const vtkIdType* c1 = c0 + z.corners->GetNumberOfIds();
          if (std::all_of(z.support.begin(), z.support.end(), [&](vtkIdType q) { return std::find(c0, c1, q) != c1; }))
          {
            z.candidates.push_back(around[k]);
          }
        }
        // The cells that hold the sample (a sample outside every cell, within
        // the tolerance of the domain's boundary, keeps the locator's cell).
        z.accepted.clear();
        for (const vtkIdType c : z.candidates)
        {
          if (holds(z, c, x))
          {
            z.accepted.push_back(c);
          }
        }
        if (!z.accepted.empty())
        {
          chosen = z.accepted[0];
          auto best = cornerKey(z, chosen);
          for (std::size_t k = 1; k < z.accepted.size(); ++k)
          {
            const auto key = cornerKey(z, z.accepted[k]);
            if (key < best)
            {
              chosen = z.accepted[k];
              best = key;
            }
          }
        }
      }
      if (ghosts && (ghosts->GetValue(cellIds->GetId(chosen)) & vtkDataSetAttributes::DUPLICATECELL))
      {
        return; // its owner answers
      }
      band->GetCell(chosen, z.cell);
      double closest[3], d2;
      z.cell->EvaluatePosition(x, closest, sub, pc, d2, z.wts.data());
      for (std::size_t a = 0; a < arrays.size(); ++a)
      {
        for (int c = 0; probed[a] && c < arrays[a].Components; ++c)
        {
          double v = 0.0;
          for (vtkIdType k = 0; k < z.cell->GetNumberOfPoints(); ++k)
          {
            v += z.wts[k] * probed[a]->GetComponent(z.cell->GetPointId(k), c);
          }
          acc[(offsetOf[a] + c) * static_cast<std::size_t>(m) + i] = v;
        }
        acc[(components + a) * static_cast<std::size_t>(m) + i] = probed[a] ? 1.0 : 0.0;
      }
    };
    if (values && band->GetNumberOfCells() > 0)
    {
      vtkSMPTools::For(0, m, 1024, [&](vtkIdType b, vtkIdType e) {
        Scratch z;
        for (vtkIdType i = b; i < e; ++i)
        {
          probe(z, i);
        }
      });
    }
  }
  vtkARParallel::AllReduceSum(acc.data(), static_cast<int>(acc.size()));
  std::vector<std::vector<double>> out(arrays.size());
  for (std::size_t a = 0; a < arrays.size(); ++a)
  {
    const double* count = &acc[(components + a) * static_cast<std::size_t>(m)];
    const int nc = arrays[a].Components;
    out[a].assign(nc * static_cast<std::size_t>(m), std::numeric_limits<double>::quiet_NaN());
    for (vtkIdType i = 0; i < m; ++i)
    {
      for (int c = 0; c < nc && count[i] > 0.0; ++c)
      {
        out[a][nc * i + c] = acc[(offsetOf[a] + c) * static_cast<std::size_t>(m) + i] / count[i];
      }
    }
  }
  return out;
}

/// Samples per side of a centring line, and its half length in LocalSize.
constexpr int CentringSamples = 24;
constexpr double CentringReach = 3.0;

/**
 * The signed offset, along the line, of the half-jump point of the profile
 * `v` sampled at s = (k - K) / K * reach, k = 0..2K: the contiguous valid
 * part around the centre (at least a third of the reach on either side), the
 * smallest and largest values there, the crossing of their mean nearest the
 * centre. False where the line shows no jump of at least 5 %. With `top`
 * (given a sample's index: the value just behind a shock with that sample's
 * state upstream, NaN where unknown), the largest top of the samples in the
 * lower half of the rise, where it lies between the smallest and the
 * largest value, is taken instead of the largest value for the half-jump:
 * behind a conical shock p keeps rising towards the wall, so the largest
 * value on the line is not the shock's. With `width`: the 10-90 % width of the whole rise on the line (its
 * 10 % and 90 % crossings nearest the half-jump, in the same units as
 * `offset`), -1 where either is missing.
 */
bool HalfJumpOffset(const double* v, double reach, double& offset, double* width,
  const std::function<double(int)>& top = nullptr)
{
  const int K = CentringSamples, n = 2 * K + 1;
  if (!std::isfinite(v[K]))
  {
    return false;
  }
  int lo = K, hi = K;
  while (lo > 0 && std::isfinite(v[lo - 1]))
  {
    --lo;
  }
  while (hi < n - 1 && std::isfinite(v[hi + 1]))
  {
    ++hi;
  }
  if (K - lo < K / 3 || hi - K < K / 3)
  {
    return false;
  }
  const double* lowest = std::min_element(v + lo, v + hi + 1);
  const double vmin = *lowest;
  const double vmax = *std::max_element(v + lo, v + hi + 1);
  if (!(vmax - vmin >= 0.05 * std::max(std::abs(vmin), std::abs(vmax))) || !(vmax > vmin))
  {
    return false;
  }
  double jumpTop = vmax;
  if (top)
  {
    // The largest top of the samples in the lower half of the rise: a
    // sample inside the smeared shock (a line cut short by the domain's
    // boundary starts there) is no upstream state, and its jump is smaller.
    double t = -std::numeric_limits<double>::infinity();
    for (int k = lo; k <= hi; ++k)
    {
      const double tk = v[k] <= 0.5 * (vmin + vmax) ? top(k) : t;
      t = std::isfinite(tk) ? std::max(t, tk) : t;
    }
    jumpTop = t > vmin && t < vmax ? t : vmax;
  }
  // The crossing of `level` nearest to `near` (the centre, then the half-jump).
  auto crossing = [&](double level, double near, double& at) {
    bool found = false;
    for (int k = lo; k < hi; ++k)
    {
      const double a = v[k] - level, b = v[k + 1] - level;
      if (a * b > 0.0 || a == b)
      {
        continue;
      }
      const double s = (k - K + a / (a - b)) * reach / K;
      if (!found || std::abs(s - near) < std::abs(at - near))
      {
        at = s;
        found = true;
      }
    }
    return found;
  };
  if (!crossing(0.5 * (vmin + jumpTop), 0.0, offset))
  {
    return false;
  }
  if (width)
  {
    double s10 = 0.0, s90 = 0.0;
    *width = crossing(vmin + 0.1 * (vmax - vmin), offset, s10) && crossing(vmin + 0.9 * (vmax - vmin), offset, s90)
      ? std::abs(s90 - s10)
      : -1.0;
  }
  return true;
}

/**
 * Signed distance values at the points of a triangle mesh, for cutting it at
 * the zero level, from `phi` (1-Lipschitz, as a signed distance is; slow far
 * from the zero level, as a closest-point query is). Where phi(x_i) = D, every
 * point within |D| of x_i has phi of the same sign: those points take the
 * sign (with a value whose magnitude is a lower bound of theirs) without a
 * query. The points of triangles whose signs differ then get exact values.
 * Queries: about (length of the cut) / (edge length), not one per point.
 */
vtkSmartPointer<vtkDoubleArray> DomainDistance(
  vtkPolyData* mesh, const std::function<double(const double*)>& phi)
{
  const vtkIdType n = mesh->GetNumberOfPoints();
  auto values = vtkSmartPointer<vtkDoubleArray>::New();
  values->SetName("DomainDistance");
  values->SetNumberOfTuples(n);
  if (n == 0)
  {
    return values;
  }
  std::vector<char> exact(n, 0), known(n, 0);
  vtkNew<vtkStaticPointLocator> locator;
  locator->SetDataSet(mesh);
  locator->BuildLocator();
  vtkNew<vtkIdList> nearby;
  for (vtkIdType i = 0; i < n; ++i)
  {
    if (known[i])
    {
      continue;
    }
    double x[3];
    mesh->GetPoint(i, x);
    const double d = phi(x);
    values->SetValue(i, d);
    exact[i] = known[i] = 1;
    const double r = std::abs(d);
    if (!(r > 0.0))
    {
      continue;
    }
    locator->FindPointsWithinRadius(r, x, nearby);
    for (vtkIdType k = 0; k < nearby->GetNumberOfIds(); ++k)
    {
      const vtkIdType j = nearby->GetId(k);
      if (known[j])
      {
        continue;
      }
      double y[3];
      mesh->GetPoint(j, y);
      const double bound = r - std::sqrt(vtkMath::Distance2BetweenPoints(x, y));
      if (bound > 0.0)
      {
        values->SetValue(j, std::copysign(bound, d));
        known[j] = 1;
      }
    }
  }
  vtkIdType npts;
  const vtkIdType* ids;
  vtkCellArray* polys = mesh->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
  {
    bool below = false, above = false;
    for (vtkIdType k = 0; k < npts; ++k)
    {
      const double v = values->GetValue(ids[k]);
      below = below || v <= 0.0;
      above = above || v > 0.0;
    }
    if (!(below && above))
    {
      continue;
    }
    for (vtkIdType k = 0; k < npts; ++k)
    {
      if (!exact[ids[k]])
      {
        double x[3];
        mesh->GetPoint(ids[k], x);
        values->SetValue(ids[k], phi(x));
        exact[ids[k]] = 1;
      }
    }
  }
  return values;
}

/**
 * Keeps the part of a triangle mesh where the point scalar `values` is <= 0,
 * cut along the zero level by vtkClipPolyData. Only the triangles the level
 * crosses go through the clip (it is the expensive step); those entirely
 * below are kept as they are and joined to the clipped band by merging
 * coincident points. `fixCut` may move the points of the clipped band (the
 * triangles the level crosses) before they are joined.
 */
vtkSmartPointer<vtkPolyData> KeepBelowZero(vtkPolyData* mesh, vtkDoubleArray* values,
  const std::function<void(vtkPoints*)>& fixCut)
{
  const double* v = values->GetPointer(0);
  vtkNew<vtkCellArray> below, band;
  vtkIdType npts;
  const vtkIdType* ids;
  vtkCellArray* polys = mesh->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(npts, ids);)
  {
    double lo = v[ids[0]], hi = lo;
    for (vtkIdType k = 1; k < npts; ++k)
    {
      lo = std::min(lo, v[ids[k]]);
      hi = std::max(hi, v[ids[k]]);
    }
    if (hi <= 0.0)
    {
      below->InsertNextCell(npts, ids);
    }
    else if (lo <= 0.0)
    {
      band->InsertNextCell(npts, ids);
    }
  }
  vtkNew<vtkPolyData> inner;
  inner->SetPoints(mesh->GetPoints());
  inner->SetPolys(below);
  vtkNew<vtkPolyData> crossing;
  crossing->SetPoints(mesh->GetPoints());
  crossing->SetPolys(band);
  crossing->GetPointData()->SetScalars(values);
  vtkNew<vtkClipPolyData> clip;
  clip->SetInputData(crossing);
  clip->SetValue(0.0);
  clip->InsideOutOn(); // keep <= 0
  clip->Update();
  vtkNew<vtkPolyData> cut;
  cut->SetPoints(clip->GetOutput()->GetPoints());
  cut->SetPolys(clip->GetOutput()->GetPolys());
  if (fixCut && cut->GetPoints())
  {
    fixCut(cut->GetPoints());
  }
  vtkNew<vtkAppendPolyData> append;
  append->AddInputData(inner);
  append->AddInputData(cut);
  vtkNew<vtkStaticCleanPolyData> merge;
  merge->SetInputConnection(append->GetOutputPort());
  merge->SetTolerance(0.0);
  merge->RemoveUnusedPointsOn();
  merge->ConvertPolysToLinesOff();
  merge->Update();
  auto result = vtkSmartPointer<vtkPolyData>::New();
  result->SetPoints(merge->GetOutput()->GetPoints());
  result->SetPolys(merge->GetOutput()->GetPolys());
  return result;
}
}

//------------------------------------------------------------------------------
vtkQuadricFit::vtkQuadricFit()
{
  this->SetNumberOfInputPorts(2);
  this->SetCentringArray(vtkShockSensor::AutomaticArrayName);
}

//------------------------------------------------------------------------------
vtkQuadricFit::~vtkQuadricFit()
{
  this->SetCentringArray(nullptr);
}

//------------------------------------------------------------------------------
int vtkQuadricFit::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
    return 1;
  }
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkQuadricFit::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // Threads for this filter's own work only: the process's SMP backend is
  // left as the user has it.
  int result = 1;
  vtkARMeshKernels::Threaded([&]() { result = this->ExecuteData(request, inputVector, outputVector); });
  return result;
}

//------------------------------------------------------------------------------
namespace
{
/**
 * QuadricFit's run: the stages of vtkQuadricFit::ExecuteData over the state
 * they share (as Remesh2DRun in vtkEmbeddedRemesh2D.cxx; file-local, so its
 * members keep the names the stages had as locals). Every rank runs Gather;
 * rank 0 alone runs the rest. A stage returns false when the run ends there:
 * after Fail (an error, the output empty) or on a rank other than 0 (its
 * part done); ExecuteData checks for cancelling between the stages.
 */
class FitRun
{
public:
  FitRun(vtkQuadricFit* self_, vtkPointSet* input_, vtkDataSet* domain_, bool hasDomain_, vtkPolyData* output_)
    : self(self_)
    , input(input_)
    , domain(domain_)
    , hasDomain(hasDomain_)
    , output(output_)
    , root(vtkARParallel::Rank() == 0)
    , joinCentring(vtkARParallel::NumberOfRanks() > 1 && hasDomain_ && self_->GetShockCentring())
  {
  }
  bool Gather();        ///< every rank's points of the cluster and the domain's boundary on rank 0
  bool Points();        ///< the cluster's points checked: coordinates, Weight, LocalSize
  bool Fit();           ///< Eq. 4, then the geometric refinement
  bool Centre();        ///< shock centring: the points moved to the half-jump, fitted again
  bool Mesh();          ///< the edge length, the margin, the surface meshed around the cluster
  bool TrimToCluster(); ///< what lies within the margin of a point's foot on the surface
  bool TrimToDomain();  ///< what lies inside the Domain
  bool Output();        ///< the trimmed surface and its field data

private:
  void LocalPoints(std::ostringstream& problem, double flags[6]);
  bool FitPoints(const double* P, const double* W, std::size_t count, ar::SurfaceFitResult& f, std::string& e);
  void CentringLines(std::vector<double>& lines, std::vector<double>& normals, std::vector<double>& scale);
  void CentringArrays();
  void FitNormal(std::size_t j, double l, double g[3]) const;
  double NormalsMoved(const std::vector<double>& scale) const;
  void AlongBoundary(vtkStaticCellLocator* onBoundary, vtkIdList* near, std::size_t j, double l, double g[3]);
  bool Refit(const std::vector<std::vector<double>>& values, const std::vector<double>& normals,
    const std::vector<double>& scale, int pass);
  double RankineHugoniotTop(const std::vector<std::vector<double>>& values, std::size_t j, int k) const;
  std::vector<std::vector<double>> Exchange(std::vector<double>& lines);
  void EndCentring();
  bool Fail(const std::string& message);

  vtkQuadricFit* self;
  vtkPointSet* input;
  vtkDataSet* domain;
  const bool hasDomain;
  vtkPolyData* output;
  const bool root;
  // Gather
  std::vector<double> local;
  double status[7] = { 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0 };
  double meanFlow[3] = { 0.0, 0.0, 0.0 }; // the Domain's velocity summed (Gather), the quadric's second frame
  std::vector<double> packed;
  vtkSmartPointer<vtkPolyData> boundary;
  // ShockCentring under MPI: rank 0 sends its lines through the points, one
  // set per centring pass, then none, and every rank probes its piece of the
  // domain along each set.
  const bool joinCentring;
  bool exchanged = false; // rank 0 has sent the empty set that ends the passes
  double tolerance = 0.0; // the probe's, set by rank 0
  // The arrays probed along the lines, set by rank 0: the centring array
  // alone, or where it is the pressure or the density and the Domain has p,
  // rho and U, those three (the centring array among them, at
  // `centringIndex`), whose values on the upstream side give the
  // Rankine-Hugoniot jump (`jumpOf`: the vtkShockSensor index of the
  // centring array's quantity, -1 for none).
  std::vector<ProbedArray> probedArrays;
  std::size_t centringIndex = 0;
  int jumpOf = -1;
  std::vector<double> surfaceNormals; // the fit's unit normal at each point, for the jump
  // Points
  std::size_t n = 0;
  bool haveIds = false, haveWeight = false, haveSize = false;
  std::vector<double> xyz, w, sizes;
  // Fit
  double typical = 0.0;
  ar::SurfaceFitOptions options;
  ar::SurfaceFitResult fit;
  std::string error;
  double residuals[4] = { 0.0, 0.0, 0.0, 0.0 }; // plane, cone, quadric, quartic (automatic template)
  // Centre
  double centred = 0.0, centringShift = 0.0, shockThickness = 0.0;
  std::string centringUsed;
  // Mesh, TrimToCluster, TrimToDomain
  double h = 0.0, reach = 0.0;
  ar::SurfaceMesh mesh;
  vtkNew<vtkPolyData> surface;
  vtkSmartPointer<vtkPolyData> trimmed;
};

//------------------------------------------------------------------------------
bool FitRun::Fail(const std::string& message)
{
  vtkErrorWithObjectMacro(self, << message << " The output is empty.");
  EndCentring(); // the other ranks may wait for it
  return false;
}

//------------------------------------------------------------------------------
void FitRun::EndCentring()
{
  // Rank 0's empty set of lines, once: the other ranks' centring passes end.
  if (joinCentring && !exchanged)
  {
    std::vector<double> none;
    Exchange(none);
  }
}

//------------------------------------------------------------------------------
std::vector<std::vector<double>> FitRun::Exchange(std::vector<double>& lines)
{
  exchanged = lines.empty();
  if (joinCentring)
  {
    // The tolerance, then per array its association and components, and
    // the names one by one.
    std::vector<double> header = { tolerance };
    for (const ProbedArray& a : probedArrays)
    {
      header.insert(header.end(), { a.CellData ? 1.0 : 0.0, static_cast<double>(a.Components) });
    }
    vtkARParallel::BroadcastFromRoot(header);
    tolerance = header[0];
    probedArrays.resize((header.size() - 1) / 2);
    for (std::size_t a = 0; a < probedArrays.size(); ++a)
    {
      probedArrays[a].CellData = header[1 + 2 * a] > 0.0;
      probedArrays[a].Components = static_cast<int>(header[2 + 2 * a]);
      vtkARParallel::BroadcastFromRoot(probedArrays[a].Name);
    }
    vtkARParallel::BroadcastFromRoot(lines);
  }
  return lines.empty() || probedArrays.empty()
    ? std::vector<std::vector<double>>()
    : ProbeOnAllRanks(domain, probedArrays, lines, 2 * CentringSamples + 1, CentringReach, tolerance);
}

//------------------------------------------------------------------------------
void FitRun::LocalPoints(std::ostringstream& problem, double flags[6])
{
  const int clusterId = self->GetClusterId();
  const std::vector<int>& extra = self->GetExtraClusterIds();
  const vtkIdType npts = input ? input->GetNumberOfPoints() : 0;
  flags[0] = static_cast<double>(npts);
  if (npts > 0)
  {
    vtkPointData* pd = input->GetPointData();
    vtkDataArray* ids = pd->GetArray("ClusterId");
    vtkDataArray* weight = pd->GetArray("Weight");
    vtkDataArray* size = pd->GetArray("LocalSize");
    for (vtkDataArray* a : { ids, weight, size })
    {
      if (a && a->GetNumberOfComponents() != 1)
      {
        problem << "The point array '" << a->GetName() << "' has " << a->GetNumberOfComponents()
                << " components; it needs 1. ";
      }
    }
    if (pd->GetArray("FeatureMask") && !weight && !size)
    {
      // FeatureCluster's port 0 (the mesh with the cluster arrays) instead of
      // its port 1 (the medial points): name the wrong connection.
      problem << "The input is FeatureCluster's first output (the mesh with FeatureMask), not its "
                 "medial points: connect Input to FeatureCluster's second output "
                 "(OutputPort(cluster, 1); in the GUI, the port named Medial Points). ";
    }
    flags[1] = ids ? 1.0 : 0.0;
    flags[2] = weight ? 1.0 : 0.0;
    flags[3] = size ? 1.0 : 0.0;
    if (problem.str().empty() && (ids || clusterId < 0))
    {
      const double nan = std::numeric_limits<double>::quiet_NaN();
      vtkUnsignedCharArray* ghosts = input->GetPointGhostArray();
      for (vtkIdType p = 0; p < npts; ++p)
      {
        if (ghosts && (ghosts->GetValue(p) & vtkDataSetAttributes::DUPLICATEPOINT))
        {
          continue; // another rank's point
        }
        if (ids)
        {
          const double id = ids->GetComponent(p, 0);
          flags[4] = std::max(flags[4], id);
          flags[5] = std::max(flags[5], -id);
          if (clusterId >= 0 && id != clusterId &&
            std::find(extra.begin(), extra.end(), static_cast<int>(id)) == extra.end())
          {
            continue;
          }
        }
        double x[3];
        input->GetPoint(p, x);
        local.insert(local.end(),
          { x[0], x[1], x[2], weight ? weight->GetComponent(p, 0) : nan,
            size ? size->GetComponent(p, 0) : nan, static_cast<double>(p) });
      }
    }
  }
}

//------------------------------------------------------------------------------
bool FitRun::Gather()
{
  // ---- This rank's points of the cluster (no collective call before the
  // gathers below, so that every rank reaches them).
  std::ostringstream problem;
  problem << vtkARInputChecks::Properties()
               .InRange("ClusterId", self->GetClusterId(), -1, VTK_INT_MAX, "-1 fits every point")
               .InRange("SurfaceEdgeLength", self->GetSurfaceEdgeLength(), 0.0, VTK_DOUBLE_MAX, "0 automatic")
               .InRange("Margin", self->GetMargin(), 1.0, 1e6, "in edge lengths")
               .Message();
  // [0] input points, [1] has ClusterId, [2] has Weight, [3] has LocalSize,
  // [4] largest id, [5] -(smallest id)
  double flags[6] = { 0.0, 0.0, 0.0, 0.0, -1e300, -1e300 };
  LocalPoints(problem, flags);
  std::copy(flags, flags + 6, status);
  status[6] = problem.str().empty() ? 0.0 : 1.0;
  vtkARParallel::AllReduceSum(status, 1);
  vtkARParallel::AllReduceMax(status + 1, 6);
  if (status[6] > 0.0)
  {
    if (!problem.str().empty())
    {
      vtkErrorWithObjectMacro(self, << problem.str() << "The output is empty.");
    }
    return false;
  }
  packed = vtkARParallel::GatherOnRoot(local);
  if (hasDomain && self->GetTemplate() == vtkQuadricFit::AUTOMATIC)
  {
    // The free stream's direction: the mean velocity (the Domain's, as the
    // sensor finds it) where the speed is within 1 % of the largest, on
    // every rank. The automatic choice also fits the quadric about it
    // (ar::SurfaceFitOptions::GraphAxis), the axis a bow shock is a graph
    // over. (The mean over the whole domain leans with the flow turned
    // behind the shock: 10 degrees on the quarter sphere, and its quadric
    // missed the vertex by 1.4 cells the other way.)
    int association = -1;
    vtkDataArray* u = vtkShockSensor::FindKnownArray(vtkShockSensor::VELOCITY, 3, domain, association);
    std::vector<double> speed(u ? static_cast<std::size_t>(u->GetNumberOfTuples()) : 0);
    double fastest = 0.0;
    for (std::size_t i = 0; i < speed.size(); ++i)
    {
      speed[i] = vtkMath::Norm(u->GetTuple3(static_cast<vtkIdType>(i)));
      fastest = std::isfinite(speed[i]) ? std::max(fastest, speed[i]) : fastest;
    }
    vtkARParallel::AllReduceMax(&fastest, 1);
    for (std::size_t i = 0; i < speed.size(); ++i)
    {
      if (std::isfinite(speed[i]) && speed[i] >= 0.99 * fastest)
      {
        const double* v = u->GetTuple3(static_cast<vtkIdType>(i));
        meanFlow[0] += v[0];
        meanFlow[1] += v[1];
        meanFlow[2] += v[2];
      }
    }
    vtkARParallel::AllReduceSum(meanFlow, 3);
  }
  if (hasDomain)
  {
    vtkPolyData* given = self->GetDomainBoundary();
    boundary = given ? vtkSmartPointer<vtkPolyData>(given) : vtkARParallel::GatherDomainBoundary(domain);
  }
  if (!root)
  {
    if (joinCentring)
    {
      // Rank 0's centring passes, until it sends no lines.
      std::vector<double> lines;
      do
      {
        lines.clear();
        Exchange(lines);
      } while (!lines.empty());
    }
    return false; // rank 0 fits and meshes the surface
  }
  return true;
}

//------------------------------------------------------------------------------
bool FitRun::Points()
{
  // ---- Validate the cluster's points.
  n = packed.size() / Stride;
  haveIds = status[1] > 0.0;
  haveWeight = status[2] > 0.0;
  haveSize = status[3] > 0.0;
  if (status[0] == 0.0)
  {
    return Fail("The input has no points.");
  }
  if (self->GetClusterId() >= 0 && !haveIds)
  {
    return Fail("The input has no point array 'ClusterId' (the medial points of "
                "FeatureCluster's output port 1 have it); set ClusterId to -1 to fit all points.");
  }
  if (n == 0)
  {
    std::ostringstream msg;
    msg << "No point has ClusterId " << self->GetClusterId() << " (the ids present run from "
        << -status[5] << " to " << status[4] << ").";
    return Fail(msg.str());
  }
  xyz.assign(3 * n, 0.0);
  w.assign(n, 0.0);
  for (std::size_t j = 0; j < n; ++j)
  {
    const double* r = &packed[Stride * j];
    const long long id = static_cast<long long>(r[5]);
    if (!(std::isfinite(r[0]) && std::isfinite(r[1]) && std::isfinite(r[2])))
    {
      return Fail("Point " + std::to_string(id) + " has a NaN or infinite coordinate.");
    }
    std::copy(r, r + 3, &xyz[3 * j]);
    if (haveWeight)
    {
      if (!(std::isfinite(r[3]) && r[3] > 0.0))
      {
        std::ostringstream msg;
        msg << "The Weight of point " << id << " is " << r[3] << ": it must be positive and finite.";
        return Fail(msg.str());
      }
      w[j] = r[3];
    }
    if (haveSize)
    {
      if (!(std::isfinite(r[4]) && r[4] > 0.0))
      {
        std::ostringstream msg;
        msg << "The LocalSize of point " << id << " is " << r[4]
            << ": it must be positive and finite.";
        return Fail(msg.str());
      }
      if (!haveWeight)
      {
        w[j] = 1.0 / r[4];
      }
      sizes.push_back(r[4]);
    }
    if (!haveWeight && !haveSize)
    {
      w[j] = 1.0;
    }
  }
  if (!haveWeight && !haveSize)
  {
    vtkWarningWithObjectMacro(self, "The input has neither a 'Weight' nor a 'LocalSize' point array: every "
                    "point gets weight 1.");
  }
  return true;
}

//------------------------------------------------------------------------------
bool FitRun::FitPoints(const double* P, const double* W, std::size_t count, ar::SurfaceFitResult& f, std::string& e)
{
  return self->GetTemplate() == vtkQuadricFit::AUTOMATIC
    ? ar::FitSurfaceAutomatic(P, W, count, options, self->GetRobustFit(), typical, f, e, residuals)
    : self->GetRobustFit() ? ar::FitSurfaceRobust(P, W, count, options, f, e)
                           : ar::FitSurface(P, W, count, options, f, e);
}

//------------------------------------------------------------------------------
bool FitRun::Fit()
{
  // ---- Fit (Eq. 4, then the geometric refinement).
  const int templ = self->GetTemplate();
  if (templ < vtkQuadricFit::PLANE || templ > vtkQuadricFit::AUTOMATIC)
  {
    std::ostringstream msg;
    msg << "Template is " << templ
        << "; it must be 0 (Plane), 1 (Quadric), 2 (Cone), 3 (Quartic) or 4 (Automatic).";
    return Fail(msg.str());
  }
  if (!(self->GetGamma() > 1.0))
  {
    std::ostringstream msg;
    msg << "Gamma (the ratio of specific heats, for ShockCentring's Rankine-Hugoniot jump) is "
        << self->GetGamma() << "; it must be greater than 1.";
    return Fail(msg.str());
  }
  // The points' typical local size (the median l_j), for the automatic choice.
  if (!sizes.empty())
  {
    typical = Median(sizes);
  }
  else if (haveWeight)
  {
    std::vector<double> inv(n);
    for (std::size_t j = 0; j < n; ++j)
    {
      inv[j] = 1.0 / w[j];
    }
    typical = Median(inv);
  }
  options.Template = templ == vtkQuadricFit::AUTOMATIC ? ar::SurfaceTemplate::Plane
                                                       : static_cast<ar::SurfaceTemplate>(templ);
  options.AutomaticAxis = self->GetUseAutomaticAxis();
  const double* axisOrigin = self->GetAxisOrigin();
  const double* axisDirection = self->GetAxisDirection();
  std::copy(axisOrigin, axisOrigin + 3, options.AxisOrigin);
  std::copy(axisDirection, axisDirection + 3, options.AxisDirection);
  options.GeometricRefinement = self->GetGeometricRefinement();
  std::copy(meanFlow, meanFlow + 3, options.GraphAxis);
  if (!FitPoints(xyz.data(), w.data(), n, fit, error))
  {
    return Fail(error);
  }
  return true;
}

//------------------------------------------------------------------------------
bool FitRun::Centre()
{
  // ---- Shock centring: the points moved along the fit's normal to the
  // half-jump of the centring array, and fitted again. Where the refit's
  // template is not the one whose normals the lines followed (Automatic: a
  // weak conical shock's medial points, spread through the compression
  // behind it, fitted best by a plane within the allowance), the original
  // points are centred again along the new fit's normals: a plane's normals
  // run up to 45 degrees off a cone's, so its lines cross the whole shock
  // layer and their jump is the cone wall's pressure, not the shock's.
  if (self->GetShockCentring() && hasDomain)
  {
    constexpr int passes = 3;
    CentringArrays();
    for (int pass = 0; pass < passes; ++pass)
    {
      std::vector<double> lines, normals(3 * n, 0.0), scale(n, 0.0);
      CentringLines(lines, normals, scale);
      const std::vector<std::vector<double>> values = Exchange(lines);
      const ar::SurfaceTemplate followed = fit.Template;
      // Again along the refit's normals where its template changed, or
      // where the jump is Rankine-Hugoniot's and the normals moved by more
      // than a quarter degree: the normal Mach number, with the large
      // tangential velocity of an oblique shock, moves with the normal
      // (1.6 degrees off took 4 % off Mn and 13 % off the jump of a Mach 2.5
      // plane shock, and the surface a tenth of a cell upstream).
      if (values.empty() || !Refit(values, normals, scale, pass) ||
        (fit.Template == followed && !(jumpOf >= 0 && NormalsMoved(scale) > 0.25)))
      {
        break;
      }
    }
    EndCentring();
  }
  return true;
}

//------------------------------------------------------------------------------
void FitRun::CentringArrays()
{
  // The centring array, and where it is the pressure or the density, the
  // pressure, density and velocity for the Rankine-Hugoniot jump (none
  // without the centring array).
  probedArrays.clear();
  centringIndex = 0;
  jumpOf = -1;
  const char* centringArray = self->GetCentringArray();
  bool cellData = false;
  vtkDataArray* array = CentringArrayOf(domain, centringArray, cellData, centringUsed);
  if (!array)
  {
    centringUsed.clear();
    return;
  }
  vtkDataArray* known[3] = { nullptr, nullptr, nullptr };
  int associations[3] = { -1, -1, -1 };
  const int indices[3] = { vtkShockSensor::PRESSURE, vtkShockSensor::DENSITY, vtkShockSensor::VELOCITY };
  for (int q = 0; q < 3; ++q)
  {
    known[q] = vtkShockSensor::FindKnownArray(indices[q], q == 2 ? 3 : 1, domain, associations[q]);
  }
  for (int q = 0; q < 2 && known[0] && known[1] && known[2]; ++q)
  {
    if (known[q] == array)
    {
      jumpOf = indices[q];
      centringIndex = static_cast<std::size_t>(q);
    }
  }
  if (jumpOf < 0)
  {
    probedArrays.push_back({ centringUsed, cellData, 1 });
    return;
  }
  for (int q = 0; q < 3; ++q)
  {
    probedArrays.push_back(
      { known[q]->GetName(), associations[q] == vtkDataObject::FIELD_ASSOCIATION_CELLS, q == 2 ? 3 : 1 });
  }
}

//------------------------------------------------------------------------------
double FitRun::RankineHugoniotTop(const std::vector<std::vector<double>>& values, std::size_t j, int k) const
{
  // The value just behind a shock whose upstream state is the line's sample
  // k (p, rho and U: probedArrays 0, 1, 2): the normal Mach number
  // Mn = |U . n| / sqrt(Gamma p / rho) there, n the fitted surface's normal
  // at the line's point (not the line's direction: a point on the domain's
  // boundary centres along it, and a line along a symmetry plane runs up
  // to 45 degrees off the shock's normal);
  // p2 / p1 = 1 + 2 Gamma / (Gamma + 1) (Mn^2 - 1), rho2 / rho1 =
  // (Gamma + 1) Mn^2 / ((Gamma - 1) Mn^2 + 2). NaN where it is not known
  // (Mn at most 1: no shock by that state, and the line's largest value
  // stands).
  const std::size_t i = j * (2 * CentringSamples + 1) + static_cast<std::size_t>(k);
  const double p1 = values[0][i], rho1 = values[1][i];
  const double* u = &values[2][3 * i];
  const double* nrm = surfaceNormals.data() + 3 * j;
  const double gamma = self->GetGamma();
  const double un = u[0] * nrm[0] + u[1] * nrm[1] + u[2] * nrm[2];
  if (!(p1 > 0.0) || !(rho1 > 0.0) || !std::isfinite(un))
  {
    return std::numeric_limits<double>::quiet_NaN();
  }
  const double mn2 = un * un * rho1 / (gamma * p1);
  if (!(mn2 > 1.0))
  {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return jumpOf == vtkShockSensor::PRESSURE ? p1 * (1.0 + 2.0 * gamma / (gamma + 1.0) * (mn2 - 1.0))
                                            : rho1 * (gamma + 1.0) * mn2 / ((gamma - 1.0) * mn2 + 2.0);
}

//------------------------------------------------------------------------------
void FitRun::FitNormal(std::size_t j, double l, double g[3]) const
{
  // The unit normal of the fit at point j: the gradient of the signed
  // distance (central differences over 1e-3 of the point's size l).
  double len = 0.0;
  for (int a = 0; a < 3; ++a)
  {
    double xp[3] = { xyz[3 * j], xyz[3 * j + 1], xyz[3 * j + 2] }, xm[3] = { xp[0], xp[1], xp[2] };
    xp[a] += 1e-3 * l;
    xm[a] -= 1e-3 * l;
    g[a] = (ar::SurfaceDistance(fit, xp) - ar::SurfaceDistance(fit, xm)) / (2e-3 * l);
    len += g[a] * g[a];
  }
  len = std::sqrt(len);
  for (int a = 0; a < 3 && len > 0.0 && std::isfinite(len); ++a)
  {
    g[a] /= len;
  }
}

//------------------------------------------------------------------------------
double FitRun::NormalsMoved(const std::vector<double>& scale) const
{
  // The largest angle (degrees) between the normals the lines' jumps were
  // read with and the current fit's, at the points.
  double worst = 0.0;
  for (std::size_t j = 0; j < n; ++j)
  {
    double g[3];
    FitNormal(j, scale[j], g);
    const double c = vtkMath::Dot(g, &surfaceNormals[3 * j]);
    worst = std::max(worst, vtkMath::DegreesFromRadians(std::acos(std::min(1.0, std::abs(c)))));
  }
  return worst;
}

//------------------------------------------------------------------------------
void FitRun::CentringLines(std::vector<double>& lines, std::vector<double>& normals, std::vector<double>& scale)
{
  // The lines along the first fit's normal through the points, CentringReach
  // local sizes to either side, CentringSamples samples per side (none when
  // there is no centring array or no length).
  const char* centringArray = self->GetCentringArray();
  const int samples = 2 * CentringSamples + 1;
  if (probedArrays.empty())
  {
    vtkWarningWithObjectMacro(self, << "ShockCentring: the Domain has no one-component array "
                    << (centringArray && std::string(centringArray) != vtkShockSensor::AutomaticArrayName
                           ? std::string("'") + centringArray + "'"
                           : std::string("of pressure or density (p, Pressure, rho, Density, ...)"))
                    << "; the points are fitted where they are.");
    return;
  }
  if (!haveSize && !haveWeight)
  {
    vtkWarningWithObjectMacro(self, "ShockCentring: the points have neither LocalSize nor Weight, so no length for "
                    "the centring lines; the points are fitted where they are.");
    centringUsed.clear();
    return;
  }
  lines.resize(3 * n * samples);
  surfaceNormals.assign(3 * n, 0.0);
  tolerance = 1e-6 * typical; // typical > 0: the points have LocalSize or Weight
  vtkSmartPointer<vtkStaticCellLocator> onBoundary;
  if (boundary && boundary->GetNumberOfCells() > 0)
  {
    onBoundary = vtkSmartPointer<vtkStaticCellLocator>::New();
    onBoundary->SetDataSet(boundary);
    onBoundary->BuildLocator();
  }
  vtkNew<vtkIdList> near;
  for (std::size_t j = 0; j < n; ++j)
  {
    const double l = haveSize ? packed[Stride * j + 4] : 1.0 / w[j];
    scale[j] = l;
    double g[3];
    FitNormal(j, l, g);
    std::copy(g, g + 3, &surfaceNormals[3 * j]);
    // A point on the domain's boundary (a symmetry plane, the front or
    // back plane of a one-cell-deep mesh) centres along the boundary: a
    // normal tilted out of it by a hair would leave half the line outside.
    // (Any line across the shock finds the half-jump on the shock.)
    if (onBoundary)
    {
      AlongBoundary(onBoundary, near, j, l, g);
    }
    std::copy(g, g + 3, &normals[3 * j]);
    for (int k = 0; k < samples; ++k)
    {
      const double sk = (k - CentringSamples) * CentringReach / CentringSamples * l;
      for (int a = 0; a < 3; ++a)
      {
        lines[3 * (j * samples + k) + a] = xyz[3 * j + a] + sk * normals[3 * j + a];
      }
    }
  }
}

//------------------------------------------------------------------------------
void FitRun::AlongBoundary(vtkStaticCellLocator* onBoundary, vtkIdList* near, std::size_t j, double l, double g[3])
{
  // Every boundary face within 1e-3 LocalSize (a point on an edge of
  // two planes, e.g. the outlet and the front plane, lies on both).
  const double r = 1e-3 * l;
  double box[6] = { xyz[3 * j] - r, xyz[3 * j] + r, xyz[3 * j + 1] - r, xyz[3 * j + 1] + r,
    xyz[3 * j + 2] - r, xyz[3 * j + 2] + r };
  near->Reset();
  onBoundary->FindCellsWithinBounds(box, near);
  near->Sort(); // the bins' order varies with the threads
  // The directions normal to the boundary there, independent of the
  // faces' order: the eigenvectors of sum n n^T with a weight of at
  // least a fifth of the faces' (one for a plane, two along an edge).
  double m[3][3] = { { 0.0, 0.0, 0.0 }, { 0.0, 0.0, 0.0 }, { 0.0, 0.0, 0.0 } };
  int faces = 0;
  for (vtkIdType c = 0; c < near->GetNumberOfIds(); ++c)
  {
    vtkCell* face = boundary->GetCell(near->GetId(c));
    double nb[3], p0[3];
    vtkPolygon::ComputeNormal(face->GetPoints(), nb);
    face->GetPoints()->GetPoint(0, p0);
    const double off = nb[0] * (xyz[3 * j] - p0[0]) + nb[1] * (xyz[3 * j + 1] - p0[1]) +
      nb[2] * (xyz[3 * j + 2] - p0[2]);
    if (std::abs(off) > r)
    {
      continue;
    }
    ++faces;
    for (int u = 0; u < 3; ++u)
    {
      for (int v = 0; v < 3; ++v)
      {
        m[u][v] += nb[u] * nb[v];
      }
    }
  }
  if (faces > 0)
  {
    double* rows[3] = { m[0], m[1], m[2] };
    double eigen[3], vec[3][3];
    double* vecs[3] = { vec[0], vec[1], vec[2] };
    vtkMath::Jacobi(rows, eigen, vecs); // eigenvectors in the columns
    for (int k = 0; k < 3; ++k)
    {
      if (eigen[k] >= 0.2 * faces)
      {
        const double nb[3] = { vec[0][k], vec[1][k], vec[2][k] };
        const double d = vtkMath::Dot(g, nb);
        for (int a = 0; a < 3; ++a)
        {
          g[a] -= d * nb[a];
        }
      }
    }
    const double t = vtkMath::Norm(g);
    for (int a = 0; a < 3; ++a)
    {
      g[a] = t > 0.2 ? g[a] / t : 0.0; // a shock along the wall: not centred
    }
  }
}

//------------------------------------------------------------------------------
bool FitRun::Refit(const std::vector<std::vector<double>>& values, const std::vector<double>& normals,
  const std::vector<double>& scale, int pass)
{
  // The points moved to the half-jump on their lines, fitted again; the
  // fit the lines followed is kept when fewer than half of them found a
  // jump. True when refitted.
  const int samples = 2 * CentringSamples + 1;
  std::vector<double> moved, movedWeights, shifts, widths;
  for (std::size_t j = 0; j < n; ++j)
  {
    double offset = 0.0;
    const bool unit = std::abs(normals[3 * j] * normals[3 * j] + normals[3 * j + 1] * normals[3 * j + 1] +
                               normals[3 * j + 2] * normals[3 * j + 2] - 1.0) < 1e-6;
    double width = -1.0;
    const bool okj = unit &&
      HalfJumpOffset(&values[centringIndex][j * samples], CentringReach, offset, &width,
        jumpOf >= 0 ? std::function<double(int)>([&](int k) { return RankineHugoniotTop(values, j, k); })
                    : std::function<double(int)>());
    if (!okj)
    {
      continue;
    }
    for (int a = 0; a < 3; ++a)
    {
      moved.push_back(xyz[3 * j + a] + offset * scale[j] * normals[3 * j + a]);
    }
    movedWeights.push_back(w[j]);
    shifts.push_back(std::abs(offset));
    if (width >= 0.0)
    {
      widths.push_back(width * scale[j]);
    }
  }
  const std::size_t count = movedWeights.size();
  const std::array<double, 4> keptResiduals = { residuals[0], residuals[1], residuals[2], residuals[3] };
  ar::SurfaceFitResult refit;
  std::string refitError;
  if (count >= std::max<std::size_t>(ar::SurfaceTemplateMinimumPoints(fit.Template), (n + 1) / 2) &&
    FitPoints(moved.data(), movedWeights.data(), count, refit, refitError))
  {
    fit = refit;
    centred = static_cast<double>(count);
    centringShift = Median(shifts);
    shockThickness = widths.empty() ? 0.0 : Median(widths);
    return true;
  }
  vtkWarningWithObjectMacro(self, << "ShockCentring: only " << count << " of " << n << " points found a jump of '"
                  << centringUsed << "' within " << CentringReach
                  << " LocalSize along the fitted surface's normal"
                  << (refitError.empty() ? "" : " (" + refitError + ")")
                  << (pass == 0 ? "; the first fit, of the points where they are, is kept."
                                : "; the previous pass's centred fit is kept."));
  std::copy(keptResiduals.begin(), keptResiduals.end(), residuals); // the kept fit's
  return false;
}

//------------------------------------------------------------------------------
bool FitRun::Mesh()
{
  // ---- Edge length and margin.
  h = self->GetSurfaceEdgeLength();
  if (!(h > 0.0))
  {
    if (typical > 0.0)
    {
      h = typical;
    }
    else
    {
      double lo[3] = { VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, VTK_DOUBLE_MAX };
      double hi[3] = { -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX };
      for (std::size_t j = 0; j < n; ++j)
      {
        for (int k = 0; k < 3; ++k)
        {
          lo[k] = std::min(lo[k], xyz[3 * j + k]);
          hi[k] = std::max(hi[k], xyz[3 * j + k]);
        }
      }
      h = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
            (hi[2] - lo[2]) * (hi[2] - lo[2])) / 50.0;
      vtkWarningWithObjectMacro(self, << "Without LocalSize or Weight the automatic edge length is 1/50 of the "
                         "cluster's diagonal: "
                      << h << ". Set SurfaceEdgeLength.");
    }
  }
  reach = std::max(1.0, self->GetMargin()) * h;

  // ---- Mesh the surface around the cluster.
  if (!ar::TessellateSurface(fit, xyz.data(), n, h, reach, mesh, error))
  {
    return Fail(error);
  }
  const vtkIdType nmesh = static_cast<vtkIdType>(mesh.Points.size() / 3);
  const vtkIdType ntri = static_cast<vtkIdType>(mesh.Triangles.size() / 3);
  vtkNew<vtkDoubleArray> coords;
  coords->SetNumberOfComponents(3);
  coords->SetNumberOfTuples(nmesh);
  std::copy(mesh.Points.begin(), mesh.Points.end(), coords->GetPointer(0));
  vtkNew<vtkPoints> points;
  points->SetData(coords);
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfTuples(ntri + 1);
  connectivity->SetNumberOfTuples(3 * ntri);
  for (vtkIdType t = 0; t <= ntri; ++t)
  {
    offsets->SetValue(t, 3 * t);
  }
  std::copy(mesh.Triangles.begin(), mesh.Triangles.end(), connectivity->GetPointer(0));
  vtkNew<vtkCellArray> triangles;
  triangles->SetData(offsets, connectivity);
  surface->SetPoints(points);
  surface->SetPolys(triangles);
  return true;
}

//------------------------------------------------------------------------------
bool FitRun::TrimToCluster()
{
  // ---- Trim to the cluster: keep what lies within `reach` of a foot.
  const vtkIdType nmesh = static_cast<vtkIdType>(mesh.Points.size() / 3);
  vtkNew<vtkDoubleArray> feet;
  feet->SetNumberOfComponents(3);
  feet->SetNumberOfTuples(static_cast<vtkIdType>(n));
  for (std::size_t j = 0; j < n; ++j)
  {
    ar::ProjectOntoSurface(fit, &xyz[3 * j], feet->GetPointer(3 * j));
  }
  vtkNew<vtkPoints> footPoints;
  footPoints->SetData(feet);
  vtkNew<vtkPolyData> footSet;
  footSet->SetPoints(footPoints);
  vtkNew<vtkStaticPointLocator> locator;
  locator->SetDataSet(footSet);
  locator->BuildLocator();
  vtkNew<vtkDoubleArray> beyond;
  beyond->SetName("DistanceBeyondMargin");
  beyond->SetNumberOfTuples(nmesh);
  const double* X = mesh.Points.data();
  double* out = beyond->GetPointer(0);
  vtkSMPTools::For(0, nmesh, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType p = b; p < e; ++p)
    {
      double x[3] = { X[3 * p], X[3 * p + 1], X[3 * p + 2] };
      const vtkIdType q = locator->FindClosestPoint(x);
      const double* f = feet->GetPointer(3 * q);
      out[p] = std::sqrt(vtkMath::Distance2BetweenPoints(x, f)) - reach;
    }
  });
  // The cut's new points lie on chords of a curved surface: they go back
  // onto it (the band's other points are on it already and do not move).
  trimmed = KeepBelowZero(surface, beyond, [&](vtkPoints* band) {
    if (fit.Template == ar::SurfaceTemplate::Plane)
    {
      return;
    }
    vtkNew<vtkDoubleArray> projected;
    projected->SetNumberOfComponents(3);
    projected->SetNumberOfTuples(band->GetNumberOfPoints());
    vtkSMPTools::For(0, band->GetNumberOfPoints(), [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType p = b; p < e; ++p)
      {
        double x[3];
        band->GetPoint(p, x);
        ar::ProjectOntoSurface(fit, x, projected->GetPointer(3 * p));
      }
    });
    band->SetData(projected);
  });
  return true;
}

//------------------------------------------------------------------------------
bool FitRun::TrimToDomain()
{
  // ---- Trim to the domain.
  if (!hasDomain)
  {
    return true;
  }
  if (!boundary || boundary->GetNumberOfPolys() == 0)
  {
    return Fail("The Domain input is empty or has no boundary surface (it needs 3-D cells, or "
                "2-D cells enclosing a volume).");
  }
  vtkNew<vtkImplicitPolyDataDistance> distance;
  distance->SetInput(boundary);
  // The boundary's faces point out of volume cells that have positive
  // volume; check on a few cell centres which side is inside.
  int inside = 0, outside = 0;
  if (domain)
  {
    vtkNew<vtkGenericCell> cell;
    const vtkIdType nc = domain->GetNumberOfCells();
    const vtkIdType samples = std::min<vtkIdType>(nc, 25);
    for (vtkIdType s = 0; s < samples; ++s)
    {
      const vtkIdType c = s * nc / samples;
      domain->GetCell(c, cell);
      if (cell->GetCellDimension() != 3)
      {
        continue;
      }
      double pc[3], x[3];
      int sub = cell->GetParametricCenter(pc);
      std::vector<double> weights(std::max<vtkIdType>(cell->GetNumberOfPoints(), VTK_CELL_SIZE));
      cell->EvaluateLocation(sub, pc, x, weights.data());
      const double v = distance->EvaluateFunction(x);
      inside += v < 0.0 ? 1 : 0;
      outside += v > 0.0 ? 1 : 0;
    }
  }
  // Signed distances, negative inside, in double precision (vtkClipPolyData
  // would store its clip function's values as floats, an error of ~1e-7 of
  // the distance).
  const double sign = outside > inside ? -1.0 : 1.0;
  vtkSmartPointer<vtkDoubleArray> signedDistance =
    DomainDistance(trimmed, [&](const double x[3]) {
      double p[3] = { x[0], x[1], x[2] };
      return sign * distance->EvaluateFunction(p);
    });
  // The cut is exact where the boundary is flat and inside it where the
  // domain is convex; a point the linear cut leaves outside (near a curved
  // or concave part of the boundary) is moved onto the boundary.
  trimmed = KeepBelowZero(trimmed, signedDistance, [&](vtkPoints* band) {
    for (vtkIdType p = 0; p < band->GetNumberOfPoints(); ++p)
    {
      double x[3], closest[3];
      band->GetPoint(p, x);
      if (sign * distance->EvaluateFunctionAndGetClosestPoint(x, closest) > 0.0)
      {
        band->SetPoint(p, closest);
      }
    }
  });
  if (trimmed->GetNumberOfPolys() == 0)
  {
    return Fail("The fitted surface lies entirely outside the Domain.");
  }
  return true;
}

//------------------------------------------------------------------------------
bool FitRun::Output()
{
  output->ShallowCopy(trimmed);
  output->GetPointData()->Initialize();
  output->GetCellData()->Initialize();

  // ---- Field data.
  vtkFieldData* fd = output->GetFieldData();
  fd->Initialize();
  vtkNew<vtkStringArray> name;
  name->SetName("Template");
  name->InsertNextValue(ar::SurfaceTemplateName(fit.Template));
  fd->AddArray(name);
  fd->AddArray(vtkARMeshKernels::FieldArray("Coefficients", fit.Coefficients.data(), static_cast<int>(fit.Coefficients.size())));
  fd->AddArray(vtkARMeshKernels::FieldArray("RMSResidual", &fit.RMSResidual, 1));
  if (self->GetTemplate() == vtkQuadricFit::AUTOMATIC)
  {
    // Each candidate's RMS residual (plane, cone, quadric, quartic; NaN: not
    // tried or not fitted).
    fd->AddArray(vtkARMeshKernels::FieldArray("TemplateResiduals", residuals, 4));
  }
  fd->AddArray(vtkARMeshKernels::FieldArray("WeightedRMSResidual", &fit.WeightedRMSResidual, 1));
  const double count = static_cast<double>(n);
  fd->AddArray(vtkARMeshKernels::FieldArray("NumberOfFitPoints", &count, 1));
  fd->AddArray(vtkARMeshKernels::FieldArray("CentredPoints", &centred, 1));
  fd->AddArray(vtkARMeshKernels::FieldArray("CentringShift", &centringShift, 1));
  fd->AddArray(vtkARMeshKernels::FieldArray("ShockThickness", &shockThickness, 1));
  vtkNew<vtkStringArray> centringName;
  centringName->SetName("CentringArrayUsed");
  centringName->InsertNextValue(centred > 0.0 ? centringUsed : "none");
  fd->AddArray(centringName);
  fd->AddArray(vtkARMeshKernels::FieldArray("SurfaceEdgeLength", &h, 1));
  fd->AddArray(vtkARMeshKernels::FieldArray("FrameOrigin", fit.FrameOrigin, 3));
  double axes[9];
  std::copy(fit.FrameX, fit.FrameX + 3, axes);
  std::copy(fit.FrameY, fit.FrameY + 3, axes + 3);
  std::copy(fit.FrameZ, fit.FrameZ + 3, axes + 6);
  auto frameAxes = vtkARMeshKernels::FieldArray("FrameAxes", axes, 9);
  frameAxes->SetNumberOfComponents(3);
  frameAxes->SetNumberOfTuples(3);
  for (int i = 0; i < 9; ++i)
  {
    frameAxes->SetValue(i, axes[i]);
  }
  fd->AddArray(frameAxes);
  if (fit.Template == ar::SurfaceTemplate::Plane)
  {
    fd->AddArray(vtkARMeshKernels::FieldArray("Normal", fit.Normal, 3));
    fd->AddArray(vtkARMeshKernels::FieldArray("Origin", fit.Origin, 3));
  }
  else if (fit.Template == ar::SurfaceTemplate::Cone)
  {
    fd->AddArray(vtkARMeshKernels::FieldArray("Apex", fit.Apex, 3));
    fd->AddArray(vtkARMeshKernels::FieldArray("AxisDirection", fit.AxisDirection, 3));
    fd->AddArray(vtkARMeshKernels::FieldArray("HalfAngle", &fit.HalfAngleDegrees, 1));
  }
  return true;
}
}

//------------------------------------------------------------------------------
int vtkQuadricFit::ExecuteData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPointSet* input = vtkPointSet::GetData(inputVector[0], 0);
  const bool hasDomain = this->GetNumberOfInputConnections(1) > 0;
  vtkDataSet* domain = hasDomain ? vtkDataSet::GetData(inputVector[1], 0) : nullptr;
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  output->Initialize();
  FitRun run(this, input, domain, hasDomain, output);
  // Each stage but Gather on rank 0 alone; a stage that fails has said why.
  auto proceed = [&](double progress, bool abortable) {
    this->UpdateProgress(progress);
    return !abortable || !this->CheckAbort();
  };
  if (run.Gather() && proceed(0.1, false) && run.Points() && run.Fit() && run.Centre() && proceed(0.4, true) &&
    run.Mesh() && proceed(0.6, false) && run.TrimToCluster() && proceed(0.8, true) && run.TrimToDomain() &&
    run.Output())
  {
    this->UpdateProgress(1.0);
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkQuadricFit::SetDomainBoundary(vtkPolyData* boundary)
{
  if (this->DomainBoundary != boundary)
  {
    this->DomainBoundary = boundary;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkQuadricFit::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  static const char* names[] = { "Plane", "Quadric", "Cone", "Quartic", "Automatic" };
  os << indent << "Template: "
     << (this->Template >= PLANE && this->Template <= AUTOMATIC ? names[this->Template] : "(invalid)") << "\n";
  os << indent << "ClusterId: " << this->ClusterId << "\n";
  os << indent << "AxisOrigin: " << this->AxisOrigin[0] << " " << this->AxisOrigin[1] << " "
     << this->AxisOrigin[2] << "\n";
  os << indent << "AxisDirection: " << this->AxisDirection[0] << " " << this->AxisDirection[1]
     << " " << this->AxisDirection[2] << "\n";
  os << indent << "UseAutomaticAxis: " << this->UseAutomaticAxis << "\n";
  os << indent << "GeometricRefinement: " << this->GeometricRefinement << "\n";
  os << indent << "RobustFit: " << this->RobustFit << "\n";
  os << indent << "SurfaceEdgeLength: " << this->SurfaceEdgeLength << "\n";
  os << indent << "ShockCentring: " << this->ShockCentring << "\n";
  os << indent << "CentringArray: " << (this->CentringArray ? this->CentringArray : "(none)") << "\n";
  os << indent << "Gamma: " << this->Gamma << "\n";
  os << indent << "Margin: " << this->Margin << "\n";
}
