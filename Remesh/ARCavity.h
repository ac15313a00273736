// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file ARCavity.h
 * @brief LocalCavity remeshing (paper section 2.4): remove the nodes of a
 *        tetrahedral mesh V near an embedded surface S and refill the void
 *        with TetGen, S embedded as internal faces.
 *
 * A node V_j is removed when it lies within RemovalFactor * max(l_si, l_vj)
 * of a node S_i (l = the longest edge at the node) and is visible from S_i:
 * the segment S_i V_j crosses no boundary face of V (CGAL AABB tree). The
 * tetrahedra touching removed nodes form the cavity. Its boundary, the faces
 * it shares with kept tetrahedra and its faces on V's boundary, is kept
 * exactly (TetGen -Y): the kept cells, the domain boundary and therefore the
 * boundary patches do not change. Nodes on V's boundary stay (their faces
 * are kept); only interior nodes vanish.
 *
 * Where S reaches V's boundary, or the region of locked non-tetrahedral
 * cells of a hybrid mesh (CavityOptions::LockedCellFaces, e.g. near-wall
 * layers, the paper's Fig. 4), it is trimmed back, not cut there:
 * S triangles with a node closer than BoundaryMargin * l_si to V's boundary
 * (or to the locked region) are dropped, and so is S outside V (or inside the
 * locked region). Cutting S exactly at the boundary would retriangulate
 * boundary faces and move patch edges; the trim keeps every boundary face of
 * V, and every locked cell, bit for bit, at the price of a gap of about one S
 * edge between S and the boundary. (V holds only the tetrahedra, so the faces
 * between them and the locked cells are part of V's boundary as well; the
 * explicit locked region also holds where BoundaryTriangles replaces V's
 * boundary by the domain's.)
 *
 * The refill: TetGen on the cavity boundary plus S (internal facets, marker
 * 2) and free points off S on both sides, or off the layer stack's caps
 * (OffsetPointSpacing), with quality switches and a size field: l_v at the
 * cavity's boundary nodes, S's edge length at S's nodes and at the free
 * points. A hole point in each kept region next to the cavity stops TetGen
 * from filling kept space. The refill's input is put in a canonical order
 * (cavity-boundary nodes sorted by coordinates, mean edge lengths summed
 * exactly), so the same cavity gives the same refill whatever the numbering
 * of V: this is what lets a distributed run, which gathers the cavity to one
 * rank, equal the serial one.
 */
#ifndef ARCavity_h
#define ARCavity_h

#include "ARPrismLayers.h"
#include "ARTetGen.h"
#include "ARTetMesh.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ar
{
struct CavityOptions
{
  double RemovalFactor = 3.0;   ///< radius of removal in max(l_si, l_vj)
  bool VisibilityTest = true;   ///< a boundary face between S_i and V_j keeps V_j
  double BoundaryMargin = 1.0;  ///< S trimmed this many l_si away from V's boundary (one more with prism layers)
  /// TetGen's quality: -q1.414/12 and -o/140, its optimization flipping and
  /// smoothing away every tetrahedron with a dihedral angle over 140 degrees
  /// (slivers have one near 180). At -o/150 the validation cases' refills
  /// kept new tetrahedra at 9.8-12.7 degrees, at -o/140 13.4-15.1, in the
  /// same time (TetGen's own statistics on the five 3-D cases' refills).
  TetGenOptions Quality{ 1.414, 12.0, 0.0, true, 0, 140.0 };
  /// Remove every node: the whole domain is remeshed with S embedded
  /// (FullDomain mode); the domain boundary is still kept exactly.
  bool FullDomain = false;
  /// Per node of V, nonzero where the node must stay (e.g. the nodes of
  /// non-tetrahedral cells of a hybrid mesh, which are kept uncut): it is
  /// never removed and is in the output (CavityRemesh::SourcePoint) even
  /// where no tetrahedron uses it. Empty: none.
  std::vector<std::uint8_t> LockedNodes;
  /// The faces of the locked cells of a hybrid mesh (e.g. near-wall prism
  /// or hexahedron layers, which are kept uncut and are not in V): per face
  /// its number of nodes, then its node ids in V (a polygon, either
  /// orientation), every face of every locked cell (a face between two
  /// locked cells comes twice; the faces listed once bound the locked
  /// region). S is trimmed at that region as at V's boundary: S triangles
  /// with a node inside it or closer than BoundaryMargin * l_si to it, or
  /// crossing it, are dropped. Empty: none (no cost).
  std::vector<std::int64_t> LockedCellFaces;
  /// The domain boundary as triangles (9 coordinates each), used for
  /// trimming S and for the visibility test instead of V's own boundary
  /// faces. For a V that is one rank's piece (or a gathered part) of a
  /// distributed mesh: pass the boundary of the whole domain. Empty: V's.
  std::vector<double> BoundaryTriangles;
  /// Per tetrahedron of V, nonzero where it belongs to the cavity: the
  /// removal step is skipped and this cavity is refilled (it may still grow
  /// at forced slivers). Empty: the cavity comes from the removal test.
  std::vector<std::uint8_t> CavityCells;
  /// Per tetrahedron of V, a group id (>= 0), or -1: the tetrahedra of one
  /// group are removed together or kept together. For the tetrahedra a
  /// caller split a kept cell into (e.g. the prism layers of an earlier
  /// adaptation, split so that the new cavity may take them), which must
  /// either go whole or come back as the cell. The cavity, from the removal
  /// test, the given CavityCells or the growth at slivers, takes every group
  /// it touches. Empty: none.
  std::vector<std::int64_t> CellGroups;
  /// When not empty: the refill's complex is also written as TetGen input
  /// files under this prefix (see WriteTetGenFiles), the last attempt's.
  std::string RefillFilesPrefix;
  /// l_v, the longest edge at each node of V, when the caller has it
  /// already (LongestEdgeAtNodes of V's points and tetrahedra; one value per
  /// node): not computed again. Empty (or another size): computed here.
  std::vector<double> LongestEdges;
  /// Threads for the trim's and the removal's searches (per S point, per
  /// node of V: each its own result), and TetGen processes run at once for
  /// the refill, which is refilled in pieces, the regions its boundary and S
  /// separate (ARTetGenPieces.h), side by side. The output is the same with
  /// any number. 0: the hardware's.
  int Threads = 0;
  /// New tetrahedra whose explicit step length 2V / (sum of face areas)
  /// (ar::CellStepLength) is below this have their refill points moved as
  /// slivers' are (SmoothFreePointsAtSlivers' minStep): an explicit solver's
  /// global time step follows the mesh's smallest cell, so a stray small one
  /// costs every step. 0: off (the angles alone).
  double MinStepLength = 0.0;
  /// A cavity of at least this many tetrahedra, refilled without layers, is
  /// cut in two by a strip from S's border to its boundary
  /// (ARCavitySeparator.h; marker 5 in the refill's complex), so that its
  /// two halves are refilled side by side (one after the other with one
  /// thread: the output does not depend on Threads): a cavity around one
  /// shock is otherwise one piece. Smaller cavities are refilled whole (the
  /// second process does not pay for itself there).
  std::size_t SplitRefillAbove = 200000;
  /// Free points given to TetGen on both sides of S (with prism layers:
  /// outside the stack's caps, see below), a regular tetrahedron's height
  /// (sqrt(2/3) of the triangle's mean edge h) above the triangles'
  /// centroids, kept in triangle order where no earlier one is within this
  /// many mean edges, no other face of the complex meets a box of half-width
  /// h about it (the box holds the segment out from the centroid) and no
  /// triangle of S (of the caps) one of half-width 0.55 h (a plane at
  /// distance h does not: 0.55 sqrt(3) < 1). TetGen's size is the radius of a
  /// ball around each point that no new point may enter, so on its own it
  /// places the first points off S 1.1-1.7 of S's edges away: the cells
  /// across S (across the shock) were coarser than along it. With these
  /// points the tetrahedra on S are about regular (the longest edge at S's
  /// nodes 1.3-1.5 of the edge instead of 1.6-1.7). With layers the caps are
  /// curved like S (a cone's inner side is a bowl seen from the void) and
  /// TetGen, which may not split them (-Y), filled the space between a
  /// concave cap and its chords with slivers of four cap points (3.9 degrees
  /// on a cone sector with 8 layers); the points off the caps give it the
  /// tetrahedra on them instead (2-4 % more nodes on the validation cones).
  /// 0: off.
  double OffsetPointSpacing = 0.9;
  /// Prism layers on both sides of S (ARPrismLayers.h); NumberOfLayers = 0
  /// (the default) leaves them off and the refill is tetrahedra only. When on:
  ///  - the removal radius grows by the stack's height z_N: V_j goes when it
  ///    lies within RemovalFactor * max(l_si, l_vj) + z_N of a visible S_i;
  ///  - S (after the trim, with pinched points cleared: at a point where
  ///    S's triangles form several fans only the largest fan stays, and
  ///    with the pieces that have no interior point dropped, apart from the
  ///    largest piece: a stack on a strip or a lone triangle cut off by the
  ///    trim is closure all round and cramps TetGen beside the next piece's
  ///    closure) gets the layer stack, built against the cavity's boundary
  ///    as obstacles;
  ///  - TetGen fills the void between the cavity's boundary and the stack's
  ///    outer surface (its triangles kept exactly, marker 4, a hole point
  ///    inside the stack, the size at the stack's outer nodes = S's edge
  ///    length there); S itself is not given to TetGen.
  PrismLayerOptions Layers;
};

struct CavityRemesh
{
  TetMesh Mesh;                          ///< kept points (input order) then new ones; kept tets then new ones
  std::vector<std::int64_t> SourcePoint; ///< per output point: input point id, or -1 (new)
  std::vector<std::int64_t> SourceCell;  ///< per output tet: input tet id (kept), or -1 (new)
  std::vector<std::int64_t> Surface;     ///< the embedded S triangles, output point ids (with layers: the faces between the two sides' innermost prisms)
  std::size_t RemovedNodes = 0;          ///< interior nodes of V removed
  std::size_t RemovedCells = 0;          ///< tetrahedra of V in the cavity
  std::size_t SurfaceTrianglesUsed = 0;  ///< S triangles left after the trim
  /// Wall-clock seconds of the stages: the sizes and face adjacency of V
  /// (Setup), S's trim and the removal test with visibility (Removal), the
  /// cavity and its boundary complex (Cavity), TetGen (Refill, all
  /// attempts), the prism-layer extrusion (Layers, all attempts), the
  /// assembly of the output (Assembly).
  struct StageTimes
  {
    double Setup = 0.0, Removal = 0.0, Cavity = 0.0, Refill = 0.0, Layers = 0.0, Assembly = 0.0;
  } Seconds;
  int RefillAttempts = 0; ///< TetGen runs (more than one when the cavity grew at forced slivers)
  std::size_t RefillPieces = 0; ///< the last refill's pieces, meshed side by side (1: the cavity whole)
  std::size_t SeparatorTriangles = 0; ///< the last refill's strip cutting the cavity in two (0: none)
  std::string SeparatorSkipped;       ///< why there was none where one was tried (empty: none tried, or made)
  std::size_t SurfaceTrianglesAtLockedCells = 0; ///< S triangles dropped at the locked cells

  // ---- Prism layers (options.Layers on); all empty otherwise.
  // Output points: kept points of V, then the stack's points (S's points,
  // layer points, closure apices; ARPrismLayers.h), then TetGen's new ones.
  // Mesh.Tetrahedra: kept tets, TetGen's tets, then the stack's closure
  // tetrahedra at S's border (layer cells, thin by design).
  std::vector<std::int64_t> Prisms;      ///< 6 output point ids each, VTK_WEDGE order
  std::vector<int> PrismLayer;           ///< per prism: layer k, 0 next to S
  std::vector<int> PrismSide;            ///< per prism: +1 on S's normal side, -1 on the other
  std::vector<std::int64_t> Pyramids;    ///< 5 output point ids each, VTK_PYRAMID order (quad, apex)
  std::vector<int> PyramidLayer;         ///< per pyramid: the layer of its quad
  std::vector<int> PyramidSide;          ///< per pyramid: +1 or -1
  /// Per output tetrahedron: -1 for kept and TetGen's tetrahedra, else the
  /// layer of a closure tetrahedron of the stack.
  std::vector<int> TetrahedronLayer;
  std::vector<int> TetrahedronSide;      ///< per output tetrahedron: 0, or +1/-1 for closure ones
  std::size_t FirstStackPoint = 0;       ///< output ids FirstStackPoint .. + NumberOfStackPoints - 1 are the stack's
  std::size_t NumberOfStackPoints = 0;   ///< (S's points, layer points, closure apices, in ARPrismLayers' order)
  std::size_t LimitedColumns = 0;        ///< stack columns lowered by obstacles/proximity/validity
  double LayerStackHeight = 0.0;         ///< the requested height per side, z_N
};

/**
 * Remeshes the cavity of V around S. V: positively oriented tetrahedra (an
 * inverted or flat one is refused). S: a triangulated surface, ideally with
 * nearly uniform edges (the caller remeshes it at the user's size).
 *
 * Returns false with `error` naming the problem for: an empty V or S, an
 * inverted cell, non-finite coordinates, S entirely outside V (or nothing of
 * S left after the trim), S crossing itself, S too close to the kept mesh
 * (it crosses the cavity's boundary: raise RemovalFactor), or a TetGen failure;
 * with prism layers also for bad layer options (named as PrismLayerDistances
 * names them) or a stack that cannot be built (BuildPrismLayers' errors).
 */
bool RemeshLocalCavity(const TetMesh& V, const double* surfacePoints, std::size_t nSurfacePoints,
  const std::int64_t* surfaceTriangles, std::size_t nSurfaceTriangles, const CavityOptions& options,
  CavityRemesh& out, std::string& error);

/**
 * The removal step of RemeshLocalCavity alone: per node of V, nonzero where
 * the node would be removed (S trimmed, validated and tested as there; the
 * "nothing to remesh" case is not an error here). Deterministic: a node gets
 * the same answer in any V that holds all the tetrahedra around it, so ranks
 * holding ghost cells agree on shared nodes when they pass the same S and
 * the same options.BoundaryTriangles.
 */
bool ComputeRemovedNodes(const TetMesh& V, const double* surfacePoints, std::size_t nSurfacePoints,
  const std::int64_t* surfaceTriangles, std::size_t nSurfaceTriangles, const CavityOptions& options,
  std::vector<std::uint8_t>& removed, std::string& error);
}

#endif
