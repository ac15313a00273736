// SPDX-License-Identifier: BSD-3-Clause
#include "vtkARSolverMesh.h"
#include "vtkARMeshKernels.h"

#include "ARCellQuality.h"

#include "vtkAlgorithm.h"
#include "vtkCellData.h"
#include "vtkCellTypes.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkErrorCode.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkMultiProcessController.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkPartitionedDataSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"
#include "vtkStaticPointLocator.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include <unistd.h> // getpid

namespace
{
// ---- The faces of the linear 3-D cells (outward for a valid cell): ARCellQuality's.
ar::CellShape ShapeOf(unsigned char type)
{
  switch (type)
  {
    case VTK_TETRA:
      return ar::CellShape::Tetrahedron;
    case VTK_HEXAHEDRON:
      return ar::CellShape::Hexahedron;
    case VTK_WEDGE:
      return ar::CellShape::Wedge;
    default:
      return ar::CellShape::Pyramid;
  }
}

int NumberOfFaces(unsigned char type)
{
  return ar::NumberOfFaces(ShapeOf(type));
}

const int* Face(unsigned char type, int f)
{
  return ar::CellFace(ShapeOf(type), f);
}

int FaceSize(const int* face)
{
  return face[3] < 0 ? 3 : 4;
}

using FaceKey = std::array<vtkIdType, 4>;

FaceKey MakeKey(const vtkIdType* ids, int n)
{
  FaceKey k = { ids[0], ids[1], ids[2], n == 4 ? ids[3] : -1 };
  std::sort(k.begin(), k.begin() + n);
  return k;
}

/// The key of local face f of a cell (`cell`: its point ids, VTK order).
FaceKey CellFaceKey(unsigned char type, const vtkIdType* cell, int f)
{
  const int* face = Face(type, f);
  const int n = FaceSize(face);
  vtkIdType fids[4];
  for (int i = 0; i < n; ++i)
  {
    fids[i] = cell[face[i]];
  }
  return MakeKey(fids, n);
}

/// Lowers `target` to `value` if it is smaller (threads may race: the
/// smallest wins, so the result does not depend on the schedule).
void AtomicMin(std::atomic<vtkIdType>& target, vtkIdType value)
{
  vtkIdType now = target.load();
  while (value < now && !target.compare_exchange_weak(now, value))
  {
  }
}

bool ContainsNoCase(const std::string& text, const char* word)
{
  std::string t(text);
  std::string w(word);
  std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return std::tolower(c); });
  return t.find(w) != std::string::npos;
}

struct Leaf
{
  vtkDataSet* Data;
  std::string Name;
};

void CollectLeaves(vtkDataObject* object, const std::string& name, bool skip, std::vector<Leaf>& leaves)
{
  if (!object)
  {
    return;
  }
  if (auto* mb = vtkMultiBlockDataSet::SafeDownCast(object))
  {
    for (unsigned int i = 0; i < mb->GetNumberOfBlocks(); ++i)
    {
      std::string child;
      if (mb->HasMetaData(i) && mb->GetMetaData(i)->Has(vtkCompositeDataSet::NAME()))
      {
        child = mb->GetMetaData(i)->Get(vtkCompositeDataSet::NAME());
      }
      const bool skipChild =
        skip || ContainsNoCase(child, "lagrangian") || ContainsNoCase(child, "zones");
      CollectLeaves(mb->GetBlock(i), child, skipChild, leaves);
    }
  }
  else if (auto* pds = vtkPartitionedDataSet::SafeDownCast(object))
  {
    for (unsigned int i = 0; i < pds->GetNumberOfPartitions(); ++i)
    {
      CollectLeaves(pds->GetPartition(i), name, skip, leaves);
    }
  }
  else if (auto* ds = vtkDataSet::SafeDownCast(object))
  {
    if (!skip)
    {
      leaves.push_back({ ds, name });
    }
  }
}

bool HasCellsOfDimension(vtkDataSet* ds, int dimension)
{
  for (vtkIdType c = 0; c < ds->GetNumberOfCells(); ++c)
  {
    if (vtkCellTypes::GetDimension(static_cast<unsigned char>(ds->GetCellType(c))) == dimension)
    {
      return true;
    }
  }
  return false;
}

std::string TypeName(int type)
{
  const char* name = vtkCellTypes::GetClassNameFromTypeId(type);
  std::ostringstream s;
  s << (name ? name : "unknown cell") << " (VTK type " << type << ")";
  return s.str();
}

/// Node ids of a 2-D cell as a triangle or quad in its own order; false if
/// the cell is neither.
bool PolygonIds(int type, vtkIdList* ids, vtkIdType out[4], int& n)
{
  n = static_cast<int>(ids->GetNumberOfIds());
  if (type == VTK_TRIANGLE || type == VTK_QUAD || (type == VTK_POLYGON && (n == 3 || n == 4)))
  {
    for (int i = 0; i < n; ++i)
    {
      out[i] = ids->GetId(i);
    }
    return n == 3 || n == 4;
  }
  if (type == VTK_PIXEL && n == 4)
  {
    out[0] = ids->GetId(0);
    out[1] = ids->GetId(1);
    out[2] = ids->GetId(3);
    out[3] = ids->GetId(2);
    return true;
  }
  return false;
}
}

// ----------------------------------------------------------------------------
std::string vtkARSolverMesh::CleanName(const std::string& name, const std::string& fallback)
{
  std::string clean;
  for (char c : name)
  {
    clean += (std::isspace(static_cast<unsigned char>(c)) || c == '"' || c == '=' || c == '%')
      ? '_'
      : c;
  }
  return clean.empty() ? fallback : clean;
}


void vtkARSolverMesh::AppendDouble(std::string& s, double v)
{
  char buffer[32];
  const int n = std::snprintf(buffer, sizeof(buffer), "%.17g", v);
  s.append(buffer, static_cast<size_t>(n));
}

bool vtkARSolverMesh::WriteAtomically(const std::string& path,
  const std::function<bool(std::ostream&, std::string&)>& body, std::string& error)
{
  if (path.empty())
  {
    error = "no file name is set";
    return false;
  }
  const std::string temporary = path + ".tmp" + std::to_string(static_cast<long>(::getpid()));
  {
    std::ofstream out(temporary, std::ios::out | std::ios::trunc | std::ios::binary);
    if (!out)
    {
      error = "cannot open '" + temporary + "' for writing (does the directory exist, is it writable?)";
      return false;
    }
    bool ok = false;
    try
    {
      ok = body(out, error);
    }
    catch (const std::exception& e)
    {
      error = std::string("failed while writing: ") + e.what();
      ok = false;
    }
    out.flush();
    if (ok && !out)
    {
      error = "writing '" + temporary + "' failed (disk full?)";
      ok = false;
    }
    out.close();
    if (ok && out.fail())
    {
      error = "closing '" + temporary + "' failed";
      ok = false;
    }
    if (!ok)
    {
      std::remove(temporary.c_str());
      return false;
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0)
  {
    std::remove(temporary.c_str());
    error = "cannot rename the finished temporary file onto '" + path + "' (is it a directory?)";
    return false;
  }
  return true;
}

// ----------------------------------------------------------------------------
namespace
{
/// A cell face as its sorted points and 8 * cell + local face; ordered by
/// (Key, Packed), element by element, so equal faces sort side by side, in
/// cell order.
struct CellFace
{
  FaceKey Key;
  vtkIdType Packed;
  bool operator<(const CellFace& o) const
  {
    for (int i = 0; i < 4; ++i)
    {
      if (this->Key[i] != o.Key[i])
      {
        return this->Key[i] < o.Key[i];
      }
    }
    return this->Packed < o.Packed;
  }
  bool SameFace(const CellFace& o) const
  {
    return this->Key[0] == o.Key[0] && this->Key[1] == o.Key[1] && this->Key[2] == o.Key[2] &&
      this->Key[3] == o.Key[3];
  }
};

/**
 * One vtkARSolverMesh::Build run: the model being built, the state its
 * stages share, and one path per input form (header, (a) to (c)). Every
 * path runs the same common stages: the volume cells (Volume), the face
 * table (FaceTable), then its own patches, then the default patch and the
 * empty patches (Finish).
 */
class SolverMeshBuild
{
public:
  SolverMeshBuild(vtkARSolverMesh& mesh_, const std::string& defaultPatchName_, double tolerance_,
    vtkAlgorithm* progress_, std::string& error_)
    : mesh(mesh_)
    , defaultPatchName(defaultPatchName_)
    , tolerance(tolerance_)
    , progress(progress_)
    , error(error_)
  {
  }

  /// (a) a multiblock (or partitioned) dataset: a volume leaf, patch leaves.
  bool FromMultiBlock(vtkDataObject* input);
  /// (b) a dataset with a cell array PatchId.
  bool FromPatchIds(vtkDataSet* input);
  /// (c) a dataset without PatchId: every boundary face in the default patch.
  bool FromVolumeOnly(vtkDataSet* input);

private:
  // The common stages.
  bool Volume(vtkDataSet* volume); ///< the 3-D cells, the points they use
  void FaceBuckets();              ///< every cell face, bucketed by its smallest point
  bool MatchFaces();               ///< the face partners, the orientation check
  bool Finish();                   ///< the default patch; empty patches dropped
  /// The face table: FaceBuckets, then MatchFaces.
  bool FaceTable()
  {
    FaceBuckets();
    return MatchFaces();
  }
  // The patches of forms (a) and (b).
  bool SelectLeaves(vtkDataObject* input);   ///< (a) the volume leaf and the patch leaves
  bool MatchLeaves();                        ///< (a) the patch leaves' faces, by coordinates
  vtkDataArray* PatchIdArray();              ///< (b) PatchId, checked (null: refused)
  bool PatchIdFaces(vtkDataArray* patchIds); ///< (b) the 2-D cells with PatchId >= 0
  // Patch helpers.
  int PatchIndex(const std::string& rawName, const std::string& fallback);
  void AddFace(int patch, vtkIdType c, int f);
  bool Assign(int patch, const vtkIdType* fids, int n, const std::string& what);

  const vtkIdType* CellOf(vtkIdType c) const
  {
    return mesh.CellConnectivity.data() + mesh.CellOffsets[c];
  }
  void Progress(double f)
  {
    if (progress)
    {
      progress->UpdateProgress(f);
    }
  }

  // Inputs.
  vtkARSolverMesh& mesh;
  const std::string& defaultPatchName;
  const double tolerance;
  vtkAlgorithm* progress;
  std::string& error;

  vtkNew<vtkIdList> ids;
  std::vector<Leaf> patchLeaves; ///< form (a)
  // Volume: input point -> model point (-1: unused); the 2-D cells of the
  // volume dataset (form (b)).
  std::vector<vtkIdType> pointMap;
  std::vector<vtkIdType> surfaceCells;
  // The face table: every cell face in buckets by its smallest point (shift),
  // each bucket sorted; the patch of each boundary slot (-1: none yet).
  int shift = 0;
  vtkIdType nBuckets = 0;
  std::vector<vtkIdType> bucketStart;
  std::vector<CellFace> cellFaces;
  std::vector<int> slotPatch;
  std::map<std::string, int> patchByName;
};

bool SolverMeshBuild::FromMultiBlock(vtkDataObject* input)
{
  mesh.Form = "multiblock";
  if (!SelectLeaves(input) || !Volume(mesh.Volume) || !FaceTable() || !MatchLeaves())
  {
    return false;
  }
  Progress(0.4);
  return Finish();
}

bool SolverMeshBuild::FromPatchIds(vtkDataSet* input)
{
  if (!Volume(input) || !FaceTable())
  {
    return false;
  }
  vtkDataArray* patchIds = PatchIdArray();
  if (!patchIds)
  {
    return false;
  }
  mesh.Form = "PatchId";
  if (!PatchIdFaces(patchIds))
  {
    return false;
  }
  Progress(0.4);
  return Finish();
}

bool SolverMeshBuild::FromVolumeOnly(vtkDataSet* input)
{
  if (!Volume(input) || !FaceTable())
  {
    return false;
  }
  mesh.Form = "volume only";
  if (!surfaceCells.empty())
  {
    mesh.Warnings += std::to_string(surfaceCells.size()) +
      " 2-D cells are ignored (no PatchId cell array says which patch they belong to)\n";
  }
  Progress(0.4);
  return Finish();
}

// ---- (a) The volume leaf: "internalMesh", else the first leaf with 3-D
// cells; the other leaves with 2-D cells are the patches.
bool SolverMeshBuild::SelectLeaves(vtkDataObject* input)
{
  std::vector<Leaf> leaves;
  CollectLeaves(input, "", false, leaves);
  size_t volumeLeaf = leaves.size();
  for (size_t i = 0; i < leaves.size() && volumeLeaf == leaves.size(); ++i)
  {
    if (leaves[i].Name == "internalMesh" && HasCellsOfDimension(leaves[i].Data, 3))
    {
      volumeLeaf = i;
    }
  }
  for (size_t i = 0; i < leaves.size() && volumeLeaf == leaves.size(); ++i)
  {
    if (HasCellsOfDimension(leaves[i].Data, 3))
    {
      volumeLeaf = i;
    }
  }
  if (volumeLeaf == leaves.size())
  {
    error = "no block of the multiblock input has 3-D cells (a volume mesh, e.g. the OpenFOAM "
            "reader's internalMesh, is needed)";
    return false;
  }
  mesh.Volume = leaves[volumeLeaf].Data;
  for (size_t i = 0; i < leaves.size(); ++i)
  {
    if (i == volumeLeaf)
    {
      continue;
    }
    if (HasCellsOfDimension(leaves[i].Data, 3))
    {
      mesh.Warnings += "block '" + leaves[i].Name +
        "' has 3-D cells but is not the volume written (only one volume block is written); "
        "it is ignored\n";
    }
    else if (HasCellsOfDimension(leaves[i].Data, 2))
    {
      patchLeaves.push_back(leaves[i]);
    }
  }
  return true;
}

// ---- Volume cells, compact points.
bool SolverMeshBuild::Volume(vtkDataSet* volume)
{
  mesh.Volume = volume;
  const vtkIdType nInputCells = volume->GetNumberOfCells();
  const vtkIdType nInputPoints = volume->GetNumberOfPoints();
  pointMap.assign(static_cast<size_t>(nInputPoints), -1);
  vtkUnsignedCharArray* ghosts = volume->GetCellGhostArray();
  mesh.CellConnectivity.reserve(static_cast<size_t>(nInputCells) * 4);
  mesh.CellOffsets.reserve(static_cast<size_t>(nInputCells) + 1);
  mesh.CellTypes.reserve(static_cast<size_t>(nInputCells));
  mesh.InputCellIds.reserve(static_cast<size_t>(nInputCells));
  for (vtkIdType c = 0; c < nInputCells; ++c)
  {
    if (ghosts &&
      (ghosts->GetValue(c) & (vtkDataSetAttributes::DUPLICATECELL | vtkDataSetAttributes::HIDDENCELL)))
    {
      continue;
    }
    const int type = volume->GetCellType(c);
    const int dimension = vtkCellTypes::GetDimension(static_cast<unsigned char>(type));
    if (dimension < 3)
    {
      if (dimension == 2)
      {
        surfaceCells.push_back(c);
      }
      continue;
    }
    static const int voxelToHex[8] = { 0, 1, 3, 2, 4, 5, 7, 6 };
    unsigned char written = static_cast<unsigned char>(type);
    if (type == VTK_VOXEL)
    {
      written = VTK_HEXAHEDRON;
    }
    else if (type != VTK_TETRA && type != VTK_HEXAHEDRON && type != VTK_WEDGE && type != VTK_PYRAMID)
    {
      error = "cell " + std::to_string(c) + " is a " + TypeName(type) +
        ", which these formats cannot hold: only linear tetrahedra, hexahedra (and voxels), wedges "
        "and pyramids are written (polyhedra and quadratic cells are not)";
      return false;
    }
    vtkIdType npts = 0;
    const vtkIdType* pts = nullptr;
    volume->GetCellPoints(c, npts, pts, ids);
    for (vtkIdType i = 0; i < npts; ++i)
    {
      const vtkIdType p = pts[type == VTK_VOXEL ? voxelToHex[i] : i];
      pointMap[p] = 0; // used; numbered below, in input order
      mesh.CellConnectivity.push_back(p);
    }
    mesh.CellTypes.push_back(written);
    mesh.InputCellIds.push_back(c);
    mesh.CellOffsets.push_back(static_cast<vtkIdType>(mesh.CellConnectivity.size()));
  }
  for (vtkIdType p = 0; p < nInputPoints; ++p)
  {
    if (pointMap[p] < 0)
    {
      continue;
    }
    double x[3];
    volume->GetPoint(p, x);
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
    {
      error = "point " + std::to_string(p) + " of the volume has a NaN or Inf coordinate";
      return false;
    }
    pointMap[p] = mesh.GetNumberOfPoints();
    mesh.Points.insert(mesh.Points.end(), x, x + 3);
    mesh.InputPointIds.push_back(p);
  }
  for (vtkIdType& p : mesh.CellConnectivity)
  {
    p = pointMap[p];
  }
  if (mesh.CellTypes.empty())
  {
    error = "the input has no 3-D cells (tetrahedra, hexahedra, wedges or pyramids): a volume "
            "mesh is needed";
    return false;
  }
  Progress(0.15);
  return true;
}

// ---- The face table: every cell face bucketed by its smallest point, the
// faces of a bucket matched by their sorted points (one search, threaded per
// bucket; the buckets also find the patch faces). Every cell face as (its
// sorted points, 8 * cell + local face), moved into coarse buckets by its
// smallest point (a radix pass: the faces read in cell order, written to one
// stream per bucket, which the cache holds; filling a bucket per point
// directly cost seconds of cache misses at 5e6 cells), each bucket then
// sorted in parallel (MatchFaces): equal faces side by side, in cell order.
void SolverMeshBuild::FaceBuckets()
{
  const vtkIdType nCells = mesh.GetNumberOfCells();
  const vtkIdType nPoints = mesh.GetNumberOfPoints();
  mesh.FaceSlots.resize(static_cast<size_t>(nCells) + 1);
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    mesh.FaceSlots[c + 1] = mesh.FaceSlots[c] + NumberOfFaces(mesh.CellTypes[c]);
  }
  const vtkIdType nSlots = mesh.FaceSlots[nCells];
  while ((nPoints >> shift) >= 4096)
  {
    ++shift;
  }
  nBuckets = (nPoints >> shift) + 1;
  bucketStart.assign(static_cast<size_t>(nBuckets) + 1, 0);
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    for (int f = 0; f < NumberOfFaces(mesh.CellTypes[c]); ++f)
    {
      const int* face = Face(mesh.CellTypes[c], f);
      const vtkIdType* cell = CellOf(c);
      vtkIdType smallest = cell[face[0]];
      for (int i = 1; i < FaceSize(face); ++i)
      {
        smallest = std::min(smallest, cell[face[i]]);
      }
      ++bucketStart[(smallest >> shift) + 1];
    }
  }
  for (vtkIdType b = 0; b < nBuckets; ++b)
  {
    bucketStart[b + 1] += bucketStart[b];
  }
  cellFaces.resize(static_cast<size_t>(nSlots));
  std::vector<vtkIdType> next(bucketStart.begin(), bucketStart.end() - 1);
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    for (int f = 0; f < NumberOfFaces(mesh.CellTypes[c]); ++f)
    {
      const FaceKey key = CellFaceKey(mesh.CellTypes[c], CellOf(c), f);
      cellFaces[next[key[0] >> shift]++] = { key, 8 * c + f };
    }
  }
}

// ---- Each bucket sorted, its equal faces paired; the orientation (volume
// from the outward faces) of every cell.
bool SolverMeshBuild::MatchFaces()
{
  const vtkIdType nCells = mesh.GetNumberOfCells();
  const vtkIdType nSlots = mesh.FaceSlots[nCells];
  mesh.FacePartner.assign(static_cast<size_t>(nSlots), -1);
  std::atomic<vtkIdType> overShared(nCells); // the first cell making a face's third use
  std::atomic<vtkIdType> inverted(nCells);   // the first inverted or degenerate cell
  vtkARMeshKernels::Threaded([&]() {
    vtkSMPTools::For(0, nBuckets, 1, [&](vtkIdType first, vtkIdType last) {
      for (vtkIdType bucket = first; bucket < last; ++bucket)
      {
        CellFace* b = cellFaces.data() + bucketStart[bucket];
        CellFace* e = cellFaces.data() + bucketStart[bucket + 1];
        std::sort(b, e);
        for (CellFace *i = b, *j = b; i < e; i = j)
        {
          for (j = i + 1; j < e && j->SameFace(*i); ++j)
          {
          }
          if (j - i == 2)
          {
            const vtkIdType x = i[0].Packed, y = i[1].Packed;
            mesh.FacePartner[mesh.FaceSlots[x >> 3] + (x & 7)] = y;
            mesh.FacePartner[mesh.FaceSlots[y >> 3] + (y & 7)] = x;
          }
          else if (j - i > 2)
          {
            AtomicMin(overShared, i[2].Packed >> 3);
          }
        }
      }
    });
    vtkSMPTools::For(0, nCells, [&](vtkIdType first, vtkIdType last) {
      for (vtkIdType c = first; c < last; ++c)
      {
        const ar::CellShape shape = ShapeOf(mesh.CellTypes[c]);
        const vtkIdType* cell = CellOf(c);
        double x[8 * 3];
        for (int i = 0; i < ar::NumberOfNodes(shape); ++i)
        {
          std::copy(&mesh.Points[3 * cell[i]], &mesh.Points[3 * cell[i]] + 3, x + 3 * i);
        }
        if (!(ar::CellVolume(shape, x) > 0.0))
        {
          AtomicMin(inverted, c);
          return; // the later cells of this range cannot be the first
        }
      }
    });
  });
  if (overShared.load() < nCells && overShared.load() <= inverted.load())
  {
    error = "a face of written cell " + std::to_string(overShared.load()) +
      " is shared by more than two cells (the mesh is not a valid conforming volume mesh)";
    return false;
  }
  if (inverted.load() < nCells)
  {
    const vtkIdType c = inverted.load();
    const ar::CellShape shape = ShapeOf(mesh.CellTypes[c]);
    double x[8 * 3];
    for (int i = 0; i < ar::NumberOfNodes(shape); ++i)
    {
      std::copy(&mesh.Points[3 * CellOf(c)[i]], &mesh.Points[3 * CellOf(c)[i]] + 3, x + 3 * i);
    }
    error = "3-D cell number " + std::to_string(c) + " (a " + TypeName(mesh.CellTypes[c]) +
      ") is inverted or degenerate: its volume from its faces in VTK's node order is " +
      std::to_string(ar::CellVolume(shape, x));
    return false;
  }
  slotPatch.assign(static_cast<size_t>(nSlots), -1);
  Progress(0.3);
  return true;
}

// ---- Patches.
int SolverMeshBuild::PatchIndex(const std::string& rawName, const std::string& fallback)
{
  const std::string name = vtkARSolverMesh::CleanName(rawName, fallback);
  if (name != rawName && !rawName.empty())
  {
    mesh.Warnings += "patch name '" + rawName + "' is written as '" + name + "'\n";
  }
  auto it = patchByName.find(name);
  if (it != patchByName.end())
  {
    return it->second;
  }
  const int index = static_cast<int>(mesh.Patches.size());
  mesh.Patches.emplace_back();
  mesh.Patches.back().Name = name;
  patchByName[name] = index;
  return index;
}

void SolverMeshBuild::AddFace(int patch, vtkIdType c, int f)
{
  const vtkIdType* cell = CellOf(c);
  const int* face = Face(mesh.CellTypes[c], f);
  vtkARSolverMesh::Patch& p = mesh.Patches[patch];
  for (int i = 0; i < FaceSize(face); ++i)
  {
    p.Connectivity.push_back(cell[face[i]]);
  }
  p.Offsets.push_back(static_cast<vtkIdType>(p.Connectivity.size()));
  p.Cells.push_back(c);
}

// Assigns one input face (model point ids) to a patch.
bool SolverMeshBuild::Assign(int patch, const vtkIdType* fids, int n, const std::string& what)
{
  // the face's bucket: its smallest point's
  const FaceKey key = MakeKey(fids, n);
  const vtkIdType bucket = key[0] >> shift;
  const CellFace* b = cellFaces.data() + bucketStart[bucket];
  const CellFace* e = cellFaces.data() + bucketStart[bucket + 1];
  const CellFace* first =
    std::lower_bound(b, e, CellFace{ key, std::numeric_limits<vtkIdType>::min() });
  const vtkIdType found = first < e && first->Key == key ? first->Packed : -1; // the first cell's
  if (found < 0)
  {
    error = what + " of patch '" + mesh.Patches[patch].Name +
      "' is not a face of any 3-D cell (its points are volume points, but no cell face has "
      "exactly them)";
    return false;
  }
  const vtkIdType slot = mesh.FaceSlots[found >> 3] + (found & 7);
  if (mesh.FacePartner[slot] >= 0)
  {
    error = what + " of patch '" + mesh.Patches[patch].Name +
      "' is an interior face (shared by two cells), not a boundary face of the volume";
    return false;
  }
  if (slotPatch[slot] >= 0)
  {
    if (slotPatch[slot] != patch)
    {
      error = what + " of patch '" + mesh.Patches[patch].Name + "' is also in patch '" +
        mesh.Patches[slotPatch[slot]].Name + "' (a boundary face belongs to one patch)";
      return false;
    }
    return true; // the same face twice in one patch: written once
  }
  slotPatch[slot] = patch;
  AddFace(patch, found >> 3, static_cast<int>(found & 7));
  return true;
}

// ---- (a) Patch leaves matched by coordinates.
bool SolverMeshBuild::MatchLeaves()
{
  vtkNew<vtkPoints> modelPoints;
  modelPoints->SetDataTypeToDouble();
  modelPoints->SetNumberOfPoints(mesh.GetNumberOfPoints());
  for (vtkIdType p = 0; p < mesh.GetNumberOfPoints(); ++p)
  {
    modelPoints->SetPoint(p, &mesh.Points[3 * p]);
  }
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(modelPoints);
  vtkNew<vtkStaticPointLocator> locator;
  locator->SetDataSet(cloud);
  locator->BuildLocator();
  double bounds[6];
  modelPoints->GetBounds(bounds);
  const double diagonal = std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) +
    (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) +
    (bounds[5] - bounds[4]) * (bounds[5] - bounds[4]));
  const double radius = std::max(tolerance, 0.0) * diagonal;
  for (size_t l = 0; l < patchLeaves.size(); ++l)
  {
    vtkDataSet* leaf = patchLeaves[l].Data;
    const int patch = PatchIndex(patchLeaves[l].Name, "patch" + std::to_string(l));
    std::vector<vtkIdType> leafMap(static_cast<size_t>(leaf->GetNumberOfPoints()), -2);
    for (vtkIdType c = 0; c < leaf->GetNumberOfCells(); ++c)
    {
      const int type = leaf->GetCellType(c);
      if (vtkCellTypes::GetDimension(static_cast<unsigned char>(type)) != 2)
      {
        continue;
      }
      leaf->GetCellPoints(c, ids);
      vtkIdType local[4];
      int n = 0;
      if (!PolygonIds(type, ids, local, n))
      {
        error = "face " + std::to_string(c) + " of patch '" + mesh.Patches[patch].Name +
          "' is a " + TypeName(type) + " with " + std::to_string(ids->GetNumberOfIds()) +
          " points; only triangles and quadrilaterals can be written";
        return false;
      }
      vtkIdType fids[4];
      for (int i = 0; i < n; ++i)
      {
        vtkIdType& p = leafMap[local[i]];
        if (p == -2)
        {
          double x[3];
          leaf->GetPoint(local[i], x);
          double dist2 = 0.0;
          p = (std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]))
            ? locator->FindClosestPointWithinRadius(radius, x, dist2)
            : -1;
          if (p < 0)
          {
            std::ostringstream s;
            s << "point " << local[i] << " (" << x[0] << ", " << x[1] << ", " << x[2]
              << ") of patch '" << mesh.Patches[patch].Name
              << "' has no point of the volume within " << radius
              << " (tolerance relative to the bounding-box diagonal: " << tolerance
              << "): the patch is not on the volume's boundary";
            error = s.str();
            return false;
          }
        }
        fids[i] = p;
      }
      if (!Assign(patch, fids, n, "face " + std::to_string(c)))
      {
        return false;
      }
    }
  }
  return true;
}

// ---- (b) The PatchId array: numeric, integer, one component.
vtkDataArray* SolverMeshBuild::PatchIdArray()
{
  vtkDataArray* patchIds = mesh.Volume->GetCellData()->GetArray("PatchId");
  if (!patchIds)
  {
    error = "the cell array PatchId is not numeric (an integer array is needed)";
    return nullptr;
  }
  if (patchIds->GetDataType() == VTK_FLOAT || patchIds->GetDataType() == VTK_DOUBLE)
  {
    error = std::string("the cell array PatchId is a ") + patchIds->GetClassName() +
      "; an integer array is needed";
    return nullptr;
  }
  if (patchIds->GetNumberOfComponents() != 1)
  {
    error = "the cell array PatchId has " + std::to_string(patchIds->GetNumberOfComponents()) +
      " components; one is needed";
    return nullptr;
  }
  return patchIds;
}

// ---- (b) 2-D cells with PatchId >= 0, named by PatchNames.
bool SolverMeshBuild::PatchIdFaces(vtkDataArray* patchIds)
{
  vtkStringArray* names =
    vtkStringArray::SafeDownCast(mesh.Volume->GetFieldData()->GetAbstractArray("PatchNames"));
  std::map<long long, std::vector<vtkIdType>> byId;
  for (vtkIdType c : surfaceCells)
  {
    const long long id = static_cast<long long>(patchIds->GetComponent(c, 0));
    if (id >= 0)
    {
      byId[id].push_back(c);
    }
  }
  for (const auto& entry : byId)
  {
    std::string rawName;
    if (names && entry.first < names->GetNumberOfValues())
    {
      rawName = names->GetValue(entry.first);
    }
    else if (names)
    {
      mesh.Warnings += "PatchNames has no entry " + std::to_string(entry.first) +
        "; the patch is named patch" + std::to_string(entry.first) + "\n";
    }
    const int patch = PatchIndex(rawName, "patch" + std::to_string(entry.first));
    for (vtkIdType c : entry.second)
    {
      const int type = mesh.Volume->GetCellType(c);
      mesh.Volume->GetCellPoints(c, ids);
      vtkIdType local[4];
      int n = 0;
      if (!PolygonIds(type, ids, local, n))
      {
        error = "boundary cell " + std::to_string(c) + " of patch '" + mesh.Patches[patch].Name +
          "' is a " + TypeName(type) + " with " + std::to_string(ids->GetNumberOfIds()) +
          " points; only triangles and quadrilaterals can be written";
        return false;
      }
      vtkIdType fids[4];
      for (int i = 0; i < n; ++i)
      {
        fids[i] = pointMap[local[i]];
        if (fids[i] < 0)
        {
          error = "boundary cell " + std::to_string(c) + " of patch '" +
            mesh.Patches[patch].Name + "' uses point " + std::to_string(local[i]) +
            ", which no 3-D cell uses: the face is not on the volume's boundary";
          return false;
        }
      }
      if (!Assign(patch, fids, n, "boundary cell " + std::to_string(c)))
      {
        return false;
      }
    }
  }
  return true;
}

// ---- Boundary faces no patch covers: the default patch, in cell order.
bool SolverMeshBuild::Finish()
{
  vtkIdType unassigned = 0;
  int defaultPatch = -1;
  for (vtkIdType c = 0; c < mesh.GetNumberOfCells(); ++c)
  {
    for (vtkIdType slot = mesh.FaceSlots[c]; slot < mesh.FaceSlots[c + 1]; ++slot)
    {
      if (mesh.FacePartner[slot] < 0 && slotPatch[slot] < 0)
      {
        if (defaultPatch < 0)
        {
          defaultPatch = PatchIndex(defaultPatchName, "boundary");
        }
        slotPatch[slot] = defaultPatch;
        AddFace(defaultPatch, c, static_cast<int>(slot - mesh.FaceSlots[c]));
        ++unassigned;
      }
    }
  }
  if (unassigned > 0 && mesh.Form != "volume only")
  {
    mesh.Warnings += std::to_string(unassigned) +
      " boundary faces of the volume are in no patch; they are written to patch '" +
      mesh.Patches[defaultPatch].Name + "'\n";
  }
  // Empty patches cannot be expressed (Gmsh physical groups, SU2 markers need elements).
  std::vector<vtkARSolverMesh::Patch> kept;
  for (auto& p : mesh.Patches)
  {
    if (p.GetNumberOfFaces() > 0)
    {
      kept.push_back(std::move(p));
    }
    else
    {
      mesh.Warnings += "patch '" + p.Name + "' has no faces and is not written\n";
    }
  }
  mesh.Patches = std::move(kept);
  Progress(0.5);
  return true;
}
}

// ----------------------------------------------------------------------------
bool vtkARSolverMesh::Build(vtkDataObject* input, const std::string& defaultPatchName,
  double tolerance, vtkAlgorithm* progress, std::string& error)
{
  *this = vtkARSolverMesh();
  if (!input)
  {
    error = "there is no input";
    return false;
  }
  SolverMeshBuild run(*this, defaultPatchName, tolerance, progress, error);
  if (auto* dataSet = vtkDataSet::SafeDownCast(input))
  {
    // (b) needs the array PatchId (PatchIdArray refuses one that is not an
    // integer array); without it, (c).
    return dataSet->GetCellData()->GetAbstractArray("PatchId") ? run.FromPatchIds(dataSet)
                                                               : run.FromVolumeOnly(dataSet);
  }
  if (vtkMultiBlockDataSet::SafeDownCast(input) || vtkPartitionedDataSet::SafeDownCast(input))
  {
    return run.FromMultiBlock(input);
  }
  error = std::string("the input is a ") + input->GetClassName() +
    "; a vtkUnstructuredGrid (or any vtkDataSet) or a vtkMultiBlockDataSet is needed";
  return false;
}

//------------------------------------------------------------------------------
void vtkARSolverMesh::GetInternalFaces(std::vector<vtkIdType>& owner,
  std::vector<vtkIdType>& neighbour, std::vector<vtkIdType>& offsets,
  std::vector<vtkIdType>& connectivity) const
{
  // A shared face belongs to the side with the lower 8 * cell + local face:
  // the lower cell is the owner. Each cell's faces sorted by that of the
  // other side: upper-triangular order, ties (two cells sharing two faces)
  // in the neighbour's face order.
  const vtkIdType nCells = this->GetNumberOfCells();
  auto owns = [this](vtkIdType c, vtkIdType slot) {
    const vtkIdType other = this->FacePartner[slot];
    return other >= 0 && other > 8 * c + (slot - this->FaceSlots[c]);
  };
  std::vector<vtkIdType> firstFace(static_cast<size_t>(nCells) + 1, 0);
  std::vector<unsigned char> localFace;
  vtkARMeshKernels::Threaded([&]() {
    vtkSMPTools::For(0, nCells, [&](vtkIdType first, vtkIdType last) {
      for (vtkIdType c = first; c < last; ++c)
      {
        vtkIdType n = 0;
        for (vtkIdType slot = this->FaceSlots[c]; slot < this->FaceSlots[c + 1]; ++slot)
        {
          n += owns(c, slot) ? 1 : 0;
        }
        firstFace[c + 1] = n;
      }
    });
  });
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    firstFace[c + 1] += firstFace[c];
  }
  const vtkIdType nInternal = firstFace[nCells];
  owner.resize(static_cast<size_t>(nInternal));
  neighbour.resize(static_cast<size_t>(nInternal));
  localFace.resize(static_cast<size_t>(nInternal));
  offsets.resize(static_cast<size_t>(nInternal) + 1);
  offsets[0] = 0;
  vtkARMeshKernels::Threaded([&]() {
    vtkSMPTools::For(0, nCells, [&](vtkIdType first, vtkIdType last) {
      for (vtkIdType c = first; c < last; ++c)
      {
        std::pair<vtkIdType, int> mine[6];
        int n = 0;
        for (vtkIdType slot = this->FaceSlots[c]; slot < this->FaceSlots[c + 1]; ++slot)
        {
          if (owns(c, slot))
          {
            mine[n++] = { this->FacePartner[slot], static_cast<int>(slot - this->FaceSlots[c]) };
          }
        }
        std::sort(mine, mine + n);
        for (int i = 0; i < n; ++i)
        {
          const vtkIdType k = firstFace[c] + i;
          owner[k] = c;
          neighbour[k] = mine[i].first >> 3;
          localFace[k] = static_cast<unsigned char>(mine[i].second);
          offsets[k + 1] = FaceSize(Face(this->CellTypes[c], mine[i].second));
        }
      }
    });
  });
  for (vtkIdType k = 0; k < nInternal; ++k)
  {
    offsets[k + 1] += offsets[k];
  }
  connectivity.resize(static_cast<size_t>(offsets[nInternal]));
  vtkARMeshKernels::Threaded([&]() {
    vtkSMPTools::For(0, nInternal, [&](vtkIdType first, vtkIdType last) {
      for (vtkIdType k = first; k < last; ++k)
      {
        const vtkIdType c = owner[k];
        const vtkIdType* cell = this->CellConnectivity.data() + this->CellOffsets[c];
        const int* face = Face(this->CellTypes[c], localFace[k]);
        for (vtkIdType i = 0; i < offsets[k + 1] - offsets[k]; ++i)
        {
          connectivity[offsets[k] + i] = cell[face[i]];
        }
      }
    });
  });
}

//------------------------------------------------------------------------------
unsigned long vtkARSolverMesh::Prepare(vtkAlgorithm* writer, const char* label,
  const std::string& path, vtkDataObject* input, const char* defaultPatchName, double tolerance,
  vtkARSolverMesh& mesh, bool gathered)
{
  auto* controller = vtkMultiProcessController::GetGlobalController();
  if (!gathered && controller && controller->GetNumberOfProcesses() > 1)
  {
    vtkErrorWithObjectMacro(writer, << label << ": runs serially; with "
                                    << controller->GetNumberOfProcesses()
                                    << " MPI ranks nothing is written to '" << path << "'.");
    return vtkErrorCode::UnknownError;
  }
  std::string error;
  if (!mesh.Build(input, defaultPatchName ? defaultPatchName : "", tolerance, writer, error))
  {
    vtkErrorWithObjectMacro(
      writer, << label << ": " << error << "; nothing is written to '" << path << "'.");
    return vtkErrorCode::FileFormatError;
  }
  if (!mesh.Warnings.empty())
  {
    vtkWarningWithObjectMacro(writer, << label << " (" << path << "):\n" << mesh.Warnings);
  }
  return vtkErrorCode::NoError;
}
