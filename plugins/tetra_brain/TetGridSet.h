#pragma once
// The uniform grids of the native back-end built on one shape of the mesh
// (its reference): the rest shape at first, a deformed one when a
// TetGridRebuild builds them again off the haptic thread. Every tetrahedron's
// and boundary face's box on the reference is grown by the displacement
// margin, so while the nodes stay within the margin of the reference each
// shell point still finds its tetrahedron in its own cell.
#include <cstdint>
#include <span>
#include <vector>

#include "framework/data/TetTopology.h"
#include "plugins/tetra_brain/UniformGrid.h"

namespace trephine::tetra {

// A TetGridRebuild publishes the grids it builds on the deformed shape here.
inline constexpr const char* kGridsChannelName = "grids";

struct TetGridSet {
  uint64_t version = 0;          // 0: built on the rest shape by the back-end itself
  std::vector<Vec3> reference;   // mm, the node positions the grids were built on
  std::vector<Box3> boxes;       // per tetrahedron, on the reference (not grown)
  Box3 bounds;                   // of the reference
  double margin = 0;             // mm, by which the boxes in the grids are grown
  UniformGrid tetGrid, faceGrid;
};

// Builds the grids on `positions` (one per node of `mesh`), cells of side
// `cellSize` for the tetrahedra and `faceCellSize` for `faces` (the boundary
// faces, or every face that may become boundary: faceGrid lists indices into
// it), boxes grown by `margin` (mm). Allocates: never on the haptic thread.
void buildTetGrids(const TetMesh& mesh, std::span<const BoundaryFace> faces, std::span<const Vec3> positions,
                   double margin, double cellSize, double faceCellSize, TetGridSet& out);

// The largest distance of a node from its position in `set.reference` (mm).
double driftFromReference(const TetGridSet& set, std::span<const Vec3> positions);
// The same for the nodes first, first + 1, ... (`positions` holds those nodes only).
double driftFromReference(const TetGridSet& set, std::span<const Vec3> positions, size_t first);

}  // namespace trephine::tetra
