// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkEmbeddedRemesh
 * @brief Remeshes a volume mesh around feature surfaces so that they become
 *        faces of the new mesh (paper section 2.4).
 *
 * Input port 0: the volume mesh V (vtkUnstructuredGrid; tetrahedra are
 * remeshed, other 3-D cells are kept as they are and their nodes never
 * move, except prism layers floating inside the mesh, an earlier
 * adaptation's, which the cavity may take a layer at a time
 * (Remesh/ARLayerRelease.h, field data RemovedLayerCells; serial only);
 * triangles, quads and polygons, e.g. boundary-patch faces with a
 * PatchId, are kept too), or a vtkMultiBlockDataSet as ParaView's OpenFOAM
 * reader gives (the "internalMesh" leaf, else the first leaf with 3-D cells,
 * is remeshed; the patch leaves pass through: the boundary does not change,
 * so they still fit the new volume exactly). Input port 1: one or more feature surfaces S (QuadricFit,
 * MedialAxisDelaunay, a hand-edited surface, any polydata; several
 * connections are merged).
 *
 * 1. S is remeshed to nearly equilateral triangles of SurfaceEdgeLength
 *    (CGAL isotropic remeshing). 0 (the default) sets it relative to the
 *    input's local size at S, the paper's clustering: SurfaceSizeFactor
 *    times h_S, the median over S's points of the longest edge of V at the
 *    nearest node of V (the paper's l); the automatic factor is 0.21 for
 *    tetrahedra (0.2 in 2-D) and 1 with prism layers (which refine across
 *    S). A factor below 1 refines across the feature; the refill grades the
 *    size back to the input's through the cavity, whose radius
 *    RemovalFactor * max(l_si, l_vj) follows the input's size, so it holds
 *    the grading. In 3-D the refill is given free points a regular
 *    tetrahedron's height off S on both sides (with prism layers off the
 *    stack's caps; ar::CavityOptions::OffsetPointSpacing), so that the
 *    cells on S are as fine across it as along it and no sliver of four
 *    points of a curved S or cap is left against it.
 * 2. LOCAL_CAVITY (default): a node V_j is removed if it lies within
 *    RemovalFactor * max(l_si, l_vj) of a node S_i and, with VisibilityTest,
 *    no boundary face of V lies between them. The tetrahedra touching removed
 *    nodes form the cavity; its boundary (faces shared with kept cells and
 *    faces on V's boundary) is kept exactly and the cavity is refilled by
 *    TetGen with S embedded as internal faces, a quality bound
 *    (MaxRadiusEdgeRatio, MinDihedralAngle) and a size field graded from S's
 *    edge length to the cavity boundary's. FULL_DOMAIN remeshes every
 *    tetrahedron the same way. Where S reaches V's boundary it is trimmed
 *    back by BoundaryMargin of its edge length: V's boundary faces, and so
 *    its patches, stay bit for bit (cutting S at the boundary would
 *    retriangulate boundary faces). A hybrid V (e.g. near-wall prism or
 *    hexahedron layers of a viscous mesh, pyramids, tetrahedra elsewhere;
 *    the paper's Fig. 4) keeps every non-tetrahedral 3-D cell bit for bit;
 *    S is trimmed the same way at the region of those cells (dropped inside
 *    it and within BoundaryMargin of its faces) and the rest of the cavity
 *    is refilled with tetrahedra.
 * 3. With InterpolateFields (default on) the point and cell arrays of V are
 *    carried over: kept points and cells copy theirs exactly; new points
 *    interpolate in the input cell that contains them; new cells take the
 *    cell values of the input cell that contains their centroid.
 *
 * Output port 0: the new vtkUnstructuredGrid with cell arrays `Region` (0
 * kept, 1 new), `MinDihedralAngle` and `MaxDihedralAngle` (degrees) and
 * `AspectRatio` (longest / shortest edge) for tetrahedra, pyramids, wedges,
 * hexahedra and voxels (ar::ComputeCellQuality; -1 for 2-D cells and
 * polyhedra); field data `KeptCells`, `NewCells`, `RemovedNodes`,
 * `SurfaceTriangles`, `SurfaceTrianglesAtLockedCells` (S triangles dropped
 * at the kept non-tetrahedral cells), `SurfaceEdgeLength`,
 * `InputSizeAtSurface` (h_S), `OutputSizeAtSurface` (the median longest
 * edge of the output at S's nodes, the same measure), `SurfaceSizeRatio`
 * (their ratio: how fine the new cells at S are relative to the input's),
 * `SurfaceSizeFactor` (S's edge length over `InputSizeAtSurface`),
 * `InputNodes`, `OutputNodes`, `NewNodes`,
 * `MinDihedralAngleNew`, `MeanDihedralAngleNew` (of the cells' smallest
 * angles), `MaxAspectRatioNew`, `MaxAspectRatioLayerCells` (the kept
 * non-tetrahedral cells, thin by design), `NonPositiveJacobianCells` (cells
 * with a corner Jacobian <= 0; 0 for a valid mesh), `RelativeVolumeChange`,
 * and the explicit time step the new cells allow: `StepLengthNew` and
 * `StepLengthLayerCells` (the smallest 2V / sum of face areas,
 * ar::CellStepLength, of the new and of the new layer cells; the front and
 * back faces left out in 2-D), `StepLengthRatioNew` (over the regular
 * tetrahedron's at S's edge; 2-D: the equilateral triangle's) and
 * `StepLengthRatioLayerCells` (over the right prism one first layer high).
 * Without layers the 3-D refill moves its points at tetrahedra under half
 * the regular tetrahedron's step (ar::CavityOptions::MinStepLength).
 * Output port 1: the embedded surface (the faces of the new mesh that lie on
 * S) as vtkPolyData.
 *
 * 2-D mode (TwoDimensional = AUTO, the default, and a one-cell-deep mesh as
 * OpenFOAM's 2-D cases have: every point on one of two parallel planes
 * normal to a coordinate axis, every 3-D cell a hexahedron or wedge spanning
 * both with its depth edges along the axis). Tetrahedralizing such a mesh is
 * of no use to a 2-D solver, so the cross-section is remeshed instead and
 * extruded back: the feature surfaces are cut with the mid-depth plane
 * (vtkCutter, vtkStripper) into curves, resampled at SurfaceEdgeLength
 * (vtkSplineFilter; 0 = the median longest 2-D edge at the mesh node nearest
 * to the curve), and ar::RemeshLocalCavity2D removes the nodes near the
 * curves on the front plane (the same rule; all cells touching them go) and
 * refills the cavity with CGAL's constrained Delaunay mesher, the curves as
 * edges, new triangles at least MinTriangleAngle where the refinement can
 * reach it (cavity-boundary edges are never split; FULL_DOMAIN remeshes the
 * whole cross-section, the domain boundary kept). Each new triangle
 * becomes a VTK_WEDGE between the planes, new points come in front/back
 * pairs, kept cells keep their points and node order. Output port 1 holds
 * the embedded surface as quads (the extruded curve segments), each a face
 * of the output mesh. MinDihedralAngle is also given for wedges (a right
 * prism: the smaller of its triangle's smallest angle and 90 degrees).
 * Boundary-patch faces on the two planes (2-D cells of the grid, or
 * multiblock patch leaves such as OpenFOAM's frontAndBack/empty patches) are
 * rebuilt: the faces of kept cells stay, those of removed cells go and each
 * new wedge adds its front and back triangles to the patch that held the
 * face of the input cell containing it (with that face's cell values); all
 * other patches pass through. Field data adds TwoDimensional (1; 0 in 3-D
 * mode), InputNodes, OutputNodes, NewNodes, SurfaceQuads and
 * MinTriangleAngleNew; the node counts are 3-D points (front and back).
 * With LayerType PRISMS the 2-D mode builds layers of quads on both sides
 * of the curves (ar::RemeshLocalCavity2D's Layers: the same layer options
 * and stack rule as in 3-D, the stack tapered to 0 at a curve's ends, whose
 * segments get triangles), extruded into VTK_HEXAHEDRON (the end triangles
 * into VTK_WEDGE); Region 2, Layer and LayerSide as in 3-D, field data
 * LayerHexahedra, Prisms (the end wedges), LayerCells, LimitedColumns,
 * LayerStackHeight, FirstLayerThicknessUsed, MaxAspectRatioLayerCells; the
 * hexahedra's quads join the rebuilt front and back patches.
 * The 2-D mode runs on one rank only (refused under MPI).
 *
 * Field data in both modes: InputNodes, OutputNodes, NewNodes (points of
 * the input, of the output, and new ones; RemovedNodes = the input points
 * that are gone), TwoDimensional.
 *
 * Prism layers (LayerType = PRISMS; 3-D here, 2-D above; under MPI equal to the serial run): ar::BuildPrismLayers
 * extrudes NumberOfLayers layers of VTK_WEDGE on each side of the remeshed
 * S along smoothed normals (layer k FirstLayerThickness * GrowthRatio^k, or
 * TotalThickness per side), closes the stack at S's border with VTK_PYRAMID
 * cells and thin closure tetrahedra, and TetGen fills the void between the
 * cavity boundary and the stack's outer surface. The removal radius grows
 * by the stack height and S is trimmed one more edge back. Cell arrays
 * Region (0 kept, 1 new tetrahedron, 2 layer cell), Layer and LayerSide;
 * field data Prisms, Pyramids, LayerClosureTetrahedra, LimitedColumns,
 * LayerStackHeight, FirstLayerThicknessUsed, MaxAspectRatioLayerCells,
 * MinDihedralAngleLayerCells, SecondsLayers. Port 1 is S, the faces
 * between the two sides' innermost prisms.
 *
 * Bad input (no tetrahedra, inverted cells, non-finite points, an empty S,
 * S outside V, S crossing itself or another S, S too close to kept cells, a
 * TetGen failure) gives an error naming the problem and passes V through
 * unchanged.
 *
 * MPI (more than one rank; LocalCavity only): the result equals the serial
 * run's. The distributed volume should carry one level of ghost cells
 * (vtkGhostCellsGenerator): they complete l_v at the nodes of a rank's own
 * cells. The feature surfaces are gathered to rank 0, remeshed there and
 * broadcast; the domain boundary (owned faces with no neighbour) is
 * all-gathered. Each rank computes the removal flags at its nodes
 * (ar::ComputeRemovedNodes, the global boundary given); the cavity is its
 * owned tetrahedra at removed nodes. The cavity and three node rings of kept
 * cells around it (matched across ranks by coordinates; enough for the
 * refill to grow the cavity twice at forced slivers) go to rank 0, which
 * refills the given cavity (ar::RemeshLocalCavity with CavityCells) and
 * interpolates the new points' fields in the gathered cells. Rank 0 outputs
 * its kept cells and all new cells; every other rank outputs its own kept
 * cells, so the far field never moves. Field data (counts, angles, volume
 * change) is reduced and equal on every rank; output port 1 (the embedded
 * surface) is on rank 0. Under MPI the volume must be tetrahedral (hybrid
 * meshes and 2-D patch cells are refused with an error: run them on one
 * rank), FullDomain gathers the whole mesh to rank 0 (TetGen is serial;
 * rank 0 ends with every cell), and a
 * multiblock input must hold the volume leaf on every rank (else refused).
 */
#ifndef vtkEmbeddedRemesh_h
#define vtkEmbeddedRemesh_h

#include "AdaptiveRedistributionFiltersModule.h" // for export macro
#include "vtkDataObjectAlgorithm.h"

#include <vector> // for the surfaces

class vtkDataSet;
class vtkPolyData;
class vtkUnstructuredGrid;
struct vtkEmbeddedRemeshLayout; // 2-D mode: the two planes and the cells' faces on them
struct vtkEmbeddedRemeshPlanes; // 2-D mode: what rebuilding the patch leaves needs

class ADAPTIVEREDISTRIBUTIONFILTERS_EXPORT vtkEmbeddedRemesh : public vtkDataObjectAlgorithm
{
public:
  static vtkEmbeddedRemesh* New();
  vtkTypeMacro(vtkEmbeddedRemesh, vtkDataObjectAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Modes
  {
    LOCAL_CAVITY = 0,
    FULL_DOMAIN = 1
  };

  enum LayerTypes
  {
    TETRAHEDRA = 0, ///< the cavity is refilled with tetrahedra only
    PRISMS = 1      ///< prism layers on both sides of S, tetrahedra around them
  };

  enum TwoDimensionalModes
  {
    TWO_DIMENSIONAL_AUTO = 0, ///< a one-cell-deep mesh is remeshed as 2-D
    TWO_DIMENSIONAL_OFF = 1   ///< always the 3-D (tetrahedral) path
  };

  /// The volume that carries the mesh: the grid itself, or a multiblock's
  /// "internalMesh" leaf, else its first unstructured grid with 3-D cells
  /// (ParaView's OpenFOAM reader); nullptr when there is none.
  static vtkUnstructuredGrid* VolumeLeaf(vtkDataObject* data);

  /// RequestDataObject of a filter shaped as this one (also AdaptToShocks):
  /// output 0 of the input's kind (an unstructured grid or a multiblock),
  /// output 1 a vtkPolyData.
  static int MeshAndSurfaceDataObjects(vtkInformationVector** inputVector, vtkInformationVector* outputVector);

  /// Add a feature surface (input port 1).
  void AddSurfaceConnection(vtkAlgorithmOutput* output) { this->AddInputConnection(1, output); }
  void AddSurfaceData(vtkDataObject* data) { this->AddInputData(1, data); }
  void RemoveAllSurfaces() { this->RemoveAllInputConnections(1); }

  /// The properties below are not clamped: a value out of its range (given in
  /// the XML's documentation and domains) is refused by RequestData with an
  /// error naming the property, its value and the range, the input passed
  /// through. So is a SurfaceEdgeLength (or SurfaceSizeFactor) whose job
  /// would not fit in memory: the surface triangles (S's area over the edge
  /// length squared) and the refill's cells (the cavity's volume over the
  /// cell size cubed, graded from S's edge to the input's size) are estimated
  /// before anything is meshed and compared with
  /// vtkARInputChecks::MaximumElements() (half the machine's memory).
  vtkSetMacro(Mode, int);
  vtkGetMacro(Mode, int);
  vtkSetMacro(SurfaceEdgeLength, double);
  vtkGetMacro(SurfaceEdgeLength, double);
  /// With SurfaceEdgeLength 0: S's edge length in units of the input's local
  /// size at S. 0 (the default) is automatic: with tetrahedra 0.21 in 3-D
  /// and 0.2 in 2-D (the new cells at S at least 3x finer than the input's,
  /// measured by SurfaceSizeRatio: 0.27-0.31 on the eight 3-D OpenFOAM
  /// solutions of the validation matrix, 0.26 on the 2-D ones), 1 with prism
  /// layers (the layers refine across S; along it the input's size is kept,
  /// the paper's anisotropic cells). Not clamped: outside [0, 10] it is
  /// refused with an error naming it.
  vtkSetMacro(SurfaceSizeFactor, double);
  vtkGetMacro(SurfaceSizeFactor, double);
  /// The factor a run uses: SurfaceSizeFactor, or the automatic one (for a
  /// one-cell-deep input, which is remeshed in 2-D, `twoDimensional`).
  double GetSurfaceSizeFactorUsed(bool twoDimensional = false) const;
  vtkSetMacro(RemovalFactor, double);
  vtkGetMacro(RemovalFactor, double);
  vtkSetMacro(VisibilityTest, bool);
  vtkGetMacro(VisibilityTest, bool);
  vtkBooleanMacro(VisibilityTest, bool);
  vtkSetMacro(BoundaryMargin, double);
  vtkGetMacro(BoundaryMargin, double);
  vtkSetMacro(MaxRadiusEdgeRatio, double);
  vtkGetMacro(MaxRadiusEdgeRatio, double);
  vtkSetMacro(MinDihedralAngle, double);
  vtkGetMacro(MinDihedralAngle, double);
  vtkSetMacro(TwoDimensional, int);
  vtkGetMacro(TwoDimensional, int);
  /// 2-D mode: the angle (degrees) the new triangles are refined to reach.
  vtkSetMacro(MinTriangleAngle, double);
  vtkGetMacro(MinTriangleAngle, double);
  /// Tetrahedra (default) or Prisms: NumberOfLayers prism layers on each
  /// side of S (ar::BuildPrismLayers), layer k FirstLayerThickness *
  /// GrowthRatio^k thick, or TotalThickness per side when that is > 0;
  /// FirstLayerThickness 0 makes each side's stack half a surface edge high. Not
  /// clamped: out-of-range values are refused with an error naming them.
  vtkSetMacro(LayerType, int);
  vtkGetMacro(LayerType, int);
  vtkSetMacro(NumberOfLayers, int);
  vtkGetMacro(NumberOfLayers, int);
  vtkSetMacro(FirstLayerThickness, double);
  vtkGetMacro(FirstLayerThickness, double);
  vtkSetMacro(GrowthRatio, double);
  vtkGetMacro(GrowthRatio, double);
  vtkSetMacro(TotalThickness, double);
  vtkGetMacro(TotalThickness, double);
  vtkSetMacro(InterpolateFields, bool);
  vtkGetMacro(InterpolateFields, bool);
  vtkBooleanMacro(InterpolateFields, bool);

protected:
  vtkEmbeddedRemesh();
  ~vtkEmbeddedRemesh() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestDataObject(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  /// RequestData's work, with vtkSMPTools on threads (vtkARMeshKernels::Threaded).
  int ExecuteData(vtkInformation*, vtkInformationVector**, vtkInformationVector*);

  /// The remeshing of one volume mesh (the whole input, or a multiblock's
  /// volume leaf). In 2-D mode, `planes` (when given) receives what the
  /// multiblock's patch leaves need to be rebuilt.
  int RemeshVolume(vtkUnstructuredGrid* input, const std::vector<vtkDataSet*>& surfaces,
    vtkUnstructuredGrid* output, vtkPolyData* embedded, vtkEmbeddedRemeshPlanes* planes = nullptr);
  /// The 2-D mode (a one-cell-deep mesh, `layout` from its detection).
  int Remesh2D(vtkUnstructuredGrid* input, const vtkEmbeddedRemeshLayout& layout,
    const std::vector<vtkDataSet*>& surfaces, vtkUnstructuredGrid* output, vtkPolyData* embedded,
    vtkEmbeddedRemeshPlanes* planes);
  /// The LocalCavity remesh of a distributed volume (MPI, more than one
  /// rank): the cavity is gathered to rank 0, the far field stays. Collective.
  int RemeshDistributed(vtkUnstructuredGrid* input, const std::vector<vtkDataSet*>& surfaces,
    vtkUnstructuredGrid* output, vtkPolyData* embedded);

private:
  vtkEmbeddedRemesh(const vtkEmbeddedRemesh&) = delete;
  void operator=(const vtkEmbeddedRemesh&) = delete;

  int Mode = LOCAL_CAVITY;
  int LayerType = TETRAHEDRA;
  int NumberOfLayers = 5;
  double FirstLayerThickness = 0.0;
  double GrowthRatio = 1.2;
  double TotalThickness = 0.0;
  double SurfaceEdgeLength = 0.0;
  double SurfaceSizeFactor = 0.0;
  double RemovalFactor = 3.0;
  bool VisibilityTest = true;
  double BoundaryMargin = 1.0;
  double MaxRadiusEdgeRatio = 1.414;
  double MinDihedralAngle = 12.0;
  int TwoDimensional = TWO_DIMENSIONAL_AUTO;
  double MinTriangleAngle = 20.0;
  bool InterpolateFields = true;
};

#endif
