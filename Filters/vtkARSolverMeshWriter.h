// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkARSolverMeshWriter
 * @brief Abstract base of the writers of one solver mesh file (vtkSU2Writer, vtkGmshWriter).
 *
 * Owns what the writers share: the properties FileName, DefaultPatchName and
 * PointMatchingTolerance, any vtkDataObject as input, and WriteData's frame:
 * the error code reset, PointMatchingTolerance checked (in [0, 1], refused,
 * not clamped), the input turned into a solver mesh with its patches
 * (vtkARSolverMesh::Prepare: the input forms, the checks, the refusal under
 * MPI), and the file written all or nothing (vtkARSolverMesh::WriteAtomically)
 * through a buffer. A subclass writes the format: one hook, WriteMesh.
 *
 * @sa vtkSU2Writer vtkGmshWriter vtkOpenFOAMCaseWriter
 */
#ifndef vtkARSolverMeshWriter_h
#define vtkARSolverMeshWriter_h

#include "AdaptiveRedistributionFiltersModule.h" // for export macro
#include "vtkWriter.h"

#include <iosfwd> // for Buffer
#include <string> // for Buffer

class vtkARSolverMesh;

class ADAPTIVEREDISTRIBUTIONFILTERS_EXPORT vtkARSolverMeshWriter : public vtkWriter
{
public:
  vtkAbstractTypeMacro(vtkARSolverMeshWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The file to write.
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  ///@{
  /// Name of the patch that takes the boundary faces no patch covers (all
  /// of them for a plain volume mesh). Default "boundary".
  vtkSetStringMacro(DefaultPatchName);
  vtkGetStringMacro(DefaultPatchName);
  ///@}

  ///@{
  /// Multiblock input: a patch point matches the nearest volume point within
  /// this fraction of the volume's bounding-box diagonal. Default 1e-6.
  /// In [0, 1]: refused otherwise (nothing written), not clamped.
  vtkSetMacro(PointMatchingTolerance, double);
  vtkGetMacro(PointMatchingTolerance, double);
  ///@}

protected:
  /// `label` begins the messages ("SU2Writer").
  explicit vtkARSolverMeshWriter(const char* label);
  ~vtkARSolverMeshWriter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  void WriteData() override;

  /// The text of the file, handed to the stream in blocks of about 1 MiB.
  class Buffer
  {
  public:
    explicit Buffer(std::ostream& out);
    std::string Text;
    /// Writes Text out when it holds more than 1 MiB, or `force`; false
    /// when the stream has failed (disk full?).
    bool Flush(bool force);

  private:
    std::ostream& Out;
  };

  /// The format: writes `mesh` into `out` (Flush(true) at the end). False
  /// with `error` set when writing failed: nothing is kept.
  virtual bool WriteMesh(const vtkARSolverMesh& mesh, Buffer& out, std::string& error) = 0;

private:
  vtkARSolverMeshWriter(const vtkARSolverMeshWriter&) = delete;
  void operator=(const vtkARSolverMeshWriter&) = delete;

  char* FileName = nullptr;
  char* DefaultPatchName = nullptr;
  double PointMatchingTolerance = 1e-6;
  const char* Label;
};

#endif
