// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSU2Writer.h"
#include "vtkARInputChecks.h"
#include "vtkARSolverMesh.h"

#include "vtkAlgorithm.h"
#include "vtkCellType.h"
#include "vtkErrorCode.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"

#include <string>

vtkStandardNewMacro(vtkSU2Writer);

vtkSU2Writer::vtkSU2Writer()
{
  this->SetDefaultPatchName("boundary");
}

vtkSU2Writer::~vtkSU2Writer()
{
  this->SetFileName(nullptr);
  this->SetDefaultPatchName(nullptr);
}

int vtkSU2Writer::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
  return 1;
}

void vtkSU2Writer::WriteData()
{
  this->SetErrorCode(vtkErrorCode::NoError);
  const std::string path = this->FileName ? this->FileName : "";
  vtkARInputChecks::Properties ranges;
  ranges.InRange("PointMatchingTolerance", this->PointMatchingTolerance, 0.0, 1.0,
    "a fraction of the volume's bounding-box diagonal");
  if (!ranges.Ok())
  {
    vtkErrorMacro("SU2Writer: " << ranges.Message() << "Nothing is written to '" << path << "'.");
    this->SetErrorCode(vtkErrorCode::UnknownError);
    return;
  }
  vtkARSolverMesh mesh;
  const unsigned long code = vtkARSolverMesh::Prepare(this, "SU2Writer", path, this->GetInput(),
    this->DefaultPatchName, this->PointMatchingTolerance, mesh);
  if (code != vtkErrorCode::NoError)
  {
    this->SetErrorCode(code);
    return;
  }

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
  };
  std::string error;
  if (!vtkARSolverMesh::WriteAtomically(path, body, error))
  {
    vtkErrorMacro("SU2Writer: " << error << "; nothing is written to '" << path << "'.");
    this->SetErrorCode(vtkErrorCode::CannotOpenFileError);
    return;
  }
  this->UpdateProgress(1.0);
}

void vtkSU2Writer::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "DefaultPatchName: " << (this->DefaultPatchName ? this->DefaultPatchName : "(none)")
     << "\n";
  os << indent << "PointMatchingTolerance: " << this->PointMatchingTolerance << "\n";
}
