// SPDX-License-Identifier: BSD-3-Clause
#include "vtkFeatureCluster.h"

#include "vtkARInputChecks.h"
#include "vtkARVolumeFilterExecution.h"
#include "vtkARMeshKernels.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkStringArray.h"
#include "vtkHexagonalPrism.h"
#include "vtkHexahedron.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkPentagonalPrism.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPyramid.h"
#include "vtkTetra.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkVoxel.h"
#include "vtkWedge.h"

#include "ARFeatureGraph.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <numeric>
#include <sstream>
#include <unordered_map>
#include <vector>

vtkStandardNewMacro(vtkFeatureCluster);

namespace
{
/// Calls f(a, b) for every edge (pair of local point indices) of a cell.
template <typename F>
void ForEachEdge(vtkUnstructuredGrid* grid, vtkIdType cellId, unsigned char type, int n, F&& f)
{
  auto table = [&](const vtkIdType* (*edge)(vtkIdType), int count) {
    for (int e = 0; e < count; ++e)
    {
      const vtkIdType* v = edge(e);
      f(static_cast<int>(v[0]), static_cast<int>(v[1]));
    }
  };
  switch (type)
  {
    case VTK_TETRA:
      table(&vtkTetra::GetEdgeArray, 6);
      break;
    case VTK_PYRAMID:
      table(&vtkPyramid::GetEdgeArray, 8);
      break;
    case VTK_WEDGE:
      table(&vtkWedge::GetEdgeArray, 9);
      break;
    case VTK_HEXAHEDRON:
      table(&vtkHexahedron::GetEdgeArray, 12);
      break;
    case VTK_VOXEL:
      table(&vtkVoxel::GetEdgeArray, 12);
      break;
    case VTK_PENTAGONAL_PRISM:
      table(&vtkPentagonalPrism::GetEdgeArray, 15);
      break;
    case VTK_HEXAGONAL_PRISM:
      table(&vtkHexagonalPrism::GetEdgeArray, 18);
      break;
    case VTK_POLYHEDRON:
    {
      // Face stream: nfaces, (npts, ids...) per face; edges join consecutive ids.
      vtkNew<vtkIdList> stream;
      grid->GetFaceStream(cellId, stream);
      vtkNew<vtkIdList> pts;
      grid->GetCellPoints(cellId, pts);
      auto local = [&](vtkIdType global) {
        for (vtkIdType k = 0; k < pts->GetNumberOfIds(); ++k)
        {
          if (pts->GetId(k) == global)
          {
            return static_cast<int>(k);
          }
        }
        return -1;
      };
      vtkIdType pos = 1;
      for (vtkIdType face = 0; face < stream->GetId(0); ++face)
      {
        const vtkIdType m = stream->GetId(pos);
        for (vtkIdType k = 0; k < m; ++k)
        {
          const int a = local(stream->GetId(pos + 1 + k));
          const int b = local(stream->GetId(pos + 1 + (k + 1) % m));
          if (a >= 0 && b >= 0)
          {
            f(a, b);
          }
        }
        pos += m + 1;
      }
      break;
    }
    default:
      // Convex point sets and anything else linear: every pair of points.
      for (int a = 0; a < n; ++a)
      {
        for (int b = a + 1; b < n; ++b)
        {
          f(a, b);
        }
      }
  }
}

/// Bit-exact key of a position, to merge the copies of a node held by several ranks.
struct PositionKey
{
  double X[3];
  bool operator==(const PositionKey& o) const { return std::memcmp(X, o.X, sizeof(X)) == 0; }
};
struct PositionHash
{
  std::size_t operator()(const PositionKey& k) const
  {
    std::uint64_t h = 1469598103934665603ull;
    const unsigned char* b = reinterpret_cast<const unsigned char*>(k.X);
    for (std::size_t i = 0; i < sizeof(k.X); ++i)
    {
      h = (h ^ b[i]) * 1099511628211ull;
    }
    return static_cast<std::size_t>(h);
  }
};

/// The feature region of one rank: its nodes (positions, seed flags) and edges.
struct Region
{
  std::vector<vtkIdType> PointIds; ///< local point id of each region node
  std::vector<double> X;
  std::vector<std::uint8_t> Seeds;
  std::vector<std::int64_t> Edges;
};

const int TAG_SIZES = 48101;
const int TAG_POINTS = 48102;
const int TAG_SEEDS = 48103;
const int TAG_EDGES = 48104;
const int TAG_RESULTS = 48105;
}

//------------------------------------------------------------------------------
vtkFeatureCluster::vtkFeatureCluster()
  : vtkARVolumeFilter("feature clustering")
{
  this->SetNumberOfOutputPorts(2);
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS_THEN_CELLS, AutomaticArrayName);
}

int vtkFeatureCluster::FillOutputPortInformation(int port, vtkInformation* info)
{
  if (port == 1)
  {
    info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkPolyData");
    return 1;
  }
  return this->Superclass::FillOutputPortInformation(port, info);
}

//------------------------------------------------------------------------------
//------------------------------------------------------------------------------
/// The state of one execution, shared by the passes of Execute.
struct vtkFeatureCluster::ClusterState
{
  bool AutomaticRange = false;
  // The sensor and its range.
  int Association = -1;
  const char* Name = "";
  bool AutomaticArray = true;
  vtkDataArray* Sensor = nullptr;
  double Lo = 0.0;
  double Hi = 0.0;
  // Step 1.
  std::vector<std::uint8_t> Seeds;
  double SensorSpan[2] = { VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX };
  /// This rank's feature region.
  Region LocalRegion;
  // The regions gathered on rank 0: merged nodes, seeds, edges.
  vtkMultiProcessController* Controller = nullptr;
  int NumberOfRanks = 1;
  int Rank = 0;
  std::vector<double> X;
  std::vector<std::uint8_t> S;
  std::vector<std::int64_t> E;
  std::vector<std::vector<std::int64_t>> Merged;
  /// Steps 2-5 (rank 0), and per region node of this rank: mask, cluster id, distance, medial.
  ar::FeatureGraphResult Result;
  std::vector<int> Mine;
};

int vtkFeatureCluster::Execute(Execution& run)
{
  // The passes below share the state of this execution (ClusterState); every
  // rank reaches the same collective calls, in order.
  ClusterState st;
  std::ostringstream& problem = run.Problem;
  vtkARMeshKernels::MeshView& mesh = run.Mesh;
  const vtkIdType npts = run.Mesh.NumberOfPoints;
  const vtkIdType ncells = run.Mesh.NumberOfCells;
  bool& automaticRange = st.AutomaticRange;
  vtkDataArray*& sensor = st.Sensor;
  double& lo = st.Lo;
  double& hi = st.Hi;
  std::vector<std::uint8_t>& seeds = st.Seeds;
  double (&sensorSpan)[2] = st.SensorSpan;

  problem << vtkARInputChecks::Properties()
               .InRange("DilationRings", this->DilationRings, 0, 16)
               .InRange("MinimumClusterSize", this->MinimumClusterSize, 1, VTK_INT_MAX)
               .Message();
  automaticRange = this->SensorRange[0] == 0.0 && this->SensorRange[1] == 0.0;
  if (!automaticRange && !(this->SensorRange[0] <= this->SensorRange[1]))
  {
    problem << "SensorRange [" << this->SensorRange[0] << ", " << this->SensorRange[1]
            << "] is empty (lower bound above the upper). ";
  }

  this->FindSensor(run, st);
  this->SelectSeeds(run, st);
  // ---- A range that seeds every node isolates no feature: the one cluster
  // would be the whole domain, with no boundary and so no medial points.
  // Refused (collective: every rank takes part in the sums).
  {
    double counts[2] = { 0.0, 0.0 }; // seeded owned nodes, owned nodes
    for (vtkIdType p = 0; p < npts && ncells > 0; ++p)
    {
      if (mesh.IsOwnedPoint(p))
      {
        counts[0] += seeds[p] ? 1.0 : 0.0;
        counts[1] += 1.0;
      }
    }
    vtkARMeshKernels::AllReduceSum(counts, 2);
    double span[2] = { -sensorSpan[0], sensorSpan[1] };
    vtkARMeshKernels::AllReduceMax(span, 2);
    if (problem.str().empty() && counts[1] > 0.0 && counts[0] == counts[1])
    {
      problem << "SensorRange [" << lo << ", " << hi << "] selects every node (" << counts[0] << " of "
              << counts[1] << "): the cluster would be the whole domain, so no feature is isolated (and it has "
              << "no medial points). The sensor '" << (sensor && sensor->GetName() ? sensor->GetName() : "") << "' spans [" << -span[0] << ", "
              << span[1] << "] on this mesh: choose a range inside it that holds the feature's values only "
              << "(the automatic range, [0, 0], is [0.8, 1.2] for NormalMach, [1.5, 2] for WeightFunction). ";
    }
  }
  if (!this->Proceed(run))
  {
    return 1;
  }

  this->GrowRegion(run, st);
  this->UpdateProgress(0.5);
  if (this->Cancelled())
  {
    return 1; // cancelled (collective work under MPI runs to its end)
  }

  this->GatherRegions(run, st);
  this->ClusterOnRoot(run, st);
  this->UpdateProgress(0.8);
  if (this->Cancelled())
  {
    return 1; // cancelled (collective work under MPI runs to its end)
  }

  this->WriteOutputs(run, st);
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
void vtkFeatureCluster::FindSensor(Execution& run, ClusterState& st)
{
  vtkUnstructuredGrid* input = run.Input;
  std::ostringstream& problem = run.Problem;
  bool& automaticRange = st.AutomaticRange;
  int& association = st.Association;
  const char*& name = st.Name;
  bool& automaticArray = st.AutomaticArray;
  vtkDataArray*& sensor = st.Sensor;
  double& lo = st.Lo;
  double& hi = st.Hi;

  // ---- The sensor (named, or the sensor upstream's) and its range.
  association = -1;
  vtkInformation* info = this->GetInputArrayInformation(0);
  name = (info && info->Has(vtkDataObject::FIELD_NAME())) ? info->Get(vtkDataObject::FIELD_NAME()) : "";
  automaticArray = !name || !*name || std::string(name) == AutomaticArrayName;
  sensor = nullptr;
  if (!automaticArray)
  {
    sensor = this->GetInputArrayToProcess(0, input, association);
  }
  else
  {
    for (const char* candidate : { "NormalMach", "WeightFunction" })
    {
      for (int where = 0; where < 2 && !sensor; ++where)
      {
        vtkDataSetAttributes* data = where == 0 ? static_cast<vtkDataSetAttributes*>(input->GetPointData())
                                                : static_cast<vtkDataSetAttributes*>(input->GetCellData());
        vtkDataArray* a = data->GetArray(candidate);
        if (a && a->GetNumberOfComponents() == 1)
        {
          sensor = a;
          association = where == 0 ? vtkDataObject::FIELD_ASSOCIATION_POINTS : vtkDataObject::FIELD_ASSOCIATION_CELLS;
        }
      }
      if (sensor)
      {
        break;
      }
    }
  }
  lo = this->SensorRange[0];
  hi = this->SensorRange[1];
  if (sensor && automaticRange)
  {
    const std::string sensorName = sensor->GetName() ? sensor->GetName() : "";
    if (sensorName == "NormalMach")
    {
      lo = 0.8;
      hi = 1.2;
    }
    else if (sensorName == "WeightFunction")
    {
      lo = 1.5;
      hi = 2.0;
    }
    else
    {
      problem << "SensorRange is [0, 0] (automatic), but there is no automatic range for the sensor '"
              << sensorName << "' (only for NormalMach and WeightFunction): set SensorRange. ";
    }
  }
}

//------------------------------------------------------------------------------
void vtkFeatureCluster::SelectSeeds(Execution& run, ClusterState& st)
{
  std::ostringstream& problem = run.Problem;
  vtkARMeshKernels::MeshView& mesh = run.Mesh;
  const vtkIdType npts = run.Mesh.NumberOfPoints;
  const vtkIdType ncells = run.Mesh.NumberOfCells;
  int& association = st.Association;
  const char*& name = st.Name;
  bool& automaticArray = st.AutomaticArray;
  vtkDataArray*& sensor = st.Sensor;
  double& lo = st.Lo;
  double& hi = st.Hi;
  std::vector<std::uint8_t>& seeds = st.Seeds;
  double (&sensorSpan)[2] = st.SensorSpan;

  // ---- Step 1: the seeds.
  seeds.assign(npts, 0);
  sensorSpan[0] = VTK_DOUBLE_MAX; // this rank's finite sensor values
  sensorSpan[1] = -VTK_DOUBLE_MAX;
  if (ncells > 0)
  {
    if (!sensor && automaticArray)
    {
      problem << "The sensor array is automatic, and the input has neither NormalMach (Shock Sensor) "
                 "nor WeightFunction (Weight Function): apply a sensor first, or pick the array. ";
    }
    else if (!sensor)
    {
      problem << "The sensor array '" << name << "' is not a point or cell array of the input. ";
    }
    else if (sensor->GetNumberOfComponents() != 1)
    {
      problem << "The sensor array '" << sensor->GetName() << "' has "
              << sensor->GetNumberOfComponents() << " components; it needs 1. ";
    }
    else
    {
      const bool onPoints = association == vtkDataObject::FIELD_ASSOCIATION_POINTS;
      std::vector<double> values(onPoints ? npts : ncells);
      const vtkIdType bad = vtkARMeshKernels::PackComponents(sensor, values.data(), 1, 0);
      if (bad >= 0)
      {
        problem << "The sensor array '" << sensor->GetName() << "' holds NaN or Inf ("
                << (onPoints ? "point " : "cell ") << bad << "). ";
      }
      for (const double v : values)
      {
        sensorSpan[0] = std::isfinite(v) ? std::min(sensorSpan[0], v) : sensorSpan[0];
        sensorSpan[1] = std::isfinite(v) ? std::max(sensorSpan[1], v) : sensorSpan[1];
      }
      if (onPoints)
      {
        vtkSMPTools::For(0, npts, [&](vtkIdType b, vtkIdType e) {
          for (vtkIdType p = b; p < e; ++p)
          {
            seeds[p] = (values[p] >= lo && values[p] <= hi) ? 1 : 0;
          }
        });
      }
      else
      {
        // The nodes of the (3-D) cells in range. Benign identical writes.
        std::vector<std::atomic<std::uint8_t>> marks(npts);
        vtkSMPTools::For(0, ncells, [&](vtkIdType b, vtkIdType e) {
          for (vtkIdType c = b; c < e; ++c)
          {
            if (mesh.IsVolumeCell(c) && values[c] >= lo && values[c] <= hi)
            {
              const vtkIdType* ids = mesh.CellPoints(c);
              for (int a = 0; a < mesh.CellSize(c); ++a)
              {
                marks[ids[a]].store(1, std::memory_order_relaxed);
              }
            }
          }
        });
        for (vtkIdType p = 0; p < npts; ++p)
        {
          seeds[p] = marks[p].load(std::memory_order_relaxed);
        }
      }
    }
  }
}

//------------------------------------------------------------------------------
void vtkFeatureCluster::GrowRegion(Execution& run, ClusterState& st)
{
  vtkUnstructuredGrid* input = run.Input;
  vtkARMeshKernels::MeshView& mesh = run.Mesh;
  const vtkIdType npts = run.Mesh.NumberOfPoints;
  const vtkIdType ncells = run.Mesh.NumberOfCells;
  std::vector<std::uint8_t>& seeds = st.Seeds;
  Region& region = st.LocalRegion;

  // ---- The feature region: cells within DilationRings + 1 rings of a seed
  // (rings through shared cells, a superset of rings through edges), so that
  // every edge at a node within DilationRings edge-rings of a seed is in it.
  const int rings = this->DilationRings;
  std::vector<std::atomic<std::uint8_t>> level(npts);
  vtkSMPTools::For(0, npts, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType p = b; p < e; ++p)
    {
      level[p].store(seeds[p] ? 0 : 255, std::memory_order_relaxed);
    }
  });
  for (int ring = 0; ring < rings; ++ring)
  {
    vtkSMPTools::For(0, ncells, [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType c = b; c < e; ++c)
      {
        const vtkIdType* ids = mesh.CellPoints(c);
        const int n = mesh.CellSize(c);
        bool touches = false;
        for (int a = 0; a < n && !touches; ++a)
        {
          touches = level[ids[a]].load(std::memory_order_relaxed) == ring;
        }
        if (touches)
        {
          for (int a = 0; a < n; ++a)
          {
            if (level[ids[a]].load(std::memory_order_relaxed) > ring + 1)
            {
              level[ids[a]].store(static_cast<std::uint8_t>(ring + 1), std::memory_order_relaxed);
            }
          }
        }
      }
    });
  }
  std::vector<std::uint8_t> regionCell(ncells, 0);
  vtkSMPTools::For(0, ncells, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType c = b; c < e; ++c)
    {
      if (!mesh.IsVolumeCell(c))
      {
        continue;
      }
      const vtkIdType* ids = mesh.CellPoints(c);
      for (int a = 0; a < mesh.CellSize(c); ++a)
      {
        if (level[ids[a]].load(std::memory_order_relaxed) <= rings)
        {
          regionCell[c] = 1;
          break;
        }
      }
    }
  });

  {
    std::vector<vtkIdType> compact(npts, -1);
    for (vtkIdType c = 0; c < ncells; ++c)
    {
      if (!regionCell[c])
      {
        continue;
      }
      const vtkIdType* ids = mesh.CellPoints(c);
      const int n = mesh.CellSize(c);
      for (int a = 0; a < n; ++a)
      {
        if (compact[ids[a]] < 0)
        {
          compact[ids[a]] = static_cast<vtkIdType>(region.PointIds.size());
          region.PointIds.push_back(ids[a]);
        }
      }
      ForEachEdge(input, c, mesh.Types[c], n, [&](int a, int b) {
        region.Edges.push_back(compact[ids[a]]);
        region.Edges.push_back(compact[ids[b]]);
      });
    }
    region.X.resize(3 * region.PointIds.size());
    region.Seeds.resize(region.PointIds.size());
    for (size_t i = 0; i < region.PointIds.size(); ++i)
    {
      std::copy_n(mesh.X + 3 * region.PointIds[i], 3, &region.X[3 * i]);
      // Only owned nodes seed: a ghost copy's sensor value may come from an
      // incomplete stencil, and its owner sends the right one. (Ghost copies
      // in range still grew the region, so that this rank's nodes next to
      // another rank's seeds are in it.)
      region.Seeds[i] = mesh.IsOwnedPoint(region.PointIds[i]) ? seeds[region.PointIds[i]] : 0;
    }
  }
}

//------------------------------------------------------------------------------
void vtkFeatureCluster::GatherRegions(Execution& run, ClusterState& st)
{
  Region& region = st.LocalRegion;
  vtkMultiProcessController*& ctrl = st.Controller;
  int& nranks = st.NumberOfRanks;
  int& rank = st.Rank;
  std::vector<double>& X = st.X;
  std::vector<std::uint8_t>& S = st.S;
  std::vector<std::int64_t>& E = st.E;
  std::vector<std::vector<std::int64_t>>& merged = st.Merged;

  // ---- Gather the regions on rank 0 and merge the nodes by position.
  ctrl = vtkMultiProcessController::GetGlobalController();
  nranks = ctrl ? ctrl->GetNumberOfProcesses() : 1;
  rank = ctrl ? ctrl->GetLocalProcessId() : 0;
  merged.resize(nranks); // per rank: region node -> merged node
  if (rank == 0)
  {
    std::unordered_map<PositionKey, std::int64_t, PositionHash> index;
    auto absorb = [&](int from, const std::vector<double>& x, const std::vector<std::uint8_t>& s,
                    const std::vector<std::int64_t>& e) {
      const size_t m = s.size();
      merged[from].resize(m);
      for (size_t i = 0; i < m; ++i)
      {
        PositionKey key{ { x[3 * i], x[3 * i + 1], x[3 * i + 2] } };
        auto it = index.find(key);
        if (it == index.end())
        {
          it = index.emplace(key, static_cast<std::int64_t>(S.size())).first;
          X.insert(X.end(), key.X, key.X + 3);
          S.push_back(s[i]);
        }
        else
        {
          S[it->second] |= s[i];
        }
        merged[from][i] = it->second;
      }
      for (std::int64_t v : e)
      {
        E.push_back(merged[from][v]);
      }
    };
    absorb(0, region.X, region.Seeds, region.Edges);
    for (int r = 1; r < nranks; ++r)
    {
      vtkIdType sizes[2];
      ctrl->Receive(sizes, 2, r, TAG_SIZES);
      std::vector<double> x(3 * sizes[0]);
      std::vector<std::uint8_t> s(sizes[0]);
      std::vector<std::int64_t> e(sizes[1]);
      ctrl->Receive(x.data(), x.size(), r, TAG_POINTS);
      ctrl->Receive(reinterpret_cast<unsigned char*>(s.data()), s.size(), r, TAG_SEEDS);
      std::vector<vtkIdType> ev(e.size());
      ctrl->Receive(ev.data(), ev.size(), r, TAG_EDGES);
      std::copy(ev.begin(), ev.end(), e.begin());
      absorb(r, x, s, e);
    }
  }
  else
  {
    vtkIdType sizes[2] = { static_cast<vtkIdType>(region.Seeds.size()),
      static_cast<vtkIdType>(region.Edges.size()) };
    ctrl->Send(sizes, 2, 0, TAG_SIZES);
    ctrl->Send(region.X.data(), region.X.size(), 0, TAG_POINTS);
    ctrl->Send(reinterpret_cast<unsigned char*>(region.Seeds.data()), region.Seeds.size(), 0, TAG_SEEDS);
    std::vector<vtkIdType> ev(region.Edges.begin(), region.Edges.end());
    ctrl->Send(ev.data(), ev.size(), 0, TAG_EDGES);
  }
}

//------------------------------------------------------------------------------
void vtkFeatureCluster::ClusterOnRoot(Execution& run, ClusterState& st)
{
  Region& region = st.LocalRegion;
  vtkMultiProcessController*& ctrl = st.Controller;
  int& nranks = st.NumberOfRanks;
  int& rank = st.Rank;
  std::vector<double>& X = st.X;
  std::vector<std::uint8_t>& S = st.S;
  std::vector<std::int64_t>& E = st.E;
  std::vector<std::vector<std::int64_t>>& merged = st.Merged;
  ar::FeatureGraphResult& result = st.Result;
  std::vector<int>& mine = st.Mine;

  // ---- Steps 2-5 on rank 0, results sent back to every rank.
  // Per region node of this rank: mask, cluster id, distance, medial.
  mine.assign(4 * region.Seeds.size(), 0);
  if (rank == 0)
  {
    ar::FeatureGraphInput graph;
    graph.Points = X.data();
    graph.NumberOfPoints = S.size();
    graph.Seeds = S.data();
    graph.Edges = E.data();
    graph.NumberOfEdges = E.size() / 2;
    graph.DilationRings = this->DilationRings;
    graph.MinimumClusterSize = this->MinimumClusterSize;
    result = ar::ClusterFeatures(graph);
    for (int r = 0; r < nranks; ++r)
    {
      std::vector<int> back(4 * merged[r].size());
      for (size_t i = 0; i < merged[r].size(); ++i)
      {
        const std::int64_t m = merged[r][i];
        back[4 * i] = result.Mask[m];
        back[4 * i + 1] = result.ClusterId[m];
        back[4 * i + 2] = result.Distance[m];
        back[4 * i + 3] = result.Medial[m];
      }
      if (r == 0)
      {
        mine.swap(back);
      }
      else
      {
        ctrl->Send(back.data(), back.size(), r, TAG_RESULTS);
      }
    }
  }
  else
  {
    ctrl->Receive(mine.data(), mine.size(), 0, TAG_RESULTS);
  }
}

//------------------------------------------------------------------------------
void vtkFeatureCluster::WriteOutputs(Execution& run, ClusterState& st)
{
  vtkUnstructuredGrid* output = run.Output;
  vtkPolyData* medial = vtkPolyData::GetData(run.OutputVector, 1);
  const vtkIdType npts = run.Mesh.NumberOfPoints;
  vtkDataArray*& sensor = st.Sensor;
  double& lo = st.Lo;
  double& hi = st.Hi;
  Region& region = st.LocalRegion;
  int& rank = st.Rank;
  std::vector<double>& X = st.X;
  std::vector<std::uint8_t>& S = st.S;
  ar::FeatureGraphResult& result = st.Result;
  std::vector<int>& mine = st.Mine;

  // ---- Port 0: the point arrays.
  vtkNew<vtkUnsignedCharArray> mask;
  mask->SetName("FeatureMask");
  mask->SetNumberOfTuples(npts);
  mask->Fill(0);
  vtkNew<vtkIntArray> clusterId;
  clusterId->SetName("ClusterId");
  clusterId->SetNumberOfTuples(npts);
  clusterId->Fill(-1);
  vtkNew<vtkIntArray> distance;
  distance->SetName("BoundaryDistance");
  distance->SetNumberOfTuples(npts);
  distance->Fill(-1);
  vtkNew<vtkUnsignedCharArray> medialFlag;
  medialFlag->SetName("MedialPoint");
  medialFlag->SetNumberOfTuples(npts);
  medialFlag->Fill(0);
  for (size_t i = 0; i < region.PointIds.size(); ++i)
  {
    const vtkIdType p = region.PointIds[i];
    mask->SetValue(p, static_cast<unsigned char>(mine[4 * i]));
    clusterId->SetValue(p, mine[4 * i + 1]);
    distance->SetValue(p, mine[4 * i + 2]);
    medialFlag->SetValue(p, static_cast<unsigned char>(mine[4 * i + 3]));
  }
  output->GetPointData()->AddArray(mask);
  output->GetPointData()->AddArray(clusterId);
  output->GetPointData()->AddArray(distance);
  output->GetPointData()->AddArray(medialFlag);
  // What was selected by: the sensor and its range (both ports).
  auto addSelection = [&](vtkFieldData* fd) {
    vtkNew<vtkStringArray> used;
    used->SetName("SensorArrayUsed");
    used->InsertNextValue(sensor && sensor->GetName() ? sensor->GetName() : "");
    fd->AddArray(used);
    const double range[2] = { lo, hi };
    fd->AddArray(vtkARMeshKernels::FieldArray("SensorRangeUsed", range, 2));
  };
  addSelection(output->GetFieldData());

  // ---- Port 1 (rank 0): the medial points, ordered by cluster then position.
  if (rank == 0)
  {
    std::vector<std::int64_t> order;
    for (size_t m = 0; m < result.Medial.size(); ++m)
    {
      if (result.Medial[m])
      {
        order.push_back(static_cast<std::int64_t>(m));
      }
    }
    std::sort(order.begin(), order.end(), [&](std::int64_t a, std::int64_t b) {
      if (result.ClusterId[a] != result.ClusterId[b])
      {
        return result.ClusterId[a] < result.ClusterId[b];
      }
      return std::lexicographical_compare(&X[3 * a], &X[3 * a + 3], &X[3 * b], &X[3 * b + 3]);
    });
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble();
    pts->SetNumberOfPoints(static_cast<vtkIdType>(order.size()));
    vtkNew<vtkIntArray> cid;
    cid->SetName("ClusterId");
    vtkNew<vtkDoubleArray> size;
    size->SetName("LocalSize");
    vtkNew<vtkDoubleArray> weight;
    weight->SetName("Weight");
    vtkNew<vtkIntArray> dist;
    dist->SetName("BoundaryDistance");
    for (auto* a : { static_cast<vtkDataArray*>(cid), static_cast<vtkDataArray*>(size),
           static_cast<vtkDataArray*>(weight), static_cast<vtkDataArray*>(dist) })
    {
      a->SetNumberOfTuples(static_cast<vtkIdType>(order.size()));
    }
    vtkNew<vtkCellArray> verts;
    for (size_t k = 0; k < order.size(); ++k)
    {
      const std::int64_t m = order[k];
      pts->SetPoint(static_cast<vtkIdType>(k), &X[3 * m]);
      cid->SetValue(static_cast<vtkIdType>(k), result.ClusterId[m]);
      size->SetValue(static_cast<vtkIdType>(k), result.LocalSize[m]);
      weight->SetValue(static_cast<vtkIdType>(k), result.LocalSize[m] > 0 ? 1.0 / result.LocalSize[m] : 0.0);
      dist->SetValue(static_cast<vtkIdType>(k), result.Distance[m]);
      const vtkIdType id = static_cast<vtkIdType>(k);
      verts->InsertNextCell(1, &id);
    }
    medial->SetPoints(pts);
    medial->SetVerts(verts);
    medial->GetPointData()->AddArray(cid);
    medial->GetPointData()->AddArray(size);
    medial->GetPointData()->AddArray(weight);
    medial->GetPointData()->AddArray(dist);
    vtkNew<vtkIdTypeArray> clusterSizes;
    clusterSizes->SetName("ClusterSizes");
    clusterSizes->SetNumberOfTuples(static_cast<vtkIdType>(result.ClusterSizes.size()));
    for (size_t k = 0; k < result.ClusterSizes.size(); ++k)
    {
      clusterSizes->SetValue(static_cast<vtkIdType>(k), result.ClusterSizes[k]);
    }
    medial->GetFieldData()->AddArray(clusterSizes);
    addSelection(medial->GetFieldData());
    if (result.ClusterSizes.empty())
    {
      vtkWarningMacro(<< "No cluster: no node has a sensor value in [" << lo << ", " << hi << "]"
                      << (std::count(S.begin(), S.end(), 1) > 0
                             ? " in a cluster of at least MinimumClusterSize nodes."
                             : "."));
    }
  }
}

//------------------------------------------------------------------------------
void vtkFeatureCluster::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SensorRange: " << this->SensorRange[0] << " " << this->SensorRange[1] << "\n";
  os << indent << "DilationRings: " << this->DilationRings << "\n";
  os << indent << "MinimumClusterSize: " << this->MinimumClusterSize << "\n";
}
