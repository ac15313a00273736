// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file vtkEmbeddedRemeshPlanes.h
 * @brief Internal to vtkEmbeddedRemesh: the 2-D mode's view of a
 *        one-cell-deep mesh (its two planes and the cells' faces on them),
 *        and what rebuilding the patch faces on those planes needs.
 */
#ifndef vtkEmbeddedRemeshPlanes_h
#define vtkEmbeddedRemeshPlanes_h

#include "vtkSmartPointer.h"
#include "vtkType.h"

#include <array>
#include <map>
#include <string>
#include <vector>

class vtkPolyData;
class vtkUnstructuredGrid;

/// A one-cell-deep mesh: every point of its 3-D cells on the plane
/// x[Axis] = Lo or x[Axis] = Hi, every 3-D cell a hexahedron or wedge with one
/// face on each plane and its depth edges along Axis.
struct vtkEmbeddedRemeshLayout
{
  int Axis = 2;
  double Lo = 0.0;
  double Hi = 0.0;
  std::vector<vtkIdType> Partner;     ///< per input point on Lo: its partner on Hi (-1 elsewhere)
  std::vector<vtkIdType> VolumeCells; ///< the 3-D cells, in input order
  /// per volume cell: its face on Lo and on Hi (input point ids, in the cell's face order)
  std::vector<std::array<std::vector<vtkIdType>, 2>> Faces;
};

/// Fills `layout` and returns true when `input` is one cell deep; otherwise
/// returns false with the reason in `why`.
bool vtkEmbeddedRemeshDetect2D(vtkUnstructuredGrid* input, vtkEmbeddedRemeshLayout& layout, std::string& why);

/// After a 2-D remesh: the input's faces on the planes and what became of
/// their cells, and the new cells' faces on the planes (wedges, and the
/// layers' hexahedra).
struct vtkEmbeddedRemeshPlanes
{
  bool Valid = false;
  vtkUnstructuredGrid* Input = nullptr;  ///< the input volume
  vtkUnstructuredGrid* Output = nullptr; ///< the remeshed volume
  /// sorted input point ids of a volume cell's face on a plane -> that cell
  std::map<std::vector<vtkIdType>, vtkIdType> FaceOwner;
  /// per input cell: the sorted keys of its faces on Lo and Hi (empty if not a volume cell)
  std::vector<std::array<std::vector<vtkIdType>, 2>> CellFaceKey;
  std::vector<char> CellKept; ///< per input cell
  struct Wedge
  {
    vtkIdType Source;                 ///< the input cell that contains the wedge
    std::vector<vtkIdType> Face[2]; ///< its faces on Lo and Hi (triangles, or quads of layer hexahedra), output ids, normals pointing out of the domain
  };
  std::vector<Wedge> Wedges;
};

/// The patch leaf `leaf` rebuilt on the remeshed volume: its faces of
/// removed cells dropped, the new wedges' triangles added where the input
/// cell containing the wedge had its face in this leaf (with that face's
/// cell data; point data copied at kept points, interpolated at new ones).
/// Null when the leaf does not change.
vtkSmartPointer<vtkPolyData> vtkEmbeddedRemeshRebuildPatch(vtkPolyData* leaf, const vtkEmbeddedRemeshPlanes& planes);

#endif
