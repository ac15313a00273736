// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkRemoveSelectedCells
 * @brief Removes the cells of a selection from a surface (hand-editing a feature surface).
 *
 * Input port 0: any vtkDataSet, usually a triangulated feature surface
 * (vtkPolyData from vtkQuadricFit or MedialAxisDelaunay).
 * Input port 1, "Selection" (optional): a vtkSelection, e.g. the cells picked
 * with ParaView's Select Cells tool (the GUI offers "Copy Active Selection"
 * for it), an IDSelectionSource, a frustum or a threshold selection. Its
 * cells are found with vtkExtractSelection (PreserveTopology, so any
 * selection type and selection expression works, as in ParaView's Extract
 * Selection filter) and removed.
 *
 * Output: vtkPolyData of the input's cells that are not selected, in their
 * input order, with the points no kept cell uses dropped and every point and
 * cell array kept (a non-polydata input is turned into its surface with
 * vtkGeometryFilter after the removal; a volume cell then contributes its
 * boundary faces). The input is never modified.
 *
 * An absent selection, or one that selects no cell of the input, passes the
 * input through (as polydata) with a warning. Selecting every cell gives an
 * empty output with a warning. An input without cells gives an error and an
 * empty output.
 */
#ifndef vtkRemoveSelectedCells_h
#define vtkRemoveSelectedCells_h

#include "AdaptiveRedistributionFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

class ADAPTIVEREDISTRIBUTIONFILTERS_EXPORT vtkRemoveSelectedCells : public vtkPolyDataAlgorithm
{
public:
  static vtkRemoveSelectedCells* New();
  vtkTypeMacro(vtkRemoveSelectedCells, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The selection whose cells are removed (input port 1, optional).
  void SetSelectionConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetSelectionData(vtkDataObject* data) { this->SetInputData(1, data); }

  /// Number of cells removed by the last execution.
  vtkGetMacro(NumberOfRemovedCells, vtkIdType);

protected:
  vtkRemoveSelectedCells();
  ~vtkRemoveSelectedCells() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkRemoveSelectedCells(const vtkRemoveSelectedCells&) = delete;
  void operator=(const vtkRemoveSelectedCells&) = delete;

  vtkIdType NumberOfRemovedCells = 0;
};

#endif
