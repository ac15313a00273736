// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkGmshWriter
 * @brief Writes a volume mesh and its boundary patches as a Gmsh MSH 2.2 ASCII file.
 *
 * The format OpenFOAM's `gmshToFoam` and SU2 (and Gmsh itself) read:
 * `$MeshFormat 2.2 0 8`, `$PhysicalNames`, `$Nodes`, `$Elements`. Nodes are
 * the points used by 3-D cells, numbered from 1 in input order, written with
 * 17 significant digits (a double reads back exactly). Elements: first the
 * boundary faces, patch by patch, as triangles (Gmsh type 2) and quadrangles
 * (3), each tagged with its patch's physical group (dimension 2, one per
 * patch, named by the patch); then the volume cells in input order as
 * tetrahedra (4), hexahedra (5), prisms (6) and pyramids (7), tagged with
 * one physical group of dimension 3 named VolumeName. Physical ids: patches
 * 1..P in patch order, the volume P+1; every element has two tags, physical
 * = elementary id. Boundary faces are written as the face of their cell,
 * oriented out of the domain.
 *
 * Node order: Gmsh's tetrahedron, hexahedron and pyramid orders are VTK's
 * (the first face's right-hand normal points to the last node / the
 * opposite face / the apex). A prism is not: Gmsh's first triangle (0, 1, 2)
 * turns positively about the axis towards (3, 4, 5), VTK's wedge turns the
 * other way (its normal points away from the top face), so wedge (0..5) is
 * written as prism (0, 2, 1, 3, 5, 4).
 *
 * Input: (a) a vtkMultiBlockDataSet as ParaView's OpenFOAM reader gives it
 * (volume block "internalMesh" or the first block with 3-D cells; every
 * other block with 2-D cells is a patch named by its block name; points
 * matched by coordinates within PointMatchingTolerance times the bounding
 * box diagonal); (b) a vtkUnstructuredGrid (any vtkDataSet) with 3-D cells
 * plus triangle/quad boundary cells carrying an integer cell array
 * `PatchId` (>= 0; the volume cells -1) and a field-data vtkStringArray
 * `PatchNames` (index = PatchId; without it patches are patch0, patch1,
 * ...); (c) a plain volume mesh: all boundary faces form one patch named
 * DefaultPatchName. In (a) and (b) boundary faces no patch covers go to
 * DefaultPatchName too (warning). Patch names have whitespace, '"', '=' and
 * '%' replaced by '_'; patches with no faces are not written (warning).
 *
 * Errors (vtkErrorMacro naming the problem; nothing is written and an
 * existing file is left as it was, since the file is written under a
 * temporary name and renamed at the end): no 3-D cells; a cell type the
 * format cannot hold (polyhedra, quadratic cells); an inverted or
 * degenerate cell; NaN/Inf coordinates; a patch face not on the volume's
 * boundary, or in two patches; an unwritable path. Write() returns 0 and
 * GetErrorCode() is set on failure.
 *
 * Serial: under MPI with more than one rank it refuses to write (the pieces
 * would have to be gathered first).
 */
#ifndef vtkGmshWriter_h
#define vtkGmshWriter_h

#include "AdaptiveRedistributionFiltersModule.h" // for export macro
#include "vtkARSolverMeshWriter.h"

class ADAPTIVEREDISTRIBUTIONFILTERS_EXPORT vtkGmshWriter : public vtkARSolverMeshWriter
{
public:
  static vtkGmshWriter* New();
  vtkTypeMacro(vtkGmshWriter, vtkARSolverMeshWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Name of the 3-D physical group of the volume cells. Default "fluid".
  vtkSetStringMacro(VolumeName);
  vtkGetStringMacro(VolumeName);
  ///@}

protected:
  vtkGmshWriter();
  ~vtkGmshWriter() override;

  bool WriteMesh(const vtkARSolverMesh& mesh, Buffer& out, std::string& error) override;

private:
  vtkGmshWriter(const vtkGmshWriter&) = delete;
  void operator=(const vtkGmshWriter&) = delete;

  char* VolumeName = nullptr;
};

#endif
