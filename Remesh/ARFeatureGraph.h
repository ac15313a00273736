// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file ARFeatureGraph.h
 * @brief Feature clusters and their medial nodes on a mesh-edge graph (no VTK).
 *
 * Steps 2-5 of the paper's mathematical-representation approach (Ito et al.,
 * section 2.3) on the graph of mesh nodes joined by mesh edges: dilation of
 * the selected nodes, connected clusters, edge distance from the cluster
 * boundary, and its local maxima (the medial nodes).
 */
#ifndef ARFeatureGraph_h
#define ARFeatureGraph_h

#include <cstdint>
#include <vector>

namespace ar
{
struct FeatureGraphInput
{
  const double* Points = nullptr;        ///< x y z per node
  std::size_t NumberOfPoints = 0;
  const std::uint8_t* Seeds = nullptr;   ///< 1 for the nodes selected by the sensor (step 1)
  const std::int64_t* Edges = nullptr;   ///< node pairs; duplicates and either order are fine
  std::size_t NumberOfEdges = 0;
  int DilationRings = 1;                 ///< step 2
  int MinimumClusterSize = 1;            ///< step 3: smaller clusters are dropped
};

struct FeatureGraphResult
{
  std::vector<std::uint8_t> Mask;        ///< 1 for the nodes of kept clusters
  std::vector<int> ClusterId;            ///< 0, 1, ... by decreasing size; -1 outside
  std::vector<int> Distance;             ///< edges from the cluster boundary; -1 outside
  std::vector<std::uint8_t> Medial;      ///< 1 at local maxima of Distance (>= every neighbour)
  std::vector<double> LocalSize;         ///< longest edge at each node (0 if it has none)
  std::vector<std::int64_t> ClusterSizes;
};

/**
 * Runs steps 2-5. Clusters are numbered by decreasing size, ties broken by
 * the lexicographically smallest node position, so that the numbering depends
 * on the geometry only (not on node order, hence not on MPI partitioning).
 */
FeatureGraphResult ClusterFeatures(const FeatureGraphInput& input);
}

#endif
