#pragma once
// Bringing a stored grid that is not axis-aligned (an oblique MRI plane, a
// CT stack sheared by a tilted gantry, a rotated NIfTI or NRRD frame) onto
// an axis-aligned grid by trilinear resampling. The target grid covers the
// stored voxel centres' bounding box; its spacing along each world axis is
// the component along it of the stored step closest to it (a tilted CT keeps
// its pixel spacing and table step; a rotated plane gets a finer grid). Voxels outside the scan take the lowest density (air).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <span>

#include "framework/math/Math.h"
#include "framework/data/DensityVolume.h"

namespace trephine::formats {

struct ResampledGrid {
  std::array<int32_t, 3> dims{0, 0, 0};  // along world x, y, z
  Vec3 spacing = Vec3::Ones();           // mm
  Vec3 origin = Vec3::Zero();            // mm, centre of voxel (0, 0, 0)
};

// The axis-aligned grid for stored samples at origin + axes * (i, j, k)
// (mm). Throws VolumeReadError naming `file` for degenerate axes or a grid
// beyond the voxel limit.
ResampledGrid resampledGrid(const std::array<int64_t, 3>& storedDims, const Eigen::Matrix3d& axes, const Vec3& origin,
                            const std::filesystem::path& file);

// Fills `out` (grid order, x fastest) by trilinear interpolation of `stored`
// (codes in stored order, first axis fastest); `background` outside the
// stored cells (beyond half a voxel from the outer centres).
void resampleCodes(std::span<const VoxelCode> stored, const std::array<int64_t, 3>& storedDims,
                   const Eigen::Matrix3d& axes, const Vec3& origin, const ResampledGrid& grid, VoxelCode background,
                   std::span<VoxelCode> out);

}  // namespace trephine::formats
