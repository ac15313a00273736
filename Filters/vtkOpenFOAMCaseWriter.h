// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkOpenFOAMCaseWriter
 * @brief Writes a volume mesh, its boundary patches and its fields as an OpenFOAM case directory.
 *
 * File layout: FileName is the case's marker file, `<case>/<name>.foam`
 * (empty; the file ParaView's OpenFOAM reader opens), and its directory is
 * the case: `SaveData('adapted/adapted.foam', ...)` writes
 *
 *   adapted/adapted.foam
 *   adapted/constant/polyMesh/{points,faces,owner,neighbour,boundary}
 *   adapted/<StartTime>/<field>          (volScalarField, volVectorField)
 *   adapted/system/...                    (the SourceCase's, or a minimal set)
 *   adapted/constant/...                  (the SourceCase's, but its polyMesh)
 *
 * The case directory must not exist, be empty, or hold a case this writer
 * wrote before (it leaves a stamp file `.vtkOpenFOAMCaseWriter`), which is
 * replaced as a whole (with whatever a solver added to it). Anything else in
 * an existing directory is refused: the writer never mixes its case with
 * other files nor deletes them. All-or-nothing: the case is written into a
 * temporary directory next to the target and renamed onto it at the end;
 * on any error (a vtkErrorMacro names the cause) nothing is left behind and
 * an existing case stays as it was.
 *
 * Format: ASCII (default) or OpenFOAM's binary format (`format binary`,
 * `arch "LSB;label=32;scalar=64"`): the points, the faces (a
 * faceCompactList: offsets and point ids), owner, neighbour and the fields'
 * nonuniform lists as raw 32-bit labels and doubles, everything else text:
 * the same case, half the size for double-precision fields, faster to write
 * and to read back (README, bench_foam_case.py). Binary values are the
 * doubles themselves (no float shortening). A binary case cannot be a
 * SourceCase (its fields are read as text).
 * The big lists are formatted in parallel (vtkSMPTools, chunks written in
 * order: the files do not depend on the number of threads).
 *
 * polyMesh (FoamFile headers): the points of the 3-D cells
 * in input order; the cells in input order (tetrahedra, pyramids, wedges,
 * hexahedra, voxels as hexahedra); the faces internal first, in
 * upper-triangular order (sorted by owner, then neighbour; owner <
 * neighbour), each oriented from owner to neighbour, then the boundary faces
 * patch by patch, oriented out of the domain. Input forms, patch names and
 * the refusals (no 3-D cells, polyhedra, quadratic cells, inverted cells,
 * NaN/Inf, a patch face not on the boundary, ...) are vtkGmshWriter's (see
 * vtkARSolverMesh): the OpenFOAM reader's multiblock, an unstructured grid
 * with `PatchId`/`PatchNames` boundary cells (EmbeddedRemesh's output), or
 * a plain volume (one patch, DefaultPatchName). Coordinates and values that
 * are exactly single precision (the OpenFOAM reader gives floats, and
 * filters such as EmbeddedRemesh carry them over in double arrays) are
 * written with the shortest text that reads back as the same float, so the
 * source's own digits come back; other values with the shortest text that
 * reads back as the same double (at most 17 digits).
 *
 * Patch types. With SourceCase: each patch's entries in the source's
 * `constant/polyMesh/boundary` (type, inGroups, physicalType, ...) but
 * nFaces/startFace are copied; a patch not found there is `patch` (a
 * warning names it). Without SourceCase every patch is `patch`, except on a
 * one-cell-deep mesh (every point on one of two parallel planes, as
 * OpenFOAM's 2-D cases): a patch whose every face lies in one of the two
 * planes (frontAndBack, front, back, whatever its name) is `empty`. An
 * axisymmetric `wedge` case needs its SourceCase.
 *
 * Fields: cell values. A cell array is written as it is; a point array
 * (with no cell array of the same name) is averaged to the cells
 * (vtkPointDataToCellData). With SourceCase, the fields are the
 * volScalarField and volVectorField files of the source's time directory
 * SourceTime ("latest": the largest time; "0", "0.4", ...), matched by name
 * to the input's arrays; the plugin's own arrays (Region, PatchId, quality,
 * ...) are not written. Each keeps its source's `dimensions`, its other
 * top-level entries and its `boundaryField` entry per patch (exact name,
 * else an inGroups group, else a quoted regular expression, as OpenFOAM
 * matches them), with every `nonuniform` list rewritten for the new faces:
 * `value` (and a `$internalField` that is not uniform) from the cells next
 * to the faces, any other list (refValue, gradient, ...) uniform at its old
 * mean. A patch with no entry gets `zeroGradient`, a constraint patch
 * (empty, wedge, symmetryPlane, symmetry, cyclic) its own type. A source
 * field the input has no array for is written uniform where the source's
 * internalField is uniform, else left out (warning). Without SourceCase,
 * every 1- and 3-component numeric point or cell array (but PatchId,
 * vtkGhostType, vtkOriginalCellIds / PointIds) is written, dimensions
 * `[0 0 0 0 0 0 0]`, `zeroGradient` on every patch (`empty` on empty ones).
 * Fields go to the time directory StartTime (default "0").
 *
 * system/ and constant/: with SourceCase, copied from it (constant/ without
 * polyMesh), so the case runs as the source did; the copied controlDict is
 * not changed (with `startFrom startTime`, StartTime should be its
 * startTime, else a warning says so). Without SourceCase, a minimal
 * controlDict, fvSchemes and fvSolution with which checkMesh and
 * foamToVTK run.
 *
 * Source case errors: no (or unreadable) constant/polyMesh/boundary, a
 * SourceTime that does not exist, a field file in binary or compressed
 * form (foamFormatConvert / gunzip it), a malformed dictionary, an input
 * array whose components do not fit its field's class.
 *
 * Under MPI (pvbatch, pvserver; the proxy is registered with
 * supports_parallel): each rank asks for its own piece, drops its ghost
 * cells and sends it to rank 0, which merges the pieces (leaf by leaf for a
 * multiblock; the points where they meet merged, exact duplicates) and
 * writes the case as the serial run would, its points and cells numbered
 * rank by rank. Every rank's ErrorCode is rank 0's.
 */
#ifndef vtkOpenFOAMCaseWriter_h
#define vtkOpenFOAMCaseWriter_h

#include "AdaptiveRedistributionFiltersModule.h" // for export macro
#include "vtkWriter.h"

class ADAPTIVEREDISTRIBUTIONFILTERS_EXPORT vtkOpenFOAMCaseWriter : public vtkWriter
{
public:
  static vtkOpenFOAMCaseWriter* New();
  vtkTypeMacro(vtkOpenFOAMCaseWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The case's marker file, `<case directory>/<name>.foam`; its directory
  /// is the case written.
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  ///@{
  /// The OpenFOAM case the solution came from (optional): patch types,
  /// field boundary conditions and dimensions, system/ and constant/ are
  /// taken from it. Empty (default): none.
  vtkSetStringMacro(SourceCase);
  vtkGetStringMacro(SourceCase);
  ///@}

  ///@{
  /// The SourceCase's time directory whose fields are written: "latest"
  /// (default, the largest time) or a time name such as "0".
  vtkSetStringMacro(SourceTime);
  vtkGetStringMacro(SourceTime);
  ///@}

  ///@{
  /// The time directory of the written case that holds the fields; a
  /// number. Default "0".
  vtkSetStringMacro(StartTime);
  vtkGetStringMacro(StartTime);
  ///@}

  ///@{
  /// Name of the patch that takes the boundary faces no patch covers (all
  /// of them for a plain volume mesh). Default "boundary".
  vtkSetStringMacro(DefaultPatchName);
  vtkGetStringMacro(DefaultPatchName);
  ///@}

  ///@{
  /// Multiblock input: a patch point matches the nearest volume point within
  /// this fraction of the volume's bounding-box diagonal. Default 1e-6. In
  /// [0, 1]: refused otherwise (nothing written), not clamped.
  vtkSetMacro(PointMatchingTolerance, double);
  vtkGetMacro(PointMatchingTolerance, double);
  ///@}

  enum FileFormat
  {
    ASCII = 0,
    BINARY = 1
  };

  ///@{
  /// The polyMesh and field files' format: ASCII (0, default) or BINARY
  /// (1, OpenFOAM's binary format, 32-bit labels, 64-bit scalars). Other
  /// values are refused (nothing written).
  vtkSetMacro(Format, int);
  vtkGetMacro(Format, int);
  void SetFormatToAscii() { this->SetFormat(ASCII); }
  void SetFormatToBinary() { this->SetFormat(BINARY); }
  ///@}

protected:
  vtkOpenFOAMCaseWriter();
  ~vtkOpenFOAMCaseWriter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  vtkTypeBool ProcessRequest(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  /// Under MPI, each rank's own piece without ghost cells.
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*);
  void WriteData() override;
  /// The case from `input` (the whole mesh; rank 0's gathered one under MPI).
  void WriteCase(vtkDataObject* input);

private:
  vtkOpenFOAMCaseWriter(const vtkOpenFOAMCaseWriter&) = delete;
  void operator=(const vtkOpenFOAMCaseWriter&) = delete;

  char* FileName = nullptr;
  char* SourceCase = nullptr;
  char* SourceTime = nullptr;
  char* StartTime = nullptr;
  char* DefaultPatchName = nullptr;
  double PointMatchingTolerance = 1e-6;
  int Format = ASCII;
};

#endif
