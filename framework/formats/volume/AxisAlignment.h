#pragma once
// Bringing a stored grid whose axes are a signed permutation of the world
// axes (flipped and/or swapped, as scanners and ITK write them) onto the
// axis-aligned, positive-spacing grid of a DensityVolume without touching a
// sample. Other grids (oblique, sheared) are resampled (ObliqueResampling.h).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>

#include "framework/math/Math.h"
#include "framework/formats/volume/SampleConversion.h"

namespace trephine::formats {

// Relative size of the off-axis components an axis may have and still count as aligned.
inline constexpr double kAxisAlignmentTolerance = 1e-3;

struct AlignedGrid {
  std::array<int32_t, 3> dims{0, 0, 0};  // along world x, y, z
  Vec3 spacing = Vec3::Ones();           // mm, positive
  Vec3 origin = Vec3::Zero();            // mm, centre of voxel (0, 0, 0) of the aligned grid
  SamplePlacement placement;             // where each stored sample goes in the aligned grid
};

// Whether each column of `axes` points along one world axis (within
// kAxisAlignmentTolerance), each along a different one.
bool isAxisAligned(const Eigen::Matrix3d& axes);

// `axes` column a is the world step (mm) between neighbouring samples along
// stored axis a; `origin` is the world position (mm) of stored sample
// (0, 0, 0). Throws VolumeReadError naming `file` for oblique or degenerate axes.
AlignedGrid alignGrid(const std::array<int64_t, 3>& storedDims, const Eigen::Matrix3d& axes, const Vec3& origin,
                      const std::filesystem::path& file);

}  // namespace trephine::formats
