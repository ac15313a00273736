// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file vtkEmbeddedRemeshQuality.h
 * @brief Internal to vtkEmbeddedRemesh: the quality arrays and field data of
 *        its output, the same in the 3-D, 2-D and distributed paths.
 */
#ifndef vtkEmbeddedRemeshQuality_h
#define vtkEmbeddedRemeshQuality_h

#include <string>

class vtkEmbeddedRemesh;
class vtkIntArray;
class vtkUnstructuredGrid;
namespace ar
{
struct CavityRemesh;
struct PrismLayerOptions;
}

/// Quality sums over this process's output cells, for the field data.
struct vtkEmbeddedRemeshQuality
{
  double NewCells = 0.0;
  double NewMinDihedral = 180.0;
  double NewDihedralSum = 0.0;
  double NewMaxAspectRatio = 0.0;
  double LayerMaxAspectRatio = 0.0; ///< layer cells: new prism layers (Region 2) and kept non-tetrahedral 3-D cells (thin by design)
  double LayerMinDihedral = 180.0;
  double LayerCells = 0.0;
  double NewPrisms = 0.0;          ///< Region 2 (new layer cells) by kind: prisms,
  double NewPyramids = 0.0;        ///< pyramids,
  double NewLayerTetrahedra = 0.0; ///< closure tetrahedra,
  double NewLayerHexahedra = 0.0;  ///< hexahedra (2-D mode: the extruded layer quads)
  double NonPositiveJacobian = 0.0; ///< 3-D cells with a corner Jacobian <= 0
};

/// Cell arrays MinDihedralAngle, MaxDihedralAngle (degrees) and AspectRatio
/// (longest / shortest edge) for every tetrahedron, pyramid, wedge,
/// hexahedron and voxel of `output` (ar::ComputeCellQuality); -1 for 2-D
/// cells and polyhedra. `region`: 0 kept, 1 new, per cell.
vtkEmbeddedRemeshQuality vtkEmbeddedRemeshAddQualityArrays(vtkUnstructuredGrid* output, vtkIntArray* region);

/// The quality part of the field data: MinDihedralAngleNew,
/// MeanDihedralAngleNew, MaxAspectRatioNew (Region 1), MaxAspectRatioLayerCells,
/// MinDihedralAngleLayerCells,
/// NonPositiveJacobianCells, and the new layer cells: LayerCells, Prisms,
/// Pyramids, LayerClosureTetrahedra, LayerHexahedra (2-D mode; 0 in 3-D).
/// In 2-D mode the layer cells are hexahedra (the layer quads) and wedges
/// (the tapered ends' triangles, counted as Prisms).
void vtkEmbeddedRemeshAddQualityFields(vtkUnstructuredGrid* output, const vtkEmbeddedRemeshQuality& sums);

/// Under MPI: the sums, minima and maxima over all ranks, on every rank.
void vtkEmbeddedRemeshReduceQuality(vtkEmbeddedRemeshQuality& sums);

/// The prism-layer options from the filter's properties (NumberOfLayers = 0
/// when LayerType is Tetrahedra), the same for the 3-D stack and the 2-D
/// mode's band. `edge`: the surface (curve) edge length, for the automatic
/// stack (FirstLayerThickness and TotalThickness 0: each side half an edge
/// high). False with `problem` naming the bad property.
bool vtkEmbeddedRemeshLayerOptions(
  vtkEmbeddedRemesh* self, double edge, ar::PrismLayerOptions& layers, std::string& problem);

/// The prism stack's field data: LimitedColumns, LayerStackHeight and
/// FirstLayerThicknessUsed (0 without layers), from the options used.
void vtkEmbeddedRemeshAddLayerFields(
  vtkUnstructuredGrid* output, const ar::PrismLayerOptions& layers, double limitedColumns);

/// The output's size at S: the median, over the embedded S's nodes, of the
/// longest edge at the node (tetrahedra, prisms, pyramids of the result) --
/// the measure of the input's size at S, so the two compare.
double vtkEmbeddedRemeshOutputSizeAtSurface(const ar::CavityRemesh& result);

/// Field data InputSizeAtSurface, SurfaceSizeFactor (S's edge length `edge`
/// over it), OutputSizeAtSurface and SurfaceSizeRatio (output / input: how
/// fine the new cells at S are relative to the input's).
void vtkEmbeddedRemeshAddSizeFields(vtkUnstructuredGrid* output, double edge, double inputSize, double outputSize);

/// False with `problem` naming every property out of its range (its value
/// and the range; the XML's domains agree), e.g. RemovalFactor outside
/// (0, 1000], MaxRadiusEdgeRatio outside [1, 100], SurfaceSizeFactor outside
/// [0, 10] when it is used (SurfaceEdgeLength 0). Nothing is clamped.
bool vtkEmbeddedRemeshOptionsValid(vtkEmbeddedRemesh* self, std::string& problem);

/// The size of the job S's edge length `edge` implies, against the memory
/// cap (vtkARInputChecks::MaximumElements). `dimension` 3: `extent` is S's
/// area, `domain` V's volume, the estimate S's triangles (area over the
/// equilateral triangle's, sqrt(3)/4 edge^2) plus the refill's tetrahedra
/// (8.5 per edge^3: the cavity's volume, a slab RemovalFactor *
/// max(edge, inputSize) thick on both sides of S or the whole domain with
/// FullDomain, over the cell size cubed graded linearly from `edge` at S to
/// `inputSize` at the cavity's boundary). `dimension` 2: `extent` is the
/// curves' length, `domain` the cross-section's area, segments plus
/// triangles likewise (2.9 per edge^2, as measured). `inputCells`: V's cells (FullDomain remeshes them
/// all, into about twice as many). With prism layers, 2 NumberOfLayers prisms per S triangle. Also refuses an edge longer than S itself (`size`, S's bounding-box
/// diagonal, or the curves' length). False with `problem` naming the
/// property that set the edge (SurfaceEdgeLength, or SurfaceSizeFactor),
/// the estimate and the cap.
bool vtkEmbeddedRemeshJobFits(vtkEmbeddedRemesh* self, int dimension, double extent, double size,
  double edge, double inputSize, double domain, double inputCells, std::string& problem);

#endif
