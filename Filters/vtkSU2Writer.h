// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkSU2Writer
 * @brief Writes a volume mesh and its boundary patches as an SU2 native ASCII mesh (.su2).
 *
 * Layout (SU2 documentation, "Mesh File"): `NDIME= 3`; `NELEM= n` and one
 * line per volume element: its VTK cell type (SU2 uses VTK's type numbers
 * and node orders: 10 tetrahedron, 12 hexahedron, 13 wedge/prism, 14
 * pyramid), its node ids (from 0), and the element index; `NPOIN= m` and one
 * line per node: x y z and the node index; `NMARK= k` and per patch
 * `MARKER_TAG= name`, `MARKER_ELEMS= f` and one line per boundary face:
 * 5 (triangle) or 9 (quadrilateral) and its node ids. Nodes are the points
 * used by 3-D cells, in input order, written with 17 significant digits;
 * elements in input order in VTK's node order (a voxel is written as a
 * hexahedron); boundary faces are the faces of their cell, oriented out of
 * the domain.
 *
 * Input forms, patch naming, errors and the all-or-nothing write are those
 * of vtkGmshWriter: (a) a vtkMultiBlockDataSet as ParaView's OpenFOAM reader
 * gives it (volume block "internalMesh" or the first block with 3-D cells,
 * patches = the other blocks with 2-D cells, by block name, matched by
 * coordinates within PointMatchingTolerance times the bounding-box
 * diagonal); (b) a vtkUnstructuredGrid with 3-D cells plus triangle/quad
 * boundary cells with an integer cell array `PatchId` and a field-data
 * vtkStringArray `PatchNames`; (c) a plain volume mesh, whose boundary faces
 * form one marker named DefaultPatchName. Marker names have whitespace, '"',
 * '=' and '%' replaced by '_'. Bad input (no 3-D cells, polyhedra or
 * quadratic cells, inverted cells, NaN/Inf, a patch face not on the volume's
 * boundary, an unwritable path) is a vtkErrorMacro naming the problem, and
 * no file is written. Serial: refuses to write under MPI with more than one
 * rank.
 */
#ifndef vtkSU2Writer_h
#define vtkSU2Writer_h

#include "AdaptiveRedistributionFiltersModule.h" // for export macro
#include "vtkARSolverMeshWriter.h"

class ADAPTIVEREDISTRIBUTIONFILTERS_EXPORT vtkSU2Writer : public vtkARSolverMeshWriter
{
public:
  static vtkSU2Writer* New();
  vtkTypeMacro(vtkSU2Writer, vtkARSolverMeshWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

protected:
  vtkSU2Writer();
  ~vtkSU2Writer() override;

  bool WriteMesh(const vtkARSolverMesh& mesh, Buffer& out, std::string& error) override;

private:
  vtkSU2Writer(const vtkSU2Writer&) = delete;
  void operator=(const vtkSU2Writer&) = delete;
};

#endif
