#pragma once
// A light, closed stand-in for a voxel grid's isosurface, in pieces by the
// grid's surface blocks: the isosurface of the volume max-pooled over f^3
// voxels (CoarseVoxelGrid), f the smallest that gives at most `triangles`,
// its vertices projected back onto the full isosurface (IsoSurfaceProjection),
// and each triangle given to the BlockedIsoSurface block whose cells hold its
// centroid. A viewer draws the pieces of the blocks it does not have at full
// resolution (the live view: all but the drilled ones; a recorded run's
// viewer: those the drill never touched), and the pieces join the full
// blocks where they meet within about a coarse voxel.
#include <array>
#include <cstdint>
#include <vector>

#include "framework/data/IsoSurfaceProjection.h"
#include "framework/data/TriangleMesh.h"
#include "framework/data/VoxelGrid.h"

namespace trephine {

struct CoarseIsoSurface {
  std::vector<TriangleMesh> pieces;  // per block of the full surface (BlockedIsoSurface's indices)
  int factor = 1;                    // voxels pooled per coarse voxel, each axis
  size_t triangles = 0;              // in all pieces
  ProjectionCounts projection;
};

// `fullTriangles`: the full isosurface's count (to start near the factor
// that fits); `blocksPerAxis`: the full surface's blocks (BlockedIsoSurface).
CoarseIsoSurface coarseIsoSurface(const VoxelGrid& grid, size_t triangles, size_t fullTriangles,
                                  const std::array<int64_t, 3>& blocksPerAxis);

}  // namespace trephine
