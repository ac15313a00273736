// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkAdaptToShocks
 * @brief The whole adaptation in one step: a flow solution in, the mesh
 *        adapted to its shocks out (Ito et al., sections 2.2-2.4).
 *
 * Runs, on the solution as a solver wrote it and with their defaults:
 * 1. vtkShockSensor (arrays found by their usual names, VariableSet and R
 *    from the data) for NormalMach;
 * 2. vtkFeatureCluster (NormalMach in [0.8, 1.2]) for the shock clusters and
 *    their medial points;
 * 3. one vtkQuadricFit per cluster whose size is at least
 *    MinimumClusterFraction of the largest cluster's (at most
 *    MaximumNumberOfSurfaces of them, largest first), the template chosen
 *    automatically (plane, cone or quadric) unless SetClusterTemplate names
 *    one, trimmed to the domain, the medial points centred on the shock
 *    (vtkQuadricFit's ShockCentring, the volume as its Domain); then the
 *    pieces of one shock joined: two clusters get one surface when one fit
 *    of both clusters' points has an RMS residual within 1.25 x the worse
 *    piece's + 0.1 edge length (clusters with a template of their own stay
 *    alone); a surface that still crosses a larger one is left out with a
 *    warning;
 * 4. vtkEmbeddedRemesh with every fitted surface (LocalCavity, refined at
 *    the surfaces: SurfaceSizeFactor, or prism layers).
 * The separate filters stay for inspecting and hand-editing each step.
 *
 * Input: a vtkUnstructuredGrid, or a vtkMultiBlockDataSet as ParaView's
 * OpenFOAM reader gives (the "internalMesh" leaf, else the first leaf with
 * 3-D cells, carries the solution; the patch leaves pass through, as
 * EmbeddedRemesh does).
 * Output port 0: the adapted mesh (vtkEmbeddedRemesh's output, its field
 * data, plus NumberOfSurfaces, the string arrays SurfaceTemplates and
 * SurfaceClusters (per surface its clusters, "0" or "0+2+1") and the
 * seconds of each stage: SecondsSensor, SecondsClusters, SecondsFit,
 * SecondsRemesh). Output port 1: all fitted surfaces in one vtkPolyData with
 * the cell array SurfaceId (0, 1, ... in cluster order). Field data
 * NormalFamilies (3 components, one tuple per cluster that gets a surface):
 * the angle in degrees between the two families of its shock normals, their
 * median spread in degrees and the lighter family's weight fraction (the
 * measures of the two-shocks-meet check below).
 *
 * Errors (vtkErrorMacro naming the stage and the cause; the underlying
 * filter's own message comes first; output 0 = the input unchanged, output 1
 * empty): no flow state among the arrays, no shock (no cluster), no surface
 * that could be fitted, a remeshing failure (e.g. two fitted surfaces that
 * cross), bad properties, two shocks that meet in one cluster (an X, a V, a
 * lambda: the shock normals at the cluster's nodes, the gradient of the
 * sensor's pressure or density weighted by its magnitude, form two
 * families at least 10 degrees and 8 times their median spread apart, the
 * lighter with at least 10% of the weight; no single template follows them
 * and EmbeddedRemesh cannot embed surfaces that meet).
 */
#ifndef vtkAdaptToShocks_h
#define vtkAdaptToShocks_h

#include "AdaptiveRedistributionFiltersModule.h" // for export macro
#include "vtkDataObjectAlgorithm.h"

#include <map> // for the per-cluster templates

class ADAPTIVEREDISTRIBUTIONFILTERS_EXPORT vtkAdaptToShocks : public vtkDataObjectAlgorithm
{
public:
  static vtkAdaptToShocks* New();
  vtkTypeMacro(vtkAdaptToShocks, vtkDataObjectAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// ShockSensor: the ratio of specific heats (default 1.4) and the gas
  /// constant (default 0: from the data).
  vtkSetMacro(Gamma, double);
  vtkGetMacro(Gamma, double);
  vtkSetMacro(GasConstant, double);
  vtkGetMacro(GasConstant, double);
  ///@}

  ///@{
  /// FeatureCluster: the NormalMach range (default [0, 0]: automatic,
  /// [0.8, 1.2]) and the smallest cluster kept (nodes, default 10).
  vtkSetVector2Macro(SensorRange, double);
  vtkGetVector2Macro(SensorRange, double);
  vtkSetMacro(MinimumClusterSize, int);
  vtkGetMacro(MinimumClusterSize, int);
  ///@}

  ///@{
  /// Which clusters get a surface: those with at least this fraction of the
  /// largest cluster's nodes (default 0.1; in (0, 1]), at most
  /// MaximumNumberOfSurfaces of them (default 8; at least 1).
  vtkSetMacro(MinimumClusterFraction, double);
  vtkGetMacro(MinimumClusterFraction, double);
  vtkSetMacro(MaximumNumberOfSurfaces, int);
  vtkGetMacro(MaximumNumberOfSurfaces, int);
  ///@}

  ///@{
  /// The template of cluster `cluster`'s surface (vtkQuadricFit::Templates);
  /// clusters not named get AUTOMATIC. Cleared by ClearClusterTemplates.
  void SetClusterTemplate(int cluster, int templ);
  void ClearClusterTemplates();
  ///@}

  ///@{
  /// EmbeddedRemesh: Mode (0 LocalCavity, 1 FullDomain), SurfaceEdgeLength
  /// (0: SurfaceSizeFactor x the input's size at S), SurfaceSizeFactor (0:
  /// automatic), LayerType (0 tetrahedra, 1 prisms), NumberOfLayers,
  /// RemovalFactor, InterpolateFields. Checked by EmbeddedRemesh.
  vtkSetMacro(Mode, int);
  vtkGetMacro(Mode, int);
  vtkSetMacro(SurfaceEdgeLength, double);
  vtkGetMacro(SurfaceEdgeLength, double);
  vtkSetMacro(SurfaceSizeFactor, double);
  vtkGetMacro(SurfaceSizeFactor, double);
  vtkSetMacro(LayerType, int);
  vtkGetMacro(LayerType, int);
  vtkSetMacro(NumberOfLayers, int);
  vtkGetMacro(NumberOfLayers, int);
  /// With LayerType prisms: the stack's height per side. 0 (the default):
  /// a quarter of the captured shock's thickness, so that the two sides
  /// together span half of it, about where the solver puts the shock on the
  /// layers (QuadricFit's ShockThickness, the 10-90 % width of p's rise
  /// along the centring lines; the median over the surfaces, in the output's
  /// field data ShockThickness); where no surface measured it, EmbeddedRemesh's
  /// default (half a surface edge). Checked by EmbeddedRemesh.
  vtkSetMacro(TotalThickness, double);
  vtkGetMacro(TotalThickness, double);
  /// With LayerType prisms: each layer this many times thicker than the one
  /// below it (EmbeddedRemesh's GrowthRatio); default 1, uniform layers,
  /// as the shock spreads over several of them. Checked by EmbeddedRemesh.
  vtkSetMacro(GrowthRatio, double);
  vtkGetMacro(GrowthRatio, double);
  vtkSetMacro(RemovalFactor, double);
  vtkGetMacro(RemovalFactor, double);
  vtkSetMacro(InterpolateFields, bool);
  vtkGetMacro(InterpolateFields, bool);
  ///@}

protected:
  vtkAdaptToShocks();
  ~vtkAdaptToShocks() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestDataObject(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  /// RequestData's work, with vtkSMPTools on threads (vtkARMeshKernels::Threaded).
  int ExecuteData(vtkInformation*, vtkInformationVector**, vtkInformationVector*);

private:
  vtkAdaptToShocks(const vtkAdaptToShocks&) = delete;
  void operator=(const vtkAdaptToShocks&) = delete;

  double Gamma = 1.4;
  double GasConstant = 0.0;
  double SensorRange[2] = { 0.0, 0.0 };
  int MinimumClusterSize = 10;
  double MinimumClusterFraction = 0.1;
  int MaximumNumberOfSurfaces = 8;
  std::map<int, int> ClusterTemplates;
  int Mode = 0;
  double SurfaceEdgeLength = 0.0;
  double SurfaceSizeFactor = 0.0;
  int LayerType = 0;
  int NumberOfLayers = 5;
  double TotalThickness = 0.0;
  double GrowthRatio = 1.0;
  double RemovalFactor = 3.0;
  bool InterpolateFields = true;
};

#endif
