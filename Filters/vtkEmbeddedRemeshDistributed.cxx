// SPDX-License-Identifier: BSD-3-Clause
// vtkEmbeddedRemesh's distributed driver (MPI, more than one rank): each rank
// finds the cavity in its piece, the cavity and three rings of cells around
// it are gathered to rank 0 and refilled there (TetGen is serial), every
// rank keeps its far field. The stages it shares with the serial driver are
// in vtkEmbeddedRemeshStages.h.
#include "vtkEmbeddedRemesh.h"
#include "vtkEmbeddedRemeshStages.h"

#include "ARCavity.h"
#include "ARMeshSize.h"
#include "ARTetGeometry.h"
#include "vtkARMeshKernels.h"
#include "vtkARParallel.h"
#include "vtkARFieldTransfer.h"

#include "vtkAppendFilter.h"
#include "vtkCellData.h"
#include "vtkDataSetAttributes.h"
#include "vtkDataSetAttributesFieldList.h"
#include "vtkExtractCells.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace
{
using Coord = std::array<double, 3>;

/// This rank's piece as the core's mesh: its tetrahedra, owned and ghost
/// (the ghosts complete l_v at the owned cells' nodes).
struct Piece
{
  ar::TetMesh V;
  std::vector<vtkIdType> TetCell; ///< input cell of each tetrahedron
  std::vector<char> Owned;        ///< per tetrahedron: not a ghost
  std::vector<char> OwnedNode;    ///< per point: a node of an owned tetrahedron
  vtkIdType NumberOfPoints() const { return static_cast<vtkIdType>(this->V.Points.size() / 3); }
  std::size_t NumberOfTetrahedra() const { return this->TetCell.size(); }
};

/// False with `problem` when the piece has a cell other than a tetrahedron.
bool BuildPiece(vtkUnstructuredGrid* input, bool twoDimensionalAuto, Piece& piece, std::string& problem)
{
  const vtkIdType nPoints = input->GetNumberOfPoints();
  vtkUnsignedCharArray* ghosts = input->GetCellGhostArray();
  piece.V.Points.resize(3 * nPoints);
  for (vtkIdType i = 0; i < nPoints; ++i)
  {
    input->GetPoint(i, &piece.V.Points[3 * i]);
  }
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < input->GetNumberOfCells(); ++c)
  {
    const bool ghost = ghosts && (ghosts->GetValue(c) & vtkDataSetAttributes::DUPLICATECELL);
    const int type = input->GetCellType(c);
    if (type != VTK_TETRA)
    {
      problem = "EmbeddedRemesh under MPI takes tetrahedral meshes only (cell " + std::to_string(c) +
        " has type " + std::to_string(type) + "); remesh hybrid or patch-carrying meshes on one rank." +
        ((type == VTK_HEXAHEDRON || type == VTK_WEDGE) && twoDimensionalAuto
            ? " The 2-D mode (one-cell-deep meshes) runs on one rank only."
            : "");
      return false;
    }
    input->GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < 4; ++k)
    {
      piece.V.Tetrahedra.push_back(ids->GetId(k));
    }
    piece.TetCell.push_back(c);
    piece.Owned.push_back(ghost ? 0 : 1);
  }
  piece.OwnedNode.assign(nPoints, 0);
  for (std::size_t t = 0; t < piece.NumberOfTetrahedra(); ++t)
  {
    for (int k = 0; piece.Owned[t] && k < 4; ++k)
    {
      piece.OwnedNode[piece.V.Tetrahedra[4 * t + k]] = 1;
    }
  }
  return true;
}

/// The domain boundary as triangles (9 coordinates each), from every rank:
/// owned faces with no neighbour among this rank's owned and ghost cells.
std::vector<double> DomainBoundary(const Piece& piece)
{
  const ar::TetMesh& V = piece.V;
  std::map<std::array<std::int64_t, 3>, std::pair<int, std::size_t>> faces; // count, 4 t + f
  for (std::size_t t = 0; t < piece.NumberOfTetrahedra(); ++t)
  {
    for (int f = 0; f < 4; ++f)
    {
      std::array<std::int64_t, 3> key;
      for (int k = 0; k < 3; ++k)
      {
        key[k] = V.Tetrahedra[4 * t + ar::TetFaceVertex[f][k]];
      }
      std::sort(key.begin(), key.end());
      auto& e = faces[key];
      ++e.first;
      e.second = 4 * t + f;
    }
  }
  std::vector<double> mine;
  for (const auto& e : faces)
  {
    const std::size_t t = e.second.second / 4;
    const int f = static_cast<int>(e.second.second % 4);
    if (e.second.first == 1 && piece.Owned[t])
    {
      for (int k = 0; k < 3; ++k)
      {
        const double* x = &V.Points[3 * V.Tetrahedra[4 * t + ar::TetFaceVertex[f][k]]];
        mine.insert(mine.end(), x, x + 3);
      }
    }
  }
  return vtkARParallel::AllGather(mine);
}

/// The cells gathered to rank 0: the cavity and three node rings of kept
/// cells around it, over all ranks (by coordinates): the refill may grow
/// the cavity twice at forced slivers and needs the cells around the grown
/// cavity's nodes.
std::vector<char> WithRings(const Piece& piece, const std::vector<char>& cavity)
{
  const ar::TetMesh& V = piece.V;
  const vtkIdType nPoints = piece.NumberOfPoints();
  std::vector<char> selected = cavity;
  for (int ring = 0; ring < 3; ++ring)
  {
    std::vector<char> mark(nPoints, 0);
    std::vector<double> mine;
    for (std::size_t t = 0; t < piece.NumberOfTetrahedra(); ++t)
    {
      for (int k = 0; selected[t] && k < 4; ++k)
      {
        const std::int64_t v = V.Tetrahedra[4 * t + k];
        if (!mark[v])
        {
          mark[v] = 1;
          mine.insert(mine.end(), &V.Points[3 * v], &V.Points[3 * v] + 3);
        }
      }
    }
    const std::vector<double> all = vtkARParallel::AllGather(mine);
    std::set<Coord> nodes;
    for (std::size_t k = 0; k < all.size(); k += 3)
    {
      nodes.insert(Coord{ all[k], all[k + 1], all[k + 2] });
    }
    for (vtkIdType v = 0; v < nPoints; ++v)
    {
      mark[v] = nodes.count(Coord{ V.Points[3 * v], V.Points[3 * v + 1], V.Points[3 * v + 2] }) ? 1 : 0;
    }
    for (std::size_t t = 0; t < piece.NumberOfTetrahedra(); ++t)
    {
      for (int k = 0; piece.Owned[t] && !selected[t] && k < 4; ++k)
      {
        selected[t] = mark[V.Tetrahedra[4 * t + k]];
      }
    }
  }
  return selected;
}

/// The selected cells with their fields, an ARCavity flag and their
/// ARSource (rank, cell), gathered to rank 0 and merged there into G
/// (points merged; empty on the other ranks).
vtkSmartPointer<vtkUnstructuredGrid> GatherSelected(vtkUnstructuredGrid* input, const Piece& piece,
  const std::vector<char>& cavity, const std::vector<char>& selected, int rank)
{
  vtkNew<vtkUnstructuredGrid> tagged;
  tagged->ShallowCopy(input);
  vtkNew<vtkUnsignedCharArray> cavityArray;
  cavityArray->SetName("ARCavity");
  cavityArray->SetNumberOfTuples(input->GetNumberOfCells());
  cavityArray->FillValue(0);
  vtkNew<vtkIdTypeArray> source;
  source->SetName("ARSource"); // rank, cell
  source->SetNumberOfComponents(2);
  source->SetNumberOfTuples(input->GetNumberOfCells());
  vtkNew<vtkIdList> pick;
  for (std::size_t t = 0; t < piece.NumberOfTetrahedra(); ++t)
  {
    const vtkIdType c = piece.TetCell[t];
    cavityArray->SetValue(c, cavity[t]);
    source->SetTypedComponent(c, 0, rank);
    source->SetTypedComponent(c, 1, c);
    if (selected[t])
    {
      pick->InsertNextId(c);
    }
  }
  tagged->GetCellData()->AddArray(cavityArray);
  tagged->GetCellData()->AddArray(source);
  tagged->GetCellData()->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  tagged->GetPointData()->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  vtkNew<vtkExtractCells> extract;
  extract->SetInputData(tagged);
  extract->SetCellList(pick);
  extract->Update();
  vtkNew<vtkUnstructuredGrid> part;
  part->ShallowCopy(extract->GetOutput());
  part->GetPointData()->RemoveArray("vtkOriginalPointIds");
  part->GetCellData()->RemoveArray("vtkOriginalCellIds");
  return vtkARParallel::MergeOnRoot(part);
}

/// The output's points: this rank's kept owned nodes (input order; rank 0
/// also keys them by coordinates), then on rank 0 the refill's points that
/// are no kept node. `pointSource`: input point of each of the first kind;
/// `gSource`: G point (or -1 new) of each of the second; `outOfResult`:
/// result point -> output point.
struct OutputPoints
{
  vtkNew<vtkPoints> Points;
  std::vector<vtkIdType> OutOfInput, PointSource, OutOfResult, GSource;
  vtkIdType NumberOfInputPoints = 0; ///< the first kind
  double NewNodes = 0.0;             ///< refill points that are no input point (rank 0)
};

void BuildOutputPoints(
  const Piece& piece, const std::vector<char>& gone, const ar::CavityRemesh& result, int rank, OutputPoints& out)
{
  const ar::TetMesh& V = piece.V;
  const vtkIdType nPoints = piece.NumberOfPoints();
  out.Points->SetDataTypeToDouble();
  out.OutOfInput.assign(nPoints, -1);
  for (std::size_t t = 0; t < piece.NumberOfTetrahedra(); ++t)
  {
    for (int k = 0; piece.Owned[t] && !gone[piece.TetCell[t]] && k < 4; ++k)
    {
      out.OutOfInput[V.Tetrahedra[4 * t + k]] = 0;
    }
  }
  std::map<Coord, vtkIdType> byCoord;
  for (vtkIdType v = 0; v < nPoints; ++v)
  {
    if (out.OutOfInput[v] == 0)
    {
      out.OutOfInput[v] = out.Points->InsertNextPoint(&V.Points[3 * v]);
      out.PointSource.push_back(v);
      if (rank == 0)
      {
        byCoord[Coord{ V.Points[3 * v], V.Points[3 * v + 1], V.Points[3 * v + 2] }] = out.OutOfInput[v];
      }
    }
  }
  out.NumberOfInputPoints = out.Points->GetNumberOfPoints();
  // The result's points that a new cell uses: a kept input point by its
  // coordinates, else appended with its G point (-1 when new).
  out.OutOfResult.assign(result.SourcePoint.size(), -1);
  std::vector<char> needed(result.SourcePoint.size(), 0);
  for (std::size_t t = 0; t < result.SourceCell.size(); ++t)
  {
    for (int k = 0; result.SourceCell[t] < 0 && k < 4; ++k)
    {
      needed[result.Mesh.Tetrahedra[4 * t + k]] = 1;
    }
  }
  for (const std::int64_t id : result.Prisms)
  {
    needed[id] = 1;
  }
  for (const std::int64_t id : result.Pyramids)
  {
    needed[id] = 1;
  }
  for (std::size_t i = 0; i < result.SourcePoint.size(); ++i)
  {
    if (!needed[i])
    {
      continue;
    }
    const double* x = &result.Mesh.Points[3 * i];
    auto it = byCoord.find(Coord{ x[0], x[1], x[2] });
    if (it != byCoord.end())
    {
      out.OutOfResult[i] = it->second;
      continue;
    }
    out.OutOfResult[i] = out.Points->InsertNextPoint(x);
    out.GSource.push_back(result.SourcePoint[i]);
    out.NewNodes += result.SourcePoint[i] < 0 ? 1.0 : 0.0;
  }
}

/// Fields: kept points and cells copy theirs from the input; on rank 0 the
/// refill's points copy (G points) or interpolate in G's tetrahedra, as the
/// serial run does in the input, and the new cells take the G cell holding
/// their centre.
void InterpolateDistributed(vtkUnstructuredGrid* input, vtkUnstructuredGrid* G, vtkUnstructuredGrid* output,
  const OutputPoints& op, const std::vector<vtkIdType>& cellSource, int rank)
{
  vtkPointData* inPD = input->GetPointData();
  vtkCellData* inCD = input->GetCellData();
  vtkPointData* outPD = output->GetPointData();
  vtkCellData* outCD = output->GetCellData();
  vtkDataSetAttributes::FieldList pointList(rank == 0 ? 2 : 1), cellList(rank == 0 ? 2 : 1);
  pointList.InitializeFieldList(inPD);
  cellList.InitializeFieldList(inCD);
  if (rank == 0)
  {
    pointList.IntersectFieldList(G->GetPointData());
    cellList.IntersectFieldList(G->GetCellData());
  }
  const vtkIdType nOut = output->GetNumberOfPoints();
  const auto nCellsOut = static_cast<vtkIdType>(cellSource.size());
  outPD->InterpolateAllocate(pointList, nOut);
  outCD->CopyAllocate(cellList, nCellsOut);
  vtkARFieldTransfer::TetLocator locator;
  if (rank == 0 && G->GetNumberOfCells() > 0)
  {
    locator.Build(G);
  }
  std::vector<char> isNew(nOut, 0);
  std::vector<vtkIdType> startOf(nOut, -1);
  const vtkIdType nInputOut = op.NumberOfInputPoints;
  for (vtkIdType i = nInputOut; i < nOut; ++i)
  {
    const std::int64_t g = op.GSource[i - nInputOut];
    isNew[i] = g < 0 ? 1 : 0;
    startOf[i] = g >= 0 ? locator.CellOfPoint(g) : -1;
  }
  const vtkEmbeddedRemeshNewTuples found = vtkEmbeddedRemeshLocateNew(locator, output, isNew, startOf, cellSource);
  // Each output tuple from the input (kept points and cells: list index 0)
  // or from G (rank 0's new ones: index 1).
  vtkARFieldTransfer::TupleSources pointsFromInput(nOut, 1), pointsFromG(nOut, 4);
  vtkARFieldTransfer::TupleSources cellsFromInput(nCellsOut, 1), cellsFromG(nCellsOut, 1);
  for (vtkIdType i = 0; i < nInputOut; ++i)
  {
    pointsFromInput.Copy(i, op.PointSource[i]);
  }
  for (vtkIdType i = nInputOut; i < nOut; ++i)
  {
    if (!isNew[i])
    {
      pointsFromG.Copy(i, op.GSource[i - nInputOut]);
    }
  }
  for (vtkIdType k = 0; k < nCellsOut; ++k)
  {
    if (cellSource[k] >= 0)
    {
      cellsFromInput.Copy(k, cellSource[k]);
    }
  }
  found.Fill(locator, pointsFromG, cellsFromG, nullptr);
  vtkARFieldTransfer::TransferData(pointList, 0, inPD, outPD, pointsFromInput);
  vtkARFieldTransfer::TransferData(cellList, 0, inCD, outCD, cellsFromInput);
  if (rank == 0)
  {
    vtkARFieldTransfer::TransferData(pointList, 1, G->GetPointData(), outPD, pointsFromG);
    vtkARFieldTransfer::TransferData(cellList, 1, G->GetCellData(), outCD, cellsFromG);
  }
  outPD->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  outCD->RemoveArray(vtkDataSetAttributes::GhostArrayName());
}

/// Rank 0: the gathered cells G refilled around S (`r`; the core's
/// CavityCells from G's ARCavity flags), and the (rank, cell) of every
/// gathered cell that goes. False with `error` from the core.
bool RefillGathered(vtkUnstructuredGrid* G, const vtkEmbeddedRemeshSoup& r, ar::CavityOptions& options,
  ar::CavityRemesh& result, std::vector<double>& removedCells, std::string& error)
{
  ar::TetMesh gathered;
  gathered.Points.resize(3 * G->GetNumberOfPoints());
  for (vtkIdType i = 0; i < G->GetNumberOfPoints(); ++i)
  {
    G->GetPoint(i, &gathered.Points[3 * i]);
  }
  auto* flags = vtkUnsignedCharArray::SafeDownCast(G->GetCellData()->GetArray("ARCavity"));
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < G->GetNumberOfCells(); ++c)
  {
    G->GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < 4; ++k)
    {
      gathered.Tetrahedra.push_back(ids->GetId(k));
    }
    options.CavityCells.push_back(flags ? flags->GetValue(c) : 0);
  }
  if (!ar::RemeshLocalCavity(gathered, r.Points.data(), r.NumberOfPoints(), r.Triangles.data(),
        r.NumberOfTriangles(), options, result, error))
  {
    return false;
  }
  std::vector<char> kept(G->GetNumberOfCells(), 0);
  for (std::int64_t c : result.SourceCell)
  {
    if (c >= 0)
    {
      kept[c] = 1;
    }
  }
  auto* src = vtkIdTypeArray::SafeDownCast(G->GetCellData()->GetArray("ARSource"));
  for (vtkIdType c = 0; c < G->GetNumberOfCells(); ++c)
  {
    if (!kept[c])
    {
      removedCells.push_back(static_cast<double>(src->GetTypedComponent(c, 0)));
      removedCells.push_back(static_cast<double>(src->GetTypedComponent(c, 1)));
    }
  }
  return true;
}

/// This rank's input nodes, each counted by the rank that owns it (not a
/// ghost copy of another rank's point).
double OwnedInputNodes(vtkUnstructuredGrid* input)
{
  double n = 0.0;
  vtkUnsignedCharArray* pointGhosts = input->GetPointGhostArray();
  for (vtkIdType v = 0; v < input->GetNumberOfPoints(); ++v)
  {
    n += pointGhosts && (pointGhosts->GetValue(v) & vtkDataSetAttributes::DUPLICATEPOINT) ? 0.0 : 1.0;
  }
  return n;
}
}

//------------------------------------------------------------------------------
// About 250 lines, on purpose: every rank must make the same collective calls
// in the same order, and agree on every failure before any returns, so the
// sequence of collective calls (and of the failed() agreements between them)
// is kept in this one function, where it reads top to bottom; the work between
// them is in the functions above.
int vtkEmbeddedRemesh::RemeshDistributed(vtkUnstructuredGrid* input,
  const std::vector<vtkDataSet*>& surfaces, vtkUnstructuredGrid* output, vtkPolyData* embedded)
{
  vtkMultiProcessController* ctrl = vtkMultiProcessController::GetGlobalController();
  const int rank = ctrl->GetLocalProcessId();
  // Every failure is agreed on by all ranks before anyone returns, so that
  // the collective calls stay matched.
  std::string problem;
  auto failed = [&]() {
    double bad = problem.empty() ? 0.0 : 1.0;
    vtkARParallel::AllReduceMax(&bad, 1);
    return bad > 0.0;
  };
  auto passThrough = [&]() {
    vtkErrorMacro(<< (problem.empty() ? std::string("EmbeddedRemesh failed on another rank.") : problem)
                  << " The input passes through unchanged.");
    output->ShallowCopy(input);
    return 1;
  };
  // Work on rank 0 alone (the surface remesh, the gathered cavity's merge
  // and refill): an exception there becomes the problem every rank then
  // agrees on, so the other ranks are not left waiting in a collective call.
  auto onRoot = [&](const std::function<void()>& work) {
    if (rank != 0)
    {
      return;
    }
    try
    {
      work();
    }
    catch (const std::exception& e)
    {
      problem = vtkEmbeddedRemeshFailure(e) + " (on rank 0)";
    }
  };
  vtkEmbeddedRemeshLap lap;
  vtkEmbeddedRemeshSummary summary;
  // ---- Coordinates and conformity of this rank's piece, as in serial: a
  // crack on one rank refuses the whole job.
  problem = vtkEmbeddedRemeshCheckCoordinates(input, surfaces);
  if (!problem.empty())
  {
    problem = "EmbeddedRemesh (rank " + std::to_string(rank) + "): " + problem;
  }
  Piece piece;
  if (problem.empty())
  {
    BuildPiece(input, this->TwoDimensional == TWO_DIMENSIONAL_AUTO, piece, problem);
  }
  if (failed())
  {
    return passThrough();
  }
  const ar::TetMesh& V = piece.V;
  const vtkIdType nPoints = piece.NumberOfPoints();
  const std::size_t nT = piece.NumberOfTetrahedra();
  double nOwned = static_cast<double>(std::count(piece.Owned.begin(), piece.Owned.end(), 1));
  vtkARParallel::AllReduceSum(&nOwned, 1);
  if (nOwned == 0)
  {
    problem = "The volume mesh is empty.";
    return passThrough();
  }
  // ---- S: the surface pieces gathered to rank 0, merged there, sent to all.
  const vtkEmbeddedRemeshSoup s = vtkEmbeddedRemeshCollectSurfaces(surfaces);
  if (s.Triangles.empty())
  {
    problem = "The feature surface is empty (no Surfaces connected, or none has triangles).";
    return passThrough();
  }
  this->UpdateProgress(0.1);
  summary.Seconds.emplace_back("SecondsInput", lap());

  // ---- The input's size at S (l_v complete at the owned cells' nodes,
  // thanks to the ghosts; the nearest owned node over all ranks), the edge
  // and the job's size (the same on every rank: S and the sums are global).
  const std::vector<double> lv = ar::LongestEdgeAtNodes(V.Points.data(), nPoints, V.Tetrahedra.data(), nT);
  const double inputSize =
    vtkEmbeddedRemeshInputSizeAt(V.Points.data(), nPoints, 3, lv, &piece.OwnedNode, s.Points.data(), s.NumberOfPoints());
  const double edge = this->SurfaceEdgeLength > 0.0 ? this->SurfaceEdgeLength : this->GetSurfaceSizeFactorUsed() * inputSize;
  if (!(edge > 0.0))
  {
    problem = "Could not find the mesh size near the feature surface; set SurfaceEdgeLength.";
    return passThrough();
  }
  double volumes[2] = { 0.0, 0.0 }; // |V| and V's signed volume, owned cells
  for (std::size_t t = 0; t < nT; ++t)
  {
    if (piece.Owned[t])
    {
      const std::int64_t* q = &V.Tetrahedra[4 * t];
      const double* x = V.Points.data();
      const double v = ar::TetSignedVolume(x + 3 * q[0], x + 3 * q[1], x + 3 * q[2], x + 3 * q[3]);
      volumes[0] += std::abs(v);
      volumes[1] += v;
    }
  }
  summary.VolumeBefore = volumes[1];
  vtkARParallel::AllReduceSum(volumes, 1);
  {
    double area = 0.0, diagonal = 0.0;
    vtkEmbeddedRemeshSurfaceAreaAndDiagonal(s, area, diagonal);
    if (!vtkEmbeddedRemeshJobFits(this, 3, area, diagonal, edge, inputSize, volumes[0], nOwned, problem))
    {
      return passThrough(); // the same verdict on every rank
    }
  }
  // ---- S remeshed on rank 0, sent to every rank.
  vtkEmbeddedRemeshSoup r;
  onRoot([&]() { r = vtkEmbeddedRemeshRemeshSurface(this, s, edge); });
  vtkEmbeddedRemeshBroadcast(r);
  if (failed())
  {
    return passThrough();
  }
  this->UpdateProgress(0.3);
  summary.Seconds.emplace_back("SecondsSurfaceMeshing", lap());

  // ---- Removal flags at this rank's nodes; the cavity: owned cells at
  // removed nodes; the cells around it gathered to rank 0.
  ar::CavityOptions options;
  if (!vtkEmbeddedRemeshCavityOptions(this, edge, options, problem))
  {
    return passThrough(); // the same properties on every rank: all refuse
  }
  options.BoundaryTriangles = DomainBoundary(piece);
  options.LongestEdges = lv; // the piece's l_v, not computed again
  std::vector<std::uint8_t> removed;
  std::string error;
  if (!ar::ComputeRemovedNodes(V, r.Points.data(), r.NumberOfPoints(), r.Triangles.data(), r.NumberOfTriangles(),
        options, removed, error))
  {
    problem = "EmbeddedRemesh: " + error;
  }
  options.LongestEdges.clear(); // (the gathered cells' refill below has its own)
  if (failed())
  {
    return passThrough();
  }
  std::vector<char> cavity(nT, 0);
  for (std::size_t t = 0; t < nT; ++t)
  {
    for (int k = 0; piece.Owned[t] && k < 4; ++k)
    {
      cavity[t] = cavity[t] || removed[V.Tetrahedra[4 * t + k]];
    }
  }
  double nCavity = static_cast<double>(std::count(cavity.begin(), cavity.end(), 1));
  vtkARParallel::AllReduceSum(&nCavity, 1);
  if (nCavity == 0)
  {
    problem = "EmbeddedRemesh: no node of the volume mesh lies near the feature surface: nothing to remesh.";
    return passThrough();
  }
  const std::vector<char> selected = WithRings(piece, cavity);
  vtkSmartPointer<vtkUnstructuredGrid> G;
  try
  {
    G = GatherSelected(input, piece, cavity, selected, rank); // collective, then the merge on rank 0
  }
  catch (const std::exception& e)
  {
    problem = vtkEmbeddedRemeshFailure(e) + " (gathering the cavity on rank " + std::to_string(rank) + ")";
    G = vtkSmartPointer<vtkUnstructuredGrid>::New();
  }

  // ---- Rank 0 refills the gathered cavity.
  ar::CavityRemesh result;
  std::vector<double> removedCells; // rank, cell of every gathered cell that goes
  onRoot([&]() {
    if (problem.empty() && !RefillGathered(G, r, options, result, removedCells, error))
    {
      problem = "EmbeddedRemesh: " + error;
    }
  });
  if (failed())
  {
    return passThrough();
  }
  {
    vtkEmbeddedRemeshSoup gone; // (rank, cell) pairs travel as a soup's points
    gone.Points = removedCells;
    vtkEmbeddedRemeshBroadcast(gone);
    removedCells = gone.Points;
  }
  this->UpdateProgress(0.8);
  lap();

  // ---- Output: this rank's kept owned cells; rank 0 adds the new ones.
  std::vector<char> gone(input->GetNumberOfCells(), 0);
  for (std::size_t k = 0; k < removedCells.size(); k += 2)
  {
    if (static_cast<int>(removedCells[k]) == rank)
    {
      gone[static_cast<vtkIdType>(removedCells[k + 1])] = 1;
    }
  }
  OutputPoints op;
  BuildOutputPoints(piece, gone, result, rank, op);
  vtkPoints* points = op.Points;
  output->Initialize();
  output->GetFieldData()->ShallowCopy(input->GetFieldData());
  output->SetPoints(points);
  vtkEmbeddedRemeshCells cells(output);
  cells.Reserve(nT + result.SourceCell.size() + result.Prisms.size() / 6 + result.Pyramids.size() / 5,
    4 * (nT + result.SourceCell.size()) + result.Prisms.size() + result.Pyramids.size());
  for (std::size_t t = 0; t < nT; ++t)
  {
    if (piece.Owned[t] && !gone[piece.TetCell[t]])
    {
      const std::int64_t* v = &V.Tetrahedra[4 * t];
      const vtkIdType pts[4] = { op.OutOfInput[v[0]], op.OutOfInput[v[1]], op.OutOfInput[v[2]], op.OutOfInput[v[3]] };
      cells.Add(VTK_TETRA, 4, pts, piece.TetCell[t], 0, -1, 0, points);
    }
  }
  cells.AddRefillTetrahedra(result, &op.OutOfResult, nullptr, points);
  cells.AddRefillLayers(result, &op.OutOfResult, points);
  vtkEmbeddedRemeshCompleteCells(output, cells, this->InterpolateFields,
    [&] { InterpolateDistributed(input, G, output, op, cells.Sources(), rank); }, lap, summary);

  // ---- Field data, equal on every rank and to the serial run's.
  summary.InputNodes = OwnedInputNodes(input);
  summary.NewNodes = op.NewNodes;
  summary.AddRefill(result); // rank 0's refill; nothing elsewhere
  summary.SurfaceEdgeLength = edge;
  summary.InputSize = inputSize;
  summary.VolumeAfter = cells.VolumeAfter;
  summary.Reduce();
  summary.Write(output, options.Layers);
  if (rank == 0)
  {
    vtkEmbeddedRemeshSetEmbedded(embedded, points, result.Surface, &op.OutOfResult);
  }
  else
  {
    vtkNew<vtkPoints> none;
    vtkEmbeddedRemeshSetEmbedded(embedded, none, {}, nullptr);
  }
  this->UpdateProgress(1.0);
  return 1;
}
