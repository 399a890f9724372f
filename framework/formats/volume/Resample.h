#pragma once
// Resampling a volume onto cubic voxels (e.g. to give the haptic and
// rendering code isotropic cells whatever the scan's slice thickness).
#include "framework/data/DensityVolume.h"

namespace trephine::formats {

// A volume with cubic voxels of `voxelSizeMm` covering the same world extent:
// along each axis n = max(1, round(extent / voxelSizeMm)) voxels, centred on
// the source's extent. Densities are trilinear interpolations of the source's
// at the new voxel centres, clamped at the border (outside the outermost
// centres the edge value holds), and keep the source's encoding. Throws
// std::invalid_argument for a non-positive size or a result above 2^31 voxels.
DensityVolume resampleToVoxelSize(const DensityVolume& source, double voxelSizeMm);

}  // namespace trephine::formats
