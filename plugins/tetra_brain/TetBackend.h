#pragma once
// The queries TetraBrain hands to its collision back-end (the `backend`
// field): contact of a pointshell, sweeps, the overlap of a displayed proxy
// and ray casts, on the mesh TetraBrain keeps and the node positions its
// deformation gives. A back-end reads the data and never changes it; each
// query's answer is in what it returns, so no query depends on another.
#include <array>
#include <cstdint>
#include <optional>
#include <span>

#include <string>

#include "framework/core/CollisionBackend.h"
#include "framework/data/RemainingMesh.h"
#include "framework/geometry/ShellContactTarget.h"
#include "plugins/tetra_brain/TetGridSet.h"
#include "framework/data/TetMesh.h"
#include "framework/data/TetTopology.h"

namespace trephine::tetra {

// The scene's choices that shape the queries (TetraBrain's fields). Only the
// native back-end reads the thesis's options; TetraBrain refuses them for
// another back-end.
struct TetQueryOptions {
  enum class Search { kGrid, kFirstTetrahedron, kPreviousContact };
  Search search = Search::kGrid;
  bool algorithm2 = false;        // penetration="algorithm2", else the nearest face
  bool refreshEveryBox = true;    // boxRefresh="all" (the thesis's scans on a deforming mesh)
  // When cellSize is 0: the tool query's cost model for the shells the tools
  // reserve (cell_size/ToolQueryCost.h), half the average edge, or the edge.
  enum class CellSizeRule { kToolCost, kHalfEdge, kEdge };
  double cellSize = 0;            // mm, 0: from cellSizeRule
  CellSizeRule cellSizeRule = CellSizeRule::kToolCost;
  double displacementMargin = 0;  // mm, 0: a quarter of the average edge
  double contactDepth = 0.05;     // mm, how far a swept proxy sits in the surface
  bool deformable = false;        // a deformation component moves the nodes
};

// The brain's data, owned by TetraBrain, at fixed addresses for the run.
struct TetData {
  const TetMesh* mesh = nullptr;          // the rest shape, tetrahedra positively oriented
  const TetTopology* topology = nullptr;  // its boundary faces and neighbours
  TetQueryOptions options;
};

// The node positions of one frame (a deforming mesh; the rest shape when the
// deformation's frame was refused).
struct NodeFrame {
  std::span<const Vec3> nodes;          // mm, one per mesh node
  double displacementBound = 0;         // mm, no node is farther from its rest position
  std::span<const int32_t> movedNodes;  // nodes moved since the previous frame, unless allMoved
  bool allMoved = true;                 // or a frame in between was not seen
  double largestMove = INFINITY;        // mm, no node moved farther since the previous frame; infinite when unknown
};

// A contact, and when asked for, its sites and the tetrahedra it touches
// (valid until the back-end's next query).
struct TetContact {
  ShellContact contact;
  std::span<const ContactSite> sites;
  std::span<const int32_t> tets;  // the tetrahedra holding its shell points, each once (resection)
};

class TetBackend : public CollisionBackend {
 public:
  // At init, and again whenever the data is replaced. The node positions are
  // the rest shape's until moveNodes().
  virtual void bind(const TetData& data) = 0;
  virtual void reserveShell(std::span<const ShellPoint> shell) = 0;
  // The solid a reserved shell samples (ShellContactTarget::describeTool);
  // may throw when the back-end cannot take the tool.
  virtual void describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid) {
    (void)shell;
    (void)solid;
  }
  // The most sites a contact of a reserved shell can have.
  virtual size_t siteCapacity() const = 0;
  // A deforming mesh's nodes for this frame, before any query of the frame.
  // The span stays valid until the next call.
  virtual void moveNodes(const NodeFrame& frame) = 0;
  // Acceleration structures built on a deformed shape off the haptic thread
  // (TetGridRebuild), before the frame's moveNodes(); read in place until the
  // next call. Back-ends that refit their own trees ignore them.
  virtual void adoptGrids(const TetGridSet& grids) { (void)grids; }
  // Whether adoptGrids() is used (TetGridRebuild refuses a back-end that ignores it).
  virtual bool adoptsGrids() const { return false; }
  // Resection: from now on tetrahedra are removed during the run (called at
  // init, before the run). An error message when this back-end cannot follow.
  virtual std::optional<std::string> followRemovals() {
    return std::string("cannot follow removed tetrahedra");
  }
  // The tetrahedra a resection removed (RemainingMesh::remove's answer),
  // before the next query: the queries then answer as on the mesh without
  // them. In the haptic frame: no allocation.
  virtual void removeTets(const RemainingMesh::Change& change) { (void)change; }
  // `searchStart`: the asking tool's (ContactMemory::searchStart), for a
  // search that starts at the tool's last contact; others leave it.
  virtual TetContact collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool wantSites,
                             int32_t& searchStart) = 0;
  // The broad phase of collide() alone, for timing it apart (studies): the
  // candidates the narrow phase would examine (native: the shell points in
  // tetrahedra; mesh back-ends: the boundary triangles within reach).
  virtual size_t broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) = 0;
  virtual SweepResult sweep(const SweepQuery& query) const = 0;
  virtual bool overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const = 0;
  virtual std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const = 0;
};

}  // namespace trephine::tetra
