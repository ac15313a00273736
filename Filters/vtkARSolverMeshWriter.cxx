// SPDX-License-Identifier: BSD-3-Clause
#include "vtkARSolverMeshWriter.h"

#include "vtkARInputChecks.h"
#include "vtkARSolverMesh.h"

#include "vtkAlgorithm.h"
#include "vtkErrorCode.h"
#include "vtkInformation.h"

#include <ostream>

//------------------------------------------------------------------------------
vtkARSolverMeshWriter::vtkARSolverMeshWriter(const char* label)
  : Label(label)
{
  this->SetDefaultPatchName("boundary");
}

vtkARSolverMeshWriter::~vtkARSolverMeshWriter()
{
  this->SetFileName(nullptr);
  this->SetDefaultPatchName(nullptr);
}

int vtkARSolverMeshWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
  return 1;
}

//------------------------------------------------------------------------------
vtkARSolverMeshWriter::Buffer::Buffer(std::ostream& out)
  : Out(out)
{
  this->Text.reserve(1 << 20);
}

bool vtkARSolverMeshWriter::Buffer::Flush(bool force)
{
  if (force || this->Text.size() > (1u << 20))
  {
    this->Out.write(this->Text.data(), static_cast<std::streamsize>(this->Text.size()));
    this->Text.clear();
  }
  return static_cast<bool>(this->Out);
}

//------------------------------------------------------------------------------
void vtkARSolverMeshWriter::WriteData()
{
  this->SetErrorCode(vtkErrorCode::NoError);
  const std::string path = this->FileName ? this->FileName : "";
  vtkARInputChecks::Properties ranges;
  ranges.InRange("PointMatchingTolerance", this->PointMatchingTolerance, 0.0, 1.0,
    "a fraction of the volume's bounding-box diagonal");
  if (!ranges.Ok())
  {
    vtkErrorMacro(<< this->Label << ": " << ranges.Message() << "Nothing is written to '" << path << "'.");
    this->SetErrorCode(vtkErrorCode::UnknownError);
    return;
  }
  vtkARSolverMesh mesh;
  const unsigned long code = vtkARSolverMesh::Prepare(this, this->Label, path, this->GetInput(),
    this->DefaultPatchName, this->PointMatchingTolerance, mesh);
  if (code != vtkErrorCode::NoError)
  {
    this->SetErrorCode(code);
    return;
  }
  auto body = [&](std::ostream& out, std::string& err) {
    Buffer buffer(out);
    return this->WriteMesh(mesh, buffer, err);
  };
  std::string error;
  if (!vtkARSolverMesh::WriteAtomically(path, body, error))
  {
    vtkErrorMacro(<< this->Label << ": " << error << "; nothing is written to '" << path << "'.");
    this->SetErrorCode(vtkErrorCode::CannotOpenFileError);
    return;
  }
  this->UpdateProgress(1.0);
}

//------------------------------------------------------------------------------
void vtkARSolverMeshWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "DefaultPatchName: " << (this->DefaultPatchName ? this->DefaultPatchName : "(none)")
     << "\n";
  os << indent << "PointMatchingTolerance: " << this->PointMatchingTolerance << "\n";
}
