// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class vtkFeatureCluster
 * @brief Feature regions as clusters of mesh nodes and their medial points (Ito et al., section 2.3).
 *
 * The paper's steps 1-5 of the mathematical-representation approach:
 * 1. select the mesh nodes whose sensor value lies in SensorRange (a point
 *    array, or a cell array: the nodes of the cells in range);
 * 2. add their neighbours, DilationRings rings of them (one ring = the nodes
 *    joined to a selected node by a mesh edge), to remove truncation noise;
 * 3. label the connected clusters of selected nodes (connected by mesh
 *    edges), drop those with fewer than MinimumClusterSize nodes, and number
 *    the rest 0, 1, ... by decreasing size (ties: by the smallest coordinate);
 * 4. compute at each selected node its distance, in edges, from the cluster
 *    boundary (the selected nodes with an unselected neighbour; distance 0);
 * 5. mark the local maxima of that distance: the medial points.
 *
 * Plateaus: a node is a local maximum when its distance is >= that of every
 * selected neighbour (not strictly greater). A band of even thickness has two
 * middle layers of equal distance; both are kept, so the medial layer is never
 * lost, and the two layers straddle the mid-surface symmetrically, which is
 * what a least-squares fit of the medial points (vtkQuadricFit) wants. A
 * cluster only one node thick has every node at distance 0: all are medial.
 *
 * The sensor array defaults to "(automatic)" (NormalMach, else
 * WeightFunction) and SensorRange to the range that suits it, so the filter
 * works as it stands after either sensor; the field data SensorArrayUsed and
 * SensorRangeUsed (both ports) say what was taken.
 *
 * Output port 0: the input, shallow-copied, with point arrays FeatureMask
 * (1 for nodes of kept clusters), ClusterId (-1 outside), BoundaryDistance
 * (-1 outside) and MedialPoint (1 at medial points).
 * Output port 1: the medial points as vertices (vtkPolyData) with point
 * arrays ClusterId, LocalSize (l_j: the longest mesh edge at node j),
 * Weight (1 / l_j, the weight of Eq. 4) and BoundaryDistance; field data
 * ClusterSizes (nodes per cluster).
 *
 * Which sensor: W (vtkWeightFunction) is largest where |q| is smallest, so
 * its band sits on the upstream side of a captured shock, about a cell off
 * its centre; a NormalMach band around 1 (e.g. [0.8, 1.2]) is centred on it.
 *
 * Mesh edges are the edges of the cells (the edge tables of tetrahedra,
 * pyramids, wedges, hexahedra, voxels, prisms; the face edges of polyhedra).
 *
 * Under MPI the feature region (the cells within DilationRings + 1 rings of
 * the initially selected nodes; DilationRings + 1 ghost levels are requested)
 * is small: each rank sends its part to rank 0, which merges the nodes by
 * position, runs steps 2-5 on the whole region and sends every rank the
 * results for its nodes. Cluster ids and distances are therefore global and
 * identical to the serial run; port 1 is produced on rank 0 (empty elsewhere).
 *
 * Errors (port 0 passes the input through, port 1 empty): a missing or
 * multi-component sensor array, NaN/Inf in it, an empty mesh, no 3-D cells,
 * an empty range (lo > hi). No node in range is a warning with empty results.
 *
 * @sa vtkWeightFunction vtkShockSensor vtkQuadricFit
 */
#ifndef vtkFeatureCluster_h
#define vtkFeatureCluster_h

#include "AdaptiveRedistributionFiltersModule.h" // for export macro
#include "vtkARVolumeFilter.h"

class ADAPTIVEREDISTRIBUTIONFILTERS_EXPORT vtkFeatureCluster : public vtkARVolumeFilter
{
public:
  static vtkFeatureCluster* New();
  vtkTypeMacro(vtkFeatureCluster, vtkARVolumeFilter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Closed range of sensor values that selects a node. Default [0, 0]:
  /// automatic, the range that suits the sensor: [0.8, 1.2] for NormalMach
  /// (ShockSensor: the band around Mn = 1 marks the centre of a captured
  /// shock), [1.5, 2] for WeightFunction (its strong features). Another
  /// array needs an explicit range (an error says so).
  vtkSetVector2Macro(SensorRange, double);
  vtkGetVector2Macro(SensorRange, double);
  ///@}

  /// The sensor array name that is resolved by the filter (the default of
  /// input array 0): NormalMach if the input has it (ShockSensor upstream),
  /// else WeightFunction (WeightFunction upstream), points first.
  static constexpr const char* AutomaticArrayName = "(automatic)";

  ///@{
  /// Rings of neighbours added to the selection (step 2), 0 to 16. Default 1.
  /// Not clamped: a value outside is refused with an error naming it.
  vtkSetMacro(DilationRings, int);
  vtkGetMacro(DilationRings, int);
  ///@}

  ///@{
  /// Clusters with fewer nodes are dropped. At least 1 (refused otherwise,
  /// not clamped). Default 10.
  vtkSetMacro(MinimumClusterSize, int);
  vtkGetMacro(MinimumClusterSize, int);
  ///@}

protected:
  vtkFeatureCluster();
  ~vtkFeatureCluster() override = default;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  /// DilationRings + 1: the region around a node on a partition boundary
  /// reaches that far into the neighbouring partition.
  int GetExtraGhostLevels() override { return this->DilationRings + 1; }
  int Execute(Execution& run) override;

private:
  vtkFeatureCluster(const vtkFeatureCluster&) = delete;
  void operator=(const vtkFeatureCluster&) = delete;

  ///@{
  /// The passes of Execute, in order, over the state of one execution
  /// (ClusterState, in the .cxx).
  struct ClusterState;
  void FindSensor(Execution& run, ClusterState& st);
  void SelectSeeds(Execution& run, ClusterState& st);
  void GrowRegion(Execution& run, ClusterState& st);
  void GatherRegions(Execution& run, ClusterState& st);
  void ClusterOnRoot(Execution& run, ClusterState& st);
  void WriteOutputs(Execution& run, ClusterState& st);
  ///@}

  double SensorRange[2] = { 0.0, 0.0 };
  int DilationRings = 1;
  int MinimumClusterSize = 10;
};

#endif
