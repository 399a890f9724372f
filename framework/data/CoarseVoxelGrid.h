#pragma once
// A density volume over blocks of factor^3 voxels, each the mean of its
// voxels (the volume a scanner f times coarser would give: bone thinner than
// about half a coarse voxel fades below the isovalue) or their densest (no
// wall is lost: the bone grows by up to a coarse voxel, and the coarse
// isosurface is closed wherever the full one is). Its isosurface
// (BlockedIsoSurface) has about 1/f^2 of the full one's triangles; projected
// back onto the full surface (projectOntoIsoSurface) it is a light, closed
// stand-in for it, where vertex clustering folds a wall thinner than a
// cluster onto itself in steps. Used by the live view for the skull the
// drill has not touched.
#include <vector>

#include "framework/data/VoxelGrid.h"

namespace trephine {

struct CoarseVoxelGrid {
  CoarseVoxelGrid() = default;
  CoarseVoxelGrid(CoarseVoxelGrid&&) = default;  // moved, `grid` still points at `codes`
  CoarseVoxelGrid& operator=(CoarseVoxelGrid&&) = default;
  CoarseVoxelGrid(const CoarseVoxelGrid&) = delete;  // a copy's grid would point at the original's codes
  CoarseVoxelGrid& operator=(const CoarseVoxelGrid&) = delete;

  std::vector<VoxelCode> codes;
  VoxelGrid grid;  // over `codes`: the fine grid's corner, factor times its spacing; same isoCode and outsideCode
  int factor = 1;
};

enum class VoxelPooling { kMean, kMax };

// Coarse voxel (I, J, K) is the mean (or the largest) code of the fine voxels
// f I .. f I + f - 1 (each axis) that the grid has: a partial block at the
// far edge pools the voxels it holds. `factor` >= 1.
CoarseVoxelGrid coarsenVoxels(const VoxelGrid& fine, int factor, VoxelPooling pooling);

}  // namespace trephine
