// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSU2Writer.h"
#include "vtkARSolverMesh.h"

#include "vtkCellType.h"
#include "vtkObjectFactory.h"

#include <string>

vtkStandardNewMacro(vtkSU2Writer);

vtkSU2Writer::vtkSU2Writer()
  : vtkARSolverMeshWriter("SU2Writer")
{
}

vtkSU2Writer::~vtkSU2Writer() = default;

bool vtkSU2Writer::WriteMesh(const vtkARSolverMesh& mesh, Buffer& out, std::string& err)
{
  std::string& s = out.Text;
  auto flush = [&](bool force) { return out.Flush(force); };
  s += "%\n% Problem dimension\n%\nNDIME= 3\n%\n% Inner element connectivity\n%\n";
  s += "NELEM= " + std::to_string(mesh.GetNumberOfCells()) + "\n";
  for (vtkIdType c = 0; c < mesh.GetNumberOfCells(); ++c)
  {
    // SU2 uses VTK's cell type numbers and node orders.
    s += std::to_string(static_cast<int>(mesh.CellTypes[c]));
    for (vtkIdType i = mesh.CellOffsets[c]; i < mesh.CellOffsets[c + 1]; ++i)
    {
      s += ' ' + std::to_string(mesh.CellConnectivity[i]);
    }
    s += ' ' + std::to_string(c) + '\n';
    if (!flush(false))
    {
      err = "writing the elements failed (disk full?)";
      return false;
    }
    if (c % 65536 == 0)
    {
      this->UpdateProgress(0.5 + 0.4 * static_cast<double>(c) / mesh.GetNumberOfCells());
    }
  }
  s += "%\n% Node coordinates\n%\nNPOIN= " + std::to_string(mesh.GetNumberOfPoints()) + "\n";
  for (vtkIdType i = 0; i < mesh.GetNumberOfPoints(); ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      vtkARSolverMesh::AppendDouble(s, mesh.Points[3 * i + k]);
      s += ' ';
    }
    s += std::to_string(i) + '\n';
    if (!flush(false))
    {
      err = "writing the nodes failed (disk full?)";
      return false;
    }
  }
  s += "%\n% Boundary elements\n%\nNMARK= " + std::to_string(mesh.Patches.size()) + "\n";
  for (const auto& patch : mesh.Patches)
  {
    s += "MARKER_TAG= " + patch.Name + "\n";
    s += "MARKER_ELEMS= " + std::to_string(patch.GetNumberOfFaces()) + "\n";
    for (vtkIdType f = 0; f < patch.GetNumberOfFaces(); ++f)
    {
      const vtkIdType n = patch.Offsets[f + 1] - patch.Offsets[f];
      s += n == 3 ? "5" : "9";
      for (vtkIdType i = patch.Offsets[f]; i < patch.Offsets[f + 1]; ++i)
      {
        s += ' ' + std::to_string(patch.Connectivity[i]);
      }
      s += '\n';
      if (!flush(false))
      {
        err = "writing the markers failed (disk full?)";
        return false;
      }
    }
  }
  return flush(true);
}

void vtkSU2Writer::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
