// SPDX-License-Identifier: BSD-3-Clause
#include "vtkFeatureCluster.h"

#include "vtkARInputChecks.h"
#include "vtkARVolumeFilterExecution.h"
#include "vtkARMeshKernels.h"
#include "vtkARParallel.h"
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

  problem << vtkARInputChecks::Properties()
               .InRange("DilationRings", this->DilationRings, 0, 16)
               .InRange("MinimumClusterSize", this->MinimumClusterSize, 1, VTK_INT_MAX)
               .Message();
  st.AutomaticRange = this->SensorRange[0] == 0.0 && this->SensorRange[1] == 0.0;
  if (!st.AutomaticRange && !(this->SensorRange[0] <= this->SensorRange[1]))
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
        counts[0] += st.Seeds[p] ? 1.0 : 0.0;
        counts[1] += 1.0;
      }
    }
    vtkARParallel::AllReduceSum(counts, 2);
    double span[2] = { -st.SensorSpan[0], st.SensorSpan[1] };
    vtkARParallel::AllReduceMax(span, 2);
    if (problem.str().empty() && counts[1] > 0.0 && counts[0] == counts[1])
    {
      problem << "SensorRange [" << st.Lo << ", " << st.Hi << "] selects every node (" << counts[0] << " of "
              << counts[1] << "): the cluster would be the whole domain, so no feature is isolated (and it has "
              << "no medial points). The sensor '" << (st.Sensor && st.Sensor->GetName() ? st.Sensor->GetName() : "") << "' spans [" << -span[0] << ", "
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

  // ---- The sensor (named, or the sensor upstream's) and its range.
  st.Association = -1;
  vtkInformation* info = this->GetInputArrayInformation(0);
  st.Name = (info && info->Has(vtkDataObject::FIELD_NAME())) ? info->Get(vtkDataObject::FIELD_NAME()) : "";
  st.AutomaticArray = !st.Name || !*st.Name || std::string(st.Name) == AutomaticArrayName;
  st.Sensor = nullptr;
  if (!st.AutomaticArray)
  {
    st.Sensor = this->GetInputArrayToProcess(0, input, st.Association);
  }
  else
  {
    for (const char* candidate : { "NormalMach", "WeightFunction" })
    {
      for (int where = 0; where < 2 && !st.Sensor; ++where)
      {
        vtkDataSetAttributes* data = where == 0 ? static_cast<vtkDataSetAttributes*>(input->GetPointData())
                                                : static_cast<vtkDataSetAttributes*>(input->GetCellData());
        vtkDataArray* a = data->GetArray(candidate);
        if (a && a->GetNumberOfComponents() == 1)
        {
          st.Sensor = a;
          st.Association = where == 0 ? vtkDataObject::FIELD_ASSOCIATION_POINTS : vtkDataObject::FIELD_ASSOCIATION_CELLS;
        }
      }
      if (st.Sensor)
      {
        break;
      }
    }
  }
  st.Lo = this->SensorRange[0];
  st.Hi = this->SensorRange[1];
  if (st.Sensor && st.AutomaticRange)
  {
    const std::string sensorName = st.Sensor->GetName() ? st.Sensor->GetName() : "";
    if (sensorName == "NormalMach")
    {
      st.Lo = 0.8;
      st.Hi = 1.2;
    }
    else if (sensorName == "WeightFunction")
    {
      st.Lo = 1.5;
      st.Hi = 2.0;
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

  // ---- Step 1: the seeds.
  st.Seeds.assign(npts, 0);
  st.SensorSpan[0] = VTK_DOUBLE_MAX; // this rank's finite sensor values
  st.SensorSpan[1] = -VTK_DOUBLE_MAX;
  if (ncells > 0)
  {
    if (!st.Sensor && st.AutomaticArray)
    {
      problem << "The sensor array is automatic, and the input has neither NormalMach (Shock Sensor) "
                 "nor WeightFunction (Weight Function): apply a sensor first, or pick the array. ";
    }
    else if (!st.Sensor)
    {
      problem << "The sensor array '" << st.Name << "' is not a point or cell array of the input. ";
    }
    else if (st.Sensor->GetNumberOfComponents() != 1)
    {
      problem << "The sensor array '" << st.Sensor->GetName() << "' has "
              << st.Sensor->GetNumberOfComponents() << " components; it needs 1. ";
    }
    else
    {
      const bool onPoints = st.Association == vtkDataObject::FIELD_ASSOCIATION_POINTS;
      std::vector<double> values(onPoints ? npts : ncells);
      const vtkIdType bad = vtkARMeshKernels::PackComponents(st.Sensor, values.data(), 1, 0);
      if (bad >= 0)
      {
        problem << "The sensor array '" << st.Sensor->GetName() << "' holds NaN or Inf ("
                << (onPoints ? "point " : "cell ") << bad << "). ";
      }
      for (const double v : values)
      {
        st.SensorSpan[0] = std::isfinite(v) ? std::min(st.SensorSpan[0], v) : st.SensorSpan[0];
        st.SensorSpan[1] = std::isfinite(v) ? std::max(st.SensorSpan[1], v) : st.SensorSpan[1];
      }
      if (onPoints)
      {
        vtkSMPTools::For(0, npts, [&](vtkIdType b, vtkIdType e) {
          for (vtkIdType p = b; p < e; ++p)
          {
            st.Seeds[p] = (values[p] >= st.Lo && values[p] <= st.Hi) ? 1 : 0;
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
            if (mesh.IsVolumeCell(c) && values[c] >= st.Lo && values[c] <= st.Hi)
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
          st.Seeds[p] = marks[p].load(std::memory_order_relaxed);
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

  // ---- The feature region: cells within DilationRings + 1 rings of a seed
  // (rings through shared cells, a superset of rings through edges), so that
  // every edge at a node within DilationRings edge-rings of a seed is in it.
  const int rings = this->DilationRings;
  std::vector<std::atomic<std::uint8_t>> level(npts);
  vtkSMPTools::For(0, npts, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType p = b; p < e; ++p)
    {
      level[p].store(st.Seeds[p] ? 0 : 255, std::memory_order_relaxed);
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
          compact[ids[a]] = static_cast<vtkIdType>(st.LocalRegion.PointIds.size());
          st.LocalRegion.PointIds.push_back(ids[a]);
        }
      }
      ForEachEdge(input, c, mesh.Types[c], n, [&](int a, int b) {
        st.LocalRegion.Edges.push_back(compact[ids[a]]);
        st.LocalRegion.Edges.push_back(compact[ids[b]]);
      });
    }
    st.LocalRegion.X.resize(3 * st.LocalRegion.PointIds.size());
    st.LocalRegion.Seeds.resize(st.LocalRegion.PointIds.size());
    for (size_t i = 0; i < st.LocalRegion.PointIds.size(); ++i)
    {
      std::copy_n(mesh.X + 3 * st.LocalRegion.PointIds[i], 3, &st.LocalRegion.X[3 * i]);
      // Only owned nodes seed: a ghost copy's sensor value may come from an
      // incomplete stencil, and its owner sends the right one. (Ghost copies
      // in range still grew the region, so that this rank's nodes next to
      // another rank's seeds are in it.)
      st.LocalRegion.Seeds[i] = mesh.IsOwnedPoint(st.LocalRegion.PointIds[i]) ? st.Seeds[st.LocalRegion.PointIds[i]] : 0;
    }
  }
}

//------------------------------------------------------------------------------
void vtkFeatureCluster::GatherRegions(Execution& run, ClusterState& st)
{
  // ---- Gather the regions on rank 0 and merge the nodes by position.
  st.Controller = vtkMultiProcessController::GetGlobalController();
  st.NumberOfRanks = st.Controller ? st.Controller->GetNumberOfProcesses() : 1;
  st.Rank = st.Controller ? st.Controller->GetLocalProcessId() : 0;
  st.Merged.resize(st.NumberOfRanks); // per rank: region node -> merged node
  if (st.Rank == 0)
  {
    std::unordered_map<PositionKey, std::int64_t, PositionHash> index;
    auto absorb = [&](int from, const std::vector<double>& x, const std::vector<std::uint8_t>& s,
                    const std::vector<std::int64_t>& e) {
      const size_t m = s.size();
      st.Merged[from].resize(m);
      for (size_t i = 0; i < m; ++i)
      {
        PositionKey key{ { x[3 * i], x[3 * i + 1], x[3 * i + 2] } };
        auto it = index.find(key);
        if (it == index.end())
        {
          it = index.emplace(key, static_cast<std::int64_t>(st.S.size())).first;
          st.X.insert(st.X.end(), key.X, key.X + 3);
          st.S.push_back(s[i]);
        }
        else
        {
          st.S[it->second] |= s[i];
        }
        st.Merged[from][i] = it->second;
      }
      for (std::int64_t v : e)
      {
        st.E.push_back(st.Merged[from][v]);
      }
    };
    absorb(0, st.LocalRegion.X, st.LocalRegion.Seeds, st.LocalRegion.Edges);
    for (int r = 1; r < st.NumberOfRanks; ++r)
    {
      vtkIdType sizes[2];
      st.Controller->Receive(sizes, 2, r, TAG_SIZES);
      std::vector<double> x(3 * sizes[0]);
      std::vector<std::uint8_t> s(sizes[0]);
      std::vector<std::int64_t> e(sizes[1]);
      st.Controller->Receive(x.data(), x.size(), r, TAG_POINTS);
      st.Controller->Receive(reinterpret_cast<unsigned char*>(s.data()), s.size(), r, TAG_SEEDS);
      std::vector<vtkIdType> ev(e.size());
      st.Controller->Receive(ev.data(), ev.size(), r, TAG_EDGES);
      std::copy(ev.begin(), ev.end(), e.begin());
      absorb(r, x, s, e);
    }
  }
  else
  {
    vtkIdType sizes[2] = { static_cast<vtkIdType>(st.LocalRegion.Seeds.size()),
      static_cast<vtkIdType>(st.LocalRegion.Edges.size()) };
    st.Controller->Send(sizes, 2, 0, TAG_SIZES);
    st.Controller->Send(st.LocalRegion.X.data(), st.LocalRegion.X.size(), 0, TAG_POINTS);
    st.Controller->Send(reinterpret_cast<unsigned char*>(st.LocalRegion.Seeds.data()), st.LocalRegion.Seeds.size(), 0, TAG_SEEDS);
    std::vector<vtkIdType> ev(st.LocalRegion.Edges.begin(), st.LocalRegion.Edges.end());
    st.Controller->Send(ev.data(), ev.size(), 0, TAG_EDGES);
  }
}

//------------------------------------------------------------------------------
void vtkFeatureCluster::ClusterOnRoot(Execution& run, ClusterState& st)
{
  // ---- Steps 2-5 on rank 0, results sent back to every rank.
  // Per region node of this rank: mask, cluster id, distance, medial.
  st.Mine.assign(4 * st.LocalRegion.Seeds.size(), 0);
  if (st.Rank == 0)
  {
    ar::FeatureGraphInput graph;
    graph.Points = st.X.data();
    graph.NumberOfPoints = st.S.size();
    graph.Seeds = st.S.data();
    graph.Edges = st.E.data();
    graph.NumberOfEdges = st.E.size() / 2;
    graph.DilationRings = this->DilationRings;
    graph.MinimumClusterSize = this->MinimumClusterSize;
    st.Result = ar::ClusterFeatures(graph);
    for (int r = 0; r < st.NumberOfRanks; ++r)
    {
      std::vector<int> back(4 * st.Merged[r].size());
      for (size_t i = 0; i < st.Merged[r].size(); ++i)
      {
        const std::int64_t m = st.Merged[r][i];
        back[4 * i] = st.Result.Mask[m];
        back[4 * i + 1] = st.Result.ClusterId[m];
        back[4 * i + 2] = st.Result.Distance[m];
        back[4 * i + 3] = st.Result.Medial[m];
      }
      if (r == 0)
      {
        st.Mine.swap(back);
      }
      else
      {
        st.Controller->Send(back.data(), back.size(), r, TAG_RESULTS);
      }
    }
  }
  else
  {
    st.Controller->Receive(st.Mine.data(), st.Mine.size(), 0, TAG_RESULTS);
  }
}

//------------------------------------------------------------------------------
void vtkFeatureCluster::WriteOutputs(Execution& run, ClusterState& st)
{
  vtkUnstructuredGrid* output = run.Output;
  vtkPolyData* medial = vtkPolyData::GetData(run.OutputVector, 1);
  const vtkIdType npts = run.Mesh.NumberOfPoints;

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
  for (size_t i = 0; i < st.LocalRegion.PointIds.size(); ++i)
  {
    const vtkIdType p = st.LocalRegion.PointIds[i];
    mask->SetValue(p, static_cast<unsigned char>(st.Mine[4 * i]));
    clusterId->SetValue(p, st.Mine[4 * i + 1]);
    distance->SetValue(p, st.Mine[4 * i + 2]);
    medialFlag->SetValue(p, static_cast<unsigned char>(st.Mine[4 * i + 3]));
  }
  output->GetPointData()->AddArray(mask);
  output->GetPointData()->AddArray(clusterId);
  output->GetPointData()->AddArray(distance);
  output->GetPointData()->AddArray(medialFlag);
  // What was selected by: the sensor and its range (both ports).
  auto addSelection = [&](vtkFieldData* fd) {
    vtkNew<vtkStringArray> used;
    used->SetName("SensorArrayUsed");
    used->InsertNextValue(st.Sensor && st.Sensor->GetName() ? st.Sensor->GetName() : "");
    fd->AddArray(used);
    const double range[2] = { st.Lo, st.Hi };
    fd->AddArray(vtkARMeshKernels::FieldArray("SensorRangeUsed", range, 2));
  };
  addSelection(output->GetFieldData());

  // ---- Port 1 (rank 0): the medial points, ordered by cluster then position.
  if (st.Rank == 0)
  {
    std::vector<std::int64_t> order;
    for (size_t m = 0; m < st.Result.Medial.size(); ++m)
    {
      if (st.Result.Medial[m])
      {
        order.push_back(static_cast<std::int64_t>(m));
      }
    }
    std::sort(order.begin(), order.end(), [&](std::int64_t a, std::int64_t b) {
      if (st.Result.ClusterId[a] != st.Result.ClusterId[b])
      {
        return st.Result.ClusterId[a] < st.Result.ClusterId[b];
      }
      return std::lexicographical_compare(&st.X[3 * a], &st.X[3 * a + 3], &st.X[3 * b], &st.X[3 * b + 3]);
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
      pts->SetPoint(static_cast<vtkIdType>(k), &st.X[3 * m]);
      cid->SetValue(static_cast<vtkIdType>(k), st.Result.ClusterId[m]);
      size->SetValue(static_cast<vtkIdType>(k), st.Result.LocalSize[m]);
      weight->SetValue(static_cast<vtkIdType>(k), st.Result.LocalSize[m] > 0 ? 1.0 / st.Result.LocalSize[m] : 0.0);
      dist->SetValue(static_cast<vtkIdType>(k), st.Result.Distance[m]);
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
    clusterSizes->SetNumberOfTuples(static_cast<vtkIdType>(st.Result.ClusterSizes.size()));
    for (size_t k = 0; k < st.Result.ClusterSizes.size(); ++k)
    {
      clusterSizes->SetValue(static_cast<vtkIdType>(k), st.Result.ClusterSizes[k]);
    }
    medial->GetFieldData()->AddArray(clusterSizes);
    addSelection(medial->GetFieldData());
    if (st.Result.ClusterSizes.empty())
    {
      vtkWarningMacro(<< "No cluster: no node has a sensor value in [" << st.Lo << ", " << st.Hi << "]"
                      << (std::count(st.S.begin(), st.S.end(), 1) > 0
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
