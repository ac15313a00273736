// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkARSolverMesh
 * @brief Private: the volume mesh and its boundary patches, as the solver writers need them.
 *
 * Not part of the public API. Shared by vtkGmshWriter, vtkSU2Writer and
 * vtkOpenFOAMCaseWriter:
 * `Build` turns any of the three accepted inputs into one flat model —
 *
 *   (a) a vtkMultiBlockDataSet as ParaView's OpenFOAM reader gives it: the
 *       volume is the leaf named "internalMesh" (else the first leaf with
 *       3-D cells); every other leaf with 2-D cells is a boundary patch named
 *       by its vtkCompositeDataSet::NAME() (leaves under a block whose name
 *       contains "lagrangian" or "zones", any case, are skipped). Patch
 *       points are matched to the volume's points by coordinates (a
 *       vtkStaticPointLocator, tolerance relative to the bounding-box
 *       diagonal); patches with the same name are merged;
 *   (b) a vtkDataSet holding 3-D cells and 2-D boundary cells (triangles,
 *       quads) with an integer cell array `PatchId` (>= 0 on boundary cells;
 *       the volume cells and 2-D cells with a negative id are not patch
 *       faces) and an optional field-data vtkStringArray `PatchNames`
 *       (index = PatchId; missing names are patch<id>);
 *   (c) a vtkDataSet with 3-D cells only (or 2-D cells but no `PatchId`):
 *       every boundary face goes to the patch DefaultPatchName.
 *
 * In (a) and (b) boundary faces of the volume that no patch covers also go
 * to DefaultPatchName (with a warning). Boundary faces are the faces used by
 * exactly one 3-D cell; every patch face is written as that cell face, so
 * it points out of the domain whatever the orientation of the input's patch
 * cell.
 *
 * The model keeps only points used by 3-D cells (renumbered 0..n-1 in
 * input order), the 3-D cells in input order in VTK's node ordering (voxels
 * become hexahedra), and the patches in input order, empty patches dropped.
 *
 * Refused with a message naming the problem: no 3-D cells; a 3-D cell the
 * formats cannot hold (polyhedra, quadratic and higher-order cells,
 * pentagonal / hexagonal prisms); an inverted or degenerate cell (volume
 * from its outward faces <= 0); a face shared by more than two cells;
 * NaN/Inf coordinates; a patch face that is not a triangle or quad, or not a
 * boundary face of the volume, or in two patches; a patch point with no
 * volume point within the tolerance; a non-integer PatchId array.
 *
 * WriteAtomically writes through a temporary file in the target's
 * directory renamed onto the target at the end, so a failed write leaves no
 * file (and an existing file untouched).
 */
#ifndef vtkARSolverMesh_h
#define vtkARSolverMesh_h

#include "vtkType.h"

#include <functional>
#include <ostream>
#include <string>
#include <vector>

class vtkAlgorithm;
class vtkDataObject;
class vtkDataSet;

class vtkARSolverMesh
{
public:
  struct Patch
  {
    std::string Name;
    std::vector<vtkIdType> Offsets{ 0 };
    std::vector<vtkIdType> Connectivity; // outward-oriented, model point ids
    std::vector<vtkIdType> Cells; // the model cell each face belongs to
    vtkIdType GetNumberOfFaces() const { return static_cast<vtkIdType>(this->Offsets.size()) - 1; }
  };

  std::vector<double> Points; // 3 per point
  std::vector<unsigned char> CellTypes; // VTK_TETRA, VTK_HEXAHEDRON, VTK_WEDGE, VTK_PYRAMID
  std::vector<vtkIdType> CellOffsets{ 0 };
  std::vector<vtkIdType> CellConnectivity; // VTK node order, model point ids
  std::vector<Patch> Patches;
  /// The face table, from Build's one pass over the cell faces: cell c's
  /// local face f (ar::CellFace order) is slot FaceSlots[c] + f, and
  /// FacePartner[slot] is the same face of the other cell, as 8 * cell +
  /// local face, or -1 on the boundary. GetInternalFaces reads it.
  std::vector<vtkIdType> FaceSlots{ 0 };
  std::vector<vtkIdType> FacePartner;
  /// The dataset the volume cells came from (not owned: valid while the
  /// input lives), and for each model point / cell its id there: the point
  /// and cell arrays of the input are read through these.
  vtkDataSet* Volume = nullptr;
  std::vector<vtkIdType> InputPointIds;
  std::vector<vtkIdType> InputCellIds;
  /// Which input form was recognized: "multiblock", "PatchId" or "volume only".
  std::string Form;
  /// Warnings collected while building (one per line).
  std::string Warnings;

  vtkIdType GetNumberOfPoints() const { return static_cast<vtkIdType>(this->Points.size() / 3); }
  vtkIdType GetNumberOfCells() const { return static_cast<vtkIdType>(this->CellTypes.size()); }

  /// Builds the model. `tolerance` is relative to the volume's bounding-box
  /// diagonal (form (a) only). `progress` (may be null) gets UpdateProgress
  /// calls in [0, 0.5]. Returns false with `error` set on bad input.
  bool Build(vtkDataObject* input, const std::string& defaultPatchName, double tolerance,
    vtkAlgorithm* progress, std::string& error);

  /// The faces shared by two model cells, in OpenFOAM's upper-triangular
  /// order: sorted by owner (the lower cell id), then by neighbour; each
  /// face as the owner's cell face, so its right-hand normal points from
  /// owner to neighbour. `offsets` starts with 0. From the face table (no
  /// second face search); threaded with vtkSMPTools, the same result.
  void GetInternalFaces(std::vector<vtkIdType>& owner, std::vector<vtkIdType>& neighbour,
    std::vector<vtkIdType>& offsets, std::vector<vtkIdType>& connectivity) const;

  /// Patch names as the formats need them: no whitespace, quotes or '=',
  /// not empty. Returns the cleaned name (and says so in Warnings).
  static std::string CleanName(const std::string& name, const std::string& fallback);

  /// The common start of a writer's WriteData: refuses to run on more than
  /// one MPI rank (unless `gathered`: the writer has gathered the whole
  /// mesh on this rank), builds `mesh` from `input` and reports errors and
  /// warnings on `writer` (prefixed by `label`). Returns the vtkErrorCode the
  /// writer should set (NoError when the mesh is ready).
  static unsigned long Prepare(vtkAlgorithm* writer, const char* label, const std::string& path,
    vtkDataObject* input, const char* defaultPatchName, double tolerance, vtkARSolverMesh& mesh,
    bool gathered = false);

  /// Writes `path` through a temporary file renamed at the end. `body`
  /// streams the content and returns false (with `error`) to abandon.
  static bool WriteAtomically(const std::string& path,
    const std::function<bool(std::ostream&, std::string&)>& body, std::string& error);

  /// Shortest round-trip text of a double ("%.17g").
  static void AppendDouble(std::string& s, double v);

};

#endif
