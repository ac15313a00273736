// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file vtkEmbeddedRemeshStages.h
 * @brief Internal to vtkEmbeddedRemesh: the stages its three drivers share.
 *
 * The serial 3-D driver (vtkEmbeddedRemesh::RemeshVolume), the distributed
 * one (RemeshDistributed, vtkEmbeddedRemeshDistributed.cxx) and the 2-D
 * mode (Remesh2D, vtkEmbeddedRemesh2D.cxx) run the same stages: check the
 * input, collect the feature surfaces, measure the input's size at them,
 * check the job's size, set the core's options, call the core, build the
 * output's cells (vtkEmbeddedRemeshCells), locate the new points and cells
 * in the removed cells, copy or interpolate the fields, and write one
 * summary (vtkEmbeddedRemeshSummary: reduced over the ranks under MPI, then
 * written once as the output's field data). Each driver only does what is
 * its own: the serial one its hybrid cells, the distributed one the
 * gathering of the cavity to rank 0, the 2-D one its cross-section and
 * extrusion.
 */
#ifndef vtkEmbeddedRemeshStages_h
#define vtkEmbeddedRemeshStages_h

#include "vtkARFieldTransfer.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkSmartPointer.h"
#include "vtkType.h"
#include "vtkUnsignedCharArray.h"

#include <chrono>
#include <cstdint>
#include <exception>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

class vtkAlgorithm;
class vtkDataSet;
class vtkEmbeddedRemesh;
class vtkIdList;
class vtkPoints;
class vtkPolyData;
class vtkUnstructuredGrid;
namespace ar
{
struct CavityOptions;
struct CavityRemesh;
struct Cavity2DOptions;
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
  /// The smallest explicit step length 2V / sum(face areas)
  /// (ar::CellStepLength) of the new cells (Region 1) and of the new layer
  /// cells (Region 2); infinite where there are none.
  double NewMinStep = std::numeric_limits<double>::infinity();
  double LayerMinStep = std::numeric_limits<double>::infinity();
};

/// Cell arrays MinDihedralAngle, MaxDihedralAngle (degrees) and AspectRatio
/// (longest / shortest edge) for every tetrahedron, pyramid, wedge,
/// hexahedron and voxel of `output` (ar::ComputeCellQuality); -1 for 2-D
/// cells and polyhedra. `region`: 0 kept, 1 new, 2 new layer cell, per
/// cell. `depthAxis`: a one-cell-deep mesh's depth axis (its front and back
/// faces carry no flux: left out of the step lengths), -1 in 3-D.
vtkEmbeddedRemeshQuality vtkEmbeddedRemeshAddQualityArrays(
  vtkUnstructuredGrid* output, vtkIntArray* region, int depthAxis = -1);

/// The quality part of the field data: MinDihedralAngleNew,
/// MeanDihedralAngleNew, MaxAspectRatioNew (Region 1), MaxAspectRatioLayerCells,
/// MinDihedralAngleLayerCells,
/// NonPositiveJacobianCells, and the new layer cells: LayerCells, Prisms,
/// Pyramids, LayerClosureTetrahedra, LayerHexahedra (2-D mode; 0 in 3-D).
/// In 2-D mode the layer cells are hexahedra (the layer quads) and wedges
/// (the tapered ends' triangles, counted as Prisms).
void vtkEmbeddedRemeshAddQualityFields(vtkUnstructuredGrid* output, const vtkEmbeddedRemeshQuality& sums);

/// The time-step part of the field data: StepLengthNew and
/// StepLengthLayerCells (the smallest 2V / sum(face areas) of the new cells
/// and of the new layer cells; 0 where there are none), and their ratios to
/// the cell the requested size asks for, StepLengthRatioNew (a regular
/// tetrahedron of S's edge `edge`; in 2-D an equilateral triangle) and
/// StepLengthRatioLayerCells (a right prism over that triangle, as high as
/// the first layer; in 2-D an edge x first-layer rectangle). An explicit
/// solver's global time step follows the smallest of them: a ratio of 1 is
/// the step the requested refinement costs, 0.5 half of it.
void vtkEmbeddedRemeshAddStepFields(vtkUnstructuredGrid* output, const vtkEmbeddedRemeshQuality& sums,
  double edge, const ar::PrismLayerOptions& layers, bool twoDimensional);

/// The explicit step length (ar::CellStepLength) of the cell the requested
/// size asks for: `layer` 0, the regular tetrahedron of edge `edge` (2-D:
/// the equilateral triangle, one cell deep); `layer` > 0, the right prism
/// over the equilateral triangle of side `edge`, `layer` high (2-D: the
/// `edge` x `layer` rectangle). 0 where `edge` is not positive.
double vtkEmbeddedRemeshIdealStepLength(double edge, double layer, bool twoDimensional);

/// The new tetrahedra's smallest step length asked of the 3-D refill, as a
/// fraction of vtkEmbeddedRemeshIdealStepLength at S's edge
/// (ar::CavityOptions::MinStepLength): "no smaller than about half the
/// requested size".
constexpr double vtkEmbeddedRemeshMinStepFraction = 0.5;

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

/// NaN/Inf coordinates in the volume or a surface, or duplicated points (a
/// crack) in the volume: the problem (empty when there is none), checked
/// before any mesher sees the mesh (TetGen fails on, or corrupts its heap
/// with, a crack).
std::string vtkEmbeddedRemeshCheckCoordinates(vtkUnstructuredGrid* input, const std::vector<vtkDataSet*>& surfaces);

/// The message for an exception out of the core (std::bad_alloc when a job
/// outgrows the memory despite the size estimate, a CGAL precondition),
/// which becomes an error, never an abort of the application.
std::string vtkEmbeddedRemeshFailure(const std::exception& e);

/// The feature surfaces as one triangle soup, merged (coincident points
/// joined, vtkStaticCleanPolyData at tolerance 0; only triangles kept).
/// Under MPI the pieces of every rank are gathered to rank 0, merged there
/// and the result is sent to every rank, so every rank has the same soup.
/// Collective under MPI.
struct vtkEmbeddedRemeshSoup
{
  std::vector<double> Points;          ///< xyz
  std::vector<std::int64_t> Triangles; ///< three point ids each
  std::size_t NumberOfPoints() const { return this->Points.size() / 3; }
  std::size_t NumberOfTriangles() const { return this->Triangles.size() / 3; }
};
vtkEmbeddedRemeshSoup vtkEmbeddedRemeshCollectSurfaces(const std::vector<vtkDataSet*>& surfaces);

/// S's area and its bounding box's diagonal: the job-size estimate's
/// surface terms.
void vtkEmbeddedRemeshSurfaceAreaAndDiagonal(const vtkEmbeddedRemeshSoup& soup, double& area, double& diagonal);

/// Under MPI: rank 0's soup on every rank (nothing in serial). Collective.
void vtkEmbeddedRemeshBroadcast(vtkEmbeddedRemeshSoup& soup);

/// The input's size at S: the median, over the `nQuery` points `query`
/// (S's points; `dim` 2 or 3 coordinates each), of l_v (the longest edge at
/// the node, `lv`) at the node nearest to the point. The nodes are the
/// `nNodes` points `nodes` (`dim` coordinates each) whose `candidate` flag
/// is set (null: all). Under MPI the nearest over all ranks' candidates
/// (collective). Nodes with l_v 0 (in no cell) give no size.
double vtkEmbeddedRemeshInputSizeAt(const double* nodes, vtkIdType nNodes, int dim, const std::vector<double>& lv,
  const std::vector<char>* candidate, const double* query, std::size_t nQuery);

/// S remeshed isotropically at `edge` (ar::RemeshSurfaceIsotropic); when
/// that fails, `self` warns and S is used as it is.
vtkEmbeddedRemeshSoup vtkEmbeddedRemeshRemeshSurface(vtkAlgorithm* self, const vtkEmbeddedRemeshSoup& s, double edge);

/// The core's options from the filter's properties (RemovalFactor,
/// VisibilityTest, BoundaryMargin, FullDomain, the quality bounds and the
/// layers; `edge` for the automatic layer stack). False with `problem`
/// naming a bad layer property.
bool vtkEmbeddedRemeshCavityOptions(
  vtkEmbeddedRemesh* self, double edge, ar::CavityOptions& options, std::string& problem);
bool vtkEmbeddedRemeshCavityOptions(
  vtkEmbeddedRemesh* self, double edge, ar::Cavity2DOptions& options, std::string& problem);

/// The output's cells as a driver adds them, with their Region (0 kept,
/// 1 new cell of the refill, 2 layer cell), Layer (layer cells: k, 0 next to
/// S; others -1) and LayerSide (+1 on S's normal side, -1 on the other;
/// others 0) and the input cell each comes from (-1: new). The volume of the
/// refill's cells (kept and new tetrahedra, prisms, pyramids) is summed for
/// RelativeVolumeChange, in the order the cells are added.
///
/// The cells are collected in the arrays vtkCellArray is made of and handed
/// to the output at once by Commit (vtkCellArray::SetData,
/// vtkUnstructuredGrid::SetCells), not inserted one by one: an output has
/// millions of cells, and InsertNextCell's dispatch per cell was the Output
/// stage's cost. The refill's tetrahedra, the bulk of them, are filled in
/// parallel (vtkSMPTools), each at its fixed place.
class vtkEmbeddedRemeshCells
{
public:
  explicit vtkEmbeddedRemeshCells(vtkUnstructuredGrid* output);
  ~vtkEmbeddedRemeshCells();
  /// Room for `cells` cells of `points` point ids in all, before the first
  /// Add; Commit gives back what was not used.
  void Reserve(std::size_t cells, std::size_t points);
  /// One cell of `n` output point ids `pts`; `source` the input cell it is
  /// a copy of (-1 new).
  /// With `points` (the output's), the cell's volume counts in VolumeAfter.
  void Add(int type, vtkIdType n, const vtkIdType* pts, vtkIdType source, int region, int layer, int side,
    vtkPoints* points = nullptr);
  /// A polyhedron (its face stream in output point ids) kept from `source`.
  void AddPolyhedron(vtkIdType source, vtkIdList* faces);
  /// The tetrahedra of the core's result through `pointOf` (result point ->
  /// output point; null: the same ids). Those whose SourceCell is set are
  /// kept, from input cell (*keptSource)[SourceCell]; with `keptSource`
  /// null only the new ones are added. `points`: the output's coordinates,
  /// for the volumes. `skipKept` (per input tetrahedron of the core, may be
  /// null): kept ones not to add (released layers that come back as cells).
  void AddRefillTetrahedra(const ar::CavityRemesh& result, const std::vector<vtkIdType>* pointOf,
    const std::vector<vtkIdType>* keptSource, vtkPoints* points, const std::vector<char>* skipKept = nullptr);
  /// The result's prisms and pyramids (the layers and their closure).
  void AddRefillLayers(const ar::CavityRemesh& result, const std::vector<vtkIdType>* pointOf, vtkPoints* points);
  /// Makes the cells added so far the output's cells, and Region() ready.
  /// Once, after the last Add and before anything reads the output's cells.
  void Commit();
  /// Adds the Region array, and Layer and LayerSide when `layerArrays`;
  /// after Commit.
  void Finish(bool layerArrays);
  const std::vector<vtkIdType>& Sources() const { return this->Source; }
  vtkIdType NumberOfNew() const { return this->NewCount; }
  vtkIdType NumberOfKept() const { return static_cast<vtkIdType>(this->Source.size()) - this->NewCount; }
  vtkIntArray* Region() const { return this->RegionArray; }
  double VolumeAfter = 0.0;

private:
  double Volume(int type, vtkIdType n, const vtkIdType* pts, const double* X) const;
  vtkIdType AppendCells(vtkIdType count, vtkIdType points);
  vtkUnstructuredGrid* Output;
  // The cells as vtkCellArray and vtkUnstructuredGrid take them, grown as
  // cells come and given to the output by Commit.
  vtkNew<vtkUnsignedCharArray> Types;
  vtkNew<vtkIdTypeArray> Offsets, Connectivity;
  std::vector<vtkIdType> Source;
  std::vector<std::pair<vtkIdType, vtkSmartPointer<vtkIdList>>> Polyhedra; // (cell, face stream)
  vtkNew<vtkIntArray> RegionArray, LayerArray, SideArray;
  vtkIdType NewCount = 0;
};

/// Where the new points and cells of an output take their fields from: each
/// new point located (ARMeshKernels::TetLocator: reproducible) in the
/// tetrahedra the locator was built on, with its barycentric weights, and
/// each new cell's centre walked to from a corner's cell.
struct vtkEmbeddedRemeshNewTuples
{
  std::vector<vtkIdType> Points;  ///< the new output points
  std::vector<vtkIdType> PointIn; ///< the locator's cell holding each
  std::vector<double> Weights;    ///< 4 per new point
  std::vector<vtkIdType> Cells;   ///< the new output cells (source -1)
  std::vector<vtkIdType> CellIn;  ///< the locator's cell holding each one's centre
  /// The new points interpolated in their cells, the new cells copies of
  /// the cell holding their centre (through `cellOf`, locator cell -> source
  /// tuple; null: the same ids).
  void Fill(const vtkARFieldTransfer::TetLocator& locator, vtkARFieldTransfer::TupleSources& points,
    vtkARFieldTransfer::TupleSources& cells, const std::vector<vtkIdType>* cellOf) const;
};
/// `isNew[i]`: output point i needs locating; `startOf[i]`: for a point that
/// does not, a locator cell at it (-1: none) from which its cells' centres
/// are walked; `cellSource`: the output cells' sources (-1: new). The output's
/// point and cell data must be allocated: the new cells are located only when
/// it has cell arrays, the new points only when it has point or cell arrays
/// (Cells and Points stay empty otherwise).
vtkEmbeddedRemeshNewTuples vtkEmbeddedRemeshLocateNew(const vtkARFieldTransfer::TetLocator& locator,
  vtkUnstructuredGrid* output, const std::vector<char>& isNew, const std::vector<vtkIdType>& startOf,
  const std::vector<vtkIdType>& cellSource);

/// The embedded surface (port 1): `triangles` (three result point ids each)
/// through `pointOf` (null: the same ids) on `points`.
void vtkEmbeddedRemeshSetEmbedded(vtkPolyData* embedded, vtkPoints* points, const std::vector<std::int64_t>& triangles,
  const std::vector<vtkIdType>* pointOf);

/// The output's field data: what every driver reports, in one place. The
/// distributed driver fills it with its rank's share and calls Reduce, so
/// every rank writes the same values (equal to the serial run's, apart
/// from the order of MPI's sums: MeanDihedralAngleNew and
/// RelativeVolumeChange to about 1e-15 relative).
struct vtkEmbeddedRemeshSummary
{
  bool TwoDimensional = false;
  double KeptCells = 0.0, NewCells = 0.0;
  double InputNodes = 0.0, OutputNodes = 0.0, NewNodes = 0.0, RemovedNodes = 0.0;
  double SurfaceElements = 0.0;        ///< S's triangles (3-D) or the curve's segments (2-D: SurfaceQuads)
  double SurfaceTrianglesAtLockedCells = 0.0;
  double SurfaceEdgeLength = 0.0, InputSize = 0.0, OutputSize = 0.0;
  double LimitedColumns = 0.0;
  double RefillAttempts = 0.0;
  double RefillPieces = 0.0;           ///< the cavity's pieces refilled side by side (3-D)
  double SeparatorTriangles = 0.0;     ///< the strip cutting the cavity in two for the refill (3-D; 0: none)
  double RemovedLayerCells = 0.0;      ///< prisms and pyramids of earlier layers the cavity took (3-D)
  double MinTriangleAngleNew = 0.0;    ///< 2-D only
  double PatchTrianglesNew = 0.0;      ///< 2-D only
  double VolumeBefore = 0.0, VolumeAfter = 0.0; ///< the areas of the cross-section in 2-D
  vtkEmbeddedRemeshQuality Quality;
  /// Stage timings, wall-clock seconds (the maximum over the ranks).
  std::vector<std::pair<std::string, double>> Seconds;
  /// The core's figures: RemovedNodes, S's triangles (and those dropped at
  /// locked cells), the output's size at S, LimitedColumns, RefillAttempts, RefillPieces
  /// and the core's stage timings.
  void AddRefill(const ar::CavityRemesh& result);
  /// Under MPI: sums of the counts and volumes, the maximum of the sizes
  /// (rank 0 has S) and of the timings, the quality reduced; OutputNodes
  /// from the reduced counts.
  void Reduce();
  /// Writes the field data (and the layer stack's, from `layers`).
  void Write(vtkUnstructuredGrid* output, const ar::PrismLayerOptions& layers) const;
};

/// A stopwatch for the Seconds* field data.
class vtkEmbeddedRemeshLap
{
public:
  double operator()()
  {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - this->Start).count();
    this->Start = now;
    return s;
  }

private:
  std::chrono::steady_clock::time_point Start = std::chrono::steady_clock::now();
};

/// The 3-D drivers' last stages, in their order: the cells committed
/// (SecondsOutput), the fields by `interpolate` when `interpolateFields`
/// (SecondsInterpolation), Region, Layer, LayerSide and the quality arrays
/// (SecondsQuality); the kept and new cell counts into `summary`.
void vtkEmbeddedRemeshCompleteCells(vtkUnstructuredGrid* output, vtkEmbeddedRemeshCells& cells,
  bool interpolateFields, const std::function<void()>& interpolate, vtkEmbeddedRemeshLap& lap,
  vtkEmbeddedRemeshSummary& summary);

#endif
