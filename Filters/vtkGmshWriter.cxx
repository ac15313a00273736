// SPDX-License-Identifier: BSD-3-Clause
#include "vtkGmshWriter.h"
#include "vtkARInputChecks.h"
#include "vtkARSolverMesh.h"

#include "vtkAlgorithm.h"
#include "vtkCellType.h"
#include "vtkErrorCode.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"

#include <string>

vtkStandardNewMacro(vtkGmshWriter);

vtkGmshWriter::vtkGmshWriter()
{
  this->SetVolumeName("fluid");
  this->SetDefaultPatchName("boundary");
}

vtkGmshWriter::~vtkGmshWriter()
{
  this->SetFileName(nullptr);
  this->SetVolumeName(nullptr);
  this->SetDefaultPatchName(nullptr);
}

int vtkGmshWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
  return 1;
}

void vtkGmshWriter::WriteData()
{
  this->SetErrorCode(vtkErrorCode::NoError);
  const std::string path = this->FileName ? this->FileName : "";
  vtkARInputChecks::Properties ranges;
  ranges.InRange("PointMatchingTolerance", this->PointMatchingTolerance, 0.0, 1.0,
    "a fraction of the volume's bounding-box diagonal");
  if (!ranges.Ok())
  {
    vtkErrorMacro("GmshWriter: " << ranges.Message() << "Nothing is written to '" << path << "'.");
    this->SetErrorCode(vtkErrorCode::UnknownError);
    return;
  }
  vtkARSolverMesh mesh;
  const unsigned long code = vtkARSolverMesh::Prepare(this, "GmshWriter", path, this->GetInput(),
    this->DefaultPatchName, this->PointMatchingTolerance, mesh);
  if (code != vtkErrorCode::NoError)
  {
    this->SetErrorCode(code);
    return;
  }
  const std::string volumeName =
    vtkARSolverMesh::CleanName(this->VolumeName ? this->VolumeName : "", "fluid");

  auto body = [&](std::ostream& out, std::string& err) {
    std::string s;
    s.reserve(1 << 20);
    auto flush = [&](bool force) {
      if (force || s.size() > (1u << 20))
      {
        out.write(s.data(), static_cast<std::streamsize>(s.size()));
        s.clear();
      }
      return static_cast<bool>(out);
    };
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
  };
  std::string error;
  if (!vtkARSolverMesh::WriteAtomically(path, body, error))
  {
    vtkErrorMacro("GmshWriter: " << error << "; nothing is written to '" << path << "'.");
    this->SetErrorCode(vtkErrorCode::CannotOpenFileError);
    return;
  }
  this->UpdateProgress(1.0);
}

void vtkGmshWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "VolumeName: " << (this->VolumeName ? this->VolumeName : "(none)") << "\n";
  os << indent << "DefaultPatchName: " << (this->DefaultPatchName ? this->DefaultPatchName : "(none)")
     << "\n";
  os << indent << "PointMatchingTolerance: " << this->PointMatchingTolerance << "\n";
}
