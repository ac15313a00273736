// SPDX-License-Identifier: BSD-3-Clause
#include "vtkGmshWriter.h"
#include "vtkARSolverMesh.h"

#include "vtkCellType.h"
#include "vtkObjectFactory.h"

#include <string>

vtkStandardNewMacro(vtkGmshWriter);

vtkGmshWriter::vtkGmshWriter()
  : vtkARSolverMeshWriter("GmshWriter")
{
  this->SetVolumeName("fluid");
}

vtkGmshWriter::~vtkGmshWriter()
{
  this->SetVolumeName(nullptr);
}

bool vtkGmshWriter::WriteMesh(const vtkARSolverMesh& mesh, Buffer& out, std::string& err)
{
  const std::string volumeName =
    vtkARSolverMesh::CleanName(this->VolumeName ? this->VolumeName : "", "fluid");
  std::string& s = out.Text;
  auto flush = [&](bool force) { return out.Flush(force); };
  const size_t nPatches = mesh.Patches.size();
  s += "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n";
  s += std::to_string(nPatches + 1) + "\n";
  for (size_t p = 0; p < nPatches; ++p)
  {
    s += "2 " + std::to_string(p + 1) + " \"" + mesh.Patches[p].Name + "\"\n";
  }
  s += "3 " + std::to_string(nPatches + 1) + " \"" + volumeName + "\"\n";
  s += "$EndPhysicalNames\n$Nodes\n" + std::to_string(mesh.GetNumberOfPoints()) + "\n";
  for (vtkIdType i = 0; i < mesh.GetNumberOfPoints(); ++i)
  {
    s += std::to_string(i + 1);
    for (int k = 0; k < 3; ++k)
    {
      s += ' ';
      vtkARSolverMesh::AppendDouble(s, mesh.Points[3 * i + k]);
    }
    s += '\n';
    if (!flush(false))
    {
      err = "writing the nodes failed (disk full?)";
      return false;
    }
  }
  vtkIdType nFaces = 0;
  for (const auto& patch : mesh.Patches)
  {
    nFaces += patch.GetNumberOfFaces();
  }
  s += "$EndNodes\n$Elements\n" + std::to_string(nFaces + mesh.GetNumberOfCells()) + "\n";
  vtkIdType element = 0;
  for (size_t p = 0; p < nPatches; ++p)
  {
    const auto& patch = mesh.Patches[p];
    const std::string tags = " 2 " + std::to_string(p + 1) + " " + std::to_string(p + 1);
    for (vtkIdType f = 0; f < patch.GetNumberOfFaces(); ++f)
    {
      const vtkIdType n = patch.Offsets[f + 1] - patch.Offsets[f];
      s += std::to_string(++element) + (n == 3 ? " 2" : " 3") + tags;
      for (vtkIdType i = patch.Offsets[f]; i < patch.Offsets[f + 1]; ++i)
      {
        s += ' ' + std::to_string(patch.Connectivity[i] + 1);
      }
      s += '\n';
      if (!flush(false))
      {
        err = "writing the boundary elements failed (disk full?)";
        return false;
      }
    }
  }
  // VTK wedge -> Gmsh prism: the triangles turn the other way.
  static const int wedgeToPrism[6] = { 0, 2, 1, 3, 5, 4 };
  const std::string tags = " 2 " + std::to_string(nPatches + 1) + " " + std::to_string(nPatches + 1);
  for (vtkIdType c = 0; c < mesh.GetNumberOfCells(); ++c)
  {
    const unsigned char type = mesh.CellTypes[c];
    const char* gmshType = type == VTK_TETRA ? " 4"
      : type == VTK_HEXAHEDRON               ? " 5"
      : type == VTK_WEDGE                    ? " 6"
                                             : " 7";
    s += std::to_string(++element) + gmshType + tags;
    const vtkIdType* cell = mesh.CellConnectivity.data() + mesh.CellOffsets[c];
    const vtkIdType n = mesh.CellOffsets[c + 1] - mesh.CellOffsets[c];
    for (vtkIdType i = 0; i < n; ++i)
    {
      s += ' ' + std::to_string(cell[type == VTK_WEDGE ? wedgeToPrism[i] : i] + 1);
    }
    s += '\n';
    if (!flush(false))
    {
      err = "writing the volume elements failed (disk full?)";
      return false;
    }
    if (c % 65536 == 0)
    {
      this->UpdateProgress(0.5 + 0.5 * static_cast<double>(c) / mesh.GetNumberOfCells());
    }
  }
  s += "$EndElements\n";
  return flush(true);
}

void vtkGmshWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "VolumeName: " << (this->VolumeName ? this->VolumeName : "(none)") << "\n";
}
